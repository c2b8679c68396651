"""The scene of a run as a Python object: a dict validated by fdem's own checks.

A :class:`Scene` holds the scene as a dict (the JSON of ``docs/scene-format.md``) and the
folder that its relative mesh paths are read from. It is validated when made and after
every change, by the same code and with the same messages as ``fdem check``: a refused
scene raises :class:`fdem.SceneError` with the JSON path of the field and the fix.
"""

from __future__ import annotations

import copy
import json
import math
import os
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Dict, Iterator, List, Optional, Union

from . import _core

SceneError = _core.SceneError

#: What a scene can be given as: a path of a scene file or a dict.
PathLike = Union[str, "os.PathLike[str]"]

_TOKEN = re.compile(r"\[(\d+)\]|([^.\[\]]+)")


def _parse_key_path(key_path: str) -> List[Union[str, int]]:
    """The parts of ``"bodies[0].materials.rock.young"`` or ``"bodies.0.materials.rock.young"``.

    A part in brackets is a list index; a part of digits alone is an index into a list and a
    key into a dict (decided where it is used).
    """
    if not isinstance(key_path, str) or not key_path:
        raise TypeError(
            f"a key path is a non-empty string such as 'integrator.safety' or "
            f"'bodies[0].materials.rock.young', not {key_path!r}"
        )
    parts: List[Union[str, int]] = []
    pos = 0
    for m in _TOKEN.finditer(key_path):
        gap = key_path[pos : m.start()]
        if gap not in ("", "."):
            raise KeyError(f"malformed key path {key_path!r} near {gap!r}")
        parts.append(int(m.group(1)) if m.group(1) is not None else m.group(2))
        pos = m.end()
    if pos != len(key_path) or key_path.endswith("."):
        raise KeyError(f"malformed key path {key_path!r}")
    return parts


def _show(parts: List[Union[str, int]]) -> str:
    """A key path in the JSON-path form of fdem's messages: ``bodies[0].materials``."""
    out = ""
    for p in parts:
        if isinstance(p, int):
            out += f"[{p}]"
        else:
            out += ("." if out else "") + p
    return out or "(top level)"


def _step(node: Any, part: Union[str, int], done: List[Union[str, int]], key_path: str) -> Any:
    """The child ``part`` of ``node`` (at ``done``), or a KeyError naming what is there."""
    where = _show(done)
    if isinstance(node, list):
        try:
            i = int(part)
        except ValueError:
            raise KeyError(
                f"{key_path}: {where} is a list of {len(node)}; index it with a number "
                f"({where}[0] or {where}.0), not {part!r}"
            ) from None
        if not 0 <= i < len(node):
            raise KeyError(
                f"{key_path}: {where} has {len(node)} entries (0 to {len(node) - 1}), no [{i}]"
            )
        return node[i]
    if isinstance(node, dict):
        key = str(part)
        if key not in node:
            keys = ", ".join(map(repr, node)) or "none"
            raise KeyError(f"{key_path}: no key {key!r} at {where}; the keys there: {keys}")
        return node[key]
    raise KeyError(
        f"{key_path}: {where} is a value ({type(node).__name__} {node!r}), it has no {part!r}"
    )


def _to_json_value(value: Any, path: str, file: str) -> Any:
    """``value`` as plain JSON data (dicts, lists, str, int, float, bool, None).

    Tuples become lists, paths strings, numpy scalars and arrays Python numbers and lists;
    a non-finite number or a value JSON cannot hold raises SceneError with its path.
    """
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, int):
        return int(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise _scene_error(
                file, path, f"{value!r} is not a finite number", "give a finite number"
            )
        return float(value)
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if isinstance(value, Mapping):
        out = {}
        for k, v in value.items():
            if not isinstance(k, str):
                raise _scene_error(
                    file,
                    path,
                    f"the key {k!r} is a {type(k).__name__}",
                    "JSON keys are strings: use str keys",
                )
            out[k] = _to_json_value(v, f"{path}.{k}" if path else k, file)
        return out
    if isinstance(value, (list, tuple)):
        return [_to_json_value(v, f"{path}[{i}]", file) for i, v in enumerate(value)]
    # numpy scalars and arrays (without importing numpy)
    if hasattr(value, "tolist") and callable(value.tolist):
        return _to_json_value(value.tolist(), path, file)
    raise _scene_error(
        file,
        path,
        f"a value of type {type(value).__name__} ({value!r}) has no JSON form",
        "give a number, a string, a bool, None, a list or a dict",
    )


def _scene_error(file: str, path: Optional[str], message: str, fix: str) -> SceneError:
    """A SceneError made on the Python side, with the attributes of the extension's."""
    at = f": at `{path}`" if path else ""
    e = SceneError(f"{file}{at}: {message}\n  fix: {fix}")
    e.kind = "invalid"
    e.file = file
    e.path = path
    e.message = message
    e.fix = fix
    return e


class Scene:
    """A scene: its dict, the folder its relative mesh paths are read from, and its file.

    ``Scene(path)`` reads a scene file (the folder is the file's); ``Scene(d, base=None)``
    takes a dict (deep-copied; the folder is ``base``, else the current folder). Either is
    validated at once with every check of ``fdem check`` (its meshes read, every name
    resolved, the time step found): a refused scene raises :class:`fdem.SceneError` whose
    ``path`` is the JSON path of the field and ``fix`` what to change.

    Key paths read and change fields: ``scene["integrator.safety"]``,
    ``scene["bodies[0].materials.*.young"] = 40e9`` (``bodies.0.materials...`` too). A change
    is validated; a refused one raises SceneError and leaves the scene as it was.

    Messages name the scene file; a scene made from a dict is named ``BASE/scene.json``
    (``name=`` gives another name).
    """

    __slots__ = ("_data", "_base", "_file", "_name", "_text")
    _data: Dict[str, Any]
    _base: Path
    _file: Optional[Path]
    _name: str
    _text: Optional[str]

    def __init__(
        self,
        source: Union["Scene", Mapping[str, Any], PathLike],
        base: Optional[PathLike] = None,
        *,
        name: Optional[str] = None,
    ) -> None:
        if isinstance(source, Scene):
            self._data = copy.deepcopy(source._data)
            self._base = source._base if base is None else Path(base).resolve()
            self._file = source._file
            self._name = source._name if name is None else name
            self._text = source._text if base is None else None
            if base is not None:
                self._validate(self._data)
            return
        if isinstance(source, (str, os.PathLike)):
            file = Path(source).resolve()
            try:
                text = file.read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError) as e:
                err = _scene_error(
                    str(file), None, f"cannot read the file: {e}", "check the file's path"
                )
                err.kind = "io"
                raise err from None
            self._file = file
            self._base = file.parent if base is None else Path(base).resolve()
            self._name = file.name if name is None else name
            # the file's own text goes to the checks: their line and column are the file's
            self._validate_text(text)
            self._data = json.loads(text)
            self._text = text if base is None else None
            return
        if isinstance(source, Mapping):
            self._file = None
            self._base = Path(os.getcwd() if base is None else base).resolve()
            self._name = "scene.json" if name is None else name
            data = _to_json_value(source, "", str(self.error_file))
            self._validate(data)
            self._data = data
            self._text = None
            return
        raise TypeError(
            f"Scene() takes a path of a scene file (str or os.PathLike) or a dict, not "
            f"{type(source).__name__}: {source!r}\n"
            f"  fix: fdem.Scene('examples/brazilian-disc-fracture.json') or "
            f"fdem.Scene({{'bodies': [...], ...}}, base=FOLDER_OF_THE_MESHES)"
        )

    # -- making ----------------------------------------------------------------------------

    @classmethod
    def from_file(cls, path: PathLike) -> "Scene":
        """The scene of the file ``path`` (its folder resolves relative mesh paths)."""
        if not isinstance(path, (str, os.PathLike)):
            raise TypeError(f"Scene.from_file() takes a path, not {type(path).__name__}")
        return cls(path)

    @classmethod
    def from_dict(
        cls, d: Mapping[str, Any], base: Optional[PathLike] = None, *, name: Optional[str] = None
    ) -> "Scene":
        """The scene of the dict ``d`` (deep-copied); relative mesh paths resolve against
        ``base`` (default: the current folder)."""
        if not isinstance(d, Mapping):
            raise TypeError(f"Scene.from_dict() takes a dict, not {type(d).__name__}")
        return cls(d, base, name=name)

    # -- where it is -----------------------------------------------------------------------

    @property
    def base(self) -> Path:
        """The folder that relative mesh paths are read from."""
        return self._base

    @property
    def file(self) -> Optional[Path]:
        """The file the scene was read from (None for a scene made from a dict)."""
        return self._file

    @property
    def error_file(self) -> Path:
        """The file named in messages (and in a run's checkpoint): the scene's file, or
        ``base / name`` for a scene made from a dict."""
        if self._file is not None and self._file.parent == self._base:
            return self._file
        return self._base / self._name

    # -- checks ----------------------------------------------------------------------------

    def _validate_text(self, text: str) -> None:
        _core.load_check(text, str(self.error_file))

    def _validate(self, data: Any) -> None:
        self._validate_text(json.dumps(data))

    def to_json(self, indent: Optional[int] = None) -> str:
        """The scene as JSON text (the file's own text while the scene is unchanged)."""
        if self._text is not None and indent is None:
            return self._text
        return json.dumps(self._data, indent=indent)

    # -- key paths -------------------------------------------------------------------------

    def __getitem__(self, key_path: str) -> Any:
        parts = _parse_key_path(key_path)
        node: Any = self._data
        for i, p in enumerate(parts):
            node = _step(node, p, parts[:i], key_path)
        return copy.deepcopy(node)

    def get(self, key_path: str, default: Any = None) -> Any:
        """The value at ``key_path``, or ``default`` where there is none."""
        try:
            return self[key_path]
        except KeyError:
            return default

    def __contains__(self, key_path: object) -> bool:
        if not isinstance(key_path, str):
            return False
        try:
            self[key_path]
        except KeyError:
            return False
        return True

    def __setitem__(self, key_path: str, value: Any) -> None:
        self.edit_in_place({key_path: value})

    def edit_in_place(self, changes: Mapping[str, Any]) -> None:
        """Sets every ``key_path: value`` of ``changes`` and validates once; on a refusal
        (SceneError, KeyError) the scene is left as it was."""
        data = copy.deepcopy(self._data)
        for key_path, value in changes.items():
            parts = _parse_key_path(key_path)
            if not parts:
                raise KeyError(f"empty key path {key_path!r}")
            node: Any = data
            for i, p in enumerate(parts[:-1]):
                node = _step(node, p, parts[:i], key_path)
            last = parts[-1]
            jv = _to_json_value(value, _show(parts), str(self.error_file))
            if isinstance(node, list):
                _step(node, last, parts[:-1], key_path)  # the index exists
                node[int(last)] = jv
            elif isinstance(node, dict):
                node[str(last)] = jv
            else:
                where = _show(parts[:-1])
                raise KeyError(
                    f"{key_path}: {where} is a value ({type(node).__name__}), it has no {last!r}; "
                    f"set {where} to a dict first"
                )
        self._validate(data)
        self._data = data
        self._text = None

    def edit(self, changes: Optional[Mapping[str, Any]] = None, **more: Any) -> "Scene":
        """An edited copy: ``scene.edit({"integrator.safety": 0.5})``; the scene itself is
        unchanged. Key paths that are Python names can be keywords too."""
        s = Scene(self)
        c = dict(changes or {})
        c.update(more)
        s.edit_in_place(c)
        return s

    def with_(self, **changes: Any) -> "Scene":
        """An edited copy: ``scene.with_(**{"fracture.material.tensile_strength": 4e6})``."""
        return self.edit(changes)

    def copy(self) -> "Scene":
        """A copy of the scene."""
        return Scene(self)

    # -- out -------------------------------------------------------------------------------

    def to_dict(self) -> Dict[str, Any]:
        """The scene as a dict (a deep copy)."""
        return copy.deepcopy(self._data)

    def with_absolute_meshes(self) -> Dict[str, Any]:
        """The scene's dict with every body's mesh path made absolute (against ``base``)."""
        d = self.to_dict()
        for body in d.get("bodies", []):
            if isinstance(body, dict) and isinstance(body.get("mesh"), str):
                body["mesh"] = str((self._base / body["mesh"]).resolve())
        return d

    def write(self, path: PathLike, indent: int = 2) -> Path:
        """Writes the scene as a JSON file at ``path`` with absolute mesh paths (so that it
        runs from anywhere: ``fdem run PATH``); returns the path."""
        p = Path(path)
        p.write_text(
            json.dumps(self.with_absolute_meshes(), indent=indent) + "\n", encoding="utf-8"
        )
        return p

    def keys(self) -> Iterator[str]:
        """The scene's top-level keys."""
        return iter(self._data.keys())

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Scene):
            return NotImplemented
        return self._data == other._data and self._base == other._base

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        src = str(self._file) if self._file is not None else f"dict, base {self._base}"
        title = self._data.get("title", "")
        short = (title[:60] + "...") if len(title) > 60 else title
        return f"<fdem.Scene {src}{': ' + short if short else ''}>"


def as_scene(source: Union[Scene, Mapping[str, Any], PathLike]) -> Scene:
    """``source`` as a Scene: a Scene as it is, a path or a dict read and validated."""
    if isinstance(source, Scene):
        return source
    if isinstance(source, (str, os.PathLike, Mapping)):
        return Scene(source)
    raise TypeError(
        f"expected a fdem.Scene, a path of a scene file or a dict, not {type(source).__name__}: "
        f"{source!r}\n  fix: fdem.run('examples/brazilian-disc-fracture.json') or "
        f"fdem.run(fdem.Scene(...))"
    )


__all__ = ["Scene", "SceneError", "as_scene"]
