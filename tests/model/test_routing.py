"""Routing by segments (straights and circular bends): nodes on the exact arcs, exact arc length
and curvature; the geometry summary, its plausibility warnings and ``cablecasing geometry``."""

import copy
import json

import numpy as np
import pytest

from cablecasing_core import ModelError, load_model, model_from_dict
from cablecasing_core.cli import main
from cablecasing_core.structure.geometry import centerline_of
from cablecasing_core.structure.route_summary import geometry_summary, plausibility_warnings

# the S-route: 0.15 m straight, 60 deg of R 0.15 towards +y, 0.15 m, 60 deg of R 0.2 towards +z, 0.316 m
SEGMENTS = [
    {"straight": 0.15},
    {"bend": {"radius": 0.15, "angle_deg": 60, "toward": [0, 1, 0]}},
    {"straight": 0.15},
    {"bend": {"radius": 0.20, "angle_deg": 60, "toward": [0, 0, 1]}},
    {"straight": 0.316},
]
LENGTH = 0.15 + 0.15 * np.pi / 3 + 0.15 + 0.20 * np.pi / 3 + 0.316  # m, exact


def routed(segments=SEGMENTS, n=70, **geometry):
    base = copy.deepcopy(load_model().data)
    g = {"n_elements": n, "segments": copy.deepcopy(segments), **geometry}
    return model_from_dict({**base, "geometry": g})


def bend_data():
    """Centre, plane normal, radius, start and end arc length of both bends, by hand (closed form)."""
    c60, s60 = 0.5, np.sqrt(3) / 2
    c1 = np.array([0.15, 0.15, 0.0])  # first bend: start (0.15, 0, 0), inward normal +y
    p2 = np.array([0.15 + 0.15 * s60, 0.15 * (1 - c60), 0.0]) + 0.15 * np.array([c60, s60, 0.0])
    c2 = p2 + 0.20 * np.array([0.0, 0.0, 1.0])  # second bend: tangent (c60, s60, 0), inward normal +z
    s1 = 0.15
    s2 = s1 + 0.15 * np.pi / 3 + 0.15
    return [
        (c1, np.array([0, 0, 1.0]), 0.15, s1, s1 + 0.15 * np.pi / 3),
        (c2, np.array([s60, -c60, 0.0]), 0.20, s2, s2 + 0.20 * np.pi / 3),
    ]


def test_nodes_on_the_exact_arcs_with_exact_length_and_curvature():
    cl = centerline_of(routed())
    # arc length: exact (equal arcs of L / n), to round-off
    assert cl.length == pytest.approx(LENGTH, rel=1e-14)
    np.testing.assert_allclose(np.diff(cl.s), LENGTH / 70, rtol=1e-12)
    inside_any = np.zeros(len(cl.s), bool)
    for centre, normal, R, s0, s1 in bend_data():
        inside = (cl.s > s0 + 1e-12) & (cl.s < s1 - 1e-12)
        assert inside.sum() >= 5
        inside_any |= inside
        d = cl.nodes[inside] - centre
        # on the circle: radius error below 1e-9 m (round-off is ~1e-16 m), in the bend's plane
        assert np.abs(np.linalg.norm(d, axis=1) - R).max() < 1e-9
        assert np.abs(d @ normal).max() < 1e-9
        # the curvature carried by the nodes is 1/R, and so is the circle through three consecutive nodes
        np.testing.assert_allclose(cl.curvature[inside], 1.0 / R, rtol=1e-14)
        a, b, c = cl.nodes[inside][:-2], cl.nodes[inside][1:-1], cl.nodes[inside][2:]
        ab, bc, ca = (np.linalg.norm(x, axis=1) for x in (b - a, c - b, a - c))
        area2 = np.linalg.norm(np.cross(b - a, c - a), axis=1)
        np.testing.assert_allclose(ab * bc * ca / (2 * area2), R, rtol=1e-9)  # circumradius
        # tangents: unit and normal to the radius
        t = cl.tangents[inside]
        assert np.abs(np.einsum("ij,ij->i", t, d)).max() < 1e-12
    # straights: no curvature, nodes on the lines through the junctions
    assert np.all(cl.curvature[~inside_any & (cl.s < 0.15 - 1e-12)] == 0.0)
    np.testing.assert_allclose(cl.nodes[cl.s < 0.15 - 1e-12][:, 1:], 0.0, atol=1e-15)


def test_route_is_tangent_continuous_and_ends_where_the_closed_form_says():
    cl = centerline_of(routed(n=700))
    # chord directions turn by at most the angle of one element on the tightest bend
    x = cl.frames[:, 0]
    turn = np.arccos(np.clip(np.einsum("ij,ij->i", x[:-1], x[1:]), -1, 1))
    assert turn.max() <= (LENGTH / 700) / 0.15 * (1 + 1e-9)
    _, normal2, R2, _, _ = bend_data()[1]
    centre2 = bend_data()[1][0]
    t_end = np.array([0.5, np.sqrt(3) / 2, 0.0]) * 0.5 + np.array([0, 0, 1.0]) * np.sqrt(3) / 2  # cos60 t + sin60 z
    end = centre2 - R2 * np.array([0, 0, 1.0]) * 0.5 + R2 * np.sqrt(3) / 2 * np.array([0.5, np.sqrt(3) / 2, 0.0])
    np.testing.assert_allclose(cl.nodes[-1], end + 0.316 * t_end, atol=1e-12)
    np.testing.assert_allclose(cl.tangents[-1], t_end, atol=1e-12)


def test_summary_of_segments_and_of_points():
    g = geometry_summary(routed())
    assert g["length_m"] == pytest.approx(LENGTH, rel=1e-14)
    assert g["min_radius_m"] == 0.15 and g["min_radius_at_m"] == 0.15
    assert g["total_bend_deg"] == pytest.approx(120.0, rel=1e-12)
    assert [b["radius_m"] for b in g["bends"]] == [0.15, 0.20]
    assert g["bends"][1]["start_m"] == pytest.approx(0.30 + 0.15 * np.pi / 3, rel=1e-14)
    assert g["gap_m"] == pytest.approx(0.0005)
    # the built-in specimen's points sample the same kind of route (0.15 m, 60 deg of R 0.15, 0.15 m,
    # 60 deg of R 0.2): its spline's bends are found near them (the spline smooths the corners of the
    # curvature, so the angles and radii are within 10 % and 20 %), and it overshoots to a smaller radius
    p = geometry_summary(load_model())
    assert p["source"] == "spline" and len(p["bends"]) == 2
    np.testing.assert_allclose([b["angle_deg"] for b in p["bends"]], 60.0, rtol=0.1)
    np.testing.assert_allclose([b["radius_m"] for b in p["bends"]], [0.15, 0.20], rtol=0.2)
    assert p["min_radius_m"] < 0.15
    assert p["total_bend_deg"] == pytest.approx(120.0, rel=0.1)


def test_plausibility_warnings():
    quiet = routed(n=700)
    assert plausibility_warnings(quiet) == []
    coarse = routed(n=20)
    assert any("tenth of the shortest bend" in w for w in plausibility_warnings(coarse))
    mm = routed([{"straight": 600.0}, {"bend": {"radius": 150.0, "angle_deg": 90, "toward": [0, 1, 0]}}], n=40)
    assert any("more than 10 m" in w and "mm" in w for w in plausibility_warnings(mm))
    # 8.9 mm long; the bend's 5 mm radius just clears the casing's 4.75 mm outer radius
    tiny = routed([{"straight": 0.001}, {"bend": {"radius": 0.005, "angle_deg": 90, "toward": [0, 1, 0]}}], n=40)
    w = plausibility_warnings(tiny)
    assert any("less than 1 cm" in x for x in w) and any("ten casing diameters" in x for x in w)
    base = copy.deepcopy(load_model().data)
    kinked = model_from_dict(
        {**base, "geometry": {"points": [[0, 0, 0], [0.5, 0, 0], [0.5, 0.5, 0]], "curve": "polyline", "n_elements": 20}}
    )
    assert any("kink of 90 deg at s = 0.5 m" in x for x in plausibility_warnings(kinked))


def test_a_polyline_through_a_finely_sampled_arc_is_summarised_as_that_arc():
    """Points on a 90 deg arc of R = 0.02 m (two casing diameters) every 0.9 deg, between two
    straights, joined by a polyline: no corner is a kink (each turns by 0.9 deg), yet the route
    bends by 90 deg (the sum of its corners, exactly: the first and last chords lie along the
    straights) with the arc's radius (a corner's mean chord over its angle is 2 R sin(a/2) / a =
    R (1 - a^2/24), within 1e-5 of R), below ten casing diameters: warned."""
    R, step = 0.02, 0.9
    th = np.radians(np.arange(0.0, 90.0 + 1e-9, step))
    P = np.column_stack([R * np.sin(th), R * (1 - np.cos(th)), 0 * th])
    P = np.vstack([[-0.2, 0, 0], P, P[-1] + [0, 0.2, 0]]).tolist()
    base = copy.deepcopy(load_model().data)
    m = model_from_dict({**base, "geometry": {"points": P, "curve": "polyline", "n_elements": 100}})
    g = geometry_summary(m)
    assert g["bends"] == [] and g["total_bend_deg"] == pytest.approx(90.0, rel=1e-12)
    assert g["min_radius_m"] == pytest.approx(R, rel=1e-4)
    d = base["casing"]["d_outer"]
    assert any("radius of 0.02 m" in w and f"({10 * d:.4g} m)" in w for w in plausibility_warnings(m))


def test_a_spline_bend_is_warned_by_its_smallest_radius_not_its_mean():
    """A bend whose curvature ramps linearly to 1/0.07 1/m and back (clothoid in and out, 163.7
    deg): its mean radius (0.123 m) is above ten casing diameters (0.095 m), its smallest (0.07 m,
    at its middle) below: the bend reports both and the warning names the smallest."""
    ds = 1e-4
    s = np.arange(0, 0.8 + ds, ds)
    kpk = 1 / 0.07
    k = np.where(s < 0.2, 0, np.where(s < 0.4, kpk * (s - 0.2) / 0.2, np.where(s < 0.6, kpk * (0.6 - s) / 0.2, 0)))
    ang = np.concatenate([[0], np.cumsum(0.5 * (k[1:] + k[:-1]) * ds)])
    t = np.column_stack([np.cos(ang), np.sin(ang)])
    xy = np.concatenate([[[0, 0]], np.cumsum(ds * 0.5 * (t[1:] + t[:-1]), axis=0)])
    P = np.column_stack([xy, 0 * s])[::40]
    base = copy.deepcopy(load_model().data)
    m = model_from_dict({**base, "geometry": {"points": P.tolist(), "n_elements": 200}})
    (b,) = geometry_summary(m)["bends"]
    assert b["min_radius_m"] == pytest.approx(0.07, rel=2e-3)  # (the spline through points 4 mm apart)
    assert b["radius_m"] > 10 * base["casing"]["d_outer"]
    assert any("smallest radius" in w and "of 0.06998 m" in w for w in plausibility_warnings(m))


def test_a_polyline_through_an_arc_warns_once_and_a_dictionary_warns_as_a_file():
    # 30 points on a quarter circle of 1 m: 28 corners of 90/29 = 3.1 deg, said in one line
    from cablecasing_core.errors import PlausibilityWarning

    th = np.linspace(0.0, np.pi / 2, 30)
    pts = [[float(np.cos(t)), float(np.sin(t)), 0.0] for t in th]
    base = copy.deepcopy(load_model().data)
    with pytest.warns(PlausibilityWarning) as record:
        model_from_dict({**base, "geometry": {"points": pts, "curve": "polyline", "n_elements": 40}})
    kinks = [str(w.message) for w in record if "kink" in str(w.message)]
    assert len(kinks) == 1 and "28 kinks, of 3.1 to 3.1 deg" in kinks[0]


@pytest.mark.parametrize(
    "geometry, key, words",
    [
        ({"segments": "straight"}, "geometry.segments", "a list of"),
        ({"segments": []}, "geometry.segments", "a list of"),
        ({"segments": [{"arc": 1.0}]}, "geometry.segments[0]", "straight = L_m"),
        ({"segments": [{"straight": -0.1}]}, "geometry.segments[0].straight", "[1e-06, 1000]"),
        # beyond the points' +-1000 m: 1e300 m overflowed the element matrices into warnings and a
        # meaningless clip error
        ({"segments": [{"straight": 1e300}]}, "geometry.segments[0].straight", "[1e-06, 1000]"),
        ({"segments": [{"bend": {"radius": 2e3, "angle_deg": 30, "toward": [0, 1, 0]}}]}, "radius", "[1e-06, 1000]"),
        # a centerline radius at or below the casing's outer radius (4.75 mm) folds the casing onto itself
        (
            {"segments": [{"bend": {"radius": 0.004, "angle_deg": 30, "toward": [0, 1, 0]}}]},
            "geometry.segments[0].bend.radius",
            "casing.d_outer / 2 = 0.00475 m",
        ),
        # components whose squares underflow (or overflow) have no direction in double precision
        (
            {"segments": [{"bend": {"radius": 0.1, "angle_deg": 30, "toward": [0, 1e-170, 0]}}]},
            "geometry.segments[0].bend.toward",
            "positive finite number (it is 0)",
        ),
        ({"segments": SEGMENTS, "direction": [1e200, 1e200, 0]}, "geometry.direction", "(it is inf)"),
        ({"segments": SEGMENTS, "start": [1e9, 0, 0]}, "geometry.start", "within +-1000"),
        ({"segments": [{"bend": {"radius": 0.1, "angle_deg": 30}}]}, "geometry.segments[0].bend", "toward"),
        ({"segments": [{"bend": {"radius": 0.0, "angle_deg": 30, "toward": [0, 1, 0]}}]}, "radius", "[1e-06, 1000]"),
        ({"segments": [{"bend": {"radius": 0.1, "angle_deg": 360, "toward": [0, 1, 0]}}]}, "angle_deg", "(0, 360)"),
        # a bend shorter than a straight may be: no arc to mesh (`geometry` overflowed on 5e-324 deg)
        (
            {"segments": [{"straight": 0.3}, {"bend": {"radius": 0.1, "angle_deg": 5e-324, "toward": [0, 1, 0]}}]},
            "geometry.segments[1].bend.angle_deg",
            "gives an arc of 0 m with radius 0.1 m: a bend's arc must be at least 1e-06 m",
        ),
        (
            {"segments": [{"bend": {"radius": 0.1, "angle_deg": 30, "toward": [2, 0, 0]}}]},
            "toward",
            "leave the tangent",
        ),
        ({"segments": [{"bend": {"radius": 0.1, "angle_deg": 30, "toward": [0, 0, 0]}}]}, "toward", "not all zero"),
        ({"segments": SEGMENTS, "direction": [0, 0, 0]}, "geometry.direction", "not all zero"),
        ({"segments": SEGMENTS, "start": [0, 0]}, "geometry.start", "[x, y, z]"),
        (
            {"segments": SEGMENTS, "points": [[0, 0, 0], [1, 0, 0]]},
            "geometry.segments",
            "by points or by segments, not both",
        ),
        ({}, "geometry", "needs geometry.points (a curve through points) or geometry.segments"),
        ({"points": [[0, 0, 0], [1, 0, 0]], "start": [0, 0, 0]}, "geometry.start", "segments"),
    ],
)
def test_bad_routes_name_key_value_and_what_is_allowed(geometry, key, words):
    base = copy.deepcopy(load_model().data)
    with pytest.raises(ModelError) as e:
        model_from_dict({**base, "geometry": geometry})
    assert key in e.value.key and words in str(e.value)


def test_a_second_bend_toward_its_own_tangent_is_refused():
    # after 90 deg towards +y the tangent is +y: a bend 'toward' +y then has no direction to turn to
    segs = [
        {"bend": {"radius": 0.1, "angle_deg": 90, "toward": [0, 1, 0]}},
        {"bend": {"radius": 0.1, "angle_deg": 30, "toward": [0, 1, 0]}},
    ]
    with pytest.raises(ModelError, match=r"geometry.segments\[1\].bend.toward.*leave the tangent"):
        routed(segs)


def test_round_trip_through_toml(tmp_path):
    m = routed()
    p = tmp_path / "m.toml"
    p.write_text(m.to_toml())
    assert load_model(p).data == m.data


def test_cli_geometry_json_plot_and_warnings(tmp_path, capsys):
    p = tmp_path / "route.toml"
    p.write_text(routed(n=20).to_toml())
    png = tmp_path / "route.png"
    assert main(["geometry", str(p), "--json", "--plot", str(png)]) == 0
    cap = capsys.readouterr()
    out = json.loads(cap.out)
    assert set(out) == {
        "length_m",
        "min_radius_m",
        "min_radius_at_m",
        "total_bend_deg",
        "gap_m",
        "element_length_m",
        "element_length_min_m",
        "element_length_max_m",
        "bends",
        "clips",
        "buckling",
        "band_advice",
        "band_advice_why",
    }
    assert out["clips"] == []  # (no clip on this route)
    assert out["buckling"]["casing"]["load_N"] > 0 and out["buckling"]["casing"]["supports"] == "A clamped; B clamped"
    assert out["length_m"] == pytest.approx(LENGTH, rel=1e-14)
    assert out["element_length_m"] == pytest.approx(LENGTH / 20, rel=1e-14)
    # (equal elements: the nodes at LENGTH k / 20, each element LENGTH / 20 to rounding)
    assert out["element_length_min_m"] == pytest.approx(LENGTH / 20, rel=1e-12)
    assert out["element_length_max_m"] == pytest.approx(LENGTH / 20, rel=1e-12)
    assert out["bends"][0] == {"start_m": 0.15, "radius_m": 0.15, "min_radius_m": 0.15, "angle_deg": 60.0}
    assert "warning: the elements" in cap.err
    assert png.stat().st_size > 10_000
    assert main(["geometry"]) == 0
    text = capsys.readouterr().out
    assert "routing (spline) of <built-in>" in text
    assert "buckling          casing: buckles under a compression of 54.72 N, its mode largest at s = " in text


def test_loading_a_file_warns_of_a_likely_mistake(tmp_path):
    from cablecasing_core.errors import PlausibilityWarning

    mm = routed([{"straight": 600.0}, {"bend": {"radius": 150.0, "angle_deg": 90, "toward": [0, 1, 0]}}], n=40)
    p = tmp_path / "mm.toml"
    p.write_text(mm.to_toml())
    with pytest.warns(PlausibilityWarning, match="more than 10 m: are the segments' lengths and radii in mm"):
        load_model(p)
    # the same route by its points (a polyline): the points are named (review AN: a file of segments
    # was asked about its points, which it has none of)
    points = [[0.0, 0.0, 0.0], [600.0, 0.0, 0.0], [600.0, 150.0, 0.0]]
    mm_points = model_from_dict({**copy.deepcopy(load_model().data), "geometry": {"n_elements": 40, "points": points}})
    p.write_text(mm_points.to_toml())
    with pytest.warns(PlausibilityWarning, match="more than 10 m: are the points in mm"):
        load_model(p)
    coarse = tmp_path / "coarse.toml"  # the element-length advice is cablecasing geometry's, not the loader's
    coarse.write_text(routed(n=20).to_toml())
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_model(coarse)


def test_cli_geometry_names_the_node_each_clip_acts_at(capsys):
    """A clip acts at the node nearest to its ``at``: `geometry` says which, in the text and the JSON
    (the installation example: 64 elements of 15.35 mm, so each node within half an element of it,
    and the nearest of the route's nodes)."""
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "examples" / "installation.toml"
    assert main(["geometry", str(path), "--json"]) == 0
    clips = json.loads(capsys.readouterr().out)["clips"]
    s = centerline_of(load_model(path)).s
    assert [c["at_m"] for c in clips] == [0.4, 0.6]
    for c in clips:
        assert c["node_s_m"] == s[np.argmin(np.abs(s - c["at_m"]))]
        assert abs(c["node_s_m"] - c["at_m"]) <= 0.5 * (s[1] - s[0])
    assert main(["geometry", str(path)]) == 0
    text = capsys.readouterr().out
    assert f"clip 0: at 0.4 m, acts at the node at s = {clips[0]['node_s_m']:.4g} m" in text


def test_with_clips_on_nodes_the_bend_check_takes_the_longest_element():
    """A clip 0.02 m from end A with 63 elements: the spans 0.02 m and LENGTH - 0.02 m (0.9825 m)
    share them by their largest remainders, 63 x 0.02 / LENGTH = 1.28 and 61.72, so 1 and 62 (by
    hand). The mean element, LENGTH / 63 = 0.01560 m, is within a tenth of the first bend's arc
    (0.15 pi / 3 = 0.1571 m); the clip's span, one element of 0.02 m, is not, and the check says so
    with both lengths."""

    data = copy.deepcopy(routed(n=63).data)
    data["casing"]["clip"] = [{"at": 0.02, "stiffness": [2e4, 5e4, 5e4], "damping": 8.0}]
    model = model_from_dict(data)
    g = geometry_summary(model)
    assert g["element_length_m"] == pytest.approx(LENGTH / 63, rel=1e-14)
    assert g["element_length_max_m"] == pytest.approx(0.02, rel=1e-12)  # (round-off of the stations)
    assert g["element_length_min_m"] == pytest.approx((LENGTH - 0.02) / 62, rel=1e-12)
    assert g["element_length_m"] < 0.1 * 0.15 * np.pi / 3 < g["element_length_max_m"]
    said = [w for w in plausibility_warnings(model, g) if w.startswith("the elements")]
    assert said and said[0].startswith(f"the elements ({(LENGTH - 0.02) / 62:.4g} to 0.02 m) are longer than")
    # the advice: the fewest elements whose longest is within 0.01571 m. The clip's span needs 2, which
    # the largest remainders give it first at 74 (quotas 1.506 and 72.49: floors 1 and 72, the one left
    # to the larger remainder, 0.506); the other span's 72 are then 0.01337 m. Below 74 it keeps 1.
    assert "about 74 elements (geometry.n_elements) resolve it" in said[0]
