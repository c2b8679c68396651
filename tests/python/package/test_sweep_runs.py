"""fdem.sweep with its default runner (fdem.run in each worker process) against single runs,
the Result of fdem.run read as a run folder (frames, histories, walls, fractures, the curve),
and the two Python examples (examples/python)."""

import subprocess
import sys

import fdem
import numpy as np
from conftest import DISC, REPO

STRENGTH = "fracture.material.tensile_strength"


def short_disc() -> fdem.Scene:
    """The fracturing disc over 0.9 ms (3 frames): the platens close by 0.034 mm, about the
    closure at the peak of a disc of ft = 1.8 MPa."""
    return fdem.Scene(DISC).edit({"duration": 0.9e-3, "output.frames": 3})


def test_a_sweep_on_two_processes_gives_the_numbers_of_single_runs():
    scene = short_disc()
    variants = [{STRENGTH: ft} for ft in (1.2e6, 1.4e6, 1.6e6, 1.8e6)]
    rows = fdem.sweep(scene, variants, processes=2, threads=1)
    assert [r[STRENGTH] for r in rows] == [v[STRENGTH] for v in variants]
    peaks = []
    for v, row in zip(variants, rows):
        assert row["error"] is None, row["error"]
        single = fdem.run(scene.edit(v), progress=False, threads=1)
        # 0.9 ms: the platens stop before any joint breaks, so no variant fails
        assert row["failed"] is single.failed is False and row["peak_load"] is None
        assert row["largest_load"] == single.largest_load
        assert row["steps"] == single.summary["steps"]
        assert row["energy_supplied"] == single.energy["supplied"]
        assert row["energy_dissipated"] == single.energy["dissipated"]
        assert row["energy_error"] == single.energy["error"]
        peaks.append(row["largest_load"])
    # a stronger disc carries more: the variants were applied
    assert all(a < b for a, b in zip(peaks, peaks[1:])), peaks


def test_a_sweep_reports_a_variant_that_never_fails_as_not_failed():
    """The whole disc run: at the example's strength it splits (the load falls to 0 after its
    peak); ten times stronger, it is still loading when the run ends: not failed, no peak."""
    scene = fdem.Scene(DISC).edit({"output.frames": 0})
    strong = {STRENGTH: 30e6, "fracture.material.cohesion": 100e6}
    rows = fdem.sweep(scene, [{STRENGTH: 3e6}, strong], processes=2, threads=1)
    split, strong = rows
    assert split["error"] is None and strong["error"] is None, rows
    assert split["failed"] is True and split["peak_load"] == split["largest_load"] > 2000.0
    assert strong["failed"] is False and strong["peak_load"] is None
    assert strong["largest_load"] > split["peak_load"]


def test_the_result_reads_its_folder_as_any_run_folder(tmp_path):
    r = fdem.run(short_disc(), out=tmp_path / "run", progress=False)
    o = fdem.read(tmp_path / "run")
    assert isinstance(r, fdem.Output)
    assert r.summary == o.summary
    assert len(r.frames) == len(o.frames) == 4  # the initial frame and 3
    assert np.array_equal(r.frames.times, o.frames.times)
    # the state at the end in memory equals the last frame's file bit for bit
    for name in ("positions", "displacements", "velocities", "cell_stress", "nodal_stress"):
        assert np.array_equal(getattr(r, name), getattr(o, name)), name
    assert np.array_equal(r.frames[-1].displacement, r.displacements)
    assert r.largest_load is not None and r.largest_load == o.largest_load
    u, p = r.load_displacement()
    assert len(u) == len(p) > 10 and float(np.max(p)) == r.largest_load
    assert r.walls is not None and r.histories is not None
    assert r.joint_frames is not None and len(r.joint_frames) == 4
    assert np.array_equal(r.joints["damage"], o.joints["damage"])


def test_the_calibration_example_meets_its_target():
    p = subprocess.run(
        [sys.executable, "examples/python/calibrate_disc.py", "--target", "2000"],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert p.returncode == 0, p.stderr
    last = p.stdout.strip().splitlines()[-1]
    assert last.startswith("calibrated: ft = "), p.stdout
    # "... gives a peak of P N (+x.xx% from the target 2000.0 N)"
    peak = float(last.split("gives a peak of ")[1].split(" N")[0])
    assert abs(peak - 2000.0) <= 0.005 * 2000.0, last


def test_the_plot_example_reads_a_run_into_meshio_and_matplotlib(tmp_path):
    fdem.run(short_disc(), out=tmp_path / "run", progress=False)
    png = tmp_path / "run.png"
    p = subprocess.run(
        [sys.executable, "examples/python/plot_run.py", str(tmp_path / "run"), "--png", str(png)],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert p.returncode == 0, p.stderr
    assert png.stat().st_size > 10_000
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
