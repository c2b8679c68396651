"""fdem.run of the fracturing Brazilian disc against `fdem run` of the same file: the last
frame's arrays equal the command line's last .vtu bit for bit (np.array_equal, no
tolerance), every output file is byte for byte the same, and so is the peak load."""

import json

import meshio
import numpy as np
from conftest import last_file


def vec2(a):
    """The x, y columns of a 3-component VTK vector, whose z must be 0."""
    assert np.all(a[:, 2] == 0.0)
    return a[:, :2]


def tensor4(t):
    """sxx, syy, sxy, szz of a 3x3 VTK tensor (row-major 9 components)."""
    return t[:, [0, 4, 1, 8]]


def test_last_frame_arrays_equal_the_cli_vtu(disc_runs):
    cli_out, _, r = disc_runs
    m = meshio.read(last_file(cli_out / "results.pvd"))
    p, c = m.point_data, {k: v[0] for k, v in m.cell_data.items()}
    assert np.array_equal(vec2(m.points), r.positions)
    assert r.triangles.dtype == np.int64
    assert np.array_equal(m.cells[0].data, r.triangles)
    for name, mine in [
        ("displacement", r.displacements),
        ("velocity", r.velocities),
        ("force", r.forces),
        ("reaction", r.reactions),
        ("contact_force", r.point_extra["contact_force"]),
    ]:
        assert mine.dtype == np.float64 and mine.shape == (len(r.positions), 2), name
        assert np.array_equal(vec2(p[name]), mine), name
    assert np.array_equal(tensor4(p["nodal_stress"]), r.nodal_stress)
    assert np.array_equal(p["nodal_principal_stress"], r.nodal_principal_stress)
    assert np.array_equal(p["nodal_von_mises"], r.nodal_von_mises)
    assert r.cell_stress.shape == (len(r.triangles), 4)
    assert np.array_equal(tensor4(c["stress"]), r.cell_stress)
    assert np.array_equal(c["principal_stress"], r.principal_stress)
    assert np.array_equal(c["von_mises"], r.von_mises)
    assert np.array_equal(c["strain_energy_density"], r.strain_energy_density)
    assert np.array_equal(c["material"], r.material)
    assert np.array_equal(c["body"], r.body)
    assert np.array_equal(c["contact_active"], r.cell_extra["contact_active"])
    # the material ids are not all equal to the body ids by chance: the arrays carry values
    assert np.count_nonzero(r.displacements) > 0 and np.count_nonzero(r.cell_stress) > 0


def test_last_joint_frame_equals_the_cli_joint_vtu(disc_runs):
    cli_out, _, r = disc_runs
    m = meshio.read(last_file(cli_out / "joints.pvd"))
    assert r.joints is not None
    assert np.array_equal(vec2(m.points), r.joints["points"])
    names = [
        "damage",
        "mode",
        "mode_mix",
        "broken",
        "time_of_failure",
        "opening",
        "sliding",
        "normal_traction",
        "shear_traction",
    ]
    for name in names:
        assert np.array_equal(m.cell_data[name][0], r.joints[name]), name
    # the joint state at the end agrees with the frame: the same joints broken, and the
    # disc did break (the run is the fracturing one)
    broken = r.joint_state["broken"]
    assert broken.dtype == np.bool_
    assert np.array_equal(broken, r.joints["broken"] == 1)
    assert broken.sum() > 0
    assert np.array_equal(r.joint_state["point_damage"].mean(axis=1), r.joints["damage"])


def test_every_output_file_is_byte_for_byte_the_cli_one(disc_runs):
    cli_out, py_out, _ = disc_runs
    # summary.json has the wall times; the command line also draws its curves (PNG, SVG)
    skip = {"summary.json"} | {
        f"{stem}.{ext}" for stem in ("load_displacement", "stress_strain") for ext in ("png", "svg")
    }
    names = sorted(f.name for f in cli_out.iterdir() if f.name not in skip)
    assert sorted(f.name for f in py_out.iterdir() if f.name not in skip) == names
    assert {"results.pvd", "joints.pvd", "walls.csv", "histories.csv", "fractures.csv"} <= set(
        names
    )
    for n in names:
        assert (cli_out / n).read_bytes() == (py_out / n).read_bytes(), n


def peak_load(folder):
    """The largest platen force [N] of walls.csv (the load of the load-displacement curve)."""
    w = np.genfromtxt(folder / "walls.csv", delimiter=",", names=True)
    return float(np.max(np.abs(w["force_ytop"])))


def test_peak_load_and_summary_equal_the_cli_ones(disc_runs):
    cli_out, py_out, r = disc_runs
    assert peak_load(cli_out) == peak_load(py_out)
    assert peak_load(py_out) > 1000.0  # a loaded disc (about 2 kN): not two empty columns
    s_cli = json.loads((cli_out / "summary.json").read_text())
    s_py = r.summary
    assert s_py == json.loads((py_out / "summary.json").read_text())
    for key in ["steps", "time_step", "simulated_time", "nodes", "triangles", "energy", "frames"]:
        assert s_py[key] == s_cli[key], key
    assert r.energy == s_cli["energy"]
    assert r.time == s_cli["simulated_time"]
