"""The dicts users index by name (histories, walls, fractures, the summary and its energy
ledger, a frame's point and cell arrays, the joints): a missing key raises a KeyError that
names it and lists every key there, sorted; they stay dicts (`in`, `.get`, equality, pickling,
pandas)."""

from __future__ import annotations

import copy
import json
import pickle
import re
from pathlib import Path

import pytest

import cli_runs  # noqa: F401  (puts the package on sys.path when it is not installed)
from cli_runs import example_run
from fdem._named import Named
from fdem._output import Output, read

SHORT_NOTCHED = {"duration": 4e-4, "output": {"frames": 3, "compression": 0}}


def missing(d: dict, key: str) -> str:
    """The message of the KeyError of `d[key]` (str(e) quotes it, as Python prints it)."""
    with pytest.raises(KeyError) as e:
        d[key]
    assert e.value.args[0] == str(e.value)[1:-1]
    return e.value.args[0]


def test_a_missing_key_names_it_and_lists_the_keys_sorted():
    d = Named({"time": 1, "kinetic": 2, "u_y[load]": 3}, what="history", plural="histories")
    assert missing(d, "t") == "no history 't'; the histories: kinetic, time, u_y[load]"
    assert str(KeyError(missing(d, "t"))) == (
        "\"no history 't'; the histories: kinetic, time, u_y[load]\""
    )
    # still a dict: in, get, equality, iteration order, no entry added by a miss
    assert "t" not in d and d.get("t") is None and d.get("t", 5) == 5
    assert d == {"time": 1, "kinetic": 2, "u_y[load]": 3} and isinstance(d, dict)
    assert list(d) == ["time", "kinetic", "u_y[load]"] and len(d) == 3
    assert missing(Named(what="cell array"), "x") == "no cell array 'x'; the cell arrays: (none)"


def test_pickled_and_copied_it_keeps_its_message():
    d = Named({"b": 1, "a": 2}, what="joint array")
    for c in (pickle.loads(pickle.dumps(d)), copy.deepcopy(d), copy.copy(d)):
        assert type(c) is Named and c == d
        assert missing(c, "z") == "no joint array 'z'; the joint arrays: a, b"


def folder(tmp_path: Path, files: dict) -> Path:
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    return tmp_path


def test_the_tables_and_the_summary_of_a_run_folder(tmp_path):
    d = folder(tmp_path, {
        "histories.csv": "time,kinetic,reaction_y[load],u_y[load]\n0,0,0,0\n1,2,3,4\n",
        "walls.csv": "time,u_x[top],u_y[top],force_x[top],force_y[top]\n0,0,0,0,0\n",
        "fractures.csv": "time,joint,x,y,mode,mode_mix,energy_released\n1e-5,3,0,0,I,0,1e-3\n",
        "summary.json": json.dumps({"steps": 10, "energy": {"supplied": 1.0, "kinetic": 0.5}}),
    })
    o = Output(d)
    assert o.histories["time"].tolist() == [0.0, 1.0]
    assert missing(o.histories, "t") == (
        "no history 't'; the histories: kinetic, reaction_y[load], time, u_y[load]"
    )
    assert missing(o.walls, "force_y[bottom]") == (
        "no column of walls.csv 'force_y[bottom]'; the columns of walls.csv: force_x[top], "
        "force_y[top], time, u_x[top], u_y[top]"
    )
    assert missing(o.fractures, "modes") == (
        "no column of fractures.csv 'modes'; the columns of fractures.csv: energy_released, "
        "joint, mode, mode_mix, time, x, y"
    )
    assert missing(o.summary, "step") == (
        "no summary entry 'step'; the summary entries: energy, steps"
    )
    assert missing(o.energy, "dissipated") == (
        "no energy term 'dissipated'; the energy terms: kinetic, supplied"
    )
    assert o.summary == json.loads((d / "summary.json").read_text())
    pd = pytest.importorskip("pandas")
    assert list(pd.DataFrame(o.histories).columns) == list(o.histories)


def test_a_summary_that_is_not_an_object_names_the_file(tmp_path):
    d = folder(tmp_path, {"summary.json": "[1, 2]"})
    with pytest.raises(ValueError, match=r"summary.json: holds a JSON list, not an object"):
        Output(d).summary


def test_a_frames_arrays_and_the_joints():
    o = read(example_run("notched-beam-fracture", SHORT_NOTCHED))
    f = o.frames[-1]
    points, cells = sorted(f.point_data), sorted(f.cell_data)
    assert "displacement" in points and "stress" in cells
    assert missing(f.point_data, "displacements") == (
        f"no point array 'displacements'; the point arrays: {', '.join(points)}"
    )
    assert missing(f.cell_data, "stresses") == (
        f"no cell array 'stresses'; the cell arrays: {', '.join(cells)}"
    )
    joints = sorted(o.joints)
    assert "damage" in joints and "points" in joints
    assert re.fullmatch(
        r"no joint array 'dmg'; the joint arrays: (.*)", missing(o.joints, "dmg")
    ).group(1) == ", ".join(joints)
