"""fdem: a 2D combined finite-discrete element (FDEM) solver, from Python.

- :class:`Scene`: a scene from a file or a dict, validated by the command line's checks,
  edited by key path (``scene["bodies[0].materials.*.young"] = 40e9``);
- :func:`check`: ``fdem check``'s report;
- :func:`run`: a run (the GIL released while it steps, Ctrl-C stops it with a checkpoint)
  returning a :class:`Result` with the last frame's arrays as numpy arrays and the run
  folder read lazily (frames, histories, fractures, the load-displacement curve);
- :func:`read`: any run folder (the command line's too) as an :class:`Output`, lazily;
- :func:`sweep`: variants of a scene run in parallel processes, one row per variant;
- :class:`SceneError` (a ValueError: the JSON path, the fix) and :class:`RunError`.

``docs/python.md`` of the repository is the guide.
"""

from ._core import RunError, SceneError, __version__
from ._output import CurveError, Frame, Frames, JointFrame, Output, read
from ._result import CheckReport, Result, check, run
from ._scene import Scene
from ._sweep import sweep
from ._vtu import VtuData, VtuFormatError, read_vtu

__all__ = [
    "CheckReport",
    "CurveError",
    "Frame",
    "Frames",
    "JointFrame",
    "Output",
    "Result",
    "RunError",
    "Scene",
    "SceneError",
    "VtuData",
    "VtuFormatError",
    "__version__",
    "check",
    "read",
    "read_vtu",
    "run",
    "sweep",
]
