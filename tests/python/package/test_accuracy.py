"""The accuracy indicators from Python: ``Result.accuracy`` and ``Output.accuracy`` are the
run's ``summary.json`` section by name, and ``warnings`` lists the warned ones."""

import json

import fdem

from conftest import ELASTIC


def test_the_run_result_carries_the_accuracy_section_of_its_summary(disc_runs):
    cli_out, _py_out, result = disc_runs
    section = json.loads((cli_out / "summary.json").read_text())["accuracy"]
    acc = result.accuracy
    assert [i["name"] for i in section["indicators"]] == [i["name"] for i in acc.values()]
    pz = acc["process_zone_i"]
    assert pz["subject"] == "fracture.material"
    assert pz["value"] >= pz["threshold"] and "warning" not in pz
    assert result.warnings == [] and section["warnings"] == 0
    assert fdem.read(cli_out).accuracy == acc
    try:
        acc["process_zone"]
    except KeyError as e:
        assert "process_zone_i" in str(e) and "energy_error" in str(e), e
    else:
        raise AssertionError("no KeyError")


def test_a_modulus_typed_in_gpa_is_warned_by_name(tmp_path):
    scene = fdem.Scene(ELASTIC)
    scene["bodies[0].materials.body.young"] = 30.0
    out = fdem.run(scene, out=tmp_path / "gpa", progress=False)
    names = [w.split(":")[0] for w in out.warnings]
    assert names == ["units", "static_strain"], out.warnings
    assert "young in GPa?" in out.accuracy["units"]["warning"]


def test_check_predicts_the_indicators_the_run_reports():
    report = fdem.check(ELASTIC)
    names = [i["name"] for i in report.accuracy]
    assert names == ["mesh_quality", "units"], names
    assert "accuracy before the run: 0 warnings" in report.text
    run = fdem.run(ELASTIC, progress=False)
    for i in report.accuracy:
        assert run.accuracy[i["name"]]["value"] == i["value"]


def test_the_split_disc_failed_along_its_loaded_diameter(disc_runs):
    """The fracturing disc splits: failed, its peak the largest load, the broken joints by
    mode adding up, and the crack a narrow band along the loaded (vertical) diameter."""
    cli_out, _py_out, result = disc_runs
    f = result.failure
    assert f["failed"] is True and f["peak_load"] == f["largest_load"] > 2000.0
    assert f == fdem.read(cli_out).failure
    assert sum(f["broken_by_mode"].values()) == f["broken_joints"] > 0
    assert f["broken_by_mode"]["I"] > f["broken_joints"] / 2  # a tensile split
    (x0, x1), (y0, y1) = f["crack_extent"]["x"], f["crack_extent"]["y"]
    assert max(abs(x0), abs(x1)) < 0.005 and y1 - y0 > 0.03  # R = 25 mm
    # the run's result block (Rust, at the end of the run) and Python's own reading of the
    # same files agree entry for entry
    assert f == result.failure_from_files()
    r = result.result
    assert r is not None and r["curve"]["file"] == "walls.csv"
    sp = r["specimen"]
    assert sp["shape"] == "disc" and sp["stress_measure"] == "2 P / (pi D t)"
    # 2 P / (pi D t) with D = 50 mm, t = 10 mm: within 15 % of ft = 3 MPa (row 42)
    assert abs(sp["peak_stress"] / 3e6 - 1.0) < 0.15
    assert sp["peak_stress"] == 2.0 * f["peak_load"] / (3.141592653589793 * sp["width"] * sp["thickness"])
