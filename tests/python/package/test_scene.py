"""fdem.Scene and fdem.check: the command line's checks and messages from Python, the JSON
path of every refused field, key-path edits that leave the scene unchanged when refused,
and TypeErrors with the fix for what is not a scene at all."""

import json
import math

import fdem
import numpy as np
import pytest
from conftest import DISC, ELASTIC, EXAMPLES, cli

YOUNG = "bodies[0].materials.body.young"


def elastic_dict():
    return json.loads(ELASTIC.read_text())


def test_a_file_scene_reads_and_edits_by_key_path():
    s = fdem.Scene(ELASTIC)
    assert s.file == ELASTIC and s.base == EXAMPLES
    assert s[YOUNG] == 30e9
    assert s["bodies.0.materials.body.young"] == 30e9
    assert s["boundary_conditions[0].pressure.value"] == 100e6
    s[YOUNG] = 40e9
    assert s[YOUNG] == 40e9 and s.to_dict()["bodies"][0]["materials"]["body"]["young"] == 40e9
    t = s.edit({YOUNG: 50e9, "output.frames": 2})
    assert (t[YOUNG], t["output.frames"], s[YOUNG]) == (50e9, 2, 40e9)
    u = s.with_(**{"bodies.0.thickness": 0.02})
    assert u["bodies[0].thickness"] == 0.02 and s["bodies[0].thickness"] == 0.01
    # numpy values are taken as the numbers they are
    s[YOUNG] = np.float64(35e9)
    s["output.frames"] = np.int64(1)
    assert s[YOUNG] == 35e9 and type(s["output.frames"]) is int


def test_a_dict_scene_resolves_its_meshes_against_base(tmp_path):
    d = elastic_dict()
    s = fdem.Scene(d, base=EXAMPLES)
    d["title"] = "changed after"  # deep-copied: the scene keeps its own
    assert s["title"] != "changed after"
    assert s.file is None and s.base == EXAMPLES
    # written with an absolute mesh path, it runs from anywhere
    w = s.write(tmp_path / "elastic.json")
    assert fdem.Scene(w).to_dict()["bodies"][0]["mesh"] == str(
        (EXAMPLES / "../meshes/brazilian-disc.msh").resolve()
    )


def test_unknown_key_raises_scene_error_with_its_json_path():
    d = elastic_dict()
    d["integrator"] = {"safety": 0.9, "sheme": "gear-5"}
    with pytest.raises(fdem.SceneError) as e:
        fdem.Scene(d, base=EXAMPLES)
    assert isinstance(e.value, ValueError)
    assert e.value.path == "integrator.sheme"
    assert "unknown field `sheme`" in e.value.message
    assert e.value.fix and "misspelled" in e.value.fix
    assert str(e.value).startswith(str(EXAMPLES / "scene.json"))


def test_wrong_type_raises_scene_error_with_its_json_path():
    d = elastic_dict()
    d["bodies"][0]["materials"]["body"]["young"] = "abc"
    with pytest.raises(fdem.SceneError) as e:
        fdem.Scene(d, base=EXAMPLES)
    assert e.value.path == YOUNG
    assert "expected f64" in e.value.message and e.value.fix


def test_missing_mesh_raises_scene_error_naming_the_mesh():
    d = elastic_dict()
    d["bodies"][0]["mesh"] = "no-such-mesh.msh"
    with pytest.raises(fdem.SceneError) as e:
        fdem.Scene(d, base=EXAMPLES)
    assert e.value.kind == "mesh" and e.value.path == "bodies[0].mesh"
    assert str(EXAMPLES / "no-such-mesh.msh") in str(e.value)
    assert "fix: check the path" in str(e.value)


def test_a_missing_file_raises_scene_error_naming_it(tmp_path):
    with pytest.raises(fdem.SceneError) as e:
        fdem.Scene(tmp_path / "nothing.json")
    assert e.value.file == str(tmp_path / "nothing.json") and e.value.path is None
    assert "cannot read the file" in str(e.value)


def test_messages_are_the_command_lines(tmp_path):
    d = elastic_dict()
    d["bodies"][0]["mesh"] = str((EXAMPLES / d["bodies"][0]["mesh"]).resolve())
    d["bodies"][0]["materials"]["body"]["poisson"] = 0.7
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(d, indent=2))
    with pytest.raises(fdem.SceneError) as e:
        fdem.Scene(bad)
    assert e.value.path == "bodies[0].materials.body.poisson"
    run = cli("check", str(bad), check=False)
    assert run.returncode == 2
    assert run.stderr.strip() == f"error: {e.value}"


def test_not_a_scene_raises_type_error_with_the_fix():
    for wrong in [42, 3.5, None, ["bodies"]]:
        with pytest.raises(TypeError) as e:
            fdem.Scene(wrong)
        assert "fix:" in str(e.value)
    with pytest.raises(TypeError):
        fdem.run(42)
    with pytest.raises(TypeError):
        fdem.check(object())


def test_a_refused_edit_leaves_the_scene_unchanged():
    s = fdem.Scene(ELASTIC)
    before = s.to_dict()
    for key, value, path in [
        (YOUNG, "abc", YOUNG),
        (YOUNG, -1.0, YOUNG),
        (YOUNG, math.nan, YOUNG),
        ("bodies[0].materials.body.poisson", 0.5, "bodies[0].materials.body.poisson"),
        ("output.framez", 3, "output.framez"),
    ]:
        with pytest.raises(fdem.SceneError) as e:
            s[key] = value
        assert e.value.path == path, (key, e.value)
        assert s.to_dict() == before
    # several changes at once: one refused, none made
    with pytest.raises(fdem.SceneError):
        s.edit_in_place({"output.frames": 2, YOUNG: -5.0})
    assert s.to_dict() == before
    with pytest.raises(fdem.SceneError):
        s[YOUNG] = object()
    assert s.to_dict() == before


def test_a_missing_key_raises_key_error_naming_the_keys_there():
    s = fdem.Scene(ELASTIC)
    with pytest.raises(KeyError) as e:
        s["bodies[0].materials.rock.young"]
    assert "'rock'" in str(e.value) and "'body'" in str(e.value)
    with pytest.raises(KeyError) as e:
        s["mass_scaling.factor"] = 10.0
    assert "mass_scaling" in str(e.value) and "'bodies'" in str(e.value)
    with pytest.raises(KeyError) as e:
        s["bodies[3].mesh"]
    assert "1 entries" in str(e.value)
    assert "bodies[0].mesh" in s and "bodies[0].nothing" not in s


def test_check_reports_as_the_command_line_does():
    r = fdem.check(DISC)
    out = cli("check", str(DISC)).stdout
    # the description is the command line's to the letter; the report times a force
    # evaluation, so only its form is compared
    assert out.startswith(r.describe + "\n")
    assert r.text.startswith(r.describe + "\n") and r.report in r.text
    assert out.count("\n") == r.text.count("\n") + 1
    assert (r.nodes, r.triangles, r.analysis) == (2592, 864, "dynamic")
    assert r.steps > 0 and 0 < r.time_step <= r.time_step_limit
    assert r.steps * r.time_step == pytest.approx(r.duration, rel=1e-12)
    assert f"{r.steps} steps" in r.describe


def test_scene_errors_cross_process_boundaries_with_their_attributes():
    # a sweep's worker process sends its errors back pickled
    import pickle

    with pytest.raises(fdem.SceneError) as e:
        fdem.Scene({"bodies": 3}, base=EXAMPLES)
    back = pickle.loads(pickle.dumps(e.value))
    assert type(back) is fdem.SceneError and str(back) == str(e.value)
    assert (back.path, back.fix, back.kind) == ("bodies", e.value.fix, "parse")
