"""Footprint geometry against shapely: the exact gap and the separating-axis clearance."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import forcelayout as fl
from forcelayout.geometry import (
    RoomGeometry,
    box_corners,
    box_gap,
    box_separation,
    box_sides,
    facing_point,
    front_vectors,
    obb_gap,
    right_vectors,
    toward_nearest,
    yaw_facing,
)

coord = st.floats(-3.0, 3.0, allow_nan=False)
extent = st.floats(0.05, 1.5, allow_nan=False)
angle = st.one_of(st.sampled_from([0.0, np.pi / 2, np.pi, -np.pi / 2]),
                  st.floats(-np.pi, np.pi, allow_nan=False))
box = st.tuples(coord, coord, angle, extent, extent)


def _corners(b: tuple[float, ...]) -> np.ndarray:
    x, y, yaw, w, d = b
    return box_corners(np.array([[x, y]]), np.array([yaw]), np.array([[w, d]]))[0]


@settings(max_examples=300, deadline=None)
@given(a=box, b=box)
def test_box_gap_is_the_distance_between_the_footprints(a, b):
    ca, cb = _corners(a), _corners(b)
    want = shapely.Polygon(ca).distance(shapely.Polygon(cb))
    assert abs(float(box_gap(ca, cb)) - want) < 1e-9
    sep = float(box_separation(ca, cb))
    if want > 1e-9:  # apart: the separating-axis clearance is a positive lower bound
        assert 0.0 < sep <= want + 1e-9
    if shapely.Polygon(ca).intersection(shapely.Polygon(cb)).area > 1e-9:
        assert sep < 0.0 and float(box_gap(ca, cb)) == 0.0


@settings(max_examples=50, deadline=None)
@given(boxes=st.lists(box, min_size=2, max_size=6))
def test_box_gap_broadcasts_pairwise(boxes):
    c = np.stack([_corners(b) for b in boxes])
    table = box_gap(c[:, None], c[None])
    sep = box_separation(c[:, None], c[None])
    assert table.shape == sep.shape == (len(boxes), len(boxes))
    for i in range(len(boxes)):
        for j in range(len(boxes)):
            assert table[i, j] == box_gap(c[i], c[j])
            assert sep[i, j] == box_separation(c[i], c[j])


@settings(max_examples=300, deadline=None)
@given(a=box, b=box)
def test_obb_gap_is_box_gap_from_the_axes(a, b):
    """The fast form from centres, axes and half extents, against the corners' form."""
    ca, cb = _corners(a), _corners(b)
    ya, yb = np.array([a[2]]), np.array([b[2]])
    got = obb_gap(np.array([[b[0] - a[0], b[1] - a[1]]]), right_vectors(ya), front_vectors(ya),
                  np.array([[a[3], a[4]]]), right_vectors(yb), front_vectors(yb),
                  np.array([[b[3], b[4]]]))[0]
    want = float(box_gap(ca, cb))
    assert abs(got - want) < 1e-9
    if shapely.Polygon(ca).intersection(shapely.Polygon(cb)).area > 1e-9:
        assert got == 0.0


def _axes_of(boxes: list[tuple[float, ...]]) -> tuple[np.ndarray, ...]:
    b = np.array(boxes, dtype=float).reshape(-1, 5)
    yaw = b[:, 2]
    return b[:, :2], right_vectors(yaw), front_vectors(yaw), b[:, 3:]


_CALL_EVERY_KERNEL = """
import numpy as np
from forcelayout._compiled import kernels
k = kernels()
assert k is not None
v = np.random.default_rng(0).random((7, 5, 2))
walls = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 3.0], [0.0, 3.0]])
ends = np.roll(walls, -1, axis=0)
normal = np.array([[0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [1.0, 0.0]])
k.obb_separation(*v)
k.obb_gap(*v)
k.contains_points(3.0 * v[0], walls, ends)
k.contains_boxes(3.0 * v[:, :4], walls, ends, normal)
x = np.linspace(0.0, 1.0, 4, dtype=np.float32)
k.footprint_dist2(x, x, x[:1], x[:1], x[:1], x[:1], x[:1], x[:1])
print("ok")
"""


def test_compiled_kernels_load_whole_after_processes_compiled_them_at_once(tmp_path):
    """Processes that compile the kernels at once into an empty cache (a pool's workers on
    a fresh install) leave a cache every later process loads and calls: without the lock
    they compile under, numba could pair one process's kernel with another's wrapper and
    every later call crashed the process (three processes at once, about one time in four)."""
    import os
    import subprocess
    import sys

    pytest.importorskip("numba")
    from forcelayout import _compiled

    for trial in range(4):  # the race, without the lock, struck one trial in four or five
        env = {**os.environ, _compiled.ENV: "1",
               "NUMBA_CACHE_DIR": str(tmp_path / f"cache{trial}")}
        runs = [subprocess.Popen([sys.executable, "-c", _CALL_EVERY_KERNEL], env=env,
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                for _ in range(3)]
        for run in runs:
            out, err = run.communicate(timeout=900)
            assert run.returncode == 0 and out.strip() == "ok", err[-2000:]
        later = subprocess.run([sys.executable, "-c", _CALL_EVERY_KERNEL], env=env,
                               capture_output=True, text=True, timeout=900)
        assert later.returncode == 0 and later.stdout.strip() == "ok", later.stderr[-2000:]


@settings(max_examples=100, deadline=None)
@given(boxes=st.lists(box, min_size=1, max_size=7), others=st.lists(box, min_size=1, max_size=5))
def test_compiled_kernels_equal_the_numpy_forms_bit_for_bit(boxes, others):
    """With numba (forcelayout[fast]) the kernels give the numpy forms' values exactly, on
    broadcast views as the callers pass them (candidates x placed objects)."""
    pytest.importorskip("numba")
    from forcelayout import _compiled
    from forcelayout import geometry as geo

    fast = _compiled.kernels()
    assert fast is not None
    pa, ra, fa, ha = _axes_of(boxes)
    pb, rb, fb, hb = _axes_of(others)
    args = (pb[None] - pa[:, None], ra[:, None], fa[:, None], ha[:, None], rb[None], fb[None],
            hb[None])
    for name in ("obb_separation", "obb_gap"):
        want = getattr(geo, "_" + name)(*args)
        got = getattr(fast, name)(*args)
        assert got.shape == want.shape == (len(boxes), len(others))
        assert np.array_equal(got, want), name
        assert np.array_equal(getattr(geo, name)(*args), want)  # the public form uses them


def test_the_compiled_kernels_switch_off_and_layouts_do_not_change():
    """FORCELAYOUT_COMPILED=0 runs the numpy forms; the layouts are the same bit for bit (on
    a rectangular floor and an L-shaped one)."""
    import json
    import os
    import subprocess
    import sys

    pytest.importorskip("numba")
    code = ("import json, forcelayout as fl; from forcelayout import _compiled;"
            "ls = [l for p in ('living_room', 'l_shaped_studio')"
            " for l in fl.sampling.solve_many(fl.load_plan(p), [1, 2, 3])];"
            "print(json.dumps([_compiled.kernels() is not None,"
            " [l.to_dict()['objects'] for l in ls]]))")
    out = {}
    for flag in ("1", "0"):
        env = {**os.environ, "FORCELAYOUT_COMPILED": flag}
        run = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                             text=True, check=True)
        out[flag] = json.loads(run.stdout)
    assert out["1"][0] is True and out["0"][0] is False
    assert out["1"][1] == out["0"][1]


@given(angle, extent, extent)
def test_box_sides_run_from_corner_to_corner_front_right_back_left(yaw, w, d):
    half = np.array([w, d])
    right, front = right_vectors(np.array([yaw]))[0], front_vectors(np.array([yaw]))[0]
    normals, axes, lengths, depths = box_sides(right, front, half)
    corners = box_corners(np.zeros((1, 2)), np.array([yaw]), half[None])[0]
    for k in range(4):
        for sign in (-1.0, 1.0):  # each side's two ends are two corners of the box
            end = normals[k] * depths[k] + sign * axes[k] * lengths[k]
            assert np.min(np.hypot(*(corners - end).T)) < 1e-9
    # in order front, right, back, left (the side a child of this box starts at)
    np.testing.assert_allclose(normals @ front, [1.0, 0.0, -1.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(normals @ right, [0.0, 1.0, 0.0, -1.0], atol=1e-12)


def test_contains_boxes_takes_a_box_as_wide_as_the_room_and_no_box_a_wall_crosses():
    u_room = RoomGeometry(np.array([[0, 0], [6, 0], [6, 4.8], [3.8, 4.8], [3.8, 3.6],
                                    [2.2, 3.6], [2.2, 4.8], [0, 4.8]], dtype=float))

    def box(x0, y0, x1, y1):
        return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=float)

    boxes = np.stack([box(3.8, 3.9, 6.0, 4.79),   # fills the right arm wall to wall
                      box(0.0, 3.9, 2.2, 4.79),   # and the left one
                      box(1.0, 3.8, 5.0, 4.5),    # over the notch, every corner on the floor
                      box(1.0, 1.0, 5.0, 3.0),    # in the middle
                      box(-0.1, 1.0, 1.0, 2.0)])  # through a wall
    assert u_room.contains_boxes(boxes).tolist() == [True, True, False, True, False]
    assert u_room.contains_boxes(boxes[None]).shape == (1, 5)


_FLOORS = [np.array(p, dtype=float) for p in (
    [[0, 0], [6, 0], [6, 4.8], [3.8, 4.8], [3.8, 3.6], [2.2, 3.6], [2.2, 4.8], [0, 4.8]],
    [[0, 0], [5, 0], [5, 3], [2.5, 3], [2.5, 5.5], [0, 5.5]],
    [[0, 0], [4, 0], [4.5, 2.0], [2.0, 3.5], [0, 3.0]])]
# footprints on a 5 cm grid at square turns: many touch a wall or a corner exactly
snapped = st.tuples(st.integers(-10, 130), st.integers(-10, 120), st.integers(-2, 2),
                    st.integers(1, 40), st.integers(1, 40))


@settings(max_examples=150, deadline=None)
@given(floor=st.sampled_from(range(len(_FLOORS))),
       boxes=st.lists(st.one_of(box, snapped), min_size=1, max_size=8))
def test_contains_boxes_is_shapely_contains_but_for_touching_within_a_nanometre(floor, boxes):
    """On L- and U-shaped and slanted floors: the numpy form and the compiled kernel (with
    forcelayout[fast]) agree exactly, and both with ``shapely.contains`` except for a
    footprint that crosses a wall by at most 1e-9 m."""
    from forcelayout import _compiled
    from forcelayout import geometry as geo

    room = RoomGeometry(_FLOORS[floor])
    c = np.stack([_corners(b) if isinstance(b[0], float)
                  else _corners((0.05 * b[0], 0.05 * b[1], 0.5 * np.pi * b[2], 0.025 * b[3],
                                 0.025 * b[4])) for b in boxes])
    want = geo._contains_boxes(c, room.a, room.b, room.normal)
    assert np.array_equal(room.contains_boxes(c), want)
    fast = _compiled.kernels()
    if fast is not None:
        assert np.array_equal(fast.contains_boxes(c[None], room.a, room.b, room.normal),
                              want[None])
    polys = shapely.polygons(c)
    exact = shapely.contains(room.shape, polys)
    for k in np.flatnonzero(exact != want):
        assert shapely.area(shapely.difference(polys[k], room.shape)) < 1e-8
        assert shapely.distance(shapely.boundary(room.shape), polys[k]) < 1e-8


@settings(max_examples=150, deadline=None)
@given(floor=st.sampled_from(range(len(_FLOORS))),
       points=st.lists(st.one_of(st.tuples(st.floats(-1, 7), st.floats(-1, 6)),
                                 st.tuples(st.integers(-10, 130), st.integers(-10, 120)).map(
                                     lambda ij: (0.05 * ij[0], 0.05 * ij[1]))),
                       min_size=1, max_size=12))
def test_contains_points_is_the_same_in_numpy_and_compiled(floor, points):
    """Points on L- and U-shaped and slanted floors, many on a wall or at a corner (a 5 cm
    grid): the compiled kernel (with forcelayout[fast]) agrees with the numpy form exactly,
    and both with ``shapely.contains`` off the walls."""
    from forcelayout import _compiled
    from forcelayout import geometry as geo

    room = RoomGeometry(_FLOORS[floor])
    p = np.array(points, dtype=float)
    want = geo._contains_points(p, room.a, room.b)
    assert np.array_equal(room.contains(p), want)
    assert room.contains(p[0]).shape == () and room.contains(p[None]).shape == (1, len(p))
    fast = _compiled.kernels()
    if fast is not None:
        assert np.array_equal(fast.contains_points(p, room.a, room.b), want)
    pts = shapely.points(p)
    off = shapely.distance(shapely.boundary(room.shape), pts) > 1e-9
    assert np.array_equal(want[off], shapely.contains(room.shape, pts)[off])


@given(st.floats(-np.pi + 1e-6, np.pi, allow_nan=False))
def test_yaw_facing_inverts_front_vectors(yaw):
    assert np.isclose(yaw_facing(front_vectors(yaw) * 2.5), yaw)


def test_toward_nearest_points_at_the_nearest_centre():
    centres = np.array([[0.0, 0.0], [4.0, 0.0]])
    points = np.array([[[1.0, 1.0], [3.0, -1.0]], [[2.5, 0.0], [-1.0, 0.0]]])  # (2, 2, 2)
    got = toward_nearest(points, centres)
    assert got.shape == points.shape
    assert np.allclose(got, [[[-1.0, -1.0], [1.0, 1.0]], [[1.5, 0.0], [1.0, 0.0]]])
    # a point turned by yaw_facing of it faces that centre
    assert np.allclose(front_vectors(yaw_facing(got[0, 0])), got[0, 0] / np.sqrt(2.0))


def test_openings_centres_are_every_one_or_the_one_picked():
    room = RoomGeometry.from_room(fl.Plan.from_dict({
        "name": "hall", "room": {"polygon": [[0, 0], [4, 0], [4, 3], [0, 3]],
                                 "doors": [{"wall": 0, "offset": 1.0}, {"wall": 2, "offset": 2.5}]},
        "objects": [{"id": "box", "category": "box", "size": [0.5, 0.5, 0.5]}]}).room)
    doors = room.doors
    assert np.allclose(doors.centres(), doors.centre)
    assert np.allclose(doors.centres(1), doors.centre[[1]])
    assert np.allclose(doors.centres(2), doors.centre)  # past the last: every one


def test_openings_zones_are_boxes_in_front_as_wide_as_each_opening():
    room = RoomGeometry.from_room(fl.Plan.from_dict({
        "name": "hall", "room": {"polygon": [[0, 0], [4, 0], [4, 3], [0, 3]],
                                 "windows": [{"wall": 0, "offset": 1.0, "width": 1.2},
                                             {"wall": 1, "offset": 1.5, "width": 0.8}]},
        "objects": [{"id": "box", "category": "box", "size": [0.5, 0.5, 0.5]}]}).room)
    w = room.windows
    centre, half = w.zones(0.5)  # one depth for all
    assert np.allclose(centre, [[1.0, 0.25], [3.75, 1.5]])
    assert np.allclose(half, [[0.6, 0.25], [0.4, 0.25]])
    centre, half = w.zones(np.array([0.5, 1.0]))  # one per window
    assert np.allclose(centre[1], [3.5, 1.5]) and np.allclose(half[:, 1], [0.25, 0.5])
    centre, half = w.zones(np.array([[0.2, 0.6, 1.0]]))  # one per item, for every window
    assert centre.shape == half.shape == (2, 3, 2)
    assert np.allclose(half[:, :, 1], [[0.1, 0.3, 0.5]] * 2)
    assert np.allclose(half[:, :, 0], [[0.6] * 3, [0.4] * 3])
    assert np.allclose(centre[0, 2], [1.0, 0.5])


@settings(max_examples=60, deadline=None)
@given(box, coord, coord)
def test_facing_point_is_the_nearest_point_of_the_rectangle_or_its_centre(b, px, py):
    """Outside the rectangle, what an object faces is the footprint's point nearest it
    (shapely's distance to it is the distance to that point); inside, the centre."""
    x, y, yaw, w, d = b
    rgt, fwd = right_vectors(np.array(yaw)), front_vectors(np.array(yaw))
    half = np.array([w, d]) / 2
    p = np.array([px, py])
    aim = facing_point(p, np.array([x, y]), rgt, fwd, half)
    poly = shapely.Polygon(box_corners(np.array([[x, y]]), np.array([yaw]), half[None])[0])
    assume(poly.exterior.distance(shapely.Point(p)) > 1e-6)  # not on the edge itself
    if poly.contains(shapely.Point(p)):
        np.testing.assert_allclose(aim, [x, y])
    else:
        assert np.hypot(*(aim - p)) == pytest.approx(poly.distance(shapely.Point(p)), abs=1e-6)
    # a batch broadcasts: the same point for every row
    many = facing_point(np.tile(p, (3, 1)), np.array([x, y]), rgt, fwd, half)
    np.testing.assert_allclose(many, np.tile(aim, (3, 1)))


def test_rays_to_walls_meet_the_first_wall_in_front():
    from forcelayout.geometry import RoomGeometry, rays_to_walls

    room = RoomGeometry([(0, 0), (4, 0), (4, 3), (0, 3)])
    points = np.array([[1.0, 1.0], [1.0, 1.0], [5.0, 1.0]])
    directions = np.array([[1.0, 0.0], [0.0, -1.0], [1.0, 0.0]])
    wall, along, dist = rays_to_walls(room, points, directions)
    assert wall.tolist() == [1, 0, -1]  # the right wall, the bottom wall, none (outside)
    assert np.allclose(dist[:2], [3.0, 1.0]) and np.isinf(dist[2])
    hit = room.a[wall[:2]] + room.tangent[wall[:2]] * along[:2, None]
    assert np.allclose(hit, [[4.0, 1.0], [1.0, 0.0]])
