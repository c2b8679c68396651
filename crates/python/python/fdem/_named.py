"""The dicts of the package that are indexed by name (histories, walls, frame arrays, ...).

:class:`Named` is a plain ``dict`` in every respect (``in``, ``.get``, iteration, equality,
pandas, pickling) but one: indexing it with a key it does not hold raises a ``KeyError`` that
names the key and lists the keys it holds, sorted::

    KeyError: "no history 't'; the histories: kinetic, time, u_y[load]"
"""

from __future__ import annotations

from typing import Any, Dict, Iterable, Mapping, NoReturn, Tuple, TypeVar, Union

__all__ = ["Named"]

_V = TypeVar("_V")


class Named(Dict[str, _V]):
    """A dict whose missing key raises a ``KeyError`` naming the key and listing the keys.

    Args:
        items: the entries (a mapping, or ``(key, value)`` pairs).
        what: what one entry is, for the message (``"history"``).
        plural: what the entries are (``"histories"``); ``what + "s"`` when not given.
    """

    what: str
    plural: str

    def __init__(
        self,
        items: Union[Mapping[str, _V], Iterable[Tuple[str, _V]]] = (),
        *,
        what: str = "key",
        plural: str = "",
    ) -> None:
        super().__init__(items)
        self.what = what
        self.plural = plural or what + "s"

    def __missing__(self, key: Any) -> NoReturn:
        # a Named made without __init__ (copy, pickle of an older object) has no attributes
        what = getattr(self, "what", "key")
        plural = getattr(self, "plural", what + "s")
        keys = ", ".join(sorted(str(k) for k in self)) if self else "(none)"
        raise KeyError(f"no {what} {key!r}; the {plural}: {keys}")
