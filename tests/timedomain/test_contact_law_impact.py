"""A mass dropped onto the casing wall through the engine's own contact kernel
(``kernels.solve_contact_forces``, Newmark for the mass as in test_friction.py): contact duration
and rebound against Hertz's impact theory and against an independent integration of the
Hunt-Crossley law (scipy's solve_ivp), converging at second order with a single contact episode.
"""

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from cablecasing_core.model.schema import CONTACT_LAWS
from cablecasing_core.timedomain import kernels as K

M_ = 1.0e-3  # kg, about a cable element's mass
K_H = 1.0e9  # N/m^1.5, the order of the specimen's Hertz constant
V_IN = 0.05  # m/s, towards the wall
GAP = 1.0e-3  # m, radial gap
HERTZ, HUNT_CROSSLEY = CONTACT_LAWS.index("hertz"), CONTACT_LAWS.index("hunt_crossley")


def drop(law, c_n, dt, t_end):
    """The node starts 1 um short of the wall, moving at V_IN along +z (the wall's normal), the
    casing rigid. Returns (time of first touch, time of release, rebound speed, episodes): the first
    two from the free flights before and after (straight lines in t, so their crossing of the wall is
    exact), the rebound speed of the free flight after."""
    z0 = GAP - 1e-6
    Xc, Tc = np.array([[0.0, 0, z0]]), np.array([[1.0, 0, 0]])
    Xs, Rs, Ls = np.array([[-5.0, 0, 0], [5.0, 0, 0]]), np.eye(3)[None].copy(), np.array([10.0])
    Keff = 4 * M_ / dt**2
    Kc = np.zeros((6, 6))
    Kc[2, 2] = 1 / Keff  # only z responds
    Ks = np.zeros((12, 12))  # rigid casing
    state, elem, xi, vrel = np.zeros(1, np.int64), np.zeros(1, np.int64), np.zeros(1), np.zeros(1)
    Pn, Pp, Nn, gn, diag = np.zeros((1, 3)), np.zeros((1, 3)), np.zeros(1), np.zeros(1), np.zeros(K.DIAG_SIZE)
    fcc, fcs = np.zeros(6), np.zeros(12)
    ws = K.contact_workspace(1)
    par = (GAP, GAP + 1e-3, law, 0.0, K_H, c_n, 0.0, 0.0, dt, False, 0.0, 0.0)  # frictionless
    u, v, a = 0.0, V_IN, 0.0
    closed, episodes, t_in, t_out, v_out = False, 0, None, None, None
    for n in range(int(round(t_end / dt))):
        t = (n + 1) * dt
        us = u + dt * v + dt * dt / 4 * a
        Uc, Vc = np.zeros(6), np.zeros(6)
        Uc[2], Vc[2] = us, 2 / dt * (us - u) - v
        K.solve_contact_forces(
            Xc, Tc, Uc, Vc, Xs, Rs, Ls, np.zeros(12), np.zeros(12), Kc, Ks, par, state, elem, xi, Pn, Pp, vrel, Nn, gn,
            fcc, fcs, diag, ws,
        )  # fmt: skip
        un = us + fcc[2] / Keff
        an = 4 / dt**2 * (un - u) - 4 / dt * v - a
        vn = v + dt / 2 * (a + an)
        now = Nn[0] > 0
        if now and not closed:
            episodes += 1
            if t_in is None:  # the free flight up to the step before: z0 + u + v (t' - t_prev)
                t_in = (t - dt) + (GAP - z0 - u) / v
        if closed and not now and t_out is None:
            t_out, v_out = t + (GAP - z0 - un) / vn, vn  # the free flight after: back through the wall
        closed = now
        u, v, a = un, vn, an
    return t_in, t_out, v_out, episodes


def hertz_theory():
    """Duration and rebound of an elastic Hertz impact: max penetration (5 m v^2 / (4 k))^(2/5),
    duration 2 (delta / v) int_0^1 dx / sqrt(1 - x^(5/2)), rebound -v."""
    delta = (5 * M_ * V_IN**2 / (4 * K_H)) ** 0.4
    integral = quad(lambda x: 1 / np.sqrt(1 - x**2.5), 0, 1, limit=200)[0]
    return 2 * delta / V_IN * integral, -V_IN


def hunt_crossley_reference(alpha):
    """Duration and rebound speed of m g'' = -k g^1.5 (1 + 3/2 alpha g') (N >= 0) from g = 0,
    g' = V_IN, by solve_ivp at rtol 1e-12 with the release (g = 0 going out) as its event (the
    rebound as a velocity, negative)."""

    def rhs(t, y):
        g, gd = y
        N = max(K_H * max(g, 0.0) ** 1.5 * (1 + 1.5 * alpha * gd), 0.0)
        return [gd, -N / M_]

    out = lambda t, y: y[0] if t > 1e-9 else 1.0  # noqa: E731
    out.terminal, out.direction = True, -1
    sol = solve_ivp(rhs, (0, 1e-3), [0.0, V_IN], rtol=1e-12, atol=1e-18, events=out, method="DOP853")
    return sol.t_events[0][0], sol.y_events[0][0][1]


def errors(law, c_n, dts, T, v_ref):
    out = []
    for dt in dts:
        t_in, t_out, v_out, episodes = drop(law, c_n, dt, 4 * T)
        assert episodes == 1, f"dt {dt}: {episodes} contact episodes (no spurious bounces allowed)"
        out.append((abs((t_out - t_in) - T) / T, abs(v_out - v_ref) / abs(v_ref)))
    return np.array(out)


def test_hertz_impact_duration_and_rebound_converge_at_second_order():
    T, v_ref = hertz_theory()  # ~0.15 ms
    dts = T / np.array([20, 40, 80, 160])
    err = errors(HERTZ, 0.0, dts, T, v_ref)
    # second order: each halving of dt divides the errors by ~4 (>= 3 allows the pre-asymptotic start)
    assert np.all(err[:-1, 0] / err[1:, 0] > 3.0), err
    assert err[-1, 0] < 1e-3 and err[-1, 1] < 1e-3, err  # 160 steps per impact: well below 0.1 %


@pytest.mark.parametrize("alpha", [0.5, 2.0])
def test_hunt_crossley_restitution_is_one_less_alpha_v_for_light_damping(alpha):
    """Hunt & Crossley's e ~ 1 - alpha v_in, to first order in alpha v_in (so within (alpha v_in)^2)."""
    e = -hunt_crossley_reference(alpha)[1] / V_IN
    assert abs(e - (1 - alpha * V_IN)) < (alpha * V_IN) ** 2


@pytest.mark.parametrize("alpha", [2.0, 10.0])  # e = 0.91 and 0.66
def test_hunt_crossley_restitution_and_duration_against_an_independent_integration(alpha):
    T, v_ref = hunt_crossley_reference(alpha)
    dts = T / np.array([40, 80, 160, 320])  # (the rebound's error is pre-asymptotic at 20 steps per impact)
    err = errors(HUNT_CROSSLEY, 1.5 * alpha, dts, T, v_ref)
    assert np.all(err[:-1] / err[1:] > 3.0), err  # second order in duration and rebound
    assert err[-1].max() < 1e-3, err
