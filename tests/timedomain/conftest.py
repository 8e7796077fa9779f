"""Probes of the contact kernels for the tests: the search, the deformed casing axis, and the
paper's own form of the intersection (Eq. 39) to check the search against."""

from types import SimpleNamespace

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.timedomain import kernels as K


def search_casing(x1, t1, Xs, Rs, Ls, Us, e_guess, far_below):
    """The contact search of one cable node (point x1, unit tangent t1; Eqs. 32-39) as the contact
    solve runs it (``kernels.search_node``): (element, xi, far)."""
    e, xi, far, _, _, _ = K.search_node(x1[0], x1[1], x1[2], t1[0], t1[1], t1[2], Xs, Rs, Ls, Us, e_guess, far_below)
    return e, xi, far


def casing_point(Xs, Rs, Ls, Us, e, xi):
    """Deformed casing axis point (m) at xi of element e (``kernels.axis_at``), as an array."""
    px, py, pz, _, _, _ = K.axis_at(Xs, Rs, Ls, e, xi, K.element_dofs(Rs, Us, e))
    return np.array([px, py, pz])


def line_plane_intersection(ia, ib, p0, p1, p2):
    """Eq. (39), the paper's general form: (l, u, v) of the intersection of the line
    ia + (ib - ia) l with the plane p0 + (p1 - p0) u + (p2 - p0) v (the search itself uses the
    equivalent normal-plane form, one division; this checks it). l = nan for a parallel line."""
    A = np.column_stack([ia - ib, p1 - p0, p2 - p0])
    if abs(np.linalg.det(A)) < 1e-300:
        return np.nan, np.nan, np.nan
    return tuple(np.linalg.solve(A, ia - p0))


def run_cut_and_resumed(model):
    """The model's scenario over 0.02 s at 1e-5 s three ways, for the bitwise-reproducibility tests:
    (whole: one call, steps: 200 calls of 1e-4 s (the FMU's), resumed: the second half from
    ``get_state`` of the first), all with the motion on the exact grid (the calls' start times add
    up in floating point)."""
    from cablecasing_core.timedomain.engine import Engine
    from cablecasing_core.timedomain.scenario import scenario_motion

    grid = scenario_motion(model, dt=1e-5)
    mo = lambda t: grid(np.round(t / 1e-5) * 1e-5)  # noqa: E731
    whole = Engine(model, ledger=False, record=True)
    whole.advance(0.02, mo)
    steps = Engine(model, ledger=False, record=True)
    for _ in range(100):
        steps.advance(1e-4, mo)
    mid = steps.get_state()
    for _ in range(100):
        steps.advance(1e-4, mo)
    resumed = Engine(model, ledger=False)
    resumed.set_state(mid)
    resumed.advance(0.01, mo)
    return whole, steps, resumed


@pytest.fixture(scope="session")
def cut_and_resumed():
    """:func:`run_cut_and_resumed`, for the tests of a run's bitwise reproducibility."""
    return run_cut_and_resumed


@pytest.fixture(scope="session")
def probes():
    """``probes.search_casing``, ``probes.casing_point``, ``probes.line_plane_intersection``."""
    return SimpleNamespace(
        search_casing=search_casing, casing_point=casing_point, line_plane_intersection=line_plane_intersection
    )


@pytest.fixture(scope="session")
def pair_model(arc_points):
    """``pair_model(friction=0.0, damping=0.0, alpha=0.0, beta=0.0, n=12)``: the built-in cable and
    casing on a 60 degree arc of radius 0.3 m (n elements each), with the given contact friction and
    damping (kg/s) and Rayleigh factors (1/s, s) for both bodies."""

    def build(friction=0.0, damping=0.0, alpha=0.0, beta=0.0, n=12):
        return cc.load_model().with_overrides(
            {
                "geometry.points": arc_points(0.3, np.pi / 3, 8).tolist(),
                "geometry.n_elements": n,
                "contact.friction": friction,
                "contact.damping": damping,
                "casing.alpha": alpha,
                "casing.beta": beta,
                "cable.alpha": alpha,
                "cable.beta": beta,
            }
        )

    return build


@pytest.fixture(scope="session")
def kick():
    """``kick(eng, v0)``: give the engine's cable a half-sine field of lateral velocity (m/s, z, out of
    the arc's plane) with peak v0, by set_state."""

    def give(eng, v0):
        s = eng.get_state()
        nn = len(s["cable.V"]) // 6
        s["cable.V"][2::6] = v0 * np.sin(np.pi * np.arange(nn) / (nn - 1))
        eng.set_state(s)

    return give


@pytest.fixture(scope="session")
def energy_samples():
    """``energy_samples(eng, samples, every)``: advance the engine at rest supports ``samples`` times
    by ``every`` s; returns (kinetic + strain + contact energy, contact energy), each per sample
    over their value at the start (arrays), for the energy-conservation tests."""
    from cablecasing_core.timedomain.scenario import zero_motion

    def run(eng, samples, every):
        E0 = sum(eng.energies()[k] for k in ("kinetic", "strain", "contact_potential"))
        E, pot = np.empty(samples), np.empty(samples)
        for i in range(samples):
            eng.advance(every, zero_motion)
            e = eng.energies()
            E[i] = (e["kinetic"] + e["strain"] + e["contact_potential"]) / E0
            pot[i] = e["contact_potential"] / E0
        return E, pot

    return run
