"""fdem: a 2D combined finite-discrete element (FDEM) solver, from Python.

- :class:`Scene`: a scene from a file or a dict, validated by the command line's checks,
  edited by key path (``scene["bodies[0].materials.*.young"] = 40e9``);
- :func:`check`: ``fdem check``'s report;
- :func:`run`: a run (the GIL released while it steps, Ctrl-C stops it with a checkpoint)
  returning a :class:`Result` with the last frame's arrays as numpy arrays;
- :class:`SceneError` (a ValueError: the JSON path, the fix) and :class:`RunError`.

``docs/python.md`` of the repository is the guide.
"""

from ._core import RunError, SceneError, __version__
from ._result import CheckReport, Result, check, run
from ._scene import Scene

__all__ = [
    "CheckReport",
    "Result",
    "RunError",
    "Scene",
    "SceneError",
    "__version__",
    "check",
    "run",
]
