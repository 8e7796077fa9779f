"""Contact of the time domain (Eqs. 14-39): the Hertz constant, the normal-plane search against the
paper's Eq. (39), the far-from-wall bound, the interpolation matrix, the forces' balance and the
effective compliance the contact solve uses."""

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.structure.geometry import centerline_of
from cablecasing_core.timedomain import kernels as K
from cablecasing_core.timedomain.engine import Engine, hertz_constant
from cablecasing_core.timedomain.scenario import scenario_motion, zero_motion


def test_hertz_constant_is_eq_29():
    m = cc.load_model()
    E1, E2, nu = 5.5e10, 5.0e9, 0.3
    Es = 1 / ((1 - nu**2) / E1 + (1 - nu**2) / E2)  # Eq. (28)
    r = 1 / (1 / 0.0015 - 1 / 0.002)  # Eq. (27), concave casing
    g = 1e-5
    F, _ = K.contact_law(g, 0, 0.0, hertz_constant(m))
    assert F == pytest.approx(4 / 3 * r**0.5 * Es * g**1.5, rel=1e-12)  # Eq. (29)
    assert K.contact_law(-1e-6, 0, 0.0, hertz_constant(m))[0] == 0.0  # no adhesion


@pytest.mark.parametrize("shape", ["straight", "arc"])
def test_contact_search_exact_intersection(shape, straight, arc_points, beam_model, probes):
    if shape == "straight":
        pts = np.array([[0, 0, 0], [0.4, 0, 0]], float)
        model = straight(0.4, 8, supports=("clamped", "clamped"))
    else:
        pts = arc_points(0.2, np.pi / 2, 8)
        model = beam_model(pts, 8)
    cl = centerline_of(model)
    rng = np.random.default_rng(3)
    shift = np.array([1e-4, -2e-4, 3e-4])  # rigid translation: the Hermite axis stays straight
    Us = np.zeros(6 * len(cl.nodes))
    for i in range(len(cl.nodes)):
        Us[6 * i : 6 * i + 3] = shift
    for _ in range(20):
        e = rng.integers(0, cl.n_elements)
        x1 = cl.nodes[e] + rng.random() * (cl.nodes[e + 1] - cl.nodes[e]) + 3e-4 * rng.standard_normal(3)
        t1 = cl.frames[e][0] + 0.05 * rng.standard_normal(3)
        t1 /= np.linalg.norm(t1)
        ee, xi, far = probes.search_casing(x1, t1, cl.nodes, cl.frames, cl.lengths, Us, e, 0.0)
        # Eq. (39) with the plane through x1 spanned by two vectors normal to t1
        p1 = x1 + np.cross(t1, [0, 0, 1.0]) if abs(t1[2]) < 0.9 else x1 + np.cross(t1, [1.0, 0, 0])
        p2 = x1 + np.cross(t1, p1 - x1)
        l, u, v = probes.line_plane_intersection(cl.nodes[ee] + shift, cl.nodes[ee + 1] + shift, x1, p1, p2)
        assert not far
        assert xi == pytest.approx(l, abs=1e-9)
        point = probes.casing_point(cl.nodes, cl.frames, cl.lengths, Us, ee, xi)
        assert abs((point - x1) @ t1) < 1e-12


def test_far_test_never_claims_a_node_closer_than_the_hermite_axis_is(straight, probes):
    """The search's cheap exit (far: certainly nearer than far_below to the deformed axis) must bound
    the distance to the Hermite axis from above. The axis departs from the chord between the
    deformed nodes also when the ends' rotations differ from the chord's own turn psi (an element
    whose ends move apart sideways with no rotation is an S-curve): 0.096 L psi = 1e-5 m here."""
    model = straight(0.4, 8, supports=("clamped", "clamped"))
    cl = centerline_of(model)
    rng = np.random.default_rng(5)
    worst = 0.0
    for trial in range(400):
        Us = np.zeros(6 * len(cl.nodes))
        e = int(rng.integers(1, cl.n_elements - 1))
        Us[6 * e + 6 : 6 * e + 9] = 2e-4 * rng.standard_normal(3)  # lateral offset: psi ~ 4e-3
        if trial % 2:
            Us[6 * e : 6 * e + 12] += 1e-3 * rng.standard_normal(12) * np.repeat([1e-1, 1.0, 1e-1, 1.0], 3)
        x1 = cl.nodes[e] + rng.uniform(0.1, 0.9) * (cl.nodes[e + 1] - cl.nodes[e])
        x1 += 4e-5 * np.r_[0.0, rng.standard_normal(2)]
        t1 = cl.frames[e][0]
        ee, xi, far = probes.search_casing(x1, t1, cl.nodes, cl.frames, cl.lengths, Us, e, -1.0)
        h = np.linalg.norm(x1 - probes.casing_point(cl.nodes, cl.frames, cl.lengths, Us, ee, xi))
        # claimed nearer than h - 1e-9 m: the bound holds to first order in the rotations, whose
        # second-order terms here are ~L theta^2 ~ 1e-9 m
        _, _, far = probes.search_casing(x1, t1, cl.nodes, cl.frames, cl.lengths, Us, e, h - 1e-9)
        assert not far, (trial, h)
        # the same bound without psi (chord distance + L/4 (|theta_a| + |theta_b|)) fails on some
        a, b = cl.nodes[e] + Us[6 * e : 6 * e + 3], cl.nodes[e + 1] + Us[6 * e + 6 : 6 * e + 9]
        chord = np.linalg.norm(a + ((x1 - a) @ t1) / ((b - a) @ t1) * (b - a) - x1)
        rot = np.linalg.norm(Us[6 * e + 3 : 6 * e + 6]) + np.linalg.norm(Us[6 * e + 9 : 6 * e + 12])
        worst = max(worst, h - chord - 0.25 * cl.lengths[e] * rot)
    assert worst > 5e-6  # so the trials do reach the nodes that need psi


def test_hermite_matrix_is_the_rotated_local_interpolation_and_moves_rigidly():
    """H (6x12, global) against diag(R^T, R^T) H_local diag(R, R, R, R) built from the shape
    functions of Eq. (9) by matrix products, and against rigid-body motion, which the shape
    functions reproduce exactly (tolerance: rounding of entries up to 1/L ~ 30)."""
    from scipy.linalg import block_diag

    rng = np.random.default_rng(11)
    for _ in range(10):
        R, _ = np.linalg.qr(rng.standard_normal((3, 3)))
        R[2] *= np.sign(np.linalg.det(R))  # right-handed, as element_frames
        xi, L = rng.random(), 0.035
        N1, N2, N3, N4 = (
            1 - 3 * xi**2 + 2 * xi**3,
            L * (xi - 2 * xi**2 + xi**3),
            3 * xi**2 - 2 * xi**3,
            L * (xi**3 - xi**2),
        )
        D1, D2, D3, D4 = 6 * (xi**2 - xi) / L, 1 - 4 * xi + 3 * xi**2, 6 * (xi - xi**2) / L, 3 * xi**2 - 2 * xi
        Hl = np.zeros((6, 12))
        Hl[0, [0, 6]] = 1 - xi, xi  # axial
        Hl[1, [1, 5, 7, 11]] = N1, N2, N3, N4  # v, from theta_z
        Hl[2, [2, 4, 8, 10]] = N1, -N2, N3, -N4  # w, from -theta_y
        Hl[3, [3, 9]] = 1 - xi, xi  # twist
        Hl[4, [2, 4, 8, 10]] = -D1, D2, -D3, D4  # theta_y = -w'
        Hl[5, [1, 5, 7, 11]] = D1, D2, D3, D4  # theta_z = v'
        H = np.full((6, 12), np.nan)
        K.hermite_matrix(xi, L, R, H)
        np.testing.assert_allclose(H, block_diag(R.T, R.T) @ Hl @ block_diag(R, R, R, R), rtol=0, atol=1e-12)
        c, w = rng.standard_normal(3) * 1e-4, rng.standard_normal(3) * 1e-3  # rigid motion
        Xa = rng.standard_normal(3)
        Xb, X = Xa + L * R[0], Xa + xi * L * R[0]
        q = np.r_[c + np.cross(w, Xa), w, c + np.cross(w, Xb), w]
        np.testing.assert_allclose(H @ q, np.r_[c + np.cross(w, X), w], rtol=0, atol=1e-15)


def test_hermite_matrix_slope_is_the_derivative_of_the_displacement_rows():
    """dA/dxi (``hermite_matrix_slope``) against Richardson's extrapolation of central differences
    of ``hermite_matrix``'s displacement rows: for a cubic in xi, (4 D(h/2) - D(h)) / 3 is exact, so
    only rounding is left (entries up to ~L / h^2 eps ~ 1e-10 for h = 1e-3, L = 0.035 m; tolerance
    1e-9), at the ends too (xi = 0 and 1, where a difference quotient of the clipped kernel is one-sided)."""
    rng = np.random.default_rng(12)
    L, h = 0.035, 1e-3

    def rows(x, R):
        H = np.zeros((6, 12))
        K.hermite_matrix(x, L, R, H)
        return H[:3]

    def central(xi, s, R):  # (the cubics extend past [0, 1])
        return (rows(xi + s, R) - rows(xi - s, R)) / (2 * s)

    for xi in (0.0, 1.0, *rng.random(6)):
        R, _ = np.linalg.qr(rng.standard_normal((3, 3)))
        R[2] *= np.sign(np.linalg.det(R))
        A1 = np.full((3, 12), np.nan)
        K.hermite_matrix_slope(xi, L, R, A1)
        np.testing.assert_allclose(A1, (4 * central(xi, h / 2, R) - central(xi, h, R)) / 3, rtol=0, atol=1e-9)


def test_contact_forces_balance_force_and_moment(pair_model, kick):
    m = pair_model(friction=0.3)
    eng = Engine(m, dt=2e-5, contact=True)
    kick(eng, 0.3)
    for _ in range(200):
        eng.advance(2e-4, zero_motion)
        if eng.outputs()["contact.active"] > 0:
            break
    assert eng.outputs()["contact.active"] > 0
    tot_F = np.zeros(3)
    tot_M = np.zeros(3)
    for name, fc in (("cable", eng.fcc), ("casing", eng.fcs)):
        b = eng.bodies[name]
        X = b.system.centerline.nodes + b.U.reshape(-1, 6)[:, :3]
        f = fc.reshape(-1, 6)
        tot_F += f[:, :3].sum(axis=0)
        tot_M += (np.cross(X - 0 * X, f[:, :3]) + f[:, 3:]).sum(axis=0)
    scale = np.abs(eng.fcc).max()
    assert np.linalg.norm(tot_F) < 1e-9 * scale
    # moments about the origin: the shape functions keep the moment of the load about the element's
    # reference (undeformed) axis; the deformed lever arm differs by the displacement (~1e-4 m)
    assert np.linalg.norm(tot_M) < 1e-3 * scale


def test_contact_compliance_is_the_inverse_of_the_effective_stiffness():
    # the dense inverse the contact solve reads comes from the block LDL factor; against LAPACK's
    # inverse of the free part (measured 1.2e-15 of the largest entry; 1e-12 is rounding with room)
    dt = 1e-5
    for b in Engine(cc.load_model()).bodies.values():
        Dinv, L, LT, inv = b.factors(dt, True)
        g = slice(b.g0, b.g0 + b.ng)
        keff = (1 + 2 * b.beta / dt) * b.K_full[g, g] + (4 / dt**2 + 2 * b.alpha / dt) * b.M_full[g, g]
        f = slice(b.f0 - b.g0, b.f0 - b.g0 + b.nf)
        ref = np.linalg.inv(keff[f, f])
        free = slice(b.f0, b.f0 + b.nf)
        assert np.abs(inv[free, free] - ref).max() < 1e-12 * np.abs(ref).max()
        assert np.array_equal(inv, inv.T) and not inv[: b.f0].any() and not inv[:, b.f0 + b.nf :].any()


def test_delassus_blocks_are_the_dense_products():
    """The contact solve's Delassus blocks (Eq. 38's W = B^T K^-1 B, both bodies) against the dense
    products in numpy: the casing's G_k^T K[dofs_k, dofs_l] G_l for every pair l >= k, built from
    rows of compliance over spans of columns, here on a casing of 426 DOFs, more than one span
    (SPAN), with contacts spread and out of order; the cable's B_k^T K[dofs_k, dofs_l] B_l with
    B = [I; [a]x] written out on its nonzero entries. Tolerance 1e-13 of the largest entry: sums of
    at most 144 products of numbers of order one."""
    from cablecasing_core.timedomain.kernels._contact_forces_with_active_set import (
        SPAN,
        _cable_compliance_block,
        _casing_compliance_row,
    )

    rng = np.random.default_rng(7)
    ns = 6 * 71
    assert ns > SPAN
    A = rng.standard_normal((ns, ns))
    Ks = A + A.T
    elem = np.array([3, 4, 10, 69, 30, 31, 55, 0, 40])
    nk = len(elem)
    idx = np.arange(nk)
    Gs = rng.standard_normal((nk, 12, 3))
    W = np.zeros((3 * nk, 3 * nk))
    U = np.zeros(3 * SPAN)
    for k in range(nk):
        _casing_compliance_row(Ks, Gs, idx, elem, k, nk, W, U)
    for k in range(nk):
        for l in range(nk):
            dk, dl = slice(6 * elem[k], 6 * elem[k] + 12), slice(6 * elem[l], 6 * elem[l] + 12)
            ref = Gs[k].T @ Ks[dk, dl] @ Gs[l] if l >= k else np.zeros((3, 3))
            got = W[3 * k : 3 * k + 3, 3 * l : 3 * l + 3]
            assert np.abs(got - ref).max() <= 1e-13 * np.abs(W).max(), (k, l)

    nc = 6 * 37
    A = rng.standard_normal((nc, nc))
    Kc = A + A.T
    arms = rng.standard_normal((2, 3)) * 1e-3
    nodes = (5, 21)

    def B(a):
        b = np.zeros((6, 3))
        b[:3] = np.eye(3)
        b[3:] = [[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]]  # moment a x P
        return b

    Wc = np.zeros((3, 3))
    _cable_compliance_block(Kc, 6 * nodes[0], *arms[0], 6 * nodes[1], *arms[1], Wc, 0, 0)
    ref = B(arms[0]).T @ Kc[6 * nodes[0] : 6 * nodes[0] + 6, 6 * nodes[1] : 6 * nodes[1] + 6] @ B(arms[1])
    assert np.abs(Wc - ref).max() <= 1e-13 * np.abs(ref).max()


@pytest.mark.parametrize("m, b", [(5, 1), (36, 3), (36, 8), (40, 39)])
def test_band_factors_solve_the_band_of_the_matrix(m, b):
    """The regularised law's Newton factors the band of its Jacobian within b of the diagonal: the
    solve equals LAPACK's of the matrix with everything outside the band set to zero, including
    rows that must be swapped to pivot (a small diagonal). Tolerance 1e-11 of the solution's size
    for a matrix whose condition number is below 1e4 (checked): 1e-16 rounding times it, with room."""
    from cablecasing_core.timedomain.kernels._contact_newton_for_fixed_modes import _band_lu_factor, _band_lu_solve

    rng = np.random.default_rng(m + b)
    A = rng.standard_normal((m, m)) + 4.0 * np.eye(m)
    A[np.arange(0, m, 3), np.arange(0, m, 3)] = 1e-3  # rows that need a pivot from below
    band = np.where(np.abs(np.subtract.outer(np.arange(m), np.arange(m))) <= b, A, 0.0)
    assert np.linalg.cond(band) < 1e4
    rhs = rng.standard_normal(m)
    ref = np.linalg.solve(band, rhs)
    F, piv = A.copy(), np.zeros(m, np.int64)
    _band_lu_factor(F, m, b, piv)
    assert np.any(piv != np.arange(m))  # it pivoted
    for far_first in (True, False):  # (the back substitution's two orders of the same sums)
        x = np.zeros(m)
        _band_lu_solve(F, piv, b, rhs.copy(), m, x, far_first)
        assert np.abs(x - ref).max() <= 1e-11 * np.abs(ref).max()


def _installed_contacts(dt):
    """The installed specimen after 0.01 s at the step dt (s): (the engine, the arrays of its last
    contact solve that the Newton takes, the contacts nk, the unknowns r), every contact with its
    three unknowns (the regularised law)."""
    m = cc.load_model("installed")
    eng = Engine(m, dt=dt)
    eng.advance(0.01, scenario_motion(m, dt=dt))
    ws = eng._ws
    (_, gst, gdst, wst, _, _, _, _, _, _, _, J, R, dx, _, _, ta, tb, _, _, Ne, Nd, _, _, xt, touch) = ws[:26]
    Q, x, y, off, wkk, held, piv, sk = ws[27], ws[28], ws[29], ws[30], ws[31], ws[33], ws[34], ws[35]
    nk = int(held[0])
    r = int(off[nk])
    assert nk >= 8 and r == 3 * nk  # every contact with three unknowns
    return eng, (gst, gdst, wst, ta, tb, J, R, dx, Ne, Nd, xt, touch, Q, x, y, off, wkk, piv, sk), nk, r


def test_band_newton_finds_the_dense_newtons_forces():
    """The installed specimen's contacts (regularised friction), solved from zero forces: the
    Newton that iterates with the band factors of its Jacobian (BAND) converges to the same forces
    as the one with the whole Jacobian's, within 10 NEWTON_TOL_REGULARIZED of their size (each
    stops when the error it estimates to be left is within the tolerance, 1e-6 of the largest
    force, so they agree to a few tolerances; measured 1.5e-13: the last steps land well inside it),
    and in a comparable number of iterations."""
    from cablecasing_core.timedomain.kernels import _contact_newton_for_fixed_modes as NW

    eng, (gst, gdst, wst, ta, tb, J, R, dx, Ne, Nd, xt, touch, Q, x, y, off, wkk, piv, sk), nk, r = _installed_contacts(
        1e-5
    )
    law = eng._law()
    found = []
    for band in (NW.BAND, r):
        xs = np.zeros_like(x)
        its = NW.newton_for_fixed_modes(
            Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, xs, law.law, law.k_lin, law.k_hertz, law.c_n,
            sk, eng.dt, J, R, dx, y, Ne, Nd, xt, law.mu, law.vreg, piv, band,
        )  # fmt: skip
        assert its > 0
        found.append((xs[:r].copy(), its))
    (xb, itb), (xd, itd) = found
    assert np.abs(xb - xd).max() <= 10 * NW.NEWTON_TOL_REGULARIZED * np.abs(xd).max()
    assert itb <= 2 * itd + 2


def test_regularised_newtons_matrix_is_the_jacobian_at_the_solution():
    """The regularised friction rows take the primal-dual linearisation (the iterate's own friction
    force in the direction term); at the converged forces it must be the residual's Jacobian, or
    the iteration would lose its quadratic end. The installed specimen's contacts at the real-time
    step (1/30000 s), solved with the whole Jacobian: the matrix against central differences of
    the exact residual, to 1e-6 of its largest entry (the differences' truncation error, h^2 R''' with
    h = 1e-7 of the largest force, is far below that, and the contacts' damper kinks are not within
    h of the solution at these instants). With ``tangent`` (the fall-back of a stalled Newton) the
    matrix is the Jacobian away from the solution too."""
    from cablecasing_core.timedomain.kernels import _contact_newton_for_fixed_modes as NW

    dt = 1 / 30000
    eng, (gst, gdst, wst, ta, tb, J, R, dx, Ne, Nd, xt, touch, Q, x, y, off, wkk, piv, sk), nk, r = _installed_contacts(
        dt
    )
    law = eng._law()
    args = (law.law, law.k_lin, law.k_hertz, law.c_n, sk, dt)

    def residual(xv, with_J, tangent=False):
        return NW._residual(
            Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, xv, *args, J, R, y, Ne, Nd, with_J, law.mu, law.vreg,
            tangent,
        )  # fmt: skip

    def matrix_and_differences(xv, h, tangent=False):
        """(the Newton's matrix at xv, the central differences of the residual with step h)."""
        residual(xv, True, tangent)
        Jm, Jfd = J[:r, :r].copy(), np.empty((r, r))
        for j in range(r):
            xp, xm = xv.copy(), xv.copy()
            xp[j] += h
            xm[j] -= h
            residual(xp, False)
            Rp = R[:r].copy()
            residual(xm, False)
            Jfd[:, j] = (Rp - R[:r]) / (2 * h)
        return Jm, Jfd

    xs = x.copy()
    its = NW.newton_for_fixed_modes(
        Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, xs, *args, J, R, dx, y, Ne, Nd, xt, law.mu, law.vreg, piv, r
    )  # fmt: skip
    assert its > 0
    h = 1e-7 * np.abs(xs[:r]).max()
    Jm, Jfd = matrix_and_differences(xs, h)
    assert np.abs(Jm - Jfd).max() <= 1e-6 * np.abs(Jfd).max()
    # away from the solution the linearisation is not the tangent (a test that it is in use)
    xo = xs.copy()
    xo[1:r:3] *= -0.5  # friction turned against the slip
    Jo, Jfd = matrix_and_differences(xo, h)
    assert np.abs(Jo - Jfd).max() > 1e-3 * np.abs(Jfd).max()
    # the fall-back where the linearisation's Newton stalls takes the exact Jacobian: it is there too
    Jt, Jfd = matrix_and_differences(xo, h, tangent=True)
    assert np.abs(Jt - Jfd).max() <= 1e-6 * np.abs(Jfd).max()


def test_steps_whose_contact_newton_did_not_converge_are_said():
    """Where the law is pushed to its limits (the built-in specimen with contact.damping = 1e5 kg/s,
    1000 times its own: the damper's switch at g_dot = 0 makes the residual strongly non-smooth,
    and the Newton cycles in a few steps), the steps whose last Newton ran out of iterations are
    counted, ``simulate`` warns with the count (docs/time_domain.md, "Contact", item 5; measured 6
    of 10 000), and the energy ledger still closes: the last iterate's forces do work that the
    ledger books (1e-3 of the supports' work: the ledger's bound elsewhere). At the specimen's own
    values no step is unconverged and nothing is said."""
    import re
    import warnings

    model = cc.load_model()
    with pytest.warns(cc.SolverWarning, match=r"the contact Newton did not converge in \d+ of the 10000 steps") as said:
        res = cc.simulate(model.with_overrides({"contact.damping": 1e5}), duration=0.1)
    count = int(re.search(r"in (\d+) of", str(said[0].message)).group(1))
    assert count == res.solver["unconverged_steps"] > 0, res.solver
    e = res.energies
    assert abs(e["residual"]) < 1e-3 * e["support_work"], e
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert cc.simulate(model, duration=0.1).solver["unconverged_steps"] == 0


@pytest.mark.parametrize("mu", [1.5, 3.0])
def test_a_friction_above_one_converges_through_the_exact_jacobian(mu):
    """The regularised law's Newton iterates with the primal-dual linearisation of the friction
    rows, which is not the residual's derivative away from the solution. On the installed specimen
    with contact.friction = 1.5 and 3 its line search stalled in 5 and 17 of 10 000 steps over
    0.1 s (measured before the fall-back); going on from there with the exact Jacobian, whose step
    descends |R|, every step converges, nothing is said, and the ledger closes as above."""
    import warnings

    model = cc.load_model("installed").with_overrides({"contact.friction": mu})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = cc.simulate(model, duration=0.1)
    assert res.solver["unconverged_steps"] == 0, res.solver
    e = res.energies
    assert abs(e["residual"]) < 1e-3 * e["support_work"], e
