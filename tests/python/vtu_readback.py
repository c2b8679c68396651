"""Independent read-back of fdem's output: every .vtu frame listed in results.pvd is read by
meshio and by VTK's vtkXMLUnstructuredGridReader, and its points, cells and arrays must equal
the solver's raw dump (frame_NNNN.json) exactly (the recovered nodal stresses included). In fracturing runs the joint series
(joints.pvd, joints_NNNN.vtu: one line cell per joint) is read the same way and compared with
the dump's "joints" object; a run without joints must have no joint series. The cell
connectivity and offsets are Int64, so meshio's cells are integers and index the points
(`points[cells]`, as a user's script does). Prints
'N passed, N failed'; exits non-zero on any failure."""
import json
import os
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

passed = 0
failed = 0


def check(name, ok, detail=""):
    global passed, failed
    if ok:
        passed += 1
    else:
        failed += 1
        print(f"FAIL {name} {detail}")


def vec3(a):
    a = np.asarray(a, dtype=float)
    return np.column_stack([a, np.zeros(len(a))])


def expected(raw):
    s = np.asarray(raw["stress"], dtype=float)
    z = np.zeros(len(s))
    tensor = np.column_stack([s[:, 0], s[:, 2], z, s[:, 2], s[:, 1], z, z, z, s[:, 3]])
    e = {
        "points": vec3(raw["points"]),
        "cells": np.asarray(raw["triangles"], dtype=np.int64),
        "point": {k: vec3(raw[k]) for k in ["displacement", "velocity", "force", "reaction"]},
        "cell": {
            "stress": tensor,
            "principal_stress": np.asarray(raw["principal"], dtype=float),
            "von_mises": np.asarray(raw["von_mises"], dtype=float),
            "strain_energy_density": np.asarray(raw["energy_density"], dtype=float),
            "material": np.asarray(raw["material"]),
            "body": np.asarray(raw["body"]),
        },
    }
    # Arrays of the force contributions (contact_force, contact_active), only when present.
    for k, v in raw.get("extra_point_vectors", []):
        e["point"][k] = vec3(v)
    # The recovered nodal stresses (point data), only when present.
    if "nodal_stress" in raw:
        n = np.asarray(raw["nodal_stress"], dtype=float)
        zn = np.zeros(len(n))
        e["point"]["nodal_stress"] = np.column_stack(
            [n[:, 0], n[:, 2], zn, n[:, 2], n[:, 1], zn, zn, zn, n[:, 3]])
    if "nodal_principal" in raw:
        e["point"]["nodal_principal_stress"] = np.asarray(raw["nodal_principal"], dtype=float)
    if "nodal_von_mises" in raw:
        e["point"]["nodal_von_mises"] = np.asarray(raw["nodal_von_mises"], dtype=float)
    for k, v in raw.get("extra_cell_scalars", []):
        e["cell"][k] = np.asarray(v, dtype=float)
    return e


def same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    if a.ndim == 2 and a.shape[1] == 1:
        a = a[:, 0]
    if b.ndim == 2 and b.shape[1] == 1:
        b = b[:, 0]
    return a.shape == b.shape and np.array_equal(a, b)


JOINT_ARRAYS = ["damage", "mode", "mode_mix", "broken", "time_of_failure", "opening", "sliding",
                "normal_traction", "shear_traction"]


def check_joints(out, entries):
    """The joint series of run folder `out` against the raw dumps of the frames `entries`."""
    pvd_path = os.path.join(out, "joints.pvd")
    raws = [json.load(open(os.path.join(out, f.replace(".vtu", ".json")))) for _, f in entries]
    has = ["joints" in r for r in raws]
    if not any(has):
        check(f"{out}: no joint series without joints", not os.path.exists(pvd_path))
        return
    check(f"{out}: every frame has joints", all(has))
    jp = ET.parse(pvd_path).getroot()
    jentries = [(float(d.get("timestep")), d.get("file")) for d in jp.iter("DataSet")]
    check(f"{out}: joints.pvd has the frames of results.pvd",
          [t for t, _ in jentries] == [t for t, _ in entries], f"{len(jentries)} vs {len(entries)}")
    prev_damage = None
    for (t, f), raw in zip(jentries, raws):
        j = raw["joints"]
        tag = f"{os.path.basename(out)}/{f}"
        n = len(j["damage"])
        check(f"{tag}: joint file named after its frame",
              f.replace("joints_", "frame_") in [e[1] for e in entries])
        text = open(os.path.join(out, f), "rb").read(4096)
        check(f"{tag}: zlib compressed", b"vtkZLibDataCompressor" in text)
        pts = vec3(j["points"])
        lines = np.arange(2 * n, dtype=np.int64).reshape(n, 2)
        m = meshio.read(os.path.join(out, f))
        check(f"{tag}: meshio points (joint mid-surface ends)", same(m.points, pts))
        ln = [c.data for c in m.cells if c.type == "line"]
        check(f"{tag}: meshio one line cell per joint", len(ln) == 1 and same(ln[0], lines))
        check_indexing(tag, os.path.join(out, f), m, ln, 2)
        for k in JOINT_ARRAYS:
            check(f"{tag}: meshio cell {k}", same(m.cell_data[k][0], np.asarray(j[k])))
        vp, conn, pd, cd, types = read_vtk(os.path.join(out, f), 2)
        check(f"{tag}: vtk points", same(vp, pts))
        check(f"{tag}: vtk line cells", same(conn, lines) and types == {3})
        for k in JOINT_ARRAYS:
            check(f"{tag}: vtk cell {k}", k in cd and same(cd[k], np.asarray(j[k])))
        check(f"{tag}: no NaN", all(np.isfinite(np.asarray(a, dtype=float)).all() for a in cd.values()))
        d = np.asarray(cd["damage"])
        b = np.asarray(cd["broken"])
        tof = np.asarray(cd["time_of_failure"])
        check(f"{tag}: damage in [0, 1]", ((d >= 0) & (d <= 1)).all())
        check(f"{tag}: broken joints have damage 1 and failed by the frame time",
              ((d[b == 1] == 1) & (tof[b == 1] >= 0) & (tof[b == 1] <= t * (1 + 1e-12))).all())
        check(f"{tag}: unbroken joints have time_of_failure -1", (tof[b == 0] == -1).all())
        if prev_damage is not None:
            check(f"{tag}: damage never heals", (d >= prev_damage).all())
        prev_damage = d
    # The last frame's broken joints are the rows of fractures.csv (when the last frame is the
    # end of the run), with the same failure times.
    csv_path = os.path.join(out, "fractures.csv")
    rows = [l.split(",") for l in open(csv_path).read().splitlines()[1:]]
    ev = {int(r[6]): float(r[0]) for r in rows}
    last = raws[-1]["joints"]
    broken = {i: last["time_of_failure"][i] for i, b in enumerate(last["broken"]) if b == 1}
    check(f"{out}: broken joints of the last frame are fractures.csv's",
          set(broken) == set(ev), f"{len(broken)} vs {len(ev)}")
    check(f"{out}: failure times agree with fractures.csv",
          all(abs(broken[i] - ev[i]) <= 1e-8 * abs(ev[i]) for i in set(broken) & set(ev)))


def check_indexing(tag, path, m, cells, verts):
    """A user's script indexes the points with the cells: the connectivity (and offsets) are
    Int64 in the file, so meshio gives integer cells and `points[cells]` has one row of
    `verts` points per cell."""
    header = open(path, "rb").read()
    for name in (b"connectivity", b"offsets"):
        check(f"{tag}: {name.decode()} is Int64", b'type="Int64" Name="' + name + b'"' in header)
    ok = len(cells) == 1 and np.issubdtype(cells[0].dtype, np.integer)
    check(f"{tag}: meshio cells are integers", ok, str(cells[0].dtype) if cells else "none")
    if ok:
        try:
            p = m.points[cells[0]]
            check(f"{tag}: points[cells] has shape (n, {verts}, 3)",
                  p.shape == (len(cells[0]), verts, 3), str(p.shape))
        except IndexError as e:
            check(f"{tag}: points[cells]", False, str(e))


def read_vtk(path, verts=3):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    pts = vtk_to_numpy(g.GetPoints().GetData())
    conn = vtk_to_numpy(g.GetCells().GetConnectivityArray()).reshape(-1, verts)
    pd = {g.GetPointData().GetArrayName(i): vtk_to_numpy(g.GetPointData().GetArray(i))
          for i in range(g.GetPointData().GetNumberOfArrays())}
    cd = {g.GetCellData().GetArrayName(i): vtk_to_numpy(g.GetCellData().GetArray(i))
          for i in range(g.GetCellData().GetNumberOfArrays())}
    types = {g.GetCellType(i) for i in range(g.GetNumberOfCells())}
    return pts, conn, pd, cd, types


for out in sys.argv[1:]:
    pvd = ET.parse(os.path.join(out, "results.pvd")).getroot()
    entries = [(float(d.get("timestep")), d.get("file")) for d in pvd.iter("DataSet")]
    check(f"{out}: pvd lists frames", len(entries) > 0)
    for t, f in entries:
        tag = f"{os.path.basename(out)}/{f}"
        raw = json.load(open(os.path.join(out, f.replace(".vtu", ".json"))))
        exp = expected(raw)
        check(f"{tag}: pvd time equals frame time", abs(t - raw["time"]) <= 1e-15 * max(1.0, abs(t)),
              f"{t} vs {raw['time']}")
        text = open(os.path.join(out, f), "rb").read(4096)
        check(f"{tag}: zlib compressed", b"vtkZLibDataCompressor" in text)
        # meshio
        m = meshio.read(os.path.join(out, f))
        check(f"{tag}: meshio points", same(m.points, exp["points"]))
        tri = [c.data for c in m.cells if c.type == "triangle"]
        check(f"{tag}: meshio triangles", len(tri) == 1 and same(tri[0], exp["cells"]))
        check_indexing(tag, os.path.join(out, f), m, tri, 3)
        for k, v in exp["point"].items():
            check(f"{tag}: meshio point {k}", same(m.point_data[k], v))
        for k, v in exp["cell"].items():
            check(f"{tag}: meshio cell {k}", same(m.cell_data[k][0], v))
        # VTK's own reader
        pts, conn, pd, cd, types = read_vtk(os.path.join(out, f))
        check(f"{tag}: vtk points", same(pts, exp["points"]))
        check(f"{tag}: vtk triangles", same(conn, exp["cells"]) and types == {5})
        for k, v in exp["point"].items():
            check(f"{tag}: vtk point {k}", k in pd and same(pd[k], v))
        for k, v in exp["cell"].items():
            check(f"{tag}: vtk cell {k}", k in cd and same(cd[k], v))
        check(f"{tag}: no NaN", all(np.isfinite(np.asarray(a, dtype=float)).all()
                                    for a in list(pd.values()) + list(cd.values())))
    check_joints(out, entries)

print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed else 0)
