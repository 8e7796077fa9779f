"""The static state of an installed cable (issue 23): gravity, tension, a cable straight off the reel,
held by frictionless contact across the gap; checked against closed forms (beam sag, capstan,
an arc's pure bending, a curved cantilever by Castigliano), an independent 2D frame solve, the
balance of forces and moments, and the time domain, which must stay at rest in it."""

import numpy as np
import pytest
from scipy.optimize import minimize

import cablecasing_core as cc
from cablecasing_core.model.schema import SUPPORT_OUTPUTS
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.static_state import static_state

CABLE = dict(E=5.5e10, rho=7850.0, d=0.003)
RIGID_CASING = dict(E=5e14, rho=1.0, d_outer=0.0095)  # (a casing that does not move: the wall alone)


def pair(points, n, cable=None, casing=None, loads=None, contact=None, curve="polyline", gap=5e-4):
    cab = dict(CABLE, **(cable or {}))
    cas = dict(RIGID_CASING, d_inner=cab["d"] + 2 * gap, **(casing or {}))
    return cc.model_from_dict(
        {
            "geometry": {"points": [list(map(float, p)) for p in points], "n_elements": n, "curve": curve},
            "casing": cas,
            "cable": cab,
            "contact": contact or {},
            "loads": loads or {},
        }
    )


def cable_balance(st, model):
    """Resultant force and moment (about the origin, reference positions: linear theory) of every
    force on the cable: the casing's contact forces, its supports' (minus what it exerts on them)
    and its weight (at each node, the consistent load's resultant), less the resultant of the
    geometric stiffness's forces K_G u (zero force; a moment of order T |u|: the tension's forces
    turned with the cable, the linear equilibrium's first-order share of the deformed geometry).
    The rest shape's and the prestress's loads are self-equilibrated and do not enter."""
    from cablecasing_core.structure.assembly import assemble_body
    from cablecasing_core.structure.loads import gravity_load

    s = assemble_body(model, "cable")
    X = s.centerline.nodes
    w = gravity_load(s.M, model.loads["gravity"]).reshape(-1, 6)
    kg = (s.K_G @ st.U["cable"]).reshape(-1, 6)
    F = st.contact_force.sum(0) + w[:, :3].sum(0) - kg[:, :3].sum(0)
    Mo = np.cross(X, st.contact_force).sum(0) + np.cross(X, w[:, :3]).sum(0) + w[:, 3:].sum(0)
    Mo -= np.cross(X, kg[:, :3]).sum(0) + kg[:, 3:].sum(0)
    for sup, node in (("A", 0), ("B", -1)):
        if model.bodies["cable"].supports[sup] == "clamped":
            r = -st.reaction(f"cable.{sup}")
            F += r[:3]
            Mo += np.cross(X[node], r[:3]) + r[3:]
    return F, Mo


# ------------------------------------------------------------------------------ gravity
@pytest.mark.parametrize("d, gap, touches", [(0.002, 5e-4, True), (0.0035, 5e-4, True), (0.0045, 1e-3, False)])
def test_a_horizontal_cable_sags_onto_the_wall_where_its_sag_exceeds_the_gap(d, gap, touches):
    """Straight horizontal casing (rigid), clamped cable of steel under its weight: the clamped-
    clamped sag q L^4 / (384 EI) is 7.6 and 2.5 times a 0.5 mm gap for d = 2 and 3.5 mm, and 0.76
    times a 1 mm gap for d = 4.5 mm. Touching: the cable lies on the wall in the middle (to its
    Hertz penetration, (N / k)^(2/3) < 1e-7 m), and its contact forces and support reactions balance
    its weight (to the solver's 1e-10); not touching: no contact, and the midspan sag is the closed
    form (cubic elements are exact at the nodes)."""
    L = 1.0
    model = pair([[0, 0, 0], [L, 0, 0]], 40, cable=dict(E=2.1e11, d=d), loads={"gravity": [0, 0, -9.81]}, gap=gap)
    st = static_state(model)
    q = 7850.0 * np.pi * d**2 / 4 * 9.81
    sag = q * L**4 / (384 * 2.1e11 * np.pi * d**4 / 64)
    assert (sag > gap) == touches
    uz = st.U["cable"].reshape(-1, 6)[:, 2]
    W = st.weight["cable"][2]
    Fz = st.contact_force[:, 2].sum()
    Rz = st.reaction("cable.A")[2] + st.reaction("cable.B")[2]  # what the cable exerts on its supports
    assert Fz + W - Rz == pytest.approx(0.0, abs=1e-9 * abs(W))
    if touches:
        assert st.contact_nodes > 0 and np.all(st.contact_force[:, 2] >= 0)  # the wall pushes up
        assert uz[20] == pytest.approx(-gap, abs=1e-7)  # resting on the wall
        assert Fz > 0.1 * abs(W)
    else:
        assert st.contact_nodes == 0
        assert uz[20] == pytest.approx(-sag, rel=1e-6)


def test_the_installed_specimen_carries_its_weight():
    """The installed specimen: both bodies' weight goes into the four supports (the contact is
    internal), and the cable's forces and moments balance (to 1e-9 of its largest contact force;
    with the geometric stiffness's share, see cable_balance)."""
    model = cc.load_model("installed")
    st = static_state(model)
    W = st.weight["casing"] + st.weight["cable"]
    R = st.reactions.reshape(4, 6)[:, :3].sum(0)  # forces the bodies exert on the supports
    np.testing.assert_allclose(R, W, atol=1e-9 * np.abs(st.contact_force).max())
    F, Mo = cable_balance(st, model)
    scale = np.abs(st.contact_force).max()
    np.testing.assert_allclose(F, 0.0, atol=1e-9 * scale)
    np.testing.assert_allclose(Mo, 0.0, atol=1e-9 * scale)
    assert st.contact_nodes >= 10 and st.max_penetration < 0.05 * model.radial_gap


# ------------------------------------------------------------------------------ tension
def route(R, theta, lead, h):
    """A planar route along +x: a straight lead, an arc (radius R, angle theta, towards +y), a
    straight lead, sampled every ~h (m)."""
    pts = [[x, 0.0, 0.0] for x in np.arange(-lead, 0.0, h)]
    a = np.linspace(0.0, theta, int(round(R * theta / h)) + 1)
    pts += [[R * np.sin(t), R * (1 - np.cos(t)), 0.0] for t in a]
    end, tg = np.array(pts[-1]), np.array([np.cos(theta), np.sin(theta), 0.0])
    pts += [list(end + tg * h * i) for i in range(1, int(round(lead / h)) + 1)]
    return np.array(pts)


def test_a_tensioned_cable_presses_on_the_inside_of_a_bend_by_t_over_r():
    """Capstan: a flexible cable (d = 1 mm, k = sqrt(T/EI) = 31 /m, so it bends like a string over
    the 0.2 m radius) under 20 N, in a 90 degree bend between straight leads, lies against the inside
    of the bend and presses on it with T / R per metre (within 1 %, the bending share ~ 1 / (k R)^2),
    towards the centre; the resultant over the bend is 2 T sin(theta / 2) (within 3 %: the cable
    leaves the wall over ~1 / k at each end of the arc)."""
    R, theta, T = 0.2, np.pi / 2, 20.0
    P = route(R, theta, 0.15, 0.008)  # the element nodes, on the arc
    model = pair(P, len(P) - 1, cable=dict(d=0.001), contact={"law": "linear", "stiffness": 1e7},
                 loads={"cable_tension": T})  # fmt: skip
    st = static_state(model)
    s, F = st.arc_length, st.contact_force
    ds = s[1] - s[0]
    mid = (s > 0.15 + 0.05) & (s < 0.15 + R * theta - 0.05)
    np.testing.assert_allclose(np.linalg.norm(F[mid], axis=1) / ds, T / R, rtol=0.01)
    towards = np.array([0.0, R, 0.0]) - P[mid]  # to the arc's centre
    cos = np.einsum("ij,ij->i", F[mid], towards) / np.linalg.norm(F[mid], axis=1) / np.linalg.norm(towards, axis=1)
    # the cable presses towards the centre, the wall pushes it back: within 0.01 rad (a node's tangent
    # bisects its two chords; 0.0078 rad measured, the cable's own turn across the gap; it was the
    # polyline's half corner angle, 0.02 rad, while a node took its next chord's direction)
    assert np.all(cos < -np.cos(0.01))
    assert np.linalg.norm(F.sum(0)) == pytest.approx(2 * T * np.sin(theta / 2), rel=0.03)
    # the mean axial force of the cable is the tension (the condition the pre-stretch force meets)
    assert st.prestretch_force > T


@pytest.mark.parametrize("n", [20, 21])
def test_a_tension_round_a_polyline_corner_pulls_both_legs_alike(n):
    """A 10 N tension round a 90 degree polyline corner at 0.4 m of each leg (a review's model):
    with frictionless contact the tension is the same in both legs, so each clamped end carries
    10 N along its leg (within 1 %: the bending share) and the wall pushes the cable along the
    corner's bisector with 2 T sin 45 deg = 14.1 N (within 2 %). With the corner on a node (n = 20)
    that node's normal plane leaned to the span after it, and the ends carried 19.7 and 0.3 N."""
    T = 10.0
    model = pair([[0, 0, 0], [0.4, 0, 0], [0.4, 0.4, 0]], n, loads={"cable_tension": T},
                 casing=dict(E=5e9, rho=4850.0, d_outer=0.0095, I=2.7261e-10))  # fmt: skip
    st = static_state(model)
    assert np.linalg.norm(st.reaction("cable.A")[:3]) == pytest.approx(T, rel=0.01)
    assert np.linalg.norm(st.reaction("cable.B")[:3]) == pytest.approx(T, rel=0.01)
    wall = st.contact_force.sum(0)
    assert np.linalg.norm(wall) == pytest.approx(2 * T * np.sin(np.pi / 4), rel=0.02)
    assert wall[0] == pytest.approx(-wall[1], rel=0.01)  # (along the bisector, (1, -1, 0) / sqrt 2)


def test_a_straight_tensioned_cable_pulls_on_its_supports():
    """No curvature, no contact: the cable pulls each support towards the other with T (the
    force it exerts on the support, the time domain's sign convention), and the casing pushes them
    apart with the equal compression; each support pair (cable and casing end) carries nothing net."""
    T = 7.0
    st = static_state(pair([[0, 0, 0], [0.8, 0, 0]], 20, loads={"cable_tension": T}))
    np.testing.assert_allclose(st.reaction("cable.A")[:3], [T, 0, 0], atol=1e-9)
    np.testing.assert_allclose(st.reaction("cable.B")[:3], [-T, 0, 0], atol=1e-9)
    np.testing.assert_allclose(st.reaction("casing.A")[:3], [-T, 0, 0], atol=1e-9)
    assert st.contact_nodes == 0 and st.prestretch_force == pytest.approx(T, rel=1e-12)


# ------------------------------------------------------------------------------ straight rest shape
def test_a_straight_cable_in_a_clamped_arc_carries_pure_bending():
    """A cable straight off the reel, clamped at both ends of a circular arc (R = 0.2 m, 1 rad):
    bent by end moments alone (uniform curvature needs no lateral load), so it does not move and
    touches nothing, and each support holds the moment EI / R about the arc's axis. Tolerance 1e-4:
    the polygon's corner curvature is 2 sin(theta_e / 2) / chord = 1 / R (1 + O(theta_e^2))."""
    R, th = 0.2, 1.0
    a = np.linspace(0.0, th, 41)
    model = pair([[R * np.sin(t), R * (1 - np.cos(t)), 0.0] for t in a], 40, cable={"rest_shape": "straight"})
    st = static_state(model)
    EI = CABLE["E"] * np.pi * CABLE["d"] ** 4 / 64
    assert st.contact_nodes == 0 and np.abs(st.U["cable"]).max() < 1e-12
    np.testing.assert_allclose(st.reaction("cable.A")[3:], [0, 0, EI / R], rtol=1e-4, atol=1e-9)
    np.testing.assert_allclose(st.reaction("cable.B")[3:], [0, 0, -EI / R], rtol=1e-4, atol=1e-9)


def test_a_straight_cantilever_released_from_an_arc_straightens():
    """Clamped at A and free at B, the straight cable in a circular arc springs back (contact off):
    its tip moves by the arc's deviation from its tangent, R (1 - cos theta) outwards and
    R (theta - sin theta) backwards (Castigliano, bending only; within 0.3 %: the arc's axial
    compliance and the polygon)."""
    R, th = 0.3, 0.5
    a = np.linspace(0.0, th, 41)
    pts = [[R * np.sin(t), R * (1 - np.cos(t)), 0.0] for t in a]
    model = pair(pts, 40, cable={"rest_shape": "straight", "supports": {"A": "clamped", "B": "free"}})
    st = static_state(model, contact=False)
    u = st.U["cable"].reshape(-1, 6)[-1, :3]
    out, tangent = np.array([np.sin(th), -np.cos(th), 0.0]), np.array([np.cos(th), np.sin(th), 0.0])
    assert u @ out == pytest.approx(R * (1 - np.cos(th)), rel=3e-3)
    assert u @ tangent == pytest.approx(-R * (th - np.sin(th)), rel=3e-3)


def frame_2d(P, EA, EI, e, k):
    """An independent 2D computation of the same problem: planar frame elements (axial and cubic
    bending) along the polygon P (m), the cable stress-free straight (the initial-curvature load of
    each element from the polygon's corner curvatures), clamped at both ends, against a rigid wall
    at +-e (m) on each node's normal (the bisector of its two chords), linear law k (N/m), by
    minimising the energy with scipy.optimize. Returns the force of the wall on each node along
    its normal (N)."""
    seg = np.diff(P, axis=0)
    Le = np.linalg.norm(seg, axis=1)
    t = seg / Le[:, None]
    n = len(Le)
    turn = np.arctan2(t[1:, 1], t[1:, 0]) - np.arctan2(t[:-1, 1], t[:-1, 0])
    kap = np.zeros(n + 1)
    kap[1:-1] = turn / (0.5 * (Le[:-1] + Le[1:]))
    kap[0], kap[-1] = kap[1], kap[-2]
    N = 3 * (n + 1)
    K, f = np.zeros((N, N)), np.zeros(N)
    for el in range(n):
        L, (c, s) = Le[el], t[el]
        kl = np.zeros((6, 6))
        kl[np.ix_([0, 3], [0, 3])] = EA / L * np.array([[1, -1], [-1, 1]])
        kl[np.ix_([1, 2, 4, 5], [1, 2, 4, 5])] = (
            EI / L**3 * np.array([[12, 6 * L, -12, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                                  [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]])
        )  # fmt: skip
        k1, k2 = kap[el], kap[el + 1]  # curvature strain of the bent straight cable, linear along the element
        fl = np.zeros(6)
        fl[[1, 2, 4, 5]] = -EI * np.array([(k2 - k1) / L, -k1, -(k2 - k1) / L, k2])  # -int B^T EI kappa
        T = np.zeros((6, 6))
        T[:3, :3] = T[3:, 3:] = [[c, s, 0], [-s, c, 0], [0, 0, 1]]
        i = np.arange(3 * el, 3 * el + 6)
        K[np.ix_(i, i)] += T.T @ kl @ T
        f[i] += T.T @ fl
    free = np.arange(3, N - 3)
    tn = np.vstack([t[0], t[:-1] + t[1:], t[-1]])
    tn /= np.linalg.norm(tn, axis=1)[:, None]
    nu = np.column_stack([-tn[:, 1], tn[:, 0]])

    def parts(z):
        u = np.zeros(N)
        u[free] = z
        w = (u.reshape(-1, 3)[:, :2] * nu).sum(1)
        g = np.maximum(np.abs(w) - e, 0.0)
        grad = K @ u - f
        grad.reshape(-1, 3)[:, :2] += (k * g * np.sign(w))[:, None] * nu
        H = K.copy()
        for j in np.flatnonzero(g > 0):
            H[3 * j : 3 * j + 2, 3 * j : 3 * j + 2] += k * np.outer(nu[j], nu[j])
        return 0.5 * u @ K @ u - f @ u + 0.5 * k * g @ g, grad[free], H[np.ix_(free, free)], w

    res = minimize(lambda z: parts(z)[0], np.zeros(len(free)), jac=lambda z: parts(z)[1],
                   hess=lambda z: parts(z)[2], method="trust-exact", options={"gtol": 1e-10})  # fmt: skip
    assert res.success
    w = parts(res.x)[3]
    return -k * np.maximum(np.abs(w) - e, 0.0) * np.sign(w), nu


def test_a_straight_cable_in_a_bend_against_an_independent_2d_solve():
    """A cable straight off the reel in a rigid planar casing (lead, 0.8 rad arc of radius 0.2 m,
    lead; gap 0.5 mm; linear law): it presses on the wall near both ends of the arc, where the
    curvature changes. The contact forces against a separately written 2D frame model minimised
    with scipy (frame_2d): the same nodes, forces within 0.5 % of the largest (the two models
    measure the gap in slightly different directions, the bisector normal against the 3D search's
    normal plane: a second-order difference in the 0.05 rad corner angle, 2.5e-3)."""
    P = route(0.2, 0.8, 0.1, 0.01)
    e, k = 5e-4, 1e7
    model = pair(P, len(P) - 1, cable={"rest_shape": "straight"}, contact={"law": "linear", "stiffness": k}, gap=e)
    st = static_state(model)
    A, I = np.pi * CABLE["d"] ** 2 / 4, np.pi * CABLE["d"] ** 4 / 64
    F2, nu = frame_2d(P[:, :2], CABLE["E"] * A, CABLE["E"] * I, e, k)
    F3 = (st.contact_force[:, :2] * nu).sum(1)
    assert np.array_equal(np.flatnonzero(F2), np.flatnonzero(st.normal_force))
    assert len(np.flatnonzero(F2)) >= 2
    np.testing.assert_allclose(F3, F2, atol=5e-3 * np.abs(F2).max())
    F, Mo = cable_balance(st, model)
    np.testing.assert_allclose(np.concatenate([F, Mo]), 0.0, atol=1e-9 * np.abs(F2).max())


def test_the_hertz_law_and_the_linear_law_agree_where_the_penetration_is_small():
    """The same straight cable in the bend with the Hertz law (Eq. 29): the same contact nodes, and
    the forces within 1 % of the linear law's (the penetrations, ~10 um of a 0.5 mm gap, change
    the cable's deflection by ~1 %)."""
    P = route(0.2, 0.8, 0.1, 0.01)
    linear = {"law": "linear", "stiffness": 1e7}
    lin = static_state(pair(P, len(P) - 1, cable={"rest_shape": "straight"}, contact=linear))
    hz = static_state(pair(P, len(P) - 1, cable={"rest_shape": "straight"}))
    assert np.array_equal(np.flatnonzero(lin.normal_force), np.flatnonzero(hz.normal_force))
    np.testing.assert_allclose(hz.normal_force, lin.normal_force, atol=0.01 * lin.normal_force.max())


# ------------------------------------------------------------------------------ the time domain from it
def still(t):
    z = np.zeros((len(t), 12))
    return z, z, z


def test_the_time_domain_stays_at_rest_in_the_static_state():
    """The installed specimen's engine starts from the static state with its contacts closed and
    stays there without excitation (0.01 s): its outputs at t = 0 are the static reactions (the total
    support forces), and they change by less than 1e-5 of their size. (The static state is the
    exact equilibrium; each Newmark step solves the contact linearised about its contact-free
    predictor, ~0.3 um away where the forces are 18 N, a first-order error where the cable is tilted
    against the casing axis: ~1e-4 of the contact forces in the first steps, a transient of ~1e-5 of
    the support forces that dies out. The linear part alone stays within 1e-9.)"""
    model = cc.load_model("installed")
    eng = Engine(model, dt=1e-5)
    st = eng.static
    out0 = eng.output_values().copy()
    np.testing.assert_array_equal(out0[: len(SUPPORT_OUTPUTS)], st.reactions)
    assert int(out0[24]) == st.contact_nodes
    eng.advance(0.01, still)
    out1 = eng.output_values()
    scale = np.abs(out0[:24]).max()
    assert np.abs(out1[:24] - out0[:24]).max() < 1e-5 * scale
    assert int(out1[24]) == st.contact_nodes
    for n, b in eng.bodies.items():
        assert np.abs(b.U - st.U[n]).max() < 1e-5 * np.abs(st.U[n]).max()
    linear = Engine(model, dt=1e-5, contact=False)
    out0 = linear.output_values().copy()
    linear.advance(0.01, still)
    assert np.abs(linear.output_values()[:24] - out0[:24]).max() < 1e-9 * scale
    eng.reset()
    np.testing.assert_array_equal(eng.output_values()[:24], st.reactions)


def test_the_energy_ledger_closes_with_the_preload():
    """The installed specimen through its scenario (0.1 s): kinetic + strain + contact energy equal
    the energy at the start plus the supports' and the constant loads' work less what damping and
    friction took, within 1 % of the supplied work (the trapezoidal ledger closes to ~1e-8)."""
    res = cc.simulate(cc.load_model("installed"), duration=0.1)
    e = res.energies
    assert e["support_work"] > 0 and e["friction_dissipation"] > 0
    # the friction (92 % of the supplied work) and damper dissipation, integrated from the powers the
    # contact solve reports, against the contact dissipation from the contact forces' work over the
    # steps' displacements less the stored contact energy: they differ by the normal forces' own work
    # (docs/time_domain.md, "The normal force's work on a mesh"), which on this specimen, its contacts
    # sliding along the wall, stays within 0.55 % of the total over 0.05-0.5 s (changing sign; +8e-5 at
    # 0.1 s); friction power off by 20 % misses by 20 %
    parts = e["friction_dissipation"] + e["contact_damping_dissipation"]
    assert abs(parts / e["contact_dissipation"] - 1) < 1e-2
    assert abs(e["residual"]) < 0.01 * (e["support_work"] + abs(e["load_work"]))
    assert abs(e["residual"]) < 1e-6 * e["support_work"]


def test_without_contact_the_bodies_hang_in_their_loads():
    """contact=False: each body alone under its loads (the cable passes through the wall); the
    engine starts from that state too."""
    model = cc.load_model("installed")
    st = static_state(model, contact=False)
    assert st.contact_nodes == 0
    eng = Engine(model, contact=False)
    for n in eng.bodies:
        np.testing.assert_array_equal(eng.bodies[n].U, st.U[n])


def test_without_contact_the_tension_is_a_fixed_prestress():
    """Review: with contact off, the condition that pulls the cable taut against the bends had
    nothing to hold it there and straightened the cable through the wall (the installed specimen:
    sigma = 7.9e4 N, the cable moved by 0.1 m, 6.8 kJ of strain energy). Without contact the
    tension is the fixed prestress sigma = T, under which a curved cable moves by micrometres."""
    model = cc.load_model("default").with_overrides({"loads.cable_tension": 10.0, "loads.gravity.z": 0.0})
    for st in (static_state(model, contact=False), static_state(model.with_overrides({"contact.enabled": False}))):
        assert st.prestretch_force == 10.0 and not st.pulled
        from cablecasing_core.timedomain.body_storage import time_domain_system

        s = time_domain_system(model, "cable")
        EA, L = s.E * s.section.A, s.centerline.lengths.sum()
        # the cable's hoop shortening under the capstan load T/R is of order T R / EA; its whole
        # length's stretch T L / EA bounds it (measured 1.35e-5 m against 2.6e-5 m)
        assert np.abs(st.U["cable"].reshape(-1, 6)[:, :3]).max() < 10.0 * L / EA
    assert static_state(cc.load_model("installed"), contact=False).prestretch_force == 10.0
    assert static_state(cc.load_model("installed")).pulled


def test_a_static_motion_beyond_two_per_cent_of_the_length_warns_and_is_reported():
    """A 1 m casing clamped at A, free at B, under its weight: its tip sags by q L^4 / (8 E I) =
    0.254 m (within 1e-3: the Hermite beam's nodal values are exact for a uniform load, the
    consistent load's resultant the weight), 25 % of its length, beyond SMALL_DISPLACEMENT: the
    linear statics warn, and the state reports the motion and where it is largest. The installed
    specimen (its cable moves by 7.6 mm of 0.85 m) does not warn."""
    import warnings

    from cablecasing_core.errors import ModelWarning

    casing = dict(
        E=5e9, rho=4850.0, d_outer=0.0095, d_inner=0.004, I=2.7261e-10, supports={"A": "clamped", "B": "free"}
    )
    model = cc.model_from_dict({"geometry": {"points": [[0.0, 0, 0], [1.0, 0, 0]], "n_elements": 20},
                                "casing": casing, "loads": {"gravity": [0.0, 0.0, -9.81]}})  # fmt: skip
    q = 4850.0 * np.pi / 4 * (0.0095**2 - 0.004**2) * 9.81
    with pytest.warns(
        ModelWarning, match=r"casing: the static state moves it by up to 0.254\d* m \(at s = 1 m\), 25.4 %"
    ):
        st = static_state(model)
    d, at = st.largest_displacement["casing"]
    assert d == pytest.approx(q / (8 * 5e9 * 2.7261e-10), rel=1e-3) and at == pytest.approx(1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        installed = cc.load_model("installed")
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        st = static_state(installed)
    assert not [w for w in said if "moves it by" in str(w.message)]
    assert st.largest_displacement["cable"][0] == pytest.approx(7.6e-3, rel=0.05)
