"""Top-down pictures of hand-built layouts."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import pytest
import shapely
from matplotlib.colors import to_rgba
from matplotlib.figure import Figure

from forcelayout import Layout, Plan, Pose
from forcelayout.render import draw_layout, draw_many, layout_svg
from forcelayout.validate import check_layout

PLAN = Plan.model_validate({
    "name": "studio",
    "room": {"polygon": [[0, 0], [4, 0], [4, 2.5], [2.5, 2.5], [2.5, 4], [0, 4]],
             "doors": [{"wall": 0, "offset": 2.8, "width": 0.9}],
             "windows": [{"wall": 4, "offset": 1.2, "width": 1.2}]},
    "areas": [{"name": "sleeping"}, {"name": "work"}],
    "objects": [
        {"id": "bed", "category": "bed", "size": [1.4, 2.0, 0.5], "area": "sleeping",
         "primary": True},
        {"id": "nightstand", "category": "nightstand", "size": [0.45, 0.4, 0.5],
         "area": "sleeping"},
        {"id": "lamp", "category": "lamp", "size": [0.2, 0.2, 0.4], "area": "sleeping"},
        {"id": "desk", "category": "desk", "size": [1.2, 0.6, 0.75], "area": "work",
         "primary": True},
        {"id": "chair", "category": "chair", "size": [0.5, 0.5, 0.9], "area": "work"},
        {"id": "painting", "category": "painting", "size": [0.8, 0.04, 0.6]},
        {"id": "light", "category": "ceiling_light", "size": [0.4, 0.4, 0.15]},
    ],
    "rules": [{"rule": "on_top", "object": "lamp", "target": "nightstand"},
              {"rule": "on_ceiling", "object": "light"}],
})
POSES = {
    "bed": Pose(0.7, 2.9, math.pi),
    "nightstand": Pose(1.65, 3.78, math.pi),
    "lamp": Pose(1.65, 3.78, 0.0, 0.5, "nightstand"),
    "desk": Pose(3.68, 1.5, math.pi / 2),
    "chair": Pose(3.0, 1.5, -math.pi / 2),
    "painting": Pose(0.02, 2.9, -math.pi / 2, 1.2, "wall:5"),
    "light": Pose(2.0, 2.0, 0.0, 2.55, "ceiling"),
}


def layout(**changes: Pose) -> Layout:
    return Layout(PLAN, {**POSES, **changes}, seed=3)


def test_png_is_written(tmp_path):
    out = tmp_path / "sub" / "studio.png"
    fig = draw_layout(layout(), out, show_free_space=True)
    assert isinstance(fig, Figure)
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(data) > 20_000


SMALL_ROOM = Plan.model_validate({
    "name": "wc",
    "room": {"polygon": [[0, 0], [2.5, 0], [2.5, 2.8], [0, 2.8]],
             "doors": [{"wall": 0, "offset": 0.6, "width": 0.8}]},
    "objects": [{"id": "basket", "category": "laundry_basket", "size": [0.4, 0.4, 0.6]},
                {"id": "mat", "category": "bath_mat", "size": [0.8, 0.5, 0.01]}]})


@pytest.mark.parametrize("make", [
    lambda: layout(),  # a valid layout
    # every object on one spot: a long list of failures runs past the figure's edge
    lambda: layout(**{k: Pose(1.0, 1.0, 0.0) for k in ("bed", "nightstand", "desk", "chair")}),
    # a small room's legend ends within the figure's last tenth of an inch: the margin
    # round the content runs past the canvas
    lambda: Layout(SMALL_ROOM, {"basket": Pose(2.2, 1.5, math.pi / 2),
                                "mat": Pose(1.2, 1.5, 0.0)}, seed=1),
])
def test_png_holds_what_a_tight_savefig_holds(tmp_path, make):
    # the picture is cropped to its content as savefig(bbox_inches="tight") crops it
    import numpy as np
    from PIL import Image

    lay = make()
    draw_layout(lay, tmp_path / "a.png")
    draw_layout(lay).savefig(tmp_path / "b.png", dpi=150, bbox_inches="tight")
    a, b = Image.open(tmp_path / "a.png"), Image.open(tmp_path / "b.png")
    assert abs(a.size[0] - b.size[0]) <= 3 and abs(a.size[1] - b.size[1]) <= 3
    w, h = min(a.size[0], b.size[0]), min(a.size[1], b.size[1])
    pa = np.asarray(a.convert("RGB"))[:h, :w].astype(int)
    pb = np.asarray(b.convert("RGB"))[:h, :w].astype(int)
    # the same drawing, up to a pixel's shift of the crop
    dark_a, dark_b = (pa.sum(-1) < 300).sum(), (pb.sum(-1) < 300).sum()
    assert abs(dark_a - dark_b) <= 0.02 * dark_b


def test_pdf_and_svg_follow_the_suffix(tmp_path):
    draw_layout(layout(), tmp_path / "a.pdf")
    assert (tmp_path / "a.pdf").read_bytes()[:5] == b"%PDF-"
    draw_layout(layout(), tmp_path / "a.svg")
    ET.fromstring((tmp_path / "a.svg").read_bytes())
    with pytest.raises(ValueError, match=".png"):
        draw_layout(layout(), tmp_path / "a.jpeg")


def test_svg_parses_and_names_every_object():
    svg = layout_svg(layout())
    root = ET.fromstring(svg.encode())
    assert root.tag.endswith("svg")
    for oid in PLAN.ids:
        assert oid in svg
    assert layout()._repr_svg_() == svg


def test_failures_are_listed_on_an_invalid_layout():
    bad = layout(chair=Pose(2.8, 0.5, 0.0))  # in the door's swing square
    svg = layout_svg(bad)
    assert "door: &#39;chair&#39; blocks" in svg or "door: 'chair' blocks" in svg
    assert "blocks" not in layout_svg(layout())


def test_free_space_overlay_changes_the_picture():
    plain = layout_svg(layout())
    shaded = layout_svg(layout(), show_free_space=True)
    assert "<image" in shaded and "<image" not in plain


def test_a_label_over_another_moves_down_a_line():
    """The lamp on the nightstand and the light over the desk: their labels stand below the
    labels of what they stand on or hang over, not on them (a new user's pendant over a
    table made both unreadable)."""
    fig = draw_layout(layout(light=Pose(3.68, 1.5, 0.0, 2.55, "ceiling")))
    at = {t.get_text(): t.get_position() for t in fig.axes[0].texts}
    for over, under in (("lamp", "nightstand"), ("light", "desk")):
        assert at[over][0] == pytest.approx(at[under][0])
        assert at[under][1] - at[over][1] == pytest.approx(0.11)
    # labels far apart stay at their objects' centres
    assert at["bed"] == pytest.approx((0.7, 2.9))


def test_a_label_at_the_bottom_wall_moves_up_not_out_of_the_room():
    """A vase on a sideboard against the bottom wall: its label would have moved down below
    the wall, out of the room; it moves up a line instead."""
    plan = Plan.model_validate({
        "name": "dining", "room": {"polygon": [[0, 0], [4, 0], [4, 3], [0, 3]]},
        "objects": [{"id": "sideboard", "category": "sideboard", "size": [1.6, 0.45, 0.85]},
                    {"id": "vase", "category": "vase", "size": [0.2, 0.2, 0.4]}],
        "rules": [{"rule": "on_top", "object": "vase", "target": "sideboard"}]})
    lay = Layout(plan, {"sideboard": Pose(2.0, 0.225, 0.0),
                        "vase": Pose(2.1, 0.225, 0.0, 0.85, "top:sideboard")})
    at = {t.get_text(): t.get_position() for t in draw_layout(lay).axes[0].texts}
    assert at["sideboard"] == pytest.approx((2.0, 0.225))
    assert at["vase"][1] == pytest.approx(0.225 + 0.11)


def test_draw_into_a_given_axes():
    fig = Figure()
    ax = fig.add_subplot(1, 2, 2)
    assert draw_layout(layout(), ax=ax, labels=False) is fig
    assert ax.get_title() == "studio · seed 3"
    assert not any(t.get_text() == "bed" for t in ax.texts)


def test_draw_many_contact_sheet(tmp_path):
    lays = [layout(), layout(chair=Pose(2.8, 0.5, 0.0)), layout()]
    fig = draw_many(lays, tmp_path / "sheet.png", cols=2)
    assert len([a for a in fig.axes if a.axison]) == 3
    assert (tmp_path / "sheet.png").read_bytes()[:4] == b"\x89PNG"
    with pytest.raises(ValueError, match="no layouts"):
        draw_many([])


def test_contact_sheet_titles_carry_the_checks_verdict():
    fig = draw_many([layout(), layout(chair=Pose(2.8, 0.5, 0.0))], cols=2)
    titles = [a.get_title() for a in fig.axes]
    assert titles[0].endswith("✓") and titles[1].endswith("✗")


def test_walkable_covers_are_drawn_first_and_hatched():
    data = PLAN.model_dump()
    data["objects"].append({"id": "rug", "category": "rug", "size": [1.6, 1.2, 0.01]})
    lay = Layout(Plan.model_validate(data), {**POSES, "rug": Pose(1.0, 2.4, 0.0)}, seed=3)
    svg = layout_svg(lay)
    ET.fromstring(svg)
    assert svg.index('id="walkable:rug"') < svg.index('id="object:bed"')  # beneath the bed
    assert 'id="object:rug"' not in svg
    assert "rug (walkable)" in svg  # the legend says so
    fig = draw_layout(lay)
    (cover,) = [p for p in fig.axes[0].patches if p.get_gid() == "walkable:rug"]
    bed = next(p for p in fig.axes[0].patches if p.get_gid() == "object:bed")
    assert cover.get_hatch() == "//" and cover.get_facecolor()[3] < 0.5
    assert cover.get_zorder() < bed.get_zorder()
    assert check_layout(lay).ok  # the bed stands on the rug: no collision


def test_access_zones_are_drawn_and_red_where_the_check_finds_none_free():
    def zones(lay):
        fig = draw_layout(lay, show_access=True)
        return {p.get_gid(): p for p in fig.axes[0].patches
                if (p.get_gid() or "").startswith("access:")}

    red = to_rgba("#d62728")[:3]
    # the chair stands in the desk's front zone, unrelated to it: the desk has no free side
    blocked = zones(layout())
    # the bed's right side faces the wall at x = 0: that zone lies wholly past it, not drawn
    assert set(blocked) == {"access:bed:left", "access:desk:front"}
    room = shapely.Polygon(PLAN.room.polygon)
    for patch in blocked.values():  # only the part of a zone on the floor
        assert room.buffer(1e-9).contains(shapely.Polygon(patch.get_xy()))
    assert tuple(blocked["access:desk:front"].get_edgecolor()[:3]) == pytest.approx(red)
    # the nightstand at the head of the bed leaves the rest of its free side
    assert tuple(blocked["access:bed:left"].get_edgecolor()[:3]) != pytest.approx(red)
    free = zones(layout(chair=Pose(1.8, 0.5, 0.0)))
    assert tuple(free["access:desk:front"].get_edgecolor()[:3]) != pytest.approx(red)
    assert "access zone" in layout_svg(layout(), show_access=True)
    # a contact sheet draws them too, and its ✓ / ✗ counts the access check
    fig = draw_many([layout(), layout(chair=Pose(1.8, 0.5, 0.0))], cols=2, show_access=True)
    assert [a.get_title()[-1] for a in fig.axes] == ["✗", "✓"]
    assert any((p.get_gid() or "").startswith("access:") for p in fig.axes[0].patches)
    # red also where the picture lists no failures (check=False): the zones run the check
    fig = draw_layout(layout(), show_access=True, check=False)
    (desk,) = [p for p in fig.axes[0].patches if p.get_gid() == "access:desk:front"]
    assert tuple(desk.get_edgecolor()[:3]) == pytest.approx(red)
    plain = draw_layout(layout())
    assert not [p for p in plain.axes[0].patches if (p.get_gid() or "").startswith("access:")]


def test_a_blocked_zone_beside_a_free_one_is_grey():
    """The bed's side by the wall is blocked, its other side free: grey, not red, and the
    legend says what each colour means."""
    lay = layout(bed=Pose(0.9, 2.9, math.pi), nightstand=Pose(1.85, 3.78, math.pi))
    fig = draw_layout(lay, show_access=True)
    edge = {p.get_gid(): p.get_edgecolor()[:3] for p in fig.axes[0].patches
            if (p.get_gid() or "").startswith("access:")}
    assert edge["access:bed:right"] == pytest.approx(to_rgba("#8c8c8c")[:3])
    assert edge["access:bed:left"] == pytest.approx(to_rgba("#1f77b4")[:3])
    assert edge["access:desk:front"] == pytest.approx(to_rgba("#d62728")[:3])
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert {"access zone", "access zone, blocked (another is free)",
            "access zone, no side free"} <= set(legend)
