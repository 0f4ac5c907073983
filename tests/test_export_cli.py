"""``forcelayout export``: layout files to simulator scenes from the command line."""

import json
import subprocess
import sys

import pytest

from forcelayout.cli import main
from forcelayout.layout import Layout, Pose
from forcelayout.plan import Plan

pytest.importorskip("trimesh")

PLAN = {
    "name": "cli_room",
    "room": {"polygon": [[0, 0], [4, 0], [4, 3], [0, 3]], "height": 2.5,
             "doors": [{"wall": 0, "offset": 1.0}]},
    "objects": [{"id": "desk", "category": "desk", "size": [1.2, 0.6, 0.75]},
                {"id": "lamp", "category": "lamp", "size": [0.3, 0.3, 0.4]}],
}


@pytest.fixture
def layout():
    plan = Plan.from_dict(PLAN)
    poses = {"desk": Pose(2.0, 2.5, 3.14159), "lamp": Pose(2.0, 2.5, 0.0, 0.75, "desk")}
    return Layout(plan, poses, seed=3)


def one_error_line(err: str) -> str:
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


def test_export_every_format_of_a_layout_that_embeds_its_plan(layout, tmp_path, capsys):
    src = layout.save(tmp_path / "room_3.json", include_plan=True)
    out = tmp_path / "out"
    assert main(["export", str(src), "--format", "glb,usd,mjcf,habitat", "--out", str(out),
                 "--movable", "lamp"]) == 0
    printed = capsys.readouterr().out.split()
    names = ["room_3.glb", "room_3.usda", "room_3.xml", "room_3.habitat"]
    assert printed == [str(out / n) for n in names]
    assert sorted(p.name for p in out.iterdir()) == sorted(names)
    mjcf = (out / "room_3.xml").read_text()
    assert '<freejoint name="lamp"' in mjcf and '<freejoint name="desk"' not in mjcf


def test_export_reads_the_plan_json_beside_the_layouts(layout, tmp_path, capsys):
    (tmp_path / "plan.json").write_text(layout.plan.to_json(), encoding="utf-8")
    a = layout.save(tmp_path / "cli_room_000.json")
    b = layout.save(tmp_path / "cli_room_001.json")
    assert main(["export", str(a), str(b), "--format", "mjcf", "--out", str(tmp_path / "o")]) == 0
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == ["cli_room_000.xml",
                                                                  "cli_room_001.xml"]


def test_export_without_a_plan_asks_for_plan_in_one_line(layout, tmp_path, capsys):
    src = layout.save(tmp_path / "lay.json")
    out = tmp_path / "out"
    assert main(["export", str(src), "--format", "glb", "--out", str(out)]) == 2
    err = one_error_line(capsys.readouterr().err)
    assert "cli_room" in err and "--plan" in err
    # a plan.json of another plan beside it is not taken
    (tmp_path / "plan.json").write_text(json.dumps(dict(PLAN, name="other")), encoding="utf-8")
    assert main(["export", str(src), "--format", "glb", "--out", str(out)]) == 2
    assert "--plan" in one_error_line(capsys.readouterr().err)
    assert not out.exists()
    plan_file = tmp_path / "my_plan.json"
    plan_file.write_text(layout.plan.to_json(), encoding="utf-8")
    assert main(["export", str(src), "--format", "glb", "--out", str(out),
                 "--plan", str(plan_file)]) == 0
    assert (out / "lay.glb").is_file()


@pytest.mark.parametrize("formats, reason", [
    ("glb,fbx", "unknown export format 'fbx'; accepted: glb, usd, mjcf, habitat"),
    (",", "--format names no format"),
])
def test_export_refuses_unknown_formats_in_one_line(layout, tmp_path, capsys, formats, reason):
    src = layout.save(tmp_path / "lay.json", include_plan=True)
    assert main(["export", str(src), "--format", formats, "--out", str(tmp_path / "o")]) == 2
    assert reason in one_error_line(capsys.readouterr().err)
    assert not (tmp_path / "o").exists()


def test_export_checks_every_input_before_writing(layout, tmp_path, capsys):
    good = layout.save(tmp_path / "good.json", include_plan=True)
    bogus = tmp_path / "bogus.json"
    bogus.write_text('{"a": 1}', encoding="utf-8")
    broken = tmp_path / "broken.json"
    broken.write_text('{"objects": ', encoding="utf-8")
    other = tmp_path / "sub"
    other.mkdir()
    twin = layout.save(other / "good.json", include_plan=True)
    cases = [(bogus, "not a layout"), (broken, "not a layout JSON file"),
             (tmp_path / "missing.json", "no such file"), (twin, "the same name")]
    for bad, reason in cases:
        assert main(["export", str(good), str(bad), "--format", "glb",
                     "--out", str(tmp_path / "o")]) == 2
        err = one_error_line(capsys.readouterr().err)
        assert str(bad) in err and reason in err
    assert not (tmp_path / "o").exists()


def test_export_refuses_a_plan_the_layout_is_not_of(layout, tmp_path, capsys):
    src = layout.save(tmp_path / "lay.json")
    assert main(["export", str(src), "--format", "glb", "--out", str(tmp_path / "o"),
                 "--plan", "bedroom"]) == 2
    assert "layout of plan 'cli_room', not of the --plan given ('bedroom')" in one_error_line(
        capsys.readouterr().err)
    data = json.loads(src.read_text())
    data["objects"]["sofa"] = {"x": 1.0, "y": 1.0, "yaw": 0.0}
    src.write_text(json.dumps(data), encoding="utf-8")
    plan_file = tmp_path / "plan.json"
    plan_file.write_text(layout.plan.to_json(), encoding="utf-8")
    assert main(["export", str(src), "--format", "glb", "--out", str(tmp_path / "o")]) == 2
    assert "['sofa'] are not in plan 'cli_room'" in one_error_line(capsys.readouterr().err)
    assert not (tmp_path / "o").exists()


def test_export_usd_without_usd_core_names_the_extra(layout, tmp_path, capsys, monkeypatch):
    for name in list(sys.modules):
        if name == "pxr" or name.startswith("pxr."):
            monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "pxr", None)
    src = layout.save(tmp_path / "lay.json", include_plan=True)
    assert main(["export", str(src), "--format", "mjcf,usd", "--out", str(tmp_path / "o")]) == 2
    assert 'pip install "forcelayout[export]"' in one_error_line(capsys.readouterr().err)
    assert not (tmp_path / "o").exists()


def test_export_without_the_extra_is_a_command_that_names_it(tmp_path, capsys, monkeypatch):
    monkeypatch.delitem(sys.modules, "forcelayout.export_cmd", raising=False)
    monkeypatch.setitem(sys.modules, "trimesh", None)
    assert main(["export", "lay.json", "--format", "glb", "--out", str(tmp_path)]) == 2
    err = one_error_line(capsys.readouterr().err)
    assert 'pip install "forcelayout[export]"' in err


def test_accepted_formats_in_the_help_are_the_export_formats():
    from forcelayout import export, export_cmd

    assert export_cmd._ACCEPTED == ", ".join(export.EXPORT_FORMATS)


def test_the_command_line_starts_without_importing_the_export_extra():
    code = ("import sys, forcelayout.cli as c; c.build_parser(); "
            "print(sorted(m for m in ('trimesh', 'pxr') if m in sys.modules))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"
