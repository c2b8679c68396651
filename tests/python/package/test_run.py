"""fdem.run's options: threads (1 and 2 give the same numbers), the progress callable,
the temporary folder, Ctrl-C (SIGINT) in a subprocess, and a run stopped by its progress
callable then resumed bit for bit."""

import gc
import json
import signal
import subprocess
import sys
import time

import fdem
import numpy as np
import pytest
from conftest import DISC, REPO

ARRAYS = [
    "positions",
    "displacements",
    "velocities",
    "forces",
    "reactions",
    "cell_stress",
    "principal_stress",
    "von_mises",
    "nodal_stress",
    "triangles",
    "material",
    "body",
]


def short_disc(duration: float) -> fdem.Scene:
    """The fracturing disc over a shorter duration (its platens still ramping)."""
    return fdem.Scene(DISC).edit({"duration": duration, "output.frames": 2})


def assert_same(a: fdem.Result, b: fdem.Result) -> None:
    for name in ARRAYS:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    for name, v in a.joints.items():
        assert np.array_equal(v, b.joints[name]), name
    assert a.summary["energy"] == b.summary["energy"]


@pytest.fixture(scope="module")
def short_runs(tmp_path_factory):
    """The short disc with threads=1 and threads=2, and the progress calls of the first."""
    root = tmp_path_factory.mktemp("threads")
    s = short_disc(2e-4)
    calls = []
    one = fdem.run(s, out=root / "one", threads=1, progress=lambda *a: calls.append(a))
    two = fdem.run(s, out=root / "two", threads=2, progress=False)
    return s, one, two, calls


def test_one_and_two_threads_give_identical_numbers(short_runs):
    _, one, two, _ = short_runs
    assert_same(one, two)
    for f in sorted(one.out.glob("*.vtu")):
        assert f.read_bytes() == (two.out / f.name).read_bytes(), f.name


def test_the_progress_callable_sees_the_steps(short_runs):
    _, one, _, calls = short_runs
    steps = one.summary["steps"]
    assert calls and calls[-1][0] == steps and calls[-1][1] == steps
    assert calls[-1][2] == pytest.approx(2e-4, rel=1e-12)
    assert all(a[0] <= b[0] for a, b in zip(calls, calls[1:]))


def test_a_missing_name_of_the_results_dicts_lists_the_names(short_runs):
    """Every dict of the Result indexed by name: a KeyError naming the key and listing the
    keys, sorted."""
    _, one, _, _ = short_runs
    for d, what in [
        (one.summary, "summary entries"),
        (one.energy, "energy terms"),
        (one.histories, "histories"),
        (one.walls, "columns of walls.csv"),
        (one.point_extra, "extra point arrays"),
        (one.cell_extra, "extra cell arrays"),
        (one.joints, "joint arrays"),
        (one.joint_state, "joint state arrays"),
    ]:
        assert d, what
        with pytest.raises(KeyError) as e:
            d["nope"]
        assert e.value.args[0].endswith(f"'nope'; the {what}: {', '.join(sorted(d))}"), what
        assert "nope" not in d and d.get("nope") is None


def test_a_temporary_folder_goes_with_its_result_unless_kept(tmp_path):
    s = short_disc(2e-5)
    r = fdem.run(s, progress=False)
    out = r.out
    assert (out / "summary.json").exists() and r.is_temporary
    del r
    gc.collect()
    assert not out.exists()
    r = fdem.run(s, progress=False)
    kept = r.keep(tmp_path / "kept")
    assert kept == tmp_path / "kept" and (kept / "results.pvd").exists()
    del r
    gc.collect()
    assert (kept / "results.pvd").exists()


def test_bad_run_arguments_raise_with_the_fix(tmp_path):
    s = short_disc(2e-5)
    with pytest.raises(ValueError, match="threads"):
        fdem.run(s, out=tmp_path / "a", threads=0)
    with pytest.raises(TypeError):
        fdem.run(s, out=tmp_path / "b", threads="2")
    with pytest.raises(TypeError):
        fdem.run(s, out=tmp_path / "c", progress="yes")
    with pytest.raises(ValueError, match="out=FOLDER"):
        fdem.run(s, resume=True)


def test_a_run_stopped_after_n_steps_resumes_bit_for_bit(short_runs, tmp_path):
    s, one, _, _ = short_runs
    with pytest.raises(fdem.RunError) as e:
        fdem.run(s, out=tmp_path, threads=1, progress=False, stop_after=2000)
    assert e.value.kind == "interrupted" and e.value.step == 2000
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["interrupted"]["reason"] == "stop_after" and summary["steps"] == 2000
    assert (tmp_path / "checkpoint.fdem").exists()
    r = fdem.run(s, out=tmp_path, threads=1, progress=False, resume=True)
    assert r.summary["steps"] == one.summary["steps"]
    assert_same(r, one)


class Stop(Exception):
    """Raised by a progress callable to stop a run."""


def test_an_exception_of_the_progress_callable_stops_the_run_with_a_checkpoint(tmp_path):
    s = short_disc(2e-2)  # about 6e5 steps: far longer than the first progress call

    def stop(step, steps, t):
        raise Stop(step)

    with pytest.raises(Stop):
        fdem.run(s, out=tmp_path, progress=stop)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["interrupted"]["reason"] == "SIGINT"
    assert 0 < summary["steps"] < fdem.check(s).steps
    assert (tmp_path / "checkpoint.fdem").exists()


CHILD = """
import sys, fdem
s = fdem.Scene(sys.argv[1]).edit({"duration": 2e-2})
print("running", flush=True)
fdem.run(s, out=sys.argv[2], progress=False)
print("finished", flush=True)
"""


def test_ctrl_c_stops_the_run_with_a_checkpoint_and_raises_keyboard_interrupt(tmp_path):
    out = tmp_path / "run"
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, str(DISC), str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=REPO,
    )
    assert child.stdout.readline().strip() == "running"
    time.sleep(1.0)
    started = time.monotonic()
    child.send_signal(signal.SIGINT)
    stdout, stderr = child.communicate(timeout=60)
    assert time.monotonic() - started < 10.0, "the run did not stop promptly"
    assert "finished" not in stdout
    assert "KeyboardInterrupt" in stderr, stderr
    assert "panick" not in stderr and "Fatal Python error" not in stderr, stderr
    assert child.returncode in (1, -signal.SIGINT, 128 + signal.SIGINT), child.returncode
    summary = json.loads((out / "summary.json").read_text())
    assert summary["interrupted"]["reason"] == "SIGINT"
    assert 0 < summary["steps"]
    assert (out / "checkpoint.fdem").exists()


def test_a_relaxation_that_did_not_converge_raises_with_its_written_result(tmp_path):
    s = fdem.Scene(REPO / "examples" / "brazilian-disc-relaxation.json")
    s = s.edit({"duration": 2e-5, "output.frames": 1})
    with pytest.raises(fdem.RunError) as e:
        fdem.run(s, out=tmp_path, progress=False)
    assert e.value.kind == "not_converged" and "duration" in e.value.fix
    r = e.value.result
    assert r.out == tmp_path and r.summary["converged"] is False
    assert (tmp_path / "results.pvd").exists()


def test_other_python_threads_run_while_fdem_steps(short_runs, tmp_path):
    import threading

    s = short_runs[0]
    count = [0]
    done = threading.Event()

    def spin():
        while not done.is_set():
            count[0] += 1

    t = threading.Thread(target=spin)
    t.start()
    try:
        started = time.monotonic()
        r = fdem.run(s, out=tmp_path, threads=1, progress=False)
        seconds = time.monotonic() - started
    finally:
        done.set()
        t.join()
    assert r.summary["steps"] > 0
    # a Python loop counts millions a second when it has the interpreter; with the GIL held
    # by the run it would count almost nothing
    assert count[0] > 50_000 * seconds, (count[0], seconds)
