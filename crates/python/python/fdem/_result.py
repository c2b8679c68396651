"""Running a scene from Python (:func:`run`), its :class:`Result`, and :func:`check`."""

from __future__ import annotations

import json
import shutil
import sys
import tempfile
import weakref
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Union, cast

import numpy as np

from . import _core
from ._named import Named
from ._output import Output, summary_dict
from ._scene import PathLike, Scene, as_scene

RunError = _core.RunError

#: A progress callable: ``f(step, steps, time)``.
ProgressCallable = Callable[[int, int, float], Any]


class Result(Output):
    """A finished run: its output folder, read lazily as :class:`Output` reads any run folder
    (``summary``, ``energy``, ``frames``, ``joint_frames``, ``histories``, ``walls``,
    ``fractures``, ``load_displacement()``, ``peak_load``), and the state at the end of the
    run as numpy arrays held in memory.

    Vectors are float64 ``(n, 2)`` arrays, stresses ``(m, 4)`` (sxx, syy, sxy, szz) [Pa],
    the very values of the run's last ``.vtu`` frame (when the run writes one at its end).
    ``out`` is the output folder; a run given no folder owns a temporary one, deleted with the
    Result unless kept (:meth:`keep`).
    """

    def __init__(self, out: PathLike, data: Mapping[str, Any], temporary: bool = False) -> None:
        super().__init__(out)
        frame: Dict[str, Any] = dict(data["frame"])
        # the summary and the last frame's arrays as the run returned them (Output reads the
        # same values from the folder's files)
        self._cache["summary"] = summary_dict(
            json.loads(data["summary"]), f"{self.out}: the run's summary"
        )
        self._end: Dict[str, Any] = {
            name: frame[key]
            for name, key in (
                ("points", "points"),
                ("displacement", "displacement"),
                ("velocity", "velocity"),
                ("force", "force"),
                ("reaction", "reaction"),
                ("stress", "stress"),
                ("principal_stress", "principal_stress"),
                ("von_mises", "von_mises"),
                ("nodal_stress", "nodal_stress"),
                ("triangles", "triangles"),
                ("material", "material"),
                ("body", "body"),
            )
        }
        #: The scene's description (bodies, model size, analysis, time step).
        self.describe: str = data.get("describe", "")
        #: Simulated time at the end of the run [s].
        self.time: float = frame["time"]
        #: Strain energy density per reference area [J/m^3], (m,).
        self.strain_energy_density: np.ndarray = frame["strain_energy_density"]
        #: Principal stresses of the nodal stress [Pa], (n, 2), or None.
        self.nodal_principal_stress: Optional[np.ndarray] = frame["nodal_principal_stress"]
        #: von Mises stress of the nodal stress [Pa], (n,), or None.
        self.nodal_von_mises: Optional[np.ndarray] = frame["nodal_von_mises"]
        #: Further point arrays of the frame by name (``contact_force`` with contact).
        self.point_extra: Dict[str, np.ndarray] = Named(
            frame["point_extra"], what="extra point array"
        )
        #: Further cell arrays of the frame by name (``contact_active``, ``young``).
        self.cell_extra: Dict[str, np.ndarray] = Named(
            frame["cell_extra"], what="extra cell array"
        )
        joints = data.get("joints")
        self._joints: Optional[Dict[str, np.ndarray]] = (
            None if joints is None else Named(joints, what="joint array")
        )
        #: The joints' history at the end (``point_damage`` (j, 2), ``broken``,
        #: ``broken_at``, ``work``, ``stored``, ``dissipated``), or None without joints.
        state = data.get("joint_state")
        self.joint_state: Optional[Dict[str, np.ndarray]] = (
            None if state is None else Named(state, what="joint state array")
        )
        self._finalizer: Optional[Any] = None  # a weakref.finalize
        if temporary:
            self._finalizer = weakref.finalize(self, shutil.rmtree, str(self.out), True)

    def _last(self, name: str) -> Optional[np.ndarray]:
        # the state at the end of the run, in memory (the positions, displacements, ...,
        # triangles of Output's properties)
        if name in self._end:
            return cast(Optional[np.ndarray], self._end[name])
        return super()._last(name)

    @property
    def joints(self) -> Optional[Dict[str, np.ndarray]]:
        """The joints at the end of the run as ``joints_NNNN.vtu`` holds them (one entry per
        joint: ``damage``, ``mode``, ``broken``, ``opening``, ...; ``points`` two rows per
        joint), or None for a scene without a fracture section."""
        return self._joints

    @property
    def is_temporary(self) -> bool:
        """Whether the output folder is a temporary one, deleted with this Result."""
        return self._finalizer is not None and self._finalizer.alive

    def keep(self, path: Optional[PathLike] = None) -> Path:
        """Keeps the output folder: moved to ``path`` when given (which must not exist),
        else left where it is; it is no longer deleted with this Result. Returns it."""
        if path is not None:
            dest = Path(path)
            if dest.exists():
                raise FileExistsError(
                    f"{dest} exists\n  fix: give a path that does not exist yet; the run's "
                    f"folder is moved there"
                )
            shutil.move(str(self.out), str(dest))
            self.out = dest
        if self._finalizer is not None:
            self._finalizer.detach()
            self._finalizer = None
        return self.out

    def __repr__(self) -> str:
        s = self.summary
        return (
            f"<fdem.Result {self.out}: {s.get('steps')} steps, t = {s.get('simulated_time')} s, "
            f"{len(self._end['points'])} nodes, {len(self._end['triangles'])} triangles>"
        )


@dataclass
class CheckReport:
    """What ``fdem check`` reports of a scene: ``text`` as it prints it, and its numbers."""

    #: The report as ``fdem check`` prints it.
    text: str
    #: The scene's description (the first part of ``text``).
    describe: str
    #: The stable steps of every scheme and the estimated run time (the rest of ``text``).
    report: str
    #: The analysis: ``"dynamic"``, ``"static"`` or ``"relaxation"``.
    analysis: str
    #: The time-integration scheme.
    scheme: str
    #: The time step [s] (0 for a static analysis).
    time_step: float
    #: The stable limit of the scheme [s].
    time_step_limit: float
    #: Number of steps.
    steps: int
    #: The scene's duration [s], or None.
    duration: Optional[float]
    #: Nodes of the model (after fracturing bodies are exploded).
    nodes: int
    #: Triangles of the model.
    triangles: int
    #: Free degrees of freedom.
    free_dofs: int
    #: The highest frequency bound [rad/s].
    omega_max: float
    #: Per body: ``name``, ``mesh``, ``nodes``, ``triangles`` (of its mesh as read).
    bodies: List[Dict[str, Any]] = field(default_factory=list)
    #: The accuracy indicators ``fdem check`` predicts (docs/accuracy.md), each a dict as in
    #: ``summary.json``'s ``accuracy``: ``name``, ``subject``, ``value``, ``threshold``, ...
    accuracy: List[Dict[str, Any]] = field(default_factory=list)

    def __str__(self) -> str:
        return self.text


def check(scene: Union[Scene, Mapping[str, Any], PathLike]) -> CheckReport:
    """``fdem check``: validates the scene and returns its report (stable step of every
    scheme, estimated run time, model size). Raises SceneError as the command line does."""
    s = as_scene(scene)
    d = _core.load_check(s.to_json(), str(s.error_file), True)
    keys = [k for k in CheckReport.__dataclass_fields__ if k != "accuracy"]
    accuracy: List[Dict[str, Any]] = json.loads(d["accuracy"])
    return CheckReport(**{k: d[k] for k in keys}, accuracy=accuracy)


class _StderrProgress:
    """Progress on stderr: one line rewritten in place on a terminal, else a line every 10%."""

    def __init__(self) -> None:
        self.tty = sys.stderr.isatty()
        self.last = -1.0
        self.shown = False

    def __call__(self, step: int, steps: int, time: float) -> None:
        f = 1.0 if steps == 0 else step / steps
        line = f"{100.0 * f:5.1f}%  step {step}/{steps}  t = {time:.4e} s"
        if self.tty:
            sys.stderr.write("\r" + line)
            self.shown = True
        elif f - self.last >= 0.1 or (f >= 1.0 and self.last < 1.0):
            self.last = f
            sys.stderr.write(line + "\n")
        sys.stderr.flush()

    def close(self) -> None:
        if self.tty and self.shown:
            sys.stderr.write("\n")
            sys.stderr.flush()


def run(
    scene: Union[Scene, Mapping[str, Any], PathLike],
    out: Optional[PathLike] = None,
    progress: Union[bool, ProgressCallable, None] = True,
    threads: Optional[int] = None,
    raw: bool = False,
    resume: bool = False,
    stop_after: Optional[int] = None,
) -> Result:
    """Runs a scene as ``fdem run SCENE --out OUT`` does and returns its :class:`Result`.

    - ``scene``: a :class:`Scene`, a path of a scene file, or a dict;
    - ``out``: the output folder (the run owns it: fdem's files of an earlier run there are
      removed first); None: a temporary folder owned by the Result;
    - ``progress``: True prints the progress on stderr, False none, or a callable
      ``f(step, steps, time)`` called about ten times a second (an exception it raises stops
      the run, with a checkpoint, and is raised);
    - ``threads``: rayon threads for this run (None: rayon's default or RAYON_NUM_THREADS);
    - ``raw``: also write each frame's arrays as JSON (``frame_NNNN.json``);
    - ``resume``: continue the run in ``out`` from its checkpoint;
    - ``stop_after``: stop after this many steps in all, with a checkpoint, as
      ``fdem run --stop-after`` (a run split into parts): raises RunError of kind
      ``"interrupted"``; ``resume=True`` continues it.

    The GIL is released while the run steps. Ctrl-C stops it after its current step: it
    writes its checkpoint and an interrupted summary into ``out`` and KeyboardInterrupt is
    raised (``run(scene, out=out, resume=True)`` continues it). Raises SceneError for a
    refused scene and RunError for a run that failed; a relaxation that did not converge
    raises RunError with the written run as ``e.result``.
    """
    s = as_scene(scene)
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, int)):
        raise TypeError(f"threads is an int >= 1 or None, not {threads!r}")
    if progress is True:
        cb: Optional[Any] = _StderrProgress()
    elif progress is False or progress is None:
        cb = None
    elif callable(progress):
        cb = progress
    else:
        raise TypeError(
            f"progress is True, False or a callable f(step, steps, time), not {progress!r}"
        )
    temporary = out is None
    if resume and temporary:
        raise ValueError("resume=True needs the folder of the run: give out=FOLDER")
    folder = Path(tempfile.mkdtemp(prefix="fdem-run-")) if out is None else Path(out)
    try:
        data = _core.run(
            s.to_json(),
            str(s.error_file),
            str(folder),
            threads,
            bool(raw),
            cb,
            bool(resume),
            stop_after,
        )
    except BaseException:
        if temporary:
            shutil.rmtree(folder, ignore_errors=True)
        raise
    finally:
        if isinstance(cb, _StderrProgress):
            cb.close()
    result = Result(folder, data, temporary=temporary)
    error = data.get("error")
    if error is not None:
        error.result = result
        raise error
    return result


__all__ = ["CheckReport", "Result", "RunError", "check", "run"]
