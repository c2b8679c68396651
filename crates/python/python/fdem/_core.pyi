"""Stubs of the extension module ``fdem._core`` (the Rust side of the package)."""

from typing import Any, Callable, Dict, Optional

__version__: str

class SceneError(ValueError):
    """A scene that fdem refuses; ``str(e)`` is the command line's message."""

    kind: str
    file: str
    path: Optional[str]
    message: str
    fix: Optional[str]

class RunError(RuntimeError):
    """A run that failed; ``str(e)`` is the command line's message."""

    kind: str
    file: Optional[str]
    step: Optional[int]
    time: Optional[float]
    message: str
    fix: Optional[str]

def load_check(text: str, file: str, report: bool = False) -> Dict[str, Any]:
    """Loads the scene ``text`` with every check of ``fdem check`` (``file`` names it and
    resolves its relative meshes); its description, report and numbers."""

def run(
    text: str,
    file: str,
    out_dir: str,
    threads: Optional[int] = None,
    raw: bool = False,
    progress: Optional[Callable[[int, int, float], Any]] = None,
    resume: bool = False,
    stop_after: Optional[int] = None,
) -> Dict[str, Any]:
    """Runs the scene ``text`` into ``out_dir`` as ``fdem run`` does, the GIL released;
    ``summary`` (JSON text), ``frame``, ``joints``, ``joint_state``, ``error``."""
