"""Independent read-back of fdem's output: every .vtu frame listed in results.pvd is read by
meshio and by VTK's vtkXMLUnstructuredGridReader, and its points, cells and arrays must equal
the solver's raw dump (frame_NNNN.json) exactly. Prints 'N passed, N failed'; exits non-zero
on any failure."""
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


def read_vtk(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    pts = vtk_to_numpy(g.GetPoints().GetData())
    conn = vtk_to_numpy(g.GetCells().GetConnectivityArray()).reshape(-1, 3)
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

print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed else 0)
