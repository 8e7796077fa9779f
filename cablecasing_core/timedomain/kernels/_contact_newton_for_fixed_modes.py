"""The contact forces at the end of a Newmark step for fixed stick/slip modes and a fixed active set
(Eqs. 15-23, 24/29): the unknowns of each contact (one for a slipping one, three for a sticking
one), the reduced Delassus matrix, and a semi-smooth Newton with a line search on the contact
conditions. The active set and the stick/slip passes around it are in
``_contact_forces_with_active_set.py``."""

from __future__ import annotations

import numpy as np
from numba import njit

from ._compile_options import FM
from ._contact_search_and_law import contact_law
from ._newmark_per_body import newmark_coefficients
from ._step_loop_contract import STICK

#: the residual reduction per iteration below which the regularised law's Newton keeps its factors
CHORD_RATE = 0.25
#: the regularised law's Newton stops when its forces are within this fraction of the largest one
#: (the switch law's: 1e-12). On the installed specimen 1e-6 moves the band levels by at most 2e-5
#: of themselves against 1e-8 (2e-7 against 1e-12), where the step's own error is 8e-3 at 1e-5 s and
#: 4e-2 at 3.3e-5 s (docs/time_domain.md, "Contact", item 5), and saves 0.6-0.9 of 3.0-5.2
#: iterations per step.
NEWTON_TOL_REGULARIZED = 1e-6
#: half-bandwidth (unknowns) of the regularised law's approximate Jacobian: the bodies couple a
#: contact mostly with its neighbours along the cable (docs/time_domain.md, "Contact", item 5)
BAND = 8


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _band_lu_factor(A, m, b, piv):
    """LU factors, in place, of the band of A[:m, :m] within b of its diagonal (the entries outside
    it taken as zero), by Gaussian elimination with partial pivoting among the b rows below the
    diagonal (LAPACK's dgbtrf scheme: the pivots widen the upper band of U to 2b): the multipliers
    below the diagonal, each in the row's place at its column's step; piv[c] the row swapped with
    row c at column c, which :func:`_band_lu_solve` replays in the same order. m b^2 operations;
    b = m - 1 is the dense LU. Written here for the few (3 per contact)
    unknowns inside the step loop, where a LAPACK call would cost more than the solve."""
    for i in range(m):  # the strip the pivots can fill in, zero as the band model has it
        for k in range(i + b + 1, min(i + 2 * b + 1, m)):
            A[i, k] = 0.0
    for c in range(m):
        last = min(c + b, m - 1)  # the last row with an entry in column c
        right = min(c + 2 * b, m - 1)  # the last column of U's row c
        p = c
        big = abs(A[c, c])
        for r in range(c + 1, last + 1):
            if abs(A[r, c]) > big:
                big = abs(A[r, c])
                p = r
        piv[c] = p
        if big == 0.0:
            continue
        if p != c:  # the columns from c on: a multiplier stays where its row was when it was made
            for k in range(c, right + 1):
                A[c, k], A[p, k] = A[p, k], A[c, k]
        inv = 1.0 / A[c, c]
        # (unsigned bounds: without a possibly negative index to wrap, LLVM vectorizes the row
        # update, ~1.9 x faster at 36 unknowns; element by element, so the same bits)
        lo, hi = np.uint64(c + 1), np.uint64(right + 1)
        for r in range(c + 1, last + 1):
            f = A[r, c] * inv
            A[r, c] = f
            if f != 0.0:
                for k in range(lo, hi):
                    A[r, k] -= f * A[c, k]


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _band_lu_solve(A, piv, b, rhs, m, x, far_first):
    """Solve with the factors of :func:`_band_lu_factor` (half-bandwidth b): x = A^-1 rhs[:m]
    (rhs is overwritten); an exactly zero pivot leaves its unknown at zero. The elimination of rhs
    replays the factors' operations in their order. far_first takes each row of the back
    substitution from its far end in: its chain of subtractions needs x[c + 1], the value just
    found, only at its last term, so the processor runs it beside the row before's (~1.4 x faster
    at 36 unknowns than from the near end, where every row waits for the last; other bits)."""
    for c in range(m):
        p = piv[c]
        if p != c:
            rhs[c], rhs[p] = rhs[p], rhs[c]
        for r in range(c + 1, min(c + b, m - 1) + 1):
            f = A[r, c]
            if f != 0.0:
                rhs[r] -= f * rhs[c]
    for c in range(m - 1, -1, -1):
        if A[c, c] == 0.0:
            x[c] = 0.0
            continue
        s = rhs[c]
        right = min(c + 2 * b, m - 1)
        if far_first:
            for k in range(right, c, -1):
                s -= A[c, k] * x[k]
        else:
            for k in range(c + 1, right + 1):
                s -= A[c, k] * x[k]
        x[c] = s / A[c, c]


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def matrix_times_vector(A, x, m, y):
    """y = A[:m, :m] x. Three rows at a time, whose sums advance together: three independent chains
    of multiply-adds share each x[j] instead of one chain after another, each waiting for its last
    result (there is no re-association: the package docstring); the rows left over one by one.
    Each row's sum takes its terms in order, as alone, so the bits do not depend on the grouping."""
    i = 0
    while i + 3 <= m:
        a0, a1, a2 = A[i], A[i + 1], A[i + 2]
        s0 = s1 = s2 = 0.0
        for j in range(m):
            xj = x[j]
            s0 += a0[j] * xj
            s1 += a1[j] * xj
            s2 += a2[j] * xj
        y[i], y[i + 1], y[i + 2] = s0, s1, s2
        i += 3
    for i in range(i, m):
        a0 = A[i]
        s0 = 0.0
        for j in range(m):
            s0 += a0[j] * x[j]
        y[i] = s0


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def relative_displacement(W, P, m, d):
    """d = W[:m, :m] P: the contact points' relative displacements (m) under the forces P (N), m =
    3 per contact (one contact's three rows at a time, :func:`matrix_times_vector`)."""
    matrix_times_vector(W, P, m, d)


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def unknowns_from_forces(nk, nrm, ta, tb, mode, active, P, off, x):
    """The unknowns x of the contact solve and their offsets off[k] .. off[k + 1] - 1, from the
    forces P (N, 3 per contact). The force of each contact k is a linear map of its unknowns:
      slip (one unknown, N):          P_k = -N (n + mu s)    (Coulomb, Eqs. 18-23),
      stick (three, N, f_a, f_b):     P_k = -N n + f_a t_a + f_b t_b,
      inactive (none):                P_k = 0,
    so a slip contact, the usual case, costs one unknown instead of three. Returns their number r."""
    r = 0
    for k in range(nk):
        off[k] = r
        if not active[k]:
            continue
        o = 3 * k
        x[r] = -(P[o] * nrm[k, 0] + P[o + 1] * nrm[k, 1] + P[o + 2] * nrm[k, 2])
        r += 1
        if mode[k] == STICK:
            x[r] = P[o] * ta[k, 0] + P[o + 1] * ta[k, 1] + P[o + 2] * ta[k, 2]
            x[r + 1] = P[o] * tb[k, 0] + P[o + 1] * tb[k, 1] + P[o + 2] * tb[k, 2]
            r += 2
    off[nk] = r
    return r


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def forces_from_unknowns(nk, nrm, ta, tb, sdir, mu, off, x, P):
    """P (N, 3 per contact) from the unknowns x: the map of :func:`unknowns_from_forces`."""
    for k in range(nk):
        o = 3 * k
        i = off[k]
        nu = off[k + 1] - i
        if nu == 0:
            P[o], P[o + 1], P[o + 2] = 0.0, 0.0, 0.0
        elif nu == 1:
            for c in range(3):
                P[o + c] = -x[i] * (nrm[k, c] + mu * sdir[k, c])
        else:
            for c in range(3):
                P[o + c] = -x[i] * nrm[k, c] + x[i + 1] * ta[k, c] + x[i + 2] * tb[k, c]


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def reduced_delassus(W, nk, nrm, ta, tb, sdir, mu, off, Q, S):
    """Q = O W C (r x r): how the observed relative displacements (m) of the contact points respond
    to the unknowns (N). C maps the unknowns to the forces (:func:`forces_from_unknowns`); the observations are,
    per contact, the normal displacement n.d (one per unknown N) and, for a stick contact, the
    tangential ones t_a.d and t_b.d (one per friction unknown). Two passes, each along rows: first
    the observations of W's rows, S[j, row] = t_row . W[3k:3k+3, j] (S: scratch, at least 3 nk x
    r), then each contact's columns of Q from three rows of S. The sums are those of one pass per
    3 x 3 block, in the same order (the same bits), but both inner loops run over contiguous
    memory (2.09 -> 1.57 us at 14 contacts of three unknowns, docs/performance-history.md)."""
    um = np.uint64(3 * nk)
    for k in range(nk):
        o = 3 * k
        for a in range(off[k + 1] - off[k]):
            t = nrm[k] if a == 0 else (ta[k] if a == 1 else tb[k])
            t0, t1, t2 = t[0], t[1], t[2]
            row = off[k] + a
            for j in range(um):
                S[j, row] = t0 * W[o, j] + t1 * W[o + 1, j] + t2 * W[o + 2, j]
    ur = np.uint64(off[nk])
    for l in range(nk):
        nu = off[l + 1] - off[l]
        if nu == 0:
            continue
        ol, c = 3 * l, off[l]
        n0, n1, n2 = nrm[l, 0], nrm[l, 1], nrm[l, 2]
        if nu == 1:
            s0, s1, s2 = sdir[l, 0], sdir[l, 1], sdir[l, 2]
            for i in range(ur):
                w0, w1, w2 = S[ol, i], S[ol + 1, i], S[ol + 2, i]
                wn = w0 * n0 + w1 * n1 + w2 * n2
                Q[i, c] = -(wn + mu * (w0 * s0 + w1 * s1 + w2 * s2))
        else:
            a0, a1, a2 = ta[l, 0], ta[l, 1], ta[l, 2]
            b0, b1, b2 = tb[l, 0], tb[l, 1], tb[l, 2]
            for i in range(ur):
                w0, w1, w2 = S[ol, i], S[ol + 1, i], S[ol + 2, i]
                wn = w0 * n0 + w1 * n1 + w2 * n2
                Q[i, c] = -wn
                Q[i, c + 1] = w0 * a0 + w1 * a1 + w2 * a2
                Q[i, c + 2] = w0 * b0 + w1 * b1 + w2 * b2


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _residual(
    Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, x, law, k_lin, k_hertz, c_n, sk, dt, J, R, y, Ne, Nd, with_J,
    mu, vreg, tangent,
):  # fmt: skip
    """Residual R (and, with_J, its Jacobian J) of the contact conditions of :func:`newton_for_fixed_modes` at the
    unknowns x; y = Q x, the observed relative displacements (m). Normal rows are in newtons; stick
    rows (m/s) are scaled by 1 / (2/dt W_kk) and touch rows (m) by 1 / W_kk to newtons like them.
    J is the exact Jacobian of R except in the regularised friction rows, whose primal-dual
    linearisation equals it at the solution (tangent: their exact Jacobian too). Returns the norm
    of R (N)."""
    _, c2 = newmark_coefficients(dt)  # 2/dt (1/s): a velocity change per displacement change (Eq. 18)
    ur = np.uint64(r)  # (the Jacobian's row fills vectorize over unsigned bounds, as in _band_lu_factor)
    matrix_times_vector(Q, x, r, y)
    norm = 0.0
    for k in range(nk):
        i = off[k]
        nu = off[k + 1] - i
        if nu == 0:
            Ne[k], Nd[k] = 0.0, 0.0  # inactive: no unknown, no force
            continue
        g = gst[k] + y[i]
        if touch[k]:
            # the step ends just touching: g = 0 with N free (0 <= N <= c_n g_dot, checked by the
            # caller)
            Ne[k], Nd[k] = 0.0, x[i]
            sc = 1.0 / wkk[k] if wkk[k] > 0.0 else 1.0
            R[i] = sc * g
            if with_J:
                for j in range(ur):
                    J[i, j] = sc * Q[i, j]
        else:
            # the law (Eqs. 24/29) and the damper while compressing (Eq. 16), continuous in x;
            # the caller checks g > 0 at the solution
            gd = gdst[k] + c2 * y[i]
            fe, ke = contact_law(g, law, k_lin, k_hertz)
            s = sk[k]  # the contact's share of the law (1 unless contact.law_length > 0)
            fe, ke = fe * s, ke * s
            if law == 2:
                # Hunt-Crossley: fe (1 + c_n g_dot), c_n = 3/2 alpha, on compression and restitution
                # alike; zero at first touch (fe = 0), so no switch (N <= 0 opens the contact)
                fd = c_n * fe * gd
                gam = ke * (1.0 + c_n * gd) + c_n * fe * c2
            else:
                fd = c_n * s * gd if gd > 0.0 else 0.0
                gam = ke + (c_n * s * c2 if gd > 0.0 else 0.0)
            Ne[k], Nd[k] = fe, fd
            R[i] = fe + fd - x[i]
            if with_J:
                for j in range(ur):  # dN/dx = gam dg/dx
                    J[i, j] = gam * Q[i, j]
                J[i, i] -= 1.0
        norm += R[i] * R[i]
        if vreg > 0.0 and nu == 3:
            # regularised Coulomb: f_t = -mu N v_t / sqrt(|v_t|^2 + vreg^2), v_t the tangential
            # relative velocity at the end of the step (rows in newtons)
            ia, ib = i + 1, i + 2
            va = ta[k, 0] * wst[k, 0] + ta[k, 1] * wst[k, 1] + ta[k, 2] * wst[k, 2] + c2 * y[ia]
            vb = tb[k, 0] * wst[k, 0] + tb[k, 1] * wst[k, 1] + tb[k, 2] * wst[k, 2] + c2 * y[ib]
            sq = np.sqrt(va * va + vb * vb + vreg * vreg)
            N = x[i]
            R[ia] = x[ia] + mu * N * va / sq
            R[ib] = x[ib] + mu * N * vb / sq
            if with_J:
                # the primal-dual linearisation (Chan, Golub and Mulet, SIAM J. Sci. Comput. 20
                # (1999) 1964-1977): the rows' Jacobian as that of (f_t s + mu N v_t) / s, s =
                # sqrt(|v_t|^2 + vreg^2), whose direction term takes the iterate's own f_t (held in
                # the cone |f_t| <= mu |N|) where the tangent takes -mu N v_t / s. The two agree at
                # the solution (the same quadratic end); away from it the iteration does not
                # follow the law's turn across a slip reversal, where the tangent's steps overshoot
                # from one side of the turn to the other (docs/time_domain.md, "Contact", item 5)
                if tangent:  # the exact Jacobian: the law's own force in the direction term
                    fa, fb = -mu * N * va / sq, -mu * N * vb / sq
                else:
                    fa, fb = x[ia], x[ib]
                    cone = abs(mu * N)
                    fn = np.sqrt(fa * fa + fb * fb)
                    if fn > cone:
                        fa, fb = fa * (cone / fn), fb * (cone / fn)
                s2 = sq * sq
                daa = c2 * (mu * N / sq + fa * va / s2)
                dab = c2 * fa * vb / s2
                dba = c2 * fb * va / s2
                dbb = c2 * (mu * N / sq + fb * vb / s2)
                for j in range(ur):
                    J[ia, j] = daa * Q[ia, j] + dab * Q[ib, j]
                    J[ib, j] = dba * Q[ia, j] + dbb * Q[ib, j]
                J[ia, ia] += 1.0
                J[ib, ib] += 1.0
                J[ia, i] += mu * va / sq
                J[ib, i] += mu * vb / sq
            norm += R[ia] * R[ia] + R[ib] * R[ib]
            continue
        for a in range(1, nu):
            # stick: the tangential relative velocity at the end of the step vanishes; a direction
            # with no compliance at all (a contact at a clamped node) admits any force and zero is
            # taken
            ia = i + a
            t = ta[k] if a == 1 else tb[k]
            if Q[ia, ia] <= 1e-13 * wkk[k] or wkk[k] == 0.0:
                R[ia] = x[ia]
                if with_J:
                    for j in range(ur):
                        J[ia, j] = 0.0
                    J[ia, ia] = 1.0
            else:
                sc = 1.0 / (c2 * wkk[k])
                R[ia] = sc * (t[0] * wst[k, 0] + t[1] * wst[k, 1] + t[2] * wst[k, 2] + c2 * y[ia])
                if with_J:
                    for j in range(ur):
                        J[ia, j] = sc * c2 * Q[ia, j]
            norm += R[ia] * R[ia]
    return np.sqrt(norm)


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def newton_for_fixed_modes(
    Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, x, law, k_lin, k_hertz, c_n, sk, dt, J, R, dx, y, Ne, Nd, xt,
    mu, vreg, piv, band,
):  # fmt: skip
    """Contact forces at the end of a Newmark step for fixed stick/slip modes and active set, as
    the unknowns x of :func:`unknowns_from_forces` (N).

    The relative displacement of the contact points responds linearly to the forces through the
    Delassus matrix W (m/N, from the effective stiffness of both bodies): delta = W P, and so the
    observed displacements to the unknowns through Q = O W C (:func:`reduced_delassus`). With the
    predicted penetration g* and rates (contact-free step), each active contact k satisfies
      normal (Eqs. 15-17, 24/29): N = s_k (law(max(g, 0)) + c_n max(g_dot, 0)), g = g* + n.delta,
        g_dot = g_dot* + 2/dt n.delta, s_k = sk[k] the contact's share of the law (1 unless
        ``contact.law_length`` > 0: ``engine.contact_shares``);
      touch (touch[k]):  g = 0 with N free: the step in which the implicit damper alone would push
        the bodies apart past the surface (Eq. 16's switch at g = 0, read as a set);
      stick (Eqs. 18-23): the tangential relative velocity at the end of the step is zero;
      slip (Coulomb):    P_t = -mu N s, s the unit slip direction: built into P's map, no equation;
      regularised (vreg > 0, every active contact with three unknowns): P_t = -mu N v_t /
        sqrt(|v_t|^2 + vreg^2), v_t the tangential relative velocity at the end of the step
        (``contact.friction_law = "regularized"``), in place of the stick rows;
    an inactive contact has no unknown and no force. The caller keeps a contact in the law only
    while g > 0 and in touch only while 0 <= N <= c_n g_dot. Newton iterations (semi-smooth at the
    max()) from the given x, with a backtracking line search on |R|: near g = 0 the Hertz law's
    slope vanishes and full steps can cycle across the kink. At most 15 iterations: a stick that
    needs more friction than mu N has no solution here, and the caller switches it to slip (40 with
    the regularised law, which has no such case).
    With the regularised law an iteration keeps the last factors of the Jacobian while they reduce
    the residual at least CHORD_RATE-fold per iteration (a chord step, r^2 operations against the
    r^3 / 3 of new factors; the Jacobian of 39 unknowns changes little between iterations where the
    contacts slide), and takes new factors otherwise; the converged forces satisfy the same
    conditions to the same tolerance. Its factors are first those of the Jacobian's band within
    ``band`` unknowns of the diagonal (:func:`_band_lu_factor`, the couplings between contacts
    farther apart along the cable left out: m band^2 operations instead of m^3 / 3); where new
    band factors do not cut the residual CHORD_RATE-fold, the iteration goes on with the whole
    Jacobian's. The approximation is only in the iteration's matrix: the residual is the exact one.
    The friction rows' matrix is their primal-dual linearisation (:func:`_residual`), which is not
    the residual's derivative away from the solution, so its step need not descend: where it runs
    out of iterations (its line search stalled; contact.friction > 1 does this), the Newton goes on
    from its last iterate with the exact Jacobian, whose step descends |R| wherever R is smooth,
    for as many iterations again (the converged steps are untouched, to the bit).
    Returns the number of iterations, negative when not converged; Ne, Nd hold the elastic and
    damping parts of N at the final x. mu (-) and vreg (m/s) enter only the regularised rows; piv
    (int, r) holds the factors' pivots."""
    # the switch law's cap is also its signal that a stick needs more than mu N (the caller then
    # slips it); the regularised law has a solution always, and 15 iterations left 2 steps in 30 000
    # of the installed specimen short of it (benchmarks/friction_laws.py)
    cap = 40 if vreg > 0.0 else 15
    tol = NEWTON_TOL_REGULARIZED if vreg > 0.0 else 1e-12  # of the largest force
    its = -cap
    fresh = True  # J holds the Jacobian at x, not yet factored
    exact = vreg == 0.0 or band >= r - 1  # the whole Jacobian's factors, not its band's
    last = 0.0  # the last iteration's step when it was a full one (0: none)
    tangent = False
    for attempt in range(2 if vreg > 0.0 else 1):
        if attempt == 1:
            if its > 0:
                break
            # the primal-dual linearisation ran out of iterations (its line search stalled: its
            # matrix is not the residual's derivative, so its step need not descend): on from the
            # last iterate with the exact Jacobian, whose Newton step descends |R| wherever R is smooth
            tangent, exact, fresh, last = True, True, True, 0.0
        r0 = _residual(
            Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, x, law, k_lin, k_hertz, c_n, sk, dt, J, R, y, Ne, Nd,
            True, mu, vreg, tangent,
        )  # fmt: skip
        for it in range(cap):
            for i in range(r):
                R[i] = -R[i]
            renewed = fresh
            # the whole Jacobian is the band b = r - 1; its back substitution from the near end of
            # each row, as the switch law's records have always been computed
            b = r - 1 if exact else band
            if fresh:
                _band_lu_factor(J, r, b, piv)
            _band_lu_solve(J, piv, b, R, r, dx, not exact)
            scale = 1e-30
            step = 0.0
            for i in range(r):
                scale = max(scale, abs(x[i]))
                step = max(step, abs(dx[i]))
            alpha = 1.0
            for _ in range(12):
                for i in range(r):
                    xt[i] = x[i] + alpha * dx[i]
                r1 = _residual(
                    Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, xt, law, k_lin, k_hertz, c_n, sk, dt, J, R, y,
                    Ne, Nd, False, mu, vreg, tangent,
                )  # fmt: skip
                if r1 <= (1.0 - 1e-4 * alpha) * r0 or r1 <= 1e-13 * max(scale, 1.0):
                    break
                alpha *= 0.5
            for i in range(r):
                x[i] = xt[i]
            if alpha * step <= tol * max(scale, 1e-30) or r1 <= 1e-13 * max(scale, 1.0):
                its = attempt * cap + it + 1  # Ne, Nd already belong to x (the last trial point)
                break
            if vreg > 0.0 and alpha == 1.0:
                # a full chord step after a full step contracts at theta = |dx_k| / |dx_k-1| (the
                # factors of step k-1 kept), so the error left after it is about theta / (1 - theta)
                # |dx_k| (Hairer and Wanner, Solving ODEs II, IV.8): done when that is within the
                # tolerance the step test asks of |dx_k| itself
                if last > 0.0 and not renewed and step < last:
                    theta = step / last
                    if theta / (1.0 - theta) * step <= tol * max(scale, 1e-30):
                        its = attempt * cap + it + 1
                        break
                last = step
            else:
                last = 0.0
            # the switch law takes new factors every iteration; the regularised law keeps them while
            # they converge fast (a full chord step that cut the residual CHORD_RATE-fold)
            fresh = vreg == 0.0 or alpha < 1.0 or r1 > CHORD_RATE * r0
            if fresh and renewed and not exact:
                exact = True  # new band factors were not enough: the whole Jacobian's from here on
            if fresh:
                r0 = _residual(
                    Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, x, law, k_lin, k_hertz, c_n, sk, dt, J, R, y,
                    Ne, Nd, True, mu, vreg, tangent,
                )  # fmt: skip
            else:
                r0 = r1  # R, y, Ne and Nd are the last trial's, at x: the same numbers a new call would give
    return its
