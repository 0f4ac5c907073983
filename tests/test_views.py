"""Notebook and terminal views: Summary tables and a Generation's thumbnail grid."""

from __future__ import annotations

import base64
import json
import re

import pytest

from forcelayout import Layout, Plan, Pose
from forcelayout import render as render_module
from forcelayout.layout import SampleReport
from forcelayout.sampling import Generation
from forcelayout.views import MAX_THUMBNAILS, Summary, generation_html

PLAN = Plan.model_validate({
    "name": "den",
    "room": {"polygon": [[0, 0], [4, 0], [4, 3], [0, 3]],
             "doors": [{"wall": 0, "offset": 0.5, "width": 0.9}]},
    "objects": [{"id": "sofa", "category": "sofa", "size": [2.0, 0.9, 0.8]},
                {"id": "table", "category": "table", "size": [1.0, 0.6, 0.45]}],
    "rules": [{"rule": "at_wall", "object": "sofa"}],
})


def layout(seed: int, *, satisfaction: float = 1.0) -> Layout:
    poses = {"sofa": Pose(2.0, 2.5, 3.14159), "table": Pose(2.0 + 0.01 * seed, 1.4, 0.0)}
    return Layout(PLAN, poses, seed, SampleReport(seed=seed, valid=True,
                                                  rule_satisfaction=satisfaction))


def run(k: int, *, wanted: int | None = None) -> Generation:
    layouts = [layout(1000 + i, satisfaction=0.5 if i == 1 else 1.0) for i in range(k)]
    rejected = SampleReport(seed=7, valid=False, failures=["collision: 'sofa' overlaps 'table'"])
    return Generation(PLAN, 3, layouts, [lay.report for lay in layouts] + [rejected], 1.25,
                      wanted=k if wanted is None else wanted)


def images(html: str) -> list[str]:
    return re.findall(r'<img src="data:image/png;base64,([^"]+)"', html)


def test_a_generation_shows_a_thumbnail_per_layout_with_captions_and_the_table():
    gen = run(3)
    html = gen._repr_html_()
    shown = images(html)
    assert len(shown) == 3
    assert all(base64.b64decode(s).startswith(b"\x89PNG") for s in shown)
    for i, lay in enumerate(gen):
        assert f"#{i} · seed {lay.seed}" in html
    assert html.count("100% of rules met") == 2 and "50% of rules met" in html
    assert '<table class="forcelayout-summary">' in html
    assert "<th" in html and "valid_fraction" in html and "collision ×1" in html
    assert "3 of 3 layouts" in html and "more" not in html


def test_the_grid_is_capped_and_says_how_many_more(monkeypatch):
    monkeypatch.setattr(render_module, "_thumbnail_png", lambda lay, size=1.6: b"png")
    gen = run(MAX_THUMBNAILS + 6)
    html = gen._repr_html_()
    assert len(images(html)) == MAX_THUMBNAILS
    assert "… and 6 more" in html
    assert len(images(generation_html(gen, limit=2))) == 2
    with pytest.raises(ValueError, match="limit"):
        generation_html(gen, limit=-1)


def test_a_short_run_shows_its_hint():
    html = run(2, wanted=5)._repr_html_()
    assert "2 of 5 layouts" in html and "only 2 of 5 layouts" in html


def test_an_empty_generation_shows_why_it_is_empty():
    gen = run(0, wanted=2)
    html = gen._repr_html_()
    assert not images(html)
    assert "no layout of plan &#x27;den&#x27; was accepted in 1 samples" in html
    assert "collision" in html and '<table class="forcelayout-summary">' in html


def test_repr_is_one_short_line():
    assert repr(run(3)) == "<Generation plan='den' seed=3 layouts=3/3 attempted=4 seconds=1.25>"


def test_a_thumbnail_is_a_small_png_without_checks(monkeypatch):
    def no_checks(*args, **kwargs):
        raise AssertionError("a thumbnail must not run the checks")

    monkeypatch.setattr("forcelayout.validate.check_layout", no_checks)
    png = render_module._thumbnail_png(layout(1), size=1.0, dpi=100)
    assert png.startswith(b"\x89PNG")
    width, height = int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")
    assert max(width, height) == 100 and width > height  # the room is wider than deep


SUMMARY = {"plan": "den", "seed": 0, "wanted": 4, "why": None, "valid_fraction": 0.75,
           "seconds": 1.5, "layouts_per_second": float("nan"), "feasibility_notes": [],
           "failure_reasons": {"collision": 2, "door": 1}}


def test_a_summary_is_still_a_json_ready_dict():
    s = Summary(SUMMARY)
    assert isinstance(s, dict) and s == SUMMARY and s["valid_fraction"] == 0.75
    assert json.loads(json.dumps(dict(s, layouts_per_second=0.0)))["plan"] == "den"
    s["rejected"] = [{"seed": 1, "failures": []}]  # as the command line adds
    assert "rejected" in str(s)


def test_str_of_a_summary_is_an_aligned_table():
    text = str(Summary(SUMMARY))
    lines = text.splitlines()
    assert [line.split()[0] for line in lines] == list(SUMMARY)
    column = {len(line) - len(line[line.index(" "):].lstrip()) for line in lines}
    assert len(column) == 1  # every value starts in the same column
    assert "valid_fraction      75.0%" in text
    assert "seconds             1.5 s" in text and "layouts_per_second  n/a" in text
    assert "why                 –" in text and "feasibility_notes   none" in text
    assert lines[-1].endswith("collision ×2, door ×1")


def test_long_values_wrap_under_their_column():
    s = Summary({"plan": "den", "why": "word " * 40})
    lines = str(s).splitlines()
    assert len(lines) > 2 and all(len(line) <= 88 for line in lines)
    assert all(line.startswith(" " * 6) for line in lines[2:])


def test_a_summary_shows_as_an_html_table_with_escaped_text():
    html = Summary({"plan": "<den>", "accepted": 2})._repr_html_()
    assert html.startswith('<table class="forcelayout-summary">')
    assert html.count("<tr>") == 2 and "&lt;den&gt;" in html and "<den>" not in html
