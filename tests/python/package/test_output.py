"""The package's pure-Python readers (fdem._vtu, fdem._output) against the command line's
own output: every array equal bit for bit to meshio's reading and to the raw JSON dump, the
frame times those of the .pvd, the load-displacement curve and peak load those of the CSV
files under the rules of `fdem plot load-displacement`. Exact equality throughout (the
readers decode the same bytes)."""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import meshio
import numpy as np
import pytest

import cli_runs  # noqa: F401  (puts the package on sys.path when it is not installed)
from cli_runs import example_run
from fdem._output import CurveError, Output, read
from fdem._vtu import VtuFormatError, read_vtu

SHORT_NOTCHED = {"duration": 4e-4, "output": {"frames": 3, "compression": 0}}
SHORT_DISC = {"duration": 3e-4, "output.frames": 3}


def bits(a: np.ndarray) -> bytes:
    """The array's dtype, shape and bytes (NaN-safe exact comparison)."""
    a = np.ascontiguousarray(a)
    return str(a.dtype).encode() + str(a.shape).encode() + a.tobytes()


def runs():
    """(name, folder) of the runs whose .vtu files are compared with meshio."""
    return [
        ("notched", example_run("notched-beam-fracture")),
        ("disc-elastic", example_run("brazilian-disc-elastic")),
        ("disc-elastic-level0", example_run("brazilian-disc-elastic", {"output.compression": 0})),
        ("notched-level0", example_run("notched-beam-fracture", SHORT_NOTCHED)),
    ]


def pvd_files(out: Path, name: str):
    """(time, file) of a .pvd read with a regular expression (independent of the reader)."""
    text = (out / name).read_text()
    return [(float(t), f) for t, f in re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', text)]


@pytest.mark.parametrize("which", range(4))
def test_every_vtu_equals_meshio_bit_for_bit(which):
    tag, out = runs()[which]
    files = [f for _, f in pvd_files(out, "results.pvd")]
    if (out / "joints.pvd").exists():
        files += [f for _, f in pvd_files(out, "joints.pvd")]
    assert files, f"{tag}: no frames"
    level0 = tag.endswith("level0")
    for f in files:
        path = out / f
        head = path.read_bytes()[:4096]
        # the run wrote the layout this case is meant to cover
        assert (b"vtkZLibDataCompressor" in head) != level0, f"{tag}/{f}: compression"
        d = read_vtu(path)
        m = meshio.read(path)
        assert bits(d.points) == bits(m.points), f"{tag}/{f}: points"
        assert len(m.cells) == 1
        assert bits(d.cells) == bits(m.cells[0].data), f"{tag}/{f}: cells"
        assert d.cell_type == (3 if f.startswith("joints_") else 5)
        assert list(d.point_data) == list(m.point_data), f"{tag}/{f}"
        for k, v in d.point_data.items():
            assert bits(v) == bits(m.point_data[k]), f"{tag}/{f}: point {k}"
        assert list(d.cell_data) == list(m.cell_data), f"{tag}/{f}"
        for k, v in d.cell_data.items():
            assert bits(v) == bits(m.cell_data[k][0]), f"{tag}/{f}: cell {k}"


def test_the_2d_arrays_equal_the_raw_dump():
    """displacement/velocity/force/reaction (n, 2), stress/nodal_stress (sxx, syy, sxy, szz)
    and points: equal to the solver's own arrays (fdem run --raw)."""
    out = example_run("bar-pulse", {"output.frames": 2}, raw=True)
    o = read(out)
    assert len(o.frames) == 3
    for fr in o.frames:
        raw = json.loads(fr.file.with_suffix(".json").read_text())
        assert fr.time == raw["time"]

        def as_f(k: str, raw: dict = raw) -> np.ndarray:
            return np.asarray(raw[k], dtype=np.float64)

        assert bits(fr.points) == bits(as_f("points"))
        assert bits(fr.triangles) == bits(np.asarray(raw["triangles"], dtype=np.int64))
        for k in ["displacement", "velocity", "force", "reaction"]:
            assert bits(getattr(fr, k)) == bits(as_f(k)), k
        assert bits(fr.stress) == bits(as_f("stress"))
        assert bits(fr.nodal_stress) == bits(as_f("nodal_stress"))
        assert bits(fr.principal_stress) == bits(as_f("principal"))
        assert bits(fr.von_mises) == bits(as_f("von_mises"))
        assert bits(fr.material) == bits(np.asarray(raw["material"], dtype=np.int32))
    # the run's last-frame arrays are the last frame's
    last = json.loads(o.frames[-1].file.with_suffix(".json").read_text())
    for attr, key in [("positions", "points"), ("displacements", "displacement"),
                      ("velocities", "velocity"), ("forces", "force"),
                      ("reactions", "reaction"), ("cell_stress", "stress"),
                      ("nodal_stress", "nodal_stress"), ("principal_stress", "principal"),
                      ("von_mises", "von_mises")]:
        assert bits(getattr(o, attr)) == bits(np.asarray(last[key], dtype=np.float64)), attr
    assert bits(o.triangles) == bits(np.asarray(last["triangles"], dtype=np.int64))
    assert bits(o.body) == bits(np.asarray(last["body"], dtype=np.int32))
    assert o.joints is None


def test_frames_are_the_pvds_and_joint_frames_only_with_fracture():
    notched = read(example_run("notched-beam-fracture"))
    entries = pvd_files(notched.out, "results.pvd")
    assert len(notched.frames) == len(entries) == 41
    assert [f.time for f in notched.frames] == [t for t, _ in entries]
    assert bits(notched.frames.times) == bits(np.array([t for t, _ in entries]))
    assert [f.file.name for f in notched.frames] == [f for _, f in entries]
    assert notched.frames[-1].index == 40 and notched.frames[-1] is notched.frames[40]
    assert notched.frames[-1].time == notched.summary["simulated_time"]
    joints = notched.joint_frames
    assert joints is not None
    assert [f.time for f in joints] == [t for t, _ in pvd_files(notched.out, "joints.pvd")]
    assert [f.time for f in joints] == [f.time for f in notched.frames]
    last = joints[-1]
    n = len(last.cell_data["damage"])
    assert last.lines.shape == (n, 2) and last.points.shape == (2 * n, 2)
    with pytest.raises(AttributeError, match="lines"):
        last.triangles
    # the broken joints of the last joint frame are the rows of fractures.csv
    fr = notched.fractures
    assert fr is not None and fr["joint"].dtype == np.int64
    broken = np.flatnonzero(last.cell_data["broken"] == 1)
    assert len(broken) > 0
    assert sorted(fr["joint"].tolist()) == broken.tolist()
    assert set(fr["mode"].tolist()) <= {"I", "II", "mixed"}
    j = notched.joints
    assert bits(j["broken"]) == bits(last.cell_data["broken"])
    assert bits(j["points"]) == bits(last.points) and len(j["damage"]) == n
    rows = (notched.out / "fractures.csv").read_text().splitlines()[1:]
    assert fr["time"].tolist() == [float(r.split(",")[0]) for r in rows]

    elastic = read(example_run("brazilian-disc-elastic"))
    assert elastic.joint_frames is None and elastic.fractures is None
    assert len(elastic.frames) == len(pvd_files(elastic.out, "results.pvd"))
    assert elastic.histories is None and elastic.largest_load is None


def test_summary_energy_and_histories():
    o = read(example_run("notched-beam-fracture"))
    s = json.loads((o.out / "summary.json").read_text())
    assert o.summary == s and o.energy == s["energy"]
    h = o.histories
    table = np.loadtxt(o.out / "histories.csv", delimiter=",", skiprows=1)
    head = (o.out / "histories.csv").read_text().splitlines()[0].split(",")
    assert list(h) == head
    for i, k in enumerate(head):
        assert bits(h[k]) == bits(table[:, i]), k


def test_peak_load_from_histories_equals_the_csv():
    """Notched beam: reaction and displacement probes on the group `load`."""
    o = read(example_run("notched-beam-fracture"))
    csv = o.out / "histories.csv"
    head = csv.read_text().splitlines()[0].split(",")
    t = np.loadtxt(csv, delimiter=",", skiprows=1)
    load = np.abs(t[:, head.index("reaction_y[load]")])
    disp = np.abs(t[:, head.index("u_y[load]")])
    u, p = o.load_displacement()
    assert bits(u) == bits(disp) and bits(p) == bits(load)
    assert o.largest_load == load.max() > 0
    # the beam cracks and its load falls by more than a fifth after the peak: it failed
    assert o.failed is True and o.peak_load == o.largest_load
    # named columns, as `fdem plot load-displacement --load --displacement`
    u, p = o.load_displacement(load="reaction_x[load]", displacement="u_x[load]")
    assert bits(p) == bits(np.abs(t[:, head.index("reaction_x[load]")]))
    with pytest.raises(ValueError, match="no file has both columns nope"):
        o.load_displacement(load="nope", displacement="u_x[load]")


def test_peak_load_from_walls_equals_the_csv():
    """Brazilian disc between platens (shortened): the first moving wall's force against
    the platen closure."""
    o = read(example_run("brazilian-disc-fracture", SHORT_DISC))
    csv = o.out / "walls.csv"
    head = csv.read_text().splitlines()[0].split(",")
    t = np.loadtxt(csv, delimiter=",", skiprows=1)
    col = lambda k: t[:, head.index(k)]  # noqa: E731
    u, p = o.load_displacement()
    assert bits(p) == bits(np.abs(col("force_y[top]")))
    assert bits(u) == bits(np.abs(col("u_y[top]")) + np.abs(col("u_y[bottom]")))
    assert o.largest_load == np.abs(col("force_y[top]")).max() > 0
    w = o.walls
    assert list(w) == head and bits(w["force_y[bottom]"]) == bits(col("force_y[bottom]"))


def folder(tmp_path: Path, files: dict) -> Path:
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    return tmp_path


def test_curve_rules_on_small_files(tmp_path):
    """The cases of the CLI's own unit tests (src/cmd/plot.rs)."""
    (tmp_path / "w").mkdir()
    d = folder(tmp_path / "w", {
        "walls.csv": "time,u_x[top],u_y[top],force_x[top],force_y[top],u_x[bottom],u_y[bottom],"
        "force_x[bottom],force_y[bottom]\n0,0,0,0,0,0,0,0,0\n1,0,-1e-6,0,-500,0,1e-6,0,500\n",
    })
    u, p = Output(d).load_displacement()
    assert u.tolist() == [0.0, 2e-6] and p.tolist() == [0.0, 500.0]
    (tmp_path / "h").mkdir()
    d = folder(tmp_path / "h", {
        "histories.csv": "time,reaction_x[load],reaction_y[load],u_x[load],u_y[load],kinetic\n"
        "0,0,0,0,0,0\n1,3,-700,1e-7,-1e-5,0\n",
    })
    u, p = Output(d).load_displacement()
    assert u.tolist() == [0.0, 1e-5] and p.tolist() == [0.0, 700.0]
    assert Output(d).largest_load == 700.0
    (tmp_path / "n").mkdir()
    d = folder(tmp_path / "n", {"histories.csv": "time,kinetic\n0,0\n"})
    with pytest.raises(CurveError, match='"reaction" and a "displacement" probe'):
        Output(d).load_displacement()
    assert Output(d).largest_load is None


def test_repeated_columns_are_refused_not_taken_first(tmp_path):
    (tmp_path / "h").mkdir()
    d = folder(tmp_path / "h", {
        "histories.csv": "time,reaction_y[load],u_y[load],reaction_y[load]\n0,1,2,3\n",
    })
    o = Output(d)
    with pytest.raises(ValueError, match=r"reaction_y\[load\] appears more than once"):
        o.load_displacement()
    with pytest.raises(ValueError, match="appears more than once"):
        o.largest_load
    with pytest.raises(ValueError, match="appears more than once"):
        o.histories
    (tmp_path / "w").mkdir()
    d = folder(tmp_path / "w", {
        "walls.csv": "time,u_x[top],u_y[top],force_y[top],u_y[top]\n0,0,-1,5,-1\n",
    })
    with pytest.raises(ValueError, match=r"u_y\[top\] appears more than once"):
        Output(d).load_displacement()
    # a repeated column the curve does not use is no obstacle to the curve
    (tmp_path / "k").mkdir()
    d = folder(tmp_path / "k", {
        "histories.csv": "time,v_x[c],v_x[c],reaction_y[g],u_y[g]\n0,1,1,-4,-2\n",
    })
    assert Output(d).largest_load == 4.0


def test_damaged_csv_names_the_line(tmp_path):
    d = folder(tmp_path, {"histories.csv": "time,reaction_y[g],u_y[g]\n0,1,2\n\n1,x,3\n"})
    with pytest.raises(ValueError, match=r"histories.csv line 4: not a number"):
        Output(d).histories


def test_not_a_run_folder(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such folder"):
        read(tmp_path / "missing")
    (tmp_path / "notes.txt").write_text("x")
    with pytest.raises(FileNotFoundError, match=r"not a run folder: none of summary.json"):
        read(tmp_path)
    (tmp_path / "results.pvd").write_text(
        '<VTKFile type="Collection"><Collection></Collection></VTKFile>')
    o = read(tmp_path)
    assert len(o.frames) == 0
    with pytest.raises(FileNotFoundError, match="summary.json: no summary"):
        o.summary


def test_a_vtu_of_another_layout_is_refused(tmp_path):
    src = example_run("brazilian-disc-elastic") / "frame_0000.vtu"
    m = meshio.read(src)
    ascii_file = tmp_path / "ascii.vtu"
    meshio.write(ascii_file, m, binary=False)
    with pytest.raises(VtuFormatError, match="ascii.vtu: .*read other .vtu files with meshio"):
        read_vtu(ascii_file)
    cut = tmp_path / "cut.vtu"
    data = src.read_bytes()
    cut.write_bytes(data[: len(data) - 5000])
    with pytest.raises(VtuFormatError, match="cut.vtu"):
        read_vtu(cut)
    with pytest.raises(FileNotFoundError):
        read_vtu(tmp_path / "none.vtu")


def test_frames_of_pandas(monkeypatch):
    o = read(example_run("notched-beam-fracture"))
    pd = pytest.importorskip("pandas")
    f = o.histories_frame()
    assert isinstance(f, pd.DataFrame) and list(f.columns) == list(o.histories)
    assert bits(f["reaction_y[load]"].to_numpy()) == bits(o.histories["reaction_y[load]"])
    assert len(o.fractures_frame()) == len(o.fractures["joint"])
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match="pip install pandas"):
        o.histories_frame()
