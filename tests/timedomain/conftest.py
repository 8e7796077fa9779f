"""Probes of the contact kernels for the tests: the search, the deformed casing axis, and the
paper's own form of the intersection (Eq. 39) to check the search against; and a single mass
rubbing on the casing wall through the engine's own step loop (``mass_on_the_wall``)."""

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


def mass_on_the_wall(dt, t_end, nsub, *, m, k_x, normal_force, mu, anchor, v0=0.0, a0=0.0, v_stick=1.0e-4):
    """A single mass on a spring along x, pressed on a rigid casing wall at rest and rubbing on it
    through the switch law (Coulomb, Eq. 17), run by the engine's own step loop
    (``kernels.run_steps``) so that its events go through the sub-steps and the slow-slip test as a
    cable's do. Built as a two-node 'cable': node 0 the spring's anchor (prescribed, channel
    cable.A.x), node 1 the mass m (kg) on six springs to it, k_x (N/m) along x and 1e12 N/m (N.m/rad)
    in the other five DOFs, stiff enough that the normal force stays normal_force (N) to a part in
    1e6 and the friction's arm does not turn the mass; the wall's law linear, 1e6 N/m.

    anchor(t) -> (u, v, a), the anchor's displacement (m), velocity (m/s) and acceleration (m/s2)
    along x at the times t (s, an array). The mass starts at x = 0 (the spring relaxed) with the
    velocity v0 (m/s) and acceleration a0 (m/s2), the anchor at anchor(0). Steps of dt (s) to t_end
    (s), with ``contact.event_substeps`` = nsub and the stick band v_stick (m/s). Returns (t, x, v,
    state, refined): the step-end times, the mass's displacement (m) and velocity (m/s), its contact
    state (OPEN/STICK/SLIP) and the number of steps recomputed in sub-steps."""
    import types

    import scipy.sparse as sp

    from cablecasing_core.model.schema import CHANNELS, CONTACT_LAWS
    from cablecasing_core.timedomain.body_storage import BodyStorage, body_arrays
    from cablecasing_core.timedomain.support_motion import _coefficient_matrix

    gap, k_lin, k_hold = 1.0e-3, 1.0e6, 1.0e12  # m, N/m, N/m and N.m/rad

    def system(Km, Mm, free, prescribed):
        return types.SimpleNamespace(
            f=np.zeros(12), spec=types.SimpleNamespace(alpha=0.0, beta=0.0), K=sp.csr_matrix(Km),
            M=sp.csr_matrix(Mm), ndof=12, free=np.asarray(free), prescribed=np.asarray(prescribed),
            support_nodes={"A": 0, "B": 1}, mounts=[],
        )  # fmt: skip

    Kc = np.zeros((12, 12))
    for c in range(6):
        kc = k_x if c == 0 else k_hold
        Kc[np.ix_([c, 6 + c], [c, 6 + c])] += kc * np.array([[1, -1], [-1, 1]])
    cable = BodyStorage(None, "cable", system(Kc, np.diag(np.full(12, m)), np.arange(6, 12), np.arange(6)))
    casing = BodyStorage(None, "casing", system(np.eye(12), np.eye(12), np.arange(0), np.arange(12)))
    # the mass pressed on the wall at its static deflection: at rest it sits normal_force / k_hold
    # further out, and its spring pulls it to the penetration normal_force / k_lin
    z0 = gap + normal_force / k_lin + normal_force / k_hold
    cable.U[8] = -normal_force / k_hold
    n = int(round(t_end / dt))
    t = dt * np.arange(1, n + 1)
    nch = len(CHANNELS)
    up, vp, ap = np.zeros((n, nch)), np.zeros((n, nch)), np.zeros((n, nch))
    ja = CHANNELS.index("cable.A.x")
    up[:, ja], vp[:, ja], ap[:, ja] = anchor(t)
    chan = np.zeros((3, nch))
    start = anchor(np.zeros(1))
    for q in range(3):
        chan[q, ja] = start[q][0]
    cable.U[0], cable.V[0], cable.A[0] = chan[0, ja], chan[1, ja], chan[2, ja]
    cable.V[6], cable.A[6] = v0, a0
    Xc = np.array([[-1.0, 0, 0], [0.0, 0, z0]])
    Tc = np.array([[1.0, 0, 0], [1.0, 0, 0]])
    Xs = np.array([[-5.0, 0, 0], [5.0, 0, 0]])
    nn = 2
    fcs, fcc = np.zeros(12), np.zeros(12)
    claw = K.ContactLaw(
        True, gap, gap, 1e-3, CONTACT_LAWS.index("linear"), k_lin, 0.0, 0.0, mu, v_stick, nsub, True, 0.0, 0.0
    )
    contact = K.ContactArrays(
        Xc, Tc, Xs, np.eye(3)[None].copy(), np.array([10.0]), np.zeros(nn, np.int64), np.zeros(nn, np.int64),
        np.zeros(nn), np.zeros((nn, 3)), np.zeros((nn, 3)), np.zeros(nn), np.zeros(nn), np.zeros(nn), np.zeros(nn),
        K.contact_workspace(nn), chan, _coefficient_matrix(dt), np.zeros(1, np.int64), np.ones(nn),
    )  # fmt: skip
    args = (body_arrays(casing, dt, True, fcs, nsub), body_arrays(cable, dt, True, fcc, nsub), claw, contact)
    rec = K.Recording(False, np.zeros((1, 24)), np.zeros(2, np.int64), *(np.zeros(1, d) for d in ("i4", "i1")),
                      np.zeros(1), np.zeros(1), 0)  # fmt: skip
    x, v, state = np.zeros(n), np.zeros(n), np.zeros(n, np.int64)
    info = np.zeros(K.INFO_SIZE)
    scratch = K.step_scratch(args[0], args[1], contact, nch, nsub)
    for k in range(n):  # one step per call, to read the mass's state at every step
        status = K.run_steps(
            k * dt, dt, up[k : k + 1], vp[k : k + 1], ap[k : k + 1], *args, np.zeros(24), np.zeros(K.LEDGER_SIZE),
            False, scratch, rec, info,
        )  # fmt: skip
        assert status == K.OK, status
        x[k], v[k], state[k] = cable.U[6], cable.V[6], contact.state[1]
    return t, x, v, state, int(info[K.INFO_REFINED_STEPS])


@pytest.fixture(scope="session")
def wall_mass():
    """:func:`mass_on_the_wall`, for the stick-slip tests against closed forms and event-driven
    references."""
    return mass_on_the_wall
