"""Parameter sweeps: variants of one scene run in parallel processes, one row per variant.

``sweep(scene, variants)`` edits a copy of the scene for each variant (a dict of key paths to
values, e.g. ``{"bodies[0].materials.rock.young": 20e9}``), runs each variant in a worker
process (``concurrent.futures.ProcessPoolExecutor`` with the ``spawn`` context: each run has
its own process, its own memory and its own rayon threads), and returns one row per variant,
in the order of ``variants``.

A row (a dict: a missing field raises a KeyError listing the fields) holds the variant's values under their key paths, then ``failed`` (whether the
specimen failed within the run, ``Output.failure``; None without a load-displacement curve),
``peak_load`` (N; None when it did not fail: a run that ends while the load still rises has no
peak), ``largest_load`` (N, failed or not), ``steps``, ``wall_time`` (s, the variant's wall-clock time in its worker: load, run,
output), ``converged`` (relaxation and static runs; None for dynamic runs), the energy totals
``energy_supplied``, ``energy_present``, ``energy_dissipated``, ``energy_error`` (J, from
``summary.json``), ``metric`` (when ``metric`` is given: ``metric(output)`` for the run's
folder read with :func:`fdem._output.read`), ``out`` (the run's folder, or None when the
folders were temporary) and ``error`` (None, or the text of the exception that stopped the
variant: a bad key path, a scene error with its JSON path, a failed run).
"""

from __future__ import annotations

import copy
import json
import multiprocessing
import os
import pickle
import re
import shutil
import tempfile
import time
from concurrent.futures import Future, ProcessPoolExecutor
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from ._named import Named
from ._output import Output

__all__ = ["sweep", "parse_key_path", "get_path", "set_path", "fdem_runner", "ROW_FIELDS"]

#: A runner: runs the scene ``scene_dict`` (relative paths against ``base``) into the folder
#: ``out`` with ``threads`` rayon threads (None: the default); may return a dict of extra
#: fields for the row.
Runner = Callable[[Dict[str, Any], str, str, Optional[int]], Optional[Dict[str, Any]]]

#: The fields every row has after the variant's values, in order.
ROW_FIELDS = (
    "failed",
    "peak_load",
    "largest_load",
    "steps",
    "wall_time",
    "converged",
    "energy_supplied",
    "energy_present",
    "energy_dissipated",
    "energy_error",
)

_ENERGY = ("supplied", "present", "dissipated", "error")

_TOKEN = re.compile(r"([^.\[\]]+)|\[(\d+)\]|(\.)")


def parse_key_path(key_path: str) -> List[Union[str, int]]:
    """The keys of a key path: ``"bodies[0].materials.rock.young"`` and
    ``"bodies.0.materials.rock.young"`` give ``["bodies", 0, "materials", "rock", "young"]``
    (a number between dots is kept as text; it indexes a list, or names a key of an object).

    Raises:
        TypeError: the key path is not a str.
        ValueError: an empty or malformed key path.
    """
    if not isinstance(key_path, str):
        raise TypeError(
            f"key path {key_path!r} is a {type(key_path).__name__}: give a str such as "
            "'bodies[0].materials.rock.young'"
        )
    keys: List[Union[str, int]] = []
    pos = 0
    expect_name = True
    for m in _TOKEN.finditer(key_path):
        name, index, dot = m.groups()
        # a name after a dot (or first), an index or a dot after a name or an index
        if m.start() != pos or (name is not None) != expect_name:
            break
        pos = m.end()
        if name is not None:
            keys.append(name)
            expect_name = False
        elif index is not None:
            keys.append(int(index))
        else:
            expect_name = True
    if pos != len(key_path) or expect_name or not keys:
        raise ValueError(
            f"key path {key_path!r} is not of the form 'bodies[0].materials.rock.young' "
            "(names separated by dots, list indices as [0] or .0)"
        )
    return keys


def _step(node: Any, key: Union[str, int], done: str, key_path: str) -> Tuple[Any, Any]:
    """The container ``node`` and its key for ``key`` (a list index as int)."""
    if isinstance(node, list):
        if isinstance(key, str) and not key.isdigit():
            raise KeyError(
                f"{key_path}: {done or 'the scene'} is a list of {len(node)}: index it with a "
                f"number ({done}[0]), not {key!r}"
            )
        i = int(key)
        if i >= len(node):
            raise KeyError(f"{key_path}: {done} has {len(node)} entries, no [{i}]")
        return node, i
    if isinstance(node, dict):
        if isinstance(key, int):
            raise KeyError(
                f"{key_path}: {done or 'the scene'} is an object, not a list: no [{key}]"
            )
        return node, key
    raise KeyError(
        f"{key_path}: {done} is a {type(node).__name__} ({node!r}), not an object or a list"
    )


def _walk(d: Dict[str, Any], keys: Sequence[Union[str, int]], key_path: str) -> Tuple[Any, Any]:
    """The container of the last key of ``keys`` and that key; every key before must exist."""
    node: Any = d
    done = ""
    for k in keys[:-1]:
        node, k2 = _step(node, k, done, key_path)
        if isinstance(node, dict) and k2 not in node:
            there = ", ".join(map(str, node)) or "none"
            raise KeyError(f"{key_path}: no {k2!r} in {done or 'the scene'} (keys there: {there})")
        node = node[k2]
        done = f"{done}[{k2}]" if isinstance(k2, int) else (f"{done}.{k2}" if done else k2)
    return _step(node, keys[-1], done, key_path)


def get_path(d: Dict[str, Any], key_path: str) -> Any:
    """The value at ``key_path`` in the scene dict ``d`` (KeyError naming the keys there when
    it does not exist)."""
    node, k = _walk(d, parse_key_path(key_path), key_path)
    if isinstance(node, dict) and k not in node:
        raise KeyError(f"{key_path}: no {k!r} (keys there: {', '.join(map(str, node)) or 'none'})")
    return node[k]


def set_path(d: Dict[str, Any], key_path: str, value: Any) -> None:
    """Sets ``key_path`` in the scene dict ``d`` to a deep copy of ``value``. Every key but
    the last must exist (KeyError naming the keys there); the last may be new in an object
    (the scene's validation then judges it) and must exist in a list."""
    node, k = _walk(d, parse_key_path(key_path), key_path)
    node[k] = copy.deepcopy(value)


def fdem_runner(
    scene_dict: Dict[str, Any], base: str, out: str, threads: Optional[int]
) -> Optional[Dict[str, Any]]:
    """The default runner: ``fdem.run`` of the scene in this process (needs the compiled
    extension)."""
    import fdem  # the package, imported in the worker

    scene = fdem.Scene.from_dict(scene_dict, base=base)
    fdem.run(scene, out=out, progress=False, threads=threads)
    return None


def _worker_init(threads: Optional[int]) -> None:
    if threads is not None:
        os.environ["RAYON_NUM_THREADS"] = str(threads)


def _run_variant(
    runner: Runner,
    scene_dict: Dict[str, Any],
    base: str,
    out: str,
    threads: Optional[int],
    metric: Optional[Callable[[Output], Any]],
    keep: bool,
) -> Dict[str, Any]:
    """Runs one variant in a worker and makes its row (without the variant's values)."""
    try:
        t0 = time.perf_counter()
        extra = runner(scene_dict, base, out, threads)
        wall = time.perf_counter() - t0
        o = Output(out)
        s = o.summary
        energy = s.get("energy") or {}
        failure = o.failure
        row: Dict[str, Any] = {
            "failed": failure["failed"],
            "peak_load": failure["peak_load"],
            "largest_load": failure["largest_load"],
            "steps": s.get("steps"),
            "wall_time": wall,
            "converged": s.get("converged"),
        }
        for k in _ENERGY:
            row[f"energy_{k}"] = energy.get(k)
        if metric is not None:
            row["metric"] = metric(o)
        if extra:
            row.update(extra)
        row["out"] = out if keep else None
        return row
    finally:
        if not keep:
            shutil.rmtree(out, ignore_errors=True)


def _source(scene: Any) -> Tuple[Dict[str, Any], str]:
    """The scene's dict and base folder: a Scene (``to_dict()``, ``base``), a path to a scene
    file, or a dict (base: the current folder)."""
    if hasattr(scene, "to_dict") and hasattr(scene, "base"):
        return scene.to_dict(), os.fspath(scene.base)
    if isinstance(scene, Mapping):
        return copy.deepcopy(dict(scene)), os.getcwd()
    if isinstance(scene, (str, os.PathLike)):
        p = Path(scene)
        with open(p, encoding="utf-8") as f:
            return json.load(f), os.fspath(p.resolve().parent)
    raise TypeError(
        f"scene is a {type(scene).__name__}: give an fdem.Scene, a scene file's path or a "
        "scene dict"
    )


def _error_text(e: BaseException) -> str:
    # a KeyError's str() is the repr of its message; show the message itself
    text = e.args[0] if isinstance(e, KeyError) and len(e.args) == 1 else str(e)
    return f"{type(e).__name__}: {text}"


def sweep(
    scene: Any,
    variants: Sequence[Mapping[str, Any]],
    processes: int = 2,
    threads: Optional[int] = 1,
    metric: Optional[Callable[[Output], Any]] = None,
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    raise_errors: bool = False,
    as_frame: bool = False,
    runner: Optional[Runner] = None,
) -> Any:
    """Runs variants of ``scene`` in parallel processes; one row per variant, in order.

    Args:
        scene: an ``fdem.Scene``, a scene file's path, or a scene dict (relative mesh paths
            against the current folder).
        variants: a list of dicts ``{key_path: value}`` (``"integrator.safety"``,
            ``"bodies[0].materials.rock.young"``); each is applied to a copy of the scene.
        processes: worker processes (>= 1); each runs one variant at a time.
        threads: rayon threads per run (None: rayon's default, all cores: give
            ``processes * threads`` <= the cores).
        metric: optional picklable callable (a module-level function) taking the run's
            folder read lazily (``fdem._output.Output``: ``summary``, ``histories``,
            ``frames``, ``peak_load``, ...) and returning the row's ``metric``.
        out: a folder for the runs (``out/variant_000``, ... kept, the row's ``out``); None:
            temporary folders, deleted once each row is made.
        raise_errors: True: the first failing variant (in order) raises its exception and the
            variants not yet started are cancelled; False: its row carries the ``error`` text.
        as_frame: True: a pandas DataFrame (ImportError with the fix without pandas).
        runner: how a variant is run (default :func:`fdem_runner`, ``fdem.run``); a picklable
            callable ``runner(scene_dict, base, out, threads)`` that writes a run folder at
            ``out`` and may return extra fields for the row.

    Returns:
        A list of row dicts (see the module's docs), or a DataFrame with ``as_frame``.

    The workers are started with ``spawn``: they import the calling script's main module
    again, so a script calls ``sweep`` under ``if __name__ == "__main__":``.
    """
    if isinstance(variants, Mapping) or not isinstance(variants, Sequence):
        raise TypeError(
            f"variants is a {type(variants).__name__}: give a list of dicts "
            "[{'bodies[0].materials.rock.young': 20e9}, ...]"
        )
    for i, v in enumerate(variants):
        if not isinstance(v, Mapping):
            raise TypeError(
                f"variants[{i}] is a {type(v).__name__}: give a dict {{key_path: value}}"
            )
    if not isinstance(processes, int) or processes < 1:
        raise ValueError(f"processes = {processes!r}: give a whole number >= 1")
    if threads is not None and (not isinstance(threads, int) or threads < 1):
        raise ValueError(f"threads = {threads!r}: give a whole number >= 1, or None")
    for what, f in (("metric", metric), ("runner", runner)):
        if f is None:
            continue
        if not callable(f):
            raise TypeError(f"{what} is a {type(f).__name__}: give a function")
        try:
            pickle.dumps(f)
        except Exception as e:
            raise TypeError(
                f"{what} {f!r} cannot be sent to the worker processes ({e}): give a function "
                "defined at the top level of an importable module, not a lambda or a local "
                "function"
            ) from None
    if as_frame:
        from ._output import _pandas

        _pandas()
    base_dict, base = _source(scene)
    keep = out is not None
    root = Path(out) if out is not None else Path(tempfile.mkdtemp(prefix="fdem-sweep-"))
    root.mkdir(parents=True, exist_ok=True)
    width = max(3, len(str(len(variants) - 1)))
    run = runner if runner is not None else fdem_runner

    rows: List[Dict[str, Any]] = []
    try:
        ctx = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(
            max_workers=processes, mp_context=ctx, initializer=_worker_init, initargs=(threads,)
        ) as ex:
            try:
                jobs: List[
                    Tuple[Dict[str, Any], Optional[str], Optional[Future[Any]], Optional[BaseException]]
                ] = []
                for i, v in enumerate(variants):
                    head: Dict[str, Any] = Named(
                        ((k, copy.deepcopy(val)) for k, val in v.items()), what="row field"
                    )
                    d = copy.deepcopy(base_dict)
                    try:
                        for k, val in v.items():
                            set_path(d, k, val)
                    except (KeyError, TypeError, ValueError) as e:
                        if raise_errors:
                            raise
                        jobs.append((head, None, None, e))
                        continue
                    folder = os.fspath(root / f"variant_{i:0{width}d}")
                    job = ex.submit(_run_variant, run, d, base, folder, threads, metric, keep)
                    jobs.append((head, folder, job, None))
                for head, kept, fut, err in jobs:
                    if fut is not None:
                        try:
                            head.update(fut.result())
                            head["error"] = None
                            rows.append(head)
                            continue
                        except Exception as e:
                            if raise_errors:
                                raise
                            err = e
                    head.update({f: None for f in ROW_FIELDS})
                    if metric is not None:
                        head["metric"] = None
                    # a kept folder holds what the failed run wrote
                    head["out"] = kept if keep else None
                    head["error"] = _error_text(err) if err is not None else "unknown error"
                    rows.append(head)
            except BaseException:
                ex.shutdown(wait=True, cancel_futures=True)
                raise
    finally:
        if not keep:
            shutil.rmtree(root, ignore_errors=True)
    if as_frame:
        from ._output import _pandas

        return _pandas().DataFrame(rows)
    return rows
