"""A rigid motion the supports leave free that the compression does not drive (review M, D3, D2):
a straight casing on isolators without torsional stiffness buckles at the load of its other
motions, text and JSON agree, and a loaded body with a free motion its loads do not push is
refused naming the free motion, not the load."""

from __future__ import annotations

import re

import numpy as np
import pytest
from scipy.optimize import brentq

import cablecasing_core as cc

L, K_ROT = 0.85, 20.0  # m, N.m/rad


@pytest.fixture
def model(paper_bodies):
    """``model(stiffness, rotational, gravity=(0, 0, 0), T=0.0, cable=True)``: the casing (and the
    cable, clamped) of tests/conftest.py's paper_bodies along a straight 0.85 m, 40 elements, on
    isolators of translational ``stiffness`` (N/m) and ``rotational`` stiffness (N.m/rad) at both ends."""

    def build(stiffness, rotational, gravity=(0.0, 0.0, 0.0), T=0.0, cable=True):
        iso = {"stiffness": stiffness, "rotational_stiffness": rotational}
        d = {
            "geometry": {"n_elements": 40, "curve": "polyline", "points": [[0, 0, 0], [L, 0, 0]]},
            "casing": dict(
                paper_bodies["casing"], supports={"A": "isolator", "B": "isolator"}, isolator={"A": iso, "B": iso}
            ),
            "loads": {"gravity": list(gravity), "cable_tension": T},
            "scenario": {"duration": 0.01, "dt": 1e-5},
        }
        if cable:
            d["cable"] = dict(paper_bodies["cable"], supports={"A": "clamped", "B": "clamped"})
        return cc.model_from_dict(d)

    return build


@pytest.fixture
def EI(paper_bodies):
    """The casing's bending stiffness E I (N m2)."""
    return paper_bodies["casing"]["E"] * paper_bodies["casing"]["I"]


def _symmetric_euler_load(EI):
    """The lowest buckling load of a column of length L on equal end springs (k_t, k_r): its
    symmetric mode w = A cos(lam x) + C (x from mid-span) leaves no shear at the ends (EI w''' + P w'
    = 0), so k_t carries nothing and the moment condition EI w'' = -k_r w' gives
    EI lam cos(lam L/2) + k_r sin(lam L/2) = 0, lam L/2 in (pi/2, pi), P = EI lam^2 (56.2036 N, the
    reviewer's full characteristic determinant with k_t = 1e5 N/m, whose lowest root it is)."""
    a = L / 2

    def f(lam):
        return EI * lam * np.cos(lam * a) + K_ROT * np.sin(lam * a)

    lam = brentq(f, np.pi / (2 * a) * (1 + 1e-12), np.pi / a * (1 - 1e-12), xtol=1e-15)
    return EI * lam * lam


def test_a_casing_free_to_twist_buckles_at_the_load_of_its_other_motions(model, EI):
    """Isolators [4e5, 1e5, 1e5] N/m, rotational [0, 20, 20] N.m/rad: the twist about the casing's
    own axis is free, and the compression does no work on it (the Wagner term acts on the twist's
    difference), so the load is that of the bending on the complement: 56.204 N, to 2e-6 (the FE's
    h^4 error at 40 elements, within 8.4e-7 on 40 such spring cases in the review). Text and JSON
    say the same: the load, and the twist left free."""
    b = cc.body_buckling(model([4e5, 1e5, 1e5], [0.0, K_ROT, K_ROT]), "casing")
    assert b.load == pytest.approx(_symmetric_euler_load(EI), rel=2e-6)
    assert b.mechanism is None and b.at == pytest.approx(L / 2)
    d = b.as_dict()
    assert d["load_N"] == b.load and d["free_motion"] == "a rotation about [1, 0, 0] through [0.425, 0, 0] m"
    assert f"{b.load:.4g} N" in b.text() and "free in a rotation about [1, 0, 0]" in b.text()
    held = cc.body_buckling(model([4e5, 1e5, 1e5], [5.0, K_ROT, K_ROT]), "casing")  # (torsion held: same)
    assert held.load == pytest.approx(b.load, rel=1e-9) and "free_motion" not in held.as_dict()


def test_a_casing_free_to_slide_sideways_sways_at_its_closed_form(model, EI):
    """Isolators without lateral stiffness, rotational [5, 20, 20] N.m/rad: the lateral translations
    are free and not driven (K_G1 of a rigid translation is 0), and the lowest mode is the sway
    w = A sin(lam x) (x from mid-span; the end shear EI w''' + P w' vanishes by itself): the moment
    condition EI w'' = -k_r w' gives tan(lam L/2) = k_r / (EI lam), P = EI lam^2 = 13.888 N; to 2e-6,
    the FE's h^4 error as above."""
    b = cc.body_buckling(model([4e5, 0.0, 0.0], [5.0, K_ROT, K_ROT]), "casing")
    lam = brentq(lambda x: np.tan(x * L / 2) - K_ROT / (EI * x), 1e-9, np.pi / L * (1 - 1e-12), xtol=1e-15)
    assert b.load == pytest.approx(EI * lam * lam, rel=2e-6)
    assert b.as_dict()["free_motion"].startswith("a translation along [0, ")


def test_a_mechanism_reads_alike_in_text_and_json(model):
    """Isolators without lateral stiffness nor rotational stiffness across: the compression drives
    the rigid rotation across the casing, P_cr = 0 in both outputs."""
    b = cc.body_buckling(model([4e5, 0.0, 0.0], [5.0, 0.0, 0.0]), "casing")
    assert b.load == 0.0 and b.as_dict()["load_N"] == 0.0 and b.mechanism.startswith("it is free to move: ")
    assert "buckles under any compression (buckling load 0 N)" in b.text()


@pytest.mark.parametrize(
    "stiffness, rotational, gravity, T, free",
    [
        ([4e5, 1e5, 0.0], [5.0, K_ROT, K_ROT], [0.0, 0.0, -9.81], 0.0, "a translation along [0, 1, 0]"),
        ([4e5, 1e5, 1e5], [0.0, K_ROT, K_ROT], [0.0, 0.0, -9.81], 0.0, "a rotation about [1, 0, 0]"),
        ([4e5, 1e5, 1e5], [0.0, K_ROT, K_ROT], [0.0, 0.0, 0.0], 2.0, "a rotation about [1, 0, 0]"),
    ],
)
def test_a_free_motion_the_loads_do_not_push_is_named_as_the_problem(model, stiffness, rotational, gravity, T, free):
    """The weight along -z does no work on a y translation or on a twist about x; the tension has no
    resultant: the refusal names the free motion and how to hold it, not the load as uncarried."""
    with pytest.raises(cc.ModelError) as err:
        model(stiffness, rotational, gravity=gravity, T=T)
    text = str(err.value)
    assert err.value.key == ("loads.gravity" if any(gravity) else "loads.cable_tension")
    assert "cannot be carried" not in text
    assert "needs the casing held against every rigid motion, but its supports" in text and free in text
    assert "however small" in text
    if free.startswith("a rotation"):
        assert "torsional stiffness" in text


def _straight_on_stiff_isolators(k, torsion, segments=({"straight": 1.0},)):
    """A straight casing of 1 m along x (Table 2's section; ``segments``: another route from the
    origin along x), 16 elements, on isolators of ``k`` (N/m) with the torsional stiffness
    ``torsion`` (N.m/rad) alone, under its weight along -z."""
    iso = {"stiffness": k, "rotational_stiffness": [torsion, 0.0, 0.0]}
    return {
        "geometry": {"n_elements": 16, "start": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0],
                     "segments": list(segments)},
        "casing": {"E": 5e9, "rho": 4850.0, "d_outer": 0.0095, "d_inner": 0.004, "I": 2.7261e-10,
                   "supports": {"A": "isolator", "B": "isolator"}, "isolator": {"A": iso, "B": iso}},
        "loads": {"gravity": [0.0, 0.0, -9.81]},
    }  # fmt: skip


def test_a_torsion_too_small_beside_the_isolators_is_refused_with_its_numbers():
    """Review BD1: 0.01 N.m/rad of torsion at each end beside isolators of 1e12 N/m. The twist is
    held by 2 x 0.01 = 0.02 N.m/rad; the rigid stiffness's largest eigenvalue is the isolators'
    translation, 2 x 1e12 N/m, and the threshold 64 eps of it is 64 * 2.22e-16 * 2e12 = 0.0284
    N/m, which on a twist of the 1 m casing about its axis (coordinates [t, L w]) is 0.0284
    N.m/rad: the stiffness is refused as counting as none, with these numbers, not as absent. 0.1
    N.m/rad each (0.2 in all) is above it and accepted; beside 1e6 N/m isolators (threshold
    2.8e-8 N.m/rad) 0.01 is too."""
    with pytest.raises(cc.ModelError) as err:
        cc.model_from_dict(_straight_on_stiff_isolators(1e12, 0.01))
    text = str(err.value)
    threshold = 64 * np.finfo(float).eps * 2e12  # (N/m on [t, L w], N.m/rad on the twist: L = 1 m)
    assert "have no stiffness there" not in text and "however small" not in text
    assert "the mounts' stiffness there, 0.02 N.m/rad from casing.isolator.A and casing.isolator.B" in text
    assert "2e+12 N/m (a translation)" in text and f"{threshold:.3g} N.m/rad on this motion" in text
    assert f"a stiffness above {threshold:.3g} N.m/rad in all in that direction" in text
    assert "which may be far below the others" not in text  # (the hint for a torsion not given at all)
    cc.model_from_dict(_straight_on_stiff_isolators(1e12, 0.1))
    cc.model_from_dict(_straight_on_stiff_isolators(1e6, 0.01))
    with pytest.raises(cc.ModelError, match="the mounts have no stiffness there"):  # (none given: said so)
        cc.model_from_dict(_straight_on_stiff_isolators(1e12, 0.0))


def test_a_lateral_stiffness_too_small_beside_the_axial_one_is_refused_with_its_numbers():
    """The weight along -z on isolators [1e12, 1e-3, 1e-3] N/m: the vertical translation is held by
    2e-3 N/m, below 64 eps of the axial 2e12 N/m (0.0284 N/m), and the weight drives it: refused as a
    mechanism whose stiffness counts as none, naming it (the mount's K6 in global axes rounds 1e-3
    beside 1e12 to nothing, so the stiffness is read from the model as given)."""
    d = _straight_on_stiff_isolators([1e12, 1e-3, 1e-3], 1.0)
    with pytest.raises(cc.ModelError) as err:
        cc.model_from_dict(d)
    text = str(err.value)
    assert "a translation along [0, 0, -1] (a mechanism: the mounts' stiffness there, 0.002 N/m from" in text
    assert "0.0284 N/m on this motion" in text and "a stiffness above 0.0284 N/m in all" in text


def test_every_free_motion_is_named_beside_the_buckling_load():
    """Review BD3: isolators holding only rotations (k = 0, k_rot = 10 N.m/rad) leave all three
    translations free, and the compression drives none; the text and JSON name all three, as
    free_motions does, not the first. The load is the sway of x tan x = C L / (2 EI), x = lambda L / 2
    (8.4357 N on 1 m; to 1e-6, the FE's h^4 error at 16 elements being 5e-7)."""
    from cablecasing_core.structure.support_check import free_motions

    d = _straight_on_stiff_isolators(0.0, 0.0)
    d["casing"]["isolator"] = {s: {"stiffness": 0.0, "rotational_stiffness": 10.0} for s in "AB"}
    del d["loads"]
    model = cc.model_from_dict(d)
    b = cc.body_buckling(model, "casing")
    free = free_motions(model, "casing")
    assert free == [f"a translation along {v}" for v in ("[1, 0, 0]", "[0, 1, 0]", "[0, 0, 1]")]
    named = f"{free[0]}, {free[1]} and {free[2]}"
    assert b.undriven == named and b.as_dict()["free_motion"] == named
    assert f"; free in {named}, on which the compression does no work" in b.text()
    x = brentq(lambda x: x * np.tan(x) - 10.0 / (2 * 5e9 * 2.7261e-10), 1e-9, np.pi / 2 - 1e-9, xtol=1e-15)
    assert b.load == pytest.approx(5e9 * 2.7261e-10 * (2 * x) ** 2, rel=1e-6)


def test_the_threshold_on_a_twist_scales_with_the_casings_length_squared():
    """Review BF2: on a casing of 2 m the twist's coordinate is L w, so the threshold 64 eps x 2e12
    N/m on [t, L w] is 0.0284 x L^2 = 0.114 N.m/rad on the twist: 0.05 N.m/rad at each end (0.1 in
    all) is refused with these numbers (on 1 m it would pass, above 0.0284)."""
    with pytest.raises(cc.ModelError) as err:
        cc.model_from_dict(_straight_on_stiff_isolators(1e12, 0.05, [{"straight": 2.0}]))
    text = str(err.value)
    threshold = 64 * np.finfo(float).eps * 2e12 * 2.0**2
    assert "the mounts' stiffness there, 0.1 N.m/rad from casing.isolator.A and casing.isolator.B" in text, text
    assert f"{threshold:.3g} N.m/rad on this motion" in text, text


@pytest.mark.parametrize("torsion", [1.0, 1.5])
def test_a_torsion_that_holds_a_bent_casing_only_by_its_small_share_is_named(torsion):
    """Review BF1: a 1 m arc of 170 degrees on isolators of 1e12 N/m with the torsion ``torsion``
    about each end's tangent. The ends stay put under a rotation about the chord, so only the
    torsions hold it, each by torsion cos^2 85 deg (the tangents at 85 degrees from the chord): 2
    torsion cos^2 85 deg = 0.0152 / 0.0228 N.m/rad, below the threshold 0.0297 (64 eps of the largest
    eigenvalue 2.087e12 N/m), so the weight's rotation counts as free. The torsions given are not
    small, but their share is, and it is named: at most the chord rotation's Rayleigh quotient (the
    free motion is the least stiff one; the eigenvector departs from the chord rotation by the
    coupling with the isolators' translations, which moved it 4 % in the review), at least 0.9 of it."""
    angle = 170.0
    radius = 1.0 / np.deg2rad(angle)
    d = _straight_on_stiff_isolators(
        1e12, torsion, [{"bend": {"radius": radius, "angle_deg": angle, "toward": [0, 1, 0]}}]
    )
    with pytest.raises(cc.ModelError) as err:
        cc.model_from_dict(d)
    text = str(err.value)
    assert "have no stiffness there" not in text, text
    given = float(
        re.search(
            r"the mounts' stiffness there, ([0-9.e+-]+) N.m/rad from casing.isolator.A and casing.isolator.B", text
        )[1]
    )
    chord = 2 * torsion * np.cos(np.deg2rad(angle / 2)) ** 2
    assert 0.9 * chord <= given <= chord * (1 + 1e-3), (given, chord)  # (1e-3: the message's 3 digits)
