"""fdem._sweep: key paths, and a small sweep on 2 processes with a runner that calls the
command line (no compiled extension needed): the same numbers as running the variants one by
one, rows in the order of the variants, a bad variant giving a row with its error."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import pytest

import cli_runs  # noqa: F401  (puts the package on sys.path when it is not installed)
from cli_runs import REPO, absolute_meshes, cli_runner, max_reaction
from fdem._output import Output
from fdem._sweep import ROW_FIELDS, get_path, parse_key_path, set_path, sweep

YOUNG = "bodies[0].materials.body.young"


def test_key_paths():
    assert parse_key_path("bodies[0].materials.rock.young") == [
        "bodies", 0, "materials", "rock", "young"]
    assert parse_key_path("bodies.0.materials.*.young") == [
        "bodies", "0", "materials", "*", "young"]
    assert parse_key_path("a[1][2].b") == ["a", 1, 2, "b"]
    for bad in ["", "a..b", ".a", "a.", "a[x]", "[0]", "a[0]b"]:
        with pytest.raises(ValueError, match="not of the form"):
            parse_key_path(bad)
    with pytest.raises(TypeError, match="give a str"):
        parse_key_path(3)
    d = {"bodies": [{"materials": {"rock": {"young": 1.0}}}], "integrator": {}}
    for p in ["bodies[0].materials.rock.young", "bodies.0.materials.rock.young"]:
        set_path(d, p, 2.0)
        assert get_path(d, p) == 2.0
    set_path(d, "integrator.safety", 0.5)  # a new last key: the scene's validation judges it
    assert d["integrator"] == {"safety": 0.5}
    with pytest.raises(KeyError, match=r"no 'materialz' in bodies\[0\] \(keys there: materials\)"):
        set_path(d, "bodies[0].materialz.rock.young", 1.0)
    with pytest.raises(KeyError, match=r"bodies has 1 entries, no \[3\]"):
        set_path(d, "bodies[3].thickness", 1.0)
    with pytest.raises(KeyError, match="is an object, not a list"):
        set_path(d, "integrator[0]", 1.0)
    value = [1, 2]
    set_path(d, "integrator.list", value)
    value.append(3)
    assert d["integrator"]["list"] == [1, 2]  # a copy was set


def block_scene(tmp_path: Path) -> Path:
    """The static block compression with a displacement probe on the loaded top (so that
    the run has a load-displacement curve), written with absolute mesh paths."""
    src = REPO / "examples" / "block-compression.json"
    scene = absolute_meshes(json.loads(src.read_text()), src.parent)
    scene["histories"]["probes"][1] = {"displacement": {"group": "top"}}
    path = tmp_path / "block.json"
    path.write_text(json.dumps(scene))
    return path


VARIANTS = [{YOUNG: e} for e in (10e9, 20e9, 30e9, 40e9)]


def test_sweep_on_two_processes_equals_the_runs_one_by_one(tmp_path):
    scene = block_scene(tmp_path)
    rows = sweep(scene, VARIANTS, processes=2, threads=1, runner=cli_runner,
                 metric=max_reaction, out=tmp_path / "sweep")
    assert [r[YOUNG] for r in rows] == [v[YOUNG] for v in VARIANTS]
    base = json.loads(scene.read_text())
    for i, (v, r) in enumerate(zip(VARIANTS, rows)):
        assert r["error"] is None, r["error"]
        assert list(r)[: 1 + len(ROW_FIELDS)] == [YOUNG, *ROW_FIELDS]
        assert Path(r["out"]) == tmp_path / "sweep" / f"variant_{i:03d}"
        # the same variant run alone, through the CLI, read with the same reader
        d = json.loads(json.dumps(base))
        set_path(d, YOUNG, v[YOUNG])
        alone = tmp_path / f"alone{i}"
        cli_runner(d, str(scene.parent), str(alone), 1)
        o = Output(alone)
        # an elastic block: no joint breaks, so no peak, only a largest load
        assert r["failed"] is False and r["peak_load"] is None and o.peak_load is None
        assert r["largest_load"] == o.largest_load
        assert r["metric"] == max_reaction(o) == r["largest_load"]
        assert r["steps"] == o.summary["steps"] and r["converged"] == o.summary["converged"]
        for k in ("supplied", "present", "dissipated", "error"):
            assert r[f"energy_{k}"] == o.energy[k]
        same = (Path(r["out"]) / "histories.csv").read_text()
        assert same == (alone / "histories.csv").read_text()
        assert r["wall_time"] > 0 and r["pid"] != os.getpid()
    # the load is the modulus times the strain times the area: proportional to E
    peaks = [r["largest_load"] for r in rows]
    assert all(abs(p / peaks[0] - (i + 1)) < 1e-9 for i, p in enumerate(peaks))


def test_a_bad_variant_gives_a_row_with_its_error(tmp_path):
    scene = block_scene(tmp_path)
    variants = [{YOUNG: 20e9}, {YOUNG: -1.0}, {"bodies[0].materialz.body.young": 1.0}]
    rows = sweep(scene, variants, processes=2, runner=cli_runner)
    assert rows[0]["error"] is None and rows[0]["largest_load"] > 0 and rows[0]["out"] is None
    assert YOUNG in rows[1]["error"] and rows[1]["largest_load"] is None
    assert "KeyError: bodies[0].materialz.body.young: no 'materialz'" in rows[2]["error"]
    assert set(rows[1]) - {YOUNG} == set(rows[2]) - set(variants[2])
    assert set(ROW_FIELDS) <= set(rows[2])
    fields = ", ".join(sorted(rows[0]))
    with pytest.raises(KeyError, match=re.escape(f"no row field 'peak'; the row fields: {fields}")):
        rows[0]["peak"]
    with pytest.raises(RuntimeError, match=r"bodies\[0\]\.materials\.body\.young"):
        sweep(scene, variants[:2], processes=2, runner=cli_runner, raise_errors=True)
    with pytest.raises(TypeError, match="list of dicts"):
        sweep(scene, {YOUNG: 1.0}, runner=cli_runner)
    with pytest.raises(TypeError, match="not a lambda"):
        sweep(scene, variants, runner=cli_runner, metric=lambda o: o.peak_load)
    with pytest.raises(ValueError, match="processes"):
        sweep(scene, variants, processes=0, runner=cli_runner)


def test_a_sweep_as_a_data_frame(tmp_path):
    pd = pytest.importorskip("pandas")
    f = sweep(block_scene(tmp_path), VARIANTS[:2], processes=1, runner=cli_runner,
              as_frame=True)
    assert isinstance(f, pd.DataFrame) and list(f[YOUNG]) == [10e9, 20e9]
    assert f["error"].isna().all()


