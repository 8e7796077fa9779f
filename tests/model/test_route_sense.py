"""Routes and loads checked for sense (issues 34 and 35): lengths and element sizes bounded below
as they are above, a route that meets or crosses itself warned with where, an absurd gravity warned,
and the model file's diagnostics in the right order (a route's likely unit before the clip it
misplaces; an element count suggested within the limit)."""

import warnings
from pathlib import Path

import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelWarning
from cablecasing_core.model.load import tomllib
from cablecasing_core.model.schema import MAX_ELEMENTS
from cablecasing_core.structure.route_summary import plausibility_warnings

ROOT = Path(__file__).resolve().parents[2]
CASING = dict(E=5e9, rho=4850.0, d_outer=0.0095, d_inner=0.004, I=2.7261e-10)
INSTALLATION = (ROOT / "examples" / "installation.toml").read_text()


def routed(segments, n=40, **tables):
    return cc.model_from_dict({"geometry": {"segments": segments, "n_elements": n}, "casing": CASING, **tables})


def bend(R, deg, toward=(0, 1, 0)):
    return {"bend": {"radius": R, "angle_deg": deg, "toward": list(toward)}}


def said(fn):
    """(result, texts of the ModelWarnings fn issues)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = fn()
    return out, [str(w.message) for w in caught if issubclass(w.category, ModelWarning)]


@pytest.mark.parametrize("command", ["geometry", "modes", "static", "simulate"])
def test_a_straight_of_1e_300_is_refused_cleanly_by_every_command(command, tmp_path, capsys):
    """1e-300 m gave numpy's divide-by-zero warnings in geometry and an internal error in modes."""
    text = INSTALLATION[: INSTALLATION.index("segments")] + "segments = [{straight = 1e-300}]\n"
    text += INSTALLATION[INSTALLATION.index("[casing]") :]
    (tmp_path / "m.toml").write_text(text)
    assert main([command, str(tmp_path / "m.toml")]) == 2
    err = capsys.readouterr().err
    assert err == "cablecasing: error: geometry.segments[0].straight = 1e-300: must be a number in [1e-06, 1000] in m\n"


def test_parts_of_a_route_below_a_micrometre_are_refused():
    with pytest.raises(cc.ModelError, match=r"geometry.segments\[1\].straight = 1e-09: must be a number in \[1e-06"):
        routed([bend(0.1, 60), {"straight": 1e-9}])
    with pytest.raises(cc.ModelError, match=r"geometry.segments\[0\].bend.radius = 5e-07"):
        routed([bend(5e-7, 60)])
    with pytest.raises(cc.ModelError, match=r"is 5e-07 m from the previous point .*at least 1e-06 m apart"):
        cc.model_from_dict({"geometry": {"points": [[0.0, 0, 0], [5e-7, 0, 0]]}, "casing": CASING})


def test_elements_below_a_micrometre_are_refused_with_the_most_there_may_be():
    with pytest.raises(cc.ModelError) as err:
        routed([{"straight": 2e-5}], n=40)
    assert str(err.value) == (
        "geometry.n_elements = 40: cuts the 2e-05 m route into elements of 5e-07 m, shorter than the least 1e-06 m; at "
        "most 20 elements (are the lengths in m?)"
    )
    said(lambda: routed([{"straight": 2e-5}], n=20))  # (at the bound: accepted, with the short route's warnings)


LOOPS = {
    "a 359.999 deg bend": ([{"straight": 0.1}, bend(0.1, 359.999), {"straight": 0.1}], 360),
    "a 270 deg bend between two 0.3 m straights": ([{"straight": 0.3}, bend(0.05, 270), {"straight": 0.3}], 270),
    "a closed square": (
        [s for t in ((0, 1, 0), (-1, 0, 0), (0, -1, 0), (1, 0, 0)) for s in ({"straight": 0.2}, bend(0.02, 90, t))],
        360,
    ),
}


@pytest.mark.parametrize("name", list(LOOPS))
def test_a_route_that_meets_or_crosses_itself_warns_with_where(name):
    segments, turn = LOOPS[name]
    _, texts = said(lambda: routed(segments))
    meet = [t for t in texts if "the route meets itself: at s = " in t]
    assert len(meet) == 1, texts
    assert "less than the outer diameter casing.d_outer = 0.0095 m" in meet[0]
    assert f"and turns by {turn} deg between them" in meet[0]


def test_routes_that_turn_back_without_meeting_themselves_do_not_warn():
    """A U-turn of radius 0.05 m keeps its straights 0.1 m apart (ten diameters); a hairpin of
    radius 0.0048 m (just above d / 2) 9.6 mm apart, one diameter: neither meets itself."""
    for segments in ([{"straight": 0.3}, bend(0.05, 180), {"straight": 0.3}], [{"straight": 0.3}, bend(0.0048, 180)]):
        model, texts = said(lambda s=segments: routed(s))
        assert not [t for t in plausibility_warnings(model) if "meets itself" in t]
    for model in (cc.load_model(), cc.load_model(ROOT / "examples" / "installation.toml")):
        assert not [t for t in plausibility_warnings(model) if "meets itself" in t]


def test_geometry_prints_the_meeting_and_loading_warns(tmp_path, capsys):
    text = INSTALLATION.replace(
        "segments = [ {straight = 0.15}, {bend = {radius = 0.15, angle_deg = 60, toward = [0, 1, 0]}}",
        "segments = [ {straight = 0.15}, {bend = {radius = 0.05, angle_deg = 300, toward = [0, 1, 0]}}",
    )
    (tmp_path / "m.toml").write_text(text)
    assert main(["geometry", str(tmp_path / "m.toml")]) == 0
    err = capsys.readouterr().err
    assert err.count("the route meets itself") == 1 and "cablecasing: warning: the route meets itself" in err
    _, texts = said(lambda: cc.load_model(tmp_path / "m.toml"))  # (what simulate, static, modes print)
    assert [t for t in texts if t.startswith(f"{tmp_path / 'm.toml'}: the route meets itself")]


def test_an_absurd_gravity_warns_and_the_earth_s_does_not(tmp_path, capsys):
    _, texts = said(lambda: routed([{"straight": 1.0}], loads={"gravity": [0.0, 0.0, -1e4]}, **_clamped()))
    assert [t for t in texts if t.startswith("loads.gravity = [0.0, 0.0, -10000.0] is 1e+04 m/s2, 1.02e+03 g")]
    _, texts = said(lambda: routed([{"straight": 1.0}], loads={"gravity": [0.0, 0.0, -9.81]}, **_clamped()))
    assert not [t for t in texts if "loads.gravity" in t]
    (tmp_path / "g.toml").write_text(INSTALLATION + "\n[loads]\ngravity = [0, 0, -1e4]\n")
    assert main(["geometry", str(tmp_path / "g.toml")]) == 0  # (geometry prints the load's warnings too)
    assert "cablecasing: warning: loads.gravity = [0.0, 0.0, -10000.0] is 1e+04 m/s2" in capsys.readouterr().err


def _clamped():
    return {}  # (the casing's supports default to clamped)


def test_a_route_in_mm_is_named_before_the_clip_it_misplaces():
    """Issue 34: a first straight of 200 (mm meant) put the clip at 0.51 m on the end node and said
    only that; the error now says first that the route is likely in mm."""
    raw = tomllib.loads(INSTALLATION)
    raw["geometry"]["segments"][0] = {"straight": 200.0}
    raw["casing"]["clip"][0]["at"] = 0.51
    with pytest.raises(cc.ModelError) as err:
        cc.model_from_dict(raw)
    assert err.value.key == "casing.clip[0].at"
    assert str(err.value).startswith(
        "casing.clip[0].at = 0.51: the route is 200.8 m long, more than 10 m: are the segments' lengths and radii in "
        "mm? (is 510 mm from end A (s = 0), less than half the mean element"
    )


def test_the_element_advice_stays_within_the_limit():
    """Issue 34: a 2 cm bend arc on a 10 m route asked for ~3160 elements, above the 2000 allowed."""
    model, _ = said(lambda: routed([{"straight": 9.9}, bend(0.02, 90)], n=40))
    advice = [t for t in plausibility_warnings(model) if t.startswith("the elements")]
    assert len(advice) == 1 and f"more than the {MAX_ELEMENTS} allowed" in advice[0]
    assert "elements (geometry.n_elements) resolve it" not in advice[0]
    model, _ = said(lambda: routed([{"straight": 0.5}, bend(0.1, 90)], n=10))
    advice = [t for t in plausibility_warnings(model) if t.startswith("the elements")]
    assert advice and "about 42 elements (geometry.n_elements) resolve it" in advice[0]
