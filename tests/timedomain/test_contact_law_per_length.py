"""The contact law per unit length (``contact.law_length`` > 0, docs/time_domain.md, "A contact law
per unit length"): each cable node carries the share l_i / law_length of the law (its tributary
length l_i over the law's length), so that the wall a cable lying along the casing meets does not
change with the mesh.

The kernels' share of a single contact (stiffness, damper, stored energy) is checked against Hertz's
impact and an independent integration in test_contact_law_impact.py."""

import copy

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.structure.geometry import centerline_of
from cablecasing_core.timedomain.engine import Engine, contact_shares, hertz_constant
from cablecasing_core.timedomain.static_state import static_state

R, T = 0.1, 10.0  # m, N: the bend's radius and the cable's tension


def bend_model(n, law_length):
    """A string-like cable (I = 1e-14 m^4) in a rigid casing (E = 1e12 Pa), straight 0.1 m, a 90 deg
    bend of radius R, straight 0.1 m, at tension T, no gravity: in the bend's middle the tension
    presses the cable on the inside of the wall with q = T / (R - gap) per metre (membrane
    equilibrium of a string on the radius R - gap its axis takes there)."""
    src = copy.deepcopy(cc.load_model("default").data)
    bend = {"radius": R, "angle_deg": 90.0, "toward": [0, 1, 0]}
    src["geometry"] = {"n_elements": n, "segments": [{"straight": 0.1}, {"bend": bend}, {"straight": 0.1}]}
    src["casing"]["E"] = 1e12
    src["cable"]["I"] = 1e-14
    src["contact"]["law_length"] = law_length
    src["loads"] = {"cable_tension": T}
    return cc.model_from_dict(src)


LENGTH = 0.2 + R * np.pi / 2  # m, the route's length


def test_each_node_carries_its_tributary_length_over_the_laws_length():
    """contact_shares: 1 at every node with law_length = 0 (the paper's law per node); else half of
    each adjoining element over law_length, so the shares sum to the cable's length over it."""
    m = bend_model(20, 0.0)
    lengths = centerline_of(m).lengths
    assert np.array_equal(contact_shares(m, lengths), np.ones(21))
    L_c = 0.03
    s = contact_shares(bend_model(20, L_c), lengths)
    assert s.sum() == pytest.approx(lengths.sum() / L_c, rel=1e-12)
    np.testing.assert_allclose(s[1:-1], 0.5 * (lengths[:-1] + lengths[1:]) / L_c, rtol=1e-12)
    assert s[0] == pytest.approx(0.5 * lengths[0] / L_c, rel=1e-12)


def test_a_cable_pulled_round_a_bend_presses_the_same_wall_at_every_mesh_with_the_law_per_length():
    """In the bend's middle (its central 60 %) the static penetration under the line load q = T / (R -
    gap) is, with the law per unit length (k_hertz per law_length), g = (q law_length / k_hertz)^(2/3)
    at every mesh: within 1 % at 35, 70 and 140 elements (q is within 1.5 % of T / (R - gap) there,
    and g goes as q^(2/3); measured 0.24-0.31 % low). With the law per node (law_length = 0) the
    node's force q l is what the law sees, so the penetration falls as n^(-2/3) with the mesh: 0.63
    per doubling (within 2 %)."""
    L_c = LENGTH / 35  # the paper's element length: the same wall as the law per node at 35 elements
    g = {}
    for law_length in (0.0, L_c):
        for n in (35, 70, 140):
            m = bend_model(n, law_length)
            st = static_state(m)
            s = st.arc_length
            mid = (s > 0.1 + 0.2 * R * np.pi / 2) & (s < 0.1 + 0.8 * R * np.pi / 2)
            assert mid.sum() >= 0.5 * n * (R * np.pi / 2) / LENGTH  # (the middle's nodes are all in contact)
            assert np.all(st.penetration[mid] > 0)
            g[law_length, n] = st.penetration[mid].mean()
            q = T / (R - m.radial_gap)
            if law_length:
                assert g[law_length, n] == pytest.approx((q * L_c / hertz_constant(m)) ** (2 / 3), rel=0.01)
    for n in (35, 70):
        assert g[0.0, 2 * n] / g[0.0, n] == pytest.approx(2 ** (-2 / 3), rel=0.02)
    # at 35 elements the two laws are the same wall (every node's share within 0.1 % of 1)
    assert g[L_c, 35] == pytest.approx(g[0.0, 35], rel=1e-3)


def test_energy_is_conserved_with_the_law_per_length(pair_model, kick, energy_samples):
    """The engine's contact energy is each node's share of the law's integral: kinetic + strain +
    contact energy stays what a kick gave (no damping, no friction) through the impacts of a cable on
    a 60 degree arc, each node carrying twice the law (law_length = half an element). Over 0.2 s at
    2.5 us (as test_engine.py's whole-law test, whose drift is 0.14 % over 0.5 s): within 3e-3, and
    within 1.5e-3 of the energy before each contact episode in the samples where the contact holds
    more than 2 % of it (measured 1.5e-3 and 6.2e-4; 110 samples in contact, 14 deep). A contact
    energy without the share (half the stored energy, which peaks at 10 % of the kick's) is off by
    5.1e-2 in both."""
    m = pair_model(n=12)
    lengths = centerline_of(m).lengths
    m = m.with_overrides({"contact.law_length": float(lengths.mean() / 2)})
    dt = 2.5e-6
    eng = Engine(m, dt=dt, contact=True, ledger=True)
    assert eng.share[1:-1] == pytest.approx(2.0, rel=1e-5)  # (the arc's elements differ by 1e-6)
    kick(eng, 0.3)
    E, pot = energy_samples(eng, 8_000, dt * 10)
    on = pot > 0
    assert on.sum() > 40, "the kick must bring the cable into contact"
    assert np.max(np.abs(E - 1)) < 3e-3
    before = np.maximum.accumulate(np.where(~on, np.arange(len(on)), -1))
    deep = on & (pot > 0.02) & (before >= 0)
    assert deep.sum() >= 10
    assert np.max(np.abs(E[deep] - E[before[deep]])) < 1.5e-3


def test_the_time_stepping_keeps_the_static_state_of_the_law_per_length():
    """The engine applies the law's share in its step, not only in the static state and the energy:
    started from the static state of the pulled bend with every node carrying twice the law
    (law_length = half the 35-element mesh's element), supports at rest, no excitation, 5 ms of
    steps of 1e-5 s keep the penetration in the bend's middle where the static state put it, within
    1e-3 of it (the static residual and the Newmark step's rounding move it by ~1e-5). A step
    that took each node's whole law instead would press the nodes out by 2^(2/3) = 1.59 in
    penetration at the same force (measured: 1.56 on average, the shares set to 1 after the static
    state; 1.8e-5 as it is)."""
    from cablecasing_core.timedomain.scenario import zero_motion

    m = bend_model(35, LENGTH / 70)
    eng = Engine(m, dt=1e-5, contact=True)
    assert eng.share[1:-1] == pytest.approx(2.0, rel=2e-3)
    s = eng.static.arc_length
    mid = (s > 0.1 + 0.2 * R * np.pi / 2) & (s < 0.1 + 0.8 * R * np.pi / 2)
    g0 = eng.gn[mid].copy()
    assert np.all(g0 > 0) and np.allclose(g0, eng.static.penetration[mid], rtol=1e-12)
    eng.advance(5e-3, zero_motion)
    np.testing.assert_allclose(eng.gn[mid], g0, rtol=1e-3)
