"""The evaluation scripts run end to end in their smallest mode and print valid JSON."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import forcelayout as fl

ROOT = Path(__file__).resolve().parents[1]
BENCH = ROOT / "benchmarks"

TINY_PLAN = {
    "name": "tiny",
    "room": {"polygon": [[0, 0], [3.5, 0], [3.5, 3], [0, 3]], "height": 2.6,
             "doors": [{"wall": 0, "offset": 0.8, "width": 0.9}]},
    "objects": [
        {"id": "bed", "category": "bed", "size": [1.4, 2.0, 0.5], "primary": True},
        {"id": "nightstand", "category": "nightstand", "size": [0.4, 0.4, 0.5]},
        {"id": "plant", "category": "plant", "size": [0.3, 0.3, 0.8], "decor": True},
    ],
    "rules": [{"rule": "at_wall", "object": "bed"},
              {"rule": "next_to", "object": "nightstand", "target": "bed"}],
}


def run(script: str, *args: str) -> tuple[dict, str]:
    proc = subprocess.run([sys.executable, str(BENCH / script), *args], capture_output=True,
                          text=True, timeout=240, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr[-3000:]
    out = proc.stdout
    end = out.index("\n}\n") + 3 if "\n}\n" in out else len(out)
    return json.loads(out[:end]), out[end:]


def test_paper_tables_quick(tmp_path: Path) -> None:
    plan = tmp_path / "tiny.json"
    plan.write_text(json.dumps(TINY_PLAN))
    png, out = tmp_path / "tables.png", tmp_path / "tables.json"
    result, rest = run("paper_tables.py", "--quick", "--n", "3", "--plans", str(plan),
                       "--resamples", "200", "--markdown", "--png", str(png), "--out", str(out))
    assert result["benchmark"] == "paper_tables"
    assert set(result["conditions"]) == {"Full", "-Relations", "-Decor", "Random"}
    assert result["config"]["plans"] == ["tiny"]
    for cond in result["conditions"].values():
        assert cond["samples"] == 3
        for key in ("validity_pct", "rules_pct", "good_pct", "valid_per_s", "good_per_s",
                    "geometric_intra", "topological_intra", "relational_intra"):
            ci = cond[key]
            assert set(ci) >= {"estimate", "low", "high", "level"}
            if ci["estimate"] is not None:
                assert ci["low"] <= ci["estimate"] + 1e-9 <= ci["high"] + 2e-9
        assert 0 <= cond["validity_pct"]["estimate"] <= 100
        assert cond["per_plan"][0]["plan"] == "tiny"
    assert "Table I" in rest and "| Random |" in rest
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert json.loads(out.read_text()) == result


def test_scaling_quick(tmp_path: Path) -> None:
    png = tmp_path / "scaling.png"
    result, rest = run("scaling.py", "--sizes", "3", "6", "--samples", "1", "--markdown",
                       "--png", str(png))
    assert result["benchmark"] == "scaling"
    assert [r["objects"] for r in result["results"]] == [3, 6]
    for r in result["results"]:
        assert r["ms_per_layout"]["median"] > 0 and r["peak_mib"] > 0
        assert r["median_steps"] >= 1
    assert isinstance(result["exponent_per_layout"], float)
    assert "| objects |" in rest
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_suite_quick(tmp_path: Path) -> None:
    """The plan suite runs forcelayout and the rejection baseline side by side."""
    out = tmp_path / "suite.json"
    result, rest = run("suite.py", "--quick", "--jobs", "1", "--plans", "bedroom",
                       str(tmp_path / "missing.json"), "--markdown", "--out", str(out))
    assert result["benchmark"] == "suite"
    assert result["config"]["samples"] == 3 and result["config"]["baseline_tries"] == 60
    row, bad = result["plans"]
    assert row["plan"] == "bedroom" and row["objects"] == 11 and 0 < row["fill_pct"] < 60
    f, b = row["forcelayout"], row["baseline"]
    assert f["samples"] == 3 and 0 <= f["yield_pct"] <= 100
    assert 1 <= b["tries"] <= 60 and b["accepted"] <= 3
    for side in (f, b):
        for key in ("good_per_s", "geometric", "topological", "failures", "every_rule_pct"):
            assert key in side
    assert set(row["targets"]) == {"yield", "not_below_baseline", "diversity",
                                   "diversity_clearly_below", "speed"}
    assert "error" in bad and "missing" in bad["error"]  # an error row, not a crash
    o = result["overall"]
    assert o["plans"] == 2 and o["errors"] == 1
    assert set(o["targets"]) == {"yield_each", "yield_mean", "not_below_baseline",
                                 "diversity", "speed_each", "speed_suite"}
    assert "| bedroom | 11 |" in rest and "| **overall** |" in rest and "Targets" in rest
    assert "| BL layouts |" in rest and "baseline layouts" in rest  # what diversity rests on
    assert json.loads(out.read_text()) == result
    sys.path.insert(0, str(BENCH))
    from suite import markdown

    row["targets"]["speed"] = False  # a failing plan is named in its target's line
    speed_line = next(line for line in markdown(result).splitlines() if "good/s ≥" in line)
    assert "0 of 1 plans; below: bedroom)" in speed_line
    if row["baseline"]["topological"]:  # a plan below the diversity target: ratio, interval
        row["forcelayout"]["topological"] = 0.5 * row["baseline"]["topological"]
        row["targets"]["diversity"] = False
        row["diversity_ratio"]["topological"] = [0.4, 0.6]
        assert "topo 0.50 [0.40, 0.60]" in markdown(result)
        # and how often each sampler's good layouts meet every rule (a baseline may owe its
        # diversity to a rule it leaves unmet)
        row["forcelayout"]["every_rule_pct"], row["baseline"]["every_rule_pct"] = 100.0, 4.0
        assert "every rule met in 100 % of its good layouts, the baseline's 4 %" \
            in markdown(result)


def test_suite_baseline_again(tmp_path: Path) -> None:
    """--baseline-again runs the baseline with the next seed and judges its diversity
    against the first run's, as forcelayout's is judged: the test's chance level."""
    result, rest = run("suite.py", "--quick", "--jobs", "1", "--plans", "bedroom",
                       "--baseline-again", "--markdown")
    assert result["config"]["baseline_again"] is True
    (row,) = result["plans"]
    again = row["baseline_again"]
    assert again["seed"] == 1 and again["accepted"] <= 3
    assert set(again["targets"]) == {"diversity", "diversity_clearly_below"}
    chance = result["overall"]["baseline_again"]
    assert chance["judged"] == (again["targets"]["diversity"] is not None)
    assert chance["diversity"] <= chance["judged"]
    assert ("the baseline's second run" in rest) == bool(chance)

def test_diversity_ratio_interval() -> None:
    """The suite's bootstrap interval of a diversity ratio covers the true ratio."""
    sys.path.insert(0, str(BENCH))
    from suite import ratio_interval

    rng = np.random.default_rng(1)
    pts = rng.random((30, 2))
    d = np.linalg.norm(pts[:, None] - pts[None], axis=-1)
    lo, hi = ratio_interval(d, d)
    assert lo < 1.0 < hi and hi - lo < 0.5
    lo, hi = ratio_interval(0.5 * d, d)
    assert hi < 0.95 and lo < 0.5 < hi  # half as diverse: clearly below 0.95


def test_floor_quick(tmp_path: Path) -> None:
    """Time per raw sample beside a bare Box2D loop of the same bodies and steps."""
    out = tmp_path / "floor.json"
    result, rest = run("floor.py", "--quick", "--jobs", "1", "--plans", "bedroom",
                       "--markdown", "--out", str(out))
    assert result["benchmark"] == "floor"
    (row,) = result["plans"]
    assert row["plan"] == "bedroom" and row["floor_bodies"] == 8 and row["samples"] == 3
    assert row["mean_steps"] > 0 and row["bare_ms_per_sample"] > 0
    assert row["ratio"] == pytest.approx(row["ms_per_sample"] / row["bare_ms_per_sample"])
    assert 0 <= row["good"] <= 3 and row["baseline"]["tries"] <= 60
    assert set(result["overall"]["targets"]) == {"ratio", "living_room", "speed_suite"}
    assert "| bedroom | 8 |" in rest and "| **overall** |" in rest and "Targets" in rest
    (costly,) = result["overall"]["most_cpu"]  # the plan taking the largest share of the CPU
    assert costly["plan"] == "bedroom" and costly["cpu_share"] == pytest.approx(1.0)
    assert f"bedroom 100 % ({row['good']} of 3 good)" in rest
    assert json.loads(out.read_text()) == result


def test_requests_quick() -> None:
    """The share of a batch's CPU each kind of batched request takes."""
    result, rest = run("requests.py", "--plans", "bedroom", "--samples", "4", "--markdown")
    assert result["benchmark"] == "requests"
    (row,) = result["plans"]
    assert row["plan"] == "bedroom" and row["samples"] == 4 and row["ms_per_sample"] > 0
    kinds = row["kinds"]
    assert set(kinds) == {"simulate", "judge", "propose", "relocate"}
    assert kinds["simulate"]["calls"] >= 1 and kinds["propose"]["requests"] >= 4
    assert sum(k["share"] for k in kinds.values()) + row["rest_share"] == pytest.approx(1.0)
    assert 0.0 <= row["small_share"] <= 1.0
    assert "| bedroom |" in rest


@pytest.mark.parametrize("script", ["paper_tables.py", "scaling.py", "suite.py", "floor.py",
                                    "requests.py"])
def test_scripts_reject_bad_arguments(script: str) -> None:
    bad = ["--n", "0"] if script == "paper_tables.py" else ["--samples", "0"]
    proc = subprocess.run([sys.executable, str(BENCH / script), *bad], capture_output=True,
                          text=True, timeout=60, cwd=ROOT)
    assert proc.returncode == 2
    assert "must be >= 1" in proc.stderr


def test_distinct_agrees_with_all_pairs() -> None:
    data, _ = run("distinct.py", "--n", "20", "60")
    assert [r["n"] for r in data["results"]] == [20, 60]
    assert all(r["agree"] for r in data["results"])


def test_dataset_throughput_quick() -> None:
    data, _ = run("dataset_throughput.py", "--plans", "bedroom", "-n", "2", "--no-dask")
    assert {r["executor"] for r in data["runs"]} == {"1 process", "2 processes"}
    assert all(r["layouts"] == 2 for r in data["runs"]) and data["baseline"]["seconds"] > 0


def test_dataset_resume_quick() -> None:
    data, _ = run("dataset_resume.py", "--plans", "bedroom", "-n", "3", "--workers", "1",
                  "--pictures", "none", "--kills", "1")
    assert data["identical"] and data["runs"] >= 1


def test_vlm_loop_quick(tmp_path: Path) -> None:
    plan = tmp_path / "tiny.json"
    plan.write_text(json.dumps(TINY_PLAN))
    result, _ = run("vlm_loop.py", "--plans", str(plan), "-n", "2", "--accept", "0.5")
    assert result["benchmark"] == "vlm_loop" and result["config"]["judge"] == "scripted"
    (row,) = result["plans"]
    assert row["plan"] == "tiny" and row["accepted"] <= 2
    assert row["judged"] + row["unjudged"] <= row["valid"] <= row["attempted"]
    if row["accepted"]:
        assert row["seconds_per_accepted"] == pytest.approx(row["seconds"] / row["accepted"],
                                                            abs=2e-3)


def test_grounding_quick() -> None:
    pytest.importorskip("trimesh")
    result, _ = run("grounding.py", "--samples", "1", "--plans", "bedroom",
                    "--embedders", "lexical")
    assert result["benchmark"] == "grounding"
    lex = result["retrieval"]["lexical"]
    assert lex["queries"] >= 30 and 0.0 <= lex["top1_words"] <= lex["top1"] + 1.0
    assert result["grounding"]["plans"]["bedroom"]["matched"] >= 1
    assert set(result["yield"]["bedroom"]) == {"boxes", "meshes", "meshes_hull"}


@pytest.mark.parametrize("folder", ["plans", "plans_heldout"])
def test_every_suite_plan_loads(folder):
    files = sorted((BENCH / folder).glob("*.json"))
    assert len(files) >= 12
    for f in files:
        assert fl.load_plan(f).name == f.stem


def test_access_quick() -> None:
    """Access audit: the share of layouts leaving an object with no access zone free."""
    result, rest = run("access.py", "--plans", "bedroom", "--samples", "3",
                       "--baseline-tries", "60", "--jobs", "1", "--markdown")
    assert result["benchmark"] == "access"
    (row,) = result["plans"]
    assert row["plan"] == "bedroom" and row["forcelayout"]["layouts"] == 3
    for side in ("forcelayout", "baseline"):
        s = result["overall"][side]
        assert s["blocked"] <= s["layouts"]
        req = row["required"][side]
        assert 0 <= req["yield_pct"] <= 100 and req["good"] >= 0
    assert row["required"]["forcelayout"]["samples"] == 3
    assert "| bedroom | 3 |" in rest
    sys.path.insert(0, str(BENCH))
    from access import blocked_owners

    plan = fl.Plan.from_dict({
        "name": "wardrobe", "room": {"polygon": [[0, 0], [3, 0], [3, 3], [0, 3]]},
        "objects": [{"id": "wardrobe", "category": "wardrobe", "size": [1.0, 0.6, 2.0]},
                    {"id": "box", "category": "box", "size": [0.6, 0.6, 0.5]}],
        "rules": []})
    ward = fl.Pose(1.5, 0.3, 0.0)  # back to the wall at y = 0, front towards +y
    in_front = fl.Layout(plan, {"wardrobe": ward, "box": fl.Pose(1.5, 1.0, 0.0)})
    aside = fl.Layout(plan, {"wardrobe": ward, "box": fl.Pose(2.6, 2.6, 0.0)})
    assert blocked_owners(in_front, 0.1, 0.6) == [("wardrobe", ["box"])]
    assert blocked_owners(aside, 0.1, 0.6) == []
    off = fl.Layout(plan, {"wardrobe": fl.Pose(1.5, 2.7, 0.0)})  # facing the wall at y = 3
    assert blocked_owners(off, 0.1, 0.6) == [("wardrobe", ["wall"])]
