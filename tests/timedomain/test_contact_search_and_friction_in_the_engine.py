"""What the kernel-level contact tests leave to the engine: the search's projection onto a bent
element's Hermite axis (not only the chord), the regularisation speed the engine gives the friction
law (the model's contact.stick_velocity), and the ledger's friction work by the trapezoidal rule of
the friction power (Eq. 18's average over the step)."""

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.structure.geometry import centerline_of
from cablecasing_core.timedomain import kernels as K
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion


def test_the_search_finds_the_cut_on_a_bent_elements_hermite_axis(straight):
    """A straight casing element given opposite bending rotations of 2e-3 rad at its ends (its axis
    leaves the chord by up to ~L/4 * 2e-3 = 6e-6 m here) and cable nodes whose normal planes are
    tilted against it: the cut xi is the root in [0, 1] of phi(xi) = (X(xi) + u(xi) - x) . t,
    u from the element's 6 x 12 Hermite matrix (Eq. 9, ``hermite_matrix``, another path than the
    search's), phi a cubic found exactly from four samples: to 1e-9 (the search's Newton stops
    within 1e-10). The cut on the chord is ~1e-4 off in xi."""
    model = straight(0.4, 8, supports=("clamped", "clamped"))
    cl = centerline_of(model)
    e = 3
    L, R = cl.lengths[e], cl.frames[e]
    Us = np.zeros(6 * len(cl.nodes))
    Us[6 * e + 3 : 6 * e + 6] = 2e-3 * R[2]  # rotations about the element's local z: bending in its x-y plane
    Us[6 * (e + 1) + 3 : 6 * (e + 1) + 6] = -2e-3 * R[2]
    H = np.zeros((6, 12))
    Ue = Us[6 * e : 6 * e + 12]

    def axis(xi):
        K.hermite_matrix(xi, L, R, H)
        return cl.nodes[e] + xi * (cl.nodes[e + 1] - cl.nodes[e]) + H[:3] @ Ue

    rng = np.random.default_rng(11)
    worst_chord = 0.0
    for _ in range(12):
        xi0 = rng.uniform(0.2, 0.8)
        x = axis(xi0) + 2e-4 * rng.standard_normal(3)
        t = R[0] + 0.4 * rng.standard_normal(3)
        t /= np.linalg.norm(t)
        found, xi, far, px, py, pz = K.search_node(*x, *t, cl.nodes, cl.frames, cl.lengths, Us, e, 0.0)
        assert found == e and not far
        s = np.linspace(0.0, 1.0, 4)
        phi = np.polyfit(s, [(axis(v) - x) @ t for v in s], 3)
        roots = [r.real for r in np.roots(phi) if abs(r.imag) < 1e-12 and 0.0 <= r.real <= 1.0]
        assert len(roots) == 1 and xi == pytest.approx(roots[0], abs=1e-9)
        np.testing.assert_allclose([px, py, pz], axis(xi), rtol=0, atol=1e-12)
        a, b = cl.nodes[e], cl.nodes[e + 1]
        worst_chord = max(worst_chord, abs(((x - a) @ t) / ((b - a) @ t) - roots[0]))
    assert worst_chord > 1e-5  # (the chord's cut is not the axis's: the test can tell them apart)


@pytest.fixture(scope="module")
def sliding():
    """The installed specimen with contact.stick_velocity = 0.05 m/s (its contacts slide at 0.04-0.7
    times that: the regularisation shapes their friction), 2 ms into its scenario."""
    model = cc.load_model("installed").with_overrides({"contact.stick_velocity": 0.05})
    eng = Engine(model)
    motion = scenario_motion(model)
    eng.advance(0.002, motion)
    return model, eng, motion


def test_the_engine_regularises_friction_over_the_models_stick_velocity(sliding):
    """At the end of a step every contact's tangential force is mu N |v_t| / sqrt(v_t^2 + v_s^2)
    (contact.friction_law = "regularized") with v_s the model's contact.stick_velocity: |f_t| from
    the force P and its normal part N (|P|^2 = N^2 + f_t^2), within 1e-9 of mu N (the same law in
    the same arithmetic; measured 1e-11)."""
    model, eng, _ = sliding
    on = eng.Nn > 0
    assert on.sum() >= 5
    P, N, v = eng.Pn[on], eng.Nn[on], np.abs(eng.vrel[on])
    mu, vs = model.contact["friction"], model.contact["stick_velocity"]
    ft = np.sqrt(np.maximum((P**2).sum(axis=1) - N**2, 0.0))
    assert np.sum((v > 0.3 * vs) & (v < 3 * vs)) >= 3  # (where the law's regularisation matters most)
    np.testing.assert_allclose(ft, mu * N * v / np.sqrt(v * v + vs * vs), rtol=0, atol=1e-9 * mu * N.max())


def test_the_ledgers_friction_work_is_the_trapezoidal_rule_of_the_friction_power(sliding):
    """Over 20 steps the ledger's friction_dissipation grows by the trapezoidal sum of the friction
    power sum mu N v_t^2 / sqrt(v_t^2 + v_s^2) at the steps' ends, to 1e-9 (the same products
    summed in another order); the rectangle rule of the end powers is 0.8 % off here."""
    model, eng, motion = sliding
    mu, vs = model.contact["friction"], model.contact["stick_velocity"]

    def power():
        v = np.abs(eng.vrel)
        return np.sum(mu * eng.Nn * v * v / np.sqrt(v * v + vs * vs))

    before, p = eng.energies()["friction_dissipation"], [power()]
    for _ in range(20):
        eng.advance(eng.dt, motion)
        p.append(power())
    p = np.array(p)
    grown = eng.energies()["friction_dissipation"] - before
    assert grown == pytest.approx(eng.dt * np.sum(0.5 * (p[1:] + p[:-1])), rel=1e-9)
