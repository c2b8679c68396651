"""Helpers of the package's tests: runs of the command line `fdem run` (the reference the
Python readers are checked against), made once per test run and cached, and a sweep
runner that runs a variant through the command line (so the sweep is tested without the
compiled extension)."""

from __future__ import annotations

import atexit
import json
import os
import shutil
import subprocess
import sys
import tempfile
from importlib.util import find_spec
from pathlib import Path
from typing import Any, Dict, Optional, Tuple

REPO = Path(__file__).resolve().parents[3]

# The installed package when there is one (the test command installs it into .venv), else
# the pure-Python modules of the source tree (they need no extension).
if find_spec("fdem") is None:
    sys.path.insert(0, str(REPO / "crates" / "python" / "python"))

_ROOT = Path(tempfile.mkdtemp(prefix="fdem-pytest-"))
atexit.register(shutil.rmtree, _ROOT, True)
_RUNS: Dict[Tuple[str, str, bool], Path] = {}


def fdem_bin() -> Path:
    """The release binary of the command line (FDEM_BIN, else target/release/fdem, built with
    cargo when missing)."""
    env = os.environ.get("FDEM_BIN")
    if env:
        return Path(env)
    exe = REPO / "target" / "release" / "fdem"
    if not exe.exists():
        subprocess.run(
            ["cargo", "build", "--release", "--quiet", "--bin", "fdem"], cwd=REPO, check=True
        )
    return exe


def absolute_meshes(scene: Dict[str, Any], base: Path) -> Dict[str, Any]:
    """The scene with every body's mesh path made absolute (relative ones against `base`)."""
    for body in scene.get("bodies", []):
        if isinstance(body, dict) and isinstance(body.get("mesh"), str):
            body["mesh"] = str((base / body["mesh"]).resolve())
    return scene


def set_key(d: Dict[str, Any], dotted: str, value: Any) -> None:
    """Sets `a.b.0.c` in `d` (the tests' own edits, independent of the package's)."""
    keys = dotted.split(".")
    for k in keys[:-1]:
        d = d[int(k)] if isinstance(d, list) else d[k]
    last = keys[-1]
    if isinstance(d, list):
        d[int(last)] = value
    else:
        d[last] = value


def run_cli(scene: Dict[str, Any], out: Path, threads: Optional[int] = None,
            raw: bool = False) -> subprocess.CompletedProcess:
    """Writes `scene` beside `out` and runs `fdem run` on it into `out`."""
    out.parent.mkdir(parents=True, exist_ok=True)
    path = out.parent / (out.name + ".scene.json")
    path.write_text(json.dumps(scene))
    env = dict(os.environ)
    if threads is not None:
        env["RAYON_NUM_THREADS"] = str(threads)
    cmd = [str(fdem_bin()), "run", str(path), "--out", str(out)] + (["--raw"] if raw else [])
    return subprocess.run(cmd, capture_output=True, text=True, env=env)


def example_run(name: str, edits: Optional[Dict[str, Any]] = None, raw: bool = False) -> Path:
    """The folder of `fdem run examples/NAME.json` with `edits` ({dotted key: value}), run
    once per test run."""
    key = (name, json.dumps(edits or {}, sort_keys=True), raw)
    if key not in _RUNS:
        src = REPO / "examples" / f"{name}.json"
        scene = absolute_meshes(json.loads(src.read_text()), src.parent)
        for k, v in (edits or {}).items():
            set_key(scene, k, v)
        out = _ROOT / f"run{len(_RUNS)}-{name}"
        p = run_cli(scene, out, raw=raw)
        if p.returncode != 0:
            raise RuntimeError(f"fdem run {name} failed ({p.returncode}): {p.stderr}")
        _RUNS[key] = out
    return _RUNS[key]


def cli_runner(scene: Dict[str, Any], base: str, out: str,
               threads: Optional[int]) -> Dict[str, Any]:
    """A sweep runner through the command line: writes the scene (meshes made absolute
    against `base`) beside `out` and runs it there; a failed run raises with the CLI's
    message."""
    p = run_cli(absolute_meshes(scene, Path(base)), Path(out), threads=threads)
    if p.returncode != 0:
        raise RuntimeError(p.stderr.strip())
    return {"pid": os.getpid()}


def max_reaction(output: Any) -> float:
    """A sweep metric: the largest |reaction_y[top]| of histories.csv."""
    h = output.histories
    return float(max(abs(v) for v in h["reaction_y[top]"]))
