"""numba kernels of the time domain, kept together: banded linear algebra, Hermite interpolation on
a beam element, the contact search and contact law (Eqs. 14-39), and the Newmark step loop.

All kernels are plain functions over arrays, compiled once with ``cache=True`` (the cache lives in
``NUMBA_CACHE_DIR`` when set). The orchestration (building matrices, factorising, evaluating the
support motion, packing results) stays in plain Python in ``engine.py``.

Band storage: a symmetric matrix of half-bandwidth b is stored as full rows ``Ab[i, k] = A[i, i-b+k]``,
k = 0..2b. The Cholesky factor L of the free block is stored twice for contiguous access:
``Lf[i, k] = L[i, i-k]`` (forward substitution) and ``Lb[i, k] = L[i+k, i]`` (back substitution).
SciPy computes the factor (``cholesky_banded``); the substitutions are written here because SciPy's
banded solvers cannot be called from inside a compiled time-step loop.
"""
from __future__ import annotations

import numpy as np
from numba import njit

OPEN, STICK, SLIP = 0, 1, 2

# status codes of run_steps
OK, ERR_NAN, ERR_PENETRATION, ERR_SEARCH = 0, 1, 2, 3


# ------------------------------------------------------------------------------------------------
# banded linear algebra


@njit(cache=True)
def band_rhs(Mb, Kb, y1, y2, f0, nf, b, out):
    """out[i - f0] = sum_j M[i, j] y1[j] + K[i, j] y2[j] for the free rows i = f0 .. f0+nf-1."""
    n = Mb.shape[0]
    for i in range(f0, f0 + nf):
        s = 0.0
        j0 = i - b
        for k in range(max(0, -j0), min(2 * b + 1, n - j0)):
            s += Mb[i, k] * y1[j0 + k] + Kb[i, k] * y2[j0 + k]
        out[i - f0] = s


@njit(cache=True)
def band_row(Mb, Kb, x1, x2, i, b):
    """sum_j M[i, j] x1[j] + K[i, j] x2[j] for one row i."""
    n = Mb.shape[0]
    s = 0.0
    j0 = i - b
    for k in range(max(0, -j0), min(2 * b + 1, n - j0)):
        s += Mb[i, k] * x1[j0 + k] + Kb[i, k] * x2[j0 + k]
    return s


@njit(cache=True)
def band_quadratic(Mb, Kb, cm, ck, w, b):
    """w^T (cm M + ck K) w over all DOFs (e.g. the Rayleigh dissipation rate with cm = alpha, ck = beta)."""
    n = Mb.shape[0]
    s = 0.0
    for i in range(n):
        r = 0.0
        j0 = i - b
        for k in range(max(0, -j0), min(2 * b + 1, n - j0)):
            r += (cm * Mb[i, k] + ck * Kb[i, k]) * w[j0 + k]
        s += w[i] * r
    return s


@njit(cache=True)
def band_cho_solve(Lf, Lb, r, x):
    """Solve L L^T x = r with the banded Cholesky factor (see module docstring); x may alias r."""
    n = Lf.shape[0]
    b = Lf.shape[1] - 1
    for i in range(n):
        s = r[i]
        for k in range(1, min(b, i) + 1):
            s -= Lf[i, k] * x[i - k]
        x[i] = s / Lf[i, 0]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for k in range(1, min(b, n - 1 - i) + 1):
            s -= Lb[i, k] * x[i + k]
        x[i] = s / Lb[i, 0]


# ------------------------------------------------------------------------------------------------
# element interpolation


@njit(cache=True)
def hermite_matrix(xi, L, R, H):
    """Global 6x12 interpolation matrix H of a straight beam element at xi in [0, 1].

    Maps the element's 12 global DOFs to [ux uy uz rx ry rz] (global) at xi: Hermite cubics for
    the lateral displacements and the bending rotations (their slopes), linear for axial and twist;
    the shape functions of Eq. (9). R (3x3) is the element's direction-cosine matrix. The consistent
    nodal load of a point force F and moment Mo at xi is H^T [F; Mo]; it keeps the resultant and the
    moment of the load, because the shape functions reproduce rigid-body motion exactly.
    """
    x2 = xi * xi
    x3 = x2 * xi
    N1, N2, N3, N4 = 1 - 3 * x2 + 2 * x3, L * (xi - 2 * x2 + x3), 3 * x2 - 2 * x3, L * (-x2 + x3)
    D1, D2, D3, D4 = (-6 * xi + 6 * x2) / L, 1 - 4 * xi + 3 * x2, (6 * xi - 6 * x2) / L, -2 * xi + 3 * x2
    Hl = np.zeros((6, 12))
    Hl[0, 0], Hl[0, 6] = 1 - xi, xi
    Hl[1, 1], Hl[1, 5], Hl[1, 7], Hl[1, 11] = N1, N2, N3, N4
    Hl[2, 2], Hl[2, 4], Hl[2, 8], Hl[2, 10] = N1, -N2, N3, -N4
    Hl[3, 3], Hl[3, 9] = 1 - xi, xi
    Hl[4, 2], Hl[4, 4], Hl[4, 8], Hl[4, 10] = -D1, D2, -D3, D4
    Hl[5, 1], Hl[5, 5], Hl[5, 7], Hl[5, 11] = D1, D2, D3, D4
    # H = diag(R^T, R^T) Hl diag(R, R, R, R)
    tmp = np.zeros((6, 12))
    for blk in range(4):
        for r in range(6):
            for c in range(3):
                s = 0.0
                for m in range(3):
                    s += Hl[r, 3 * blk + m] * R[m, c]
                tmp[r, 3 * blk + c] = s
    for half in range(2):
        for r in range(3):
            for c in range(12):
                s = 0.0
                for m in range(3):
                    s += R[m, r] * tmp[3 * half + m, c]
                H[3 * half + r, c] = s


# ------------------------------------------------------------------------------------------------
# contact geometry and laws


@njit(cache=True)
def contact_law(g, law, k_lin, k_hertz):
    """Normal elastic force (N) and its slope (N/m) at penetration g (m): linear (Eq. 24) or
    Hertz (Eq. 29) with k_hertz = 4/3 E* r^1/2; zero for g <= 0 (no adhesion)."""
    if g <= 0.0:
        return 0.0, 0.0
    if law == 0:
        return k_hertz * g**1.5, 1.5 * k_hertz * np.sqrt(g)
    return k_lin * g, k_lin


@njit(cache=True)
def _cross(a, b):
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


@njit(cache=True)
def line_plane_intersection(ia, ib, p0, p1, p2):
    """Eq. (39): (l, u, v) of the intersection of the line ia + (ib - ia) l with the plane
    p0 + (p1 - p0) u + (p2 - p0) v. Returns l = nan for a line parallel to the plane."""
    A = np.empty((3, 3))
    for r in range(3):
        A[r, 0] = ia[r] - ib[r]
        A[r, 1] = p1[r] - p0[r]
        A[r, 2] = p2[r] - p0[r]
    det = np.linalg.det(A)
    if abs(det) < 1e-300:
        return np.nan, np.nan, np.nan
    sol = np.linalg.solve(A, ia - p0)
    return sol[0], sol[1], sol[2]


@njit(cache=True)
def casing_point(Xs, Rs, Ls, Us, e, xi, H):
    """Deformed casing axis point (m) at xi of element e, with its Hermite matrix written into H."""
    hermite_matrix(xi, Ls[e], Rs[e], H)
    x = Xs[e] + xi * (Xs[e + 1] - Xs[e])
    for r in range(3):
        s = 0.0
        for c in range(12):
            s += H[r, c] * Us[6 * e + c]
        x[r] += s
    return x


@njit(cache=True)
def search_casing(x1, t1, Xs, Rs, Ls, Us, e_guess, H, far_below):
    """Contact search (Eqs. 32-39): where the normal plane of a cable node (point x1, unit tangent
    t1) cuts the deformed casing axis. The line between two deformed casing nodes (Eq. 37) gives the
    first estimate l (Eq. 39); Newton iterations on the element's Hermite-interpolated axis refine it.
    Returns (element, xi, far): far is True when the node is certainly more than ``far_below``
    (m) from the axis (no refinement done); element -1 when the plane misses the casing."""
    ne = Ls.shape[0]
    best_e, best_xi, best_d = -1, np.nan, 1e300
    for de in range(0, 2 * ne + 1):
        off = (de + 1) // 2 * (1 if de % 2 == 1 else -1)
        e = e_guess + off
        if e < 0 or e >= ne:
            if abs(off) > ne:
                break
            continue
        a = Xs[e] + Us[6 * e:6 * e + 3]
        b = Xs[e + 1] + Us[6 * e + 6:6 * e + 9]
        den = 0.0
        num = 0.0
        for r in range(3):
            den += (b[r] - a[r]) * t1[r]
            num += (x1[r] - a[r]) * t1[r]
        if abs(den) < 1e-300:
            continue
        xi = num / den
        if xi < -1e-9 or xi > 1 + 1e-9:
            if best_e >= 0 and abs(off) > 2:
                break
            continue
        # cheap exit: the Hermite axis departs from the chord between the deformed nodes by at most
        # L/4 (|rot_a| + |rot_b|); a node farther inside than that cannot touch (returned as far)
        dl = 0.0
        for r in range(3):
            dl += (a[r] + xi * (b[r] - a[r]) - x1[r]) ** 2
        ra = 0.0
        rb = 0.0
        for r in range(3):
            ra += Us[6 * e + 3 + r] ** 2
            rb += Us[6 * e + 9 + r] ** 2
        if np.sqrt(dl) + 0.25 * Ls[e] * (np.sqrt(ra) + np.sqrt(rb)) < far_below:
            return e, xi, True
        for _ in range(3):  # Newton on phi(xi) = (x(xi) - x1) . t1
            xa = casing_point(Xs, Rs, Ls, Us, e, min(max(xi, 0.0), 1.0), H)
            h = 1e-6
            xb = casing_point(Xs, Rs, Ls, Us, e, min(max(xi, 0.0), 1.0) + h, H)
            phi = 0.0
            dphi = 0.0
            for r in range(3):
                phi += (xa[r] - x1[r]) * t1[r]
                dphi += (xb[r] - xa[r]) / h * t1[r]
            if abs(dphi) < 1e-300:
                break
            xi = xi - phi / dphi
        xi = min(max(xi, 0.0), 1.0)
        xa = casing_point(Xs, Rs, Ls, Us, e, xi, H)
        d = 0.0
        for r in range(3):
            d += (xa[r] - x1[r]) ** 2
        if d < best_d:
            best_d, best_e, best_xi = d, e, xi
        if abs(off) >= 2 and best_e >= 0:
            break
    return best_e, best_xi, False


@njit(cache=True)
def tangent_basis(n):
    """Two unit vectors completing n to a right-handed orthonormal basis."""
    ref = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    ta = ref - (ref @ n) * n
    ta /= np.sqrt(ta @ ta)
    tb = _cross(n, ta)
    return ta, tb


@njit(cache=True)
def solve_contact_forces(W, gstar, gdstar, wstar, nrm, ta, tb, mode, sdir, Pinit,
                         law, k_lin, k_hertz, c_n, mu, dt):
    """Contact forces P (3 per contact, on the cable, N) at the end of a Newmark step.

    The relative displacement of each contact point responds linearly to the forces through the
    Delassus matrix W (m/N, from the effective stiffness of both bodies): delta = W P. With the
    predicted penetration g* and rates (contact-free step), each contact k satisfies
      normal (Eqs. 15-17, 24/29): P.n = -N,  N = law(g) + c_n max(g_dot, 0) while g > 0, else 0;
      stick (Eqs. 18-23): the tangential relative velocity at the end of the step is zero;
      slip (Coulomb):    P_t = -mu N s, s the unit slip direction.
    Solved by Newton iterations (semi-smooth at the max()), started from Pinit.
    Returns (P, N_elastic, N_damping, converged)."""
    nk = len(gstar)
    P = Pinit.copy()
    J = np.zeros((3 * nk, 3 * nk))
    R = np.zeros(3 * nk)
    Ne = np.zeros(nk)
    Nd = np.zeros(nk)
    c2 = 2.0 / dt
    converged = False
    for it in range(60):
        d = W @ P
        J[:, :] = 0.0
        for k in range(nk):
            n = nrm[k]
            dk = d[3 * k:3 * k + 3]
            g = gstar[k] + n @ dk
            gd = gdstar[k] + c2 * (n @ dk)
            fe, ke = contact_law(g, law, k_lin, k_hertz)
            fd = c_n * gd if (g > 0.0 and gd > 0.0) else 0.0
            N = fe + fd
            gam = 0.0
            if N > 0.0:
                gam = ke + (c_n * c2 if (g > 0.0 and gd > 0.0) else 0.0)
            Ne[k], Nd[k] = fe, fd
            Pk = P[3 * k:3 * k + 3]
            R[3 * k] = Pk @ n + N
            # rows: dN/dP_l = gam n^T W_kl
            for l in range(nk):
                for c in range(3):
                    s = 0.0
                    for r in range(3):
                        s += n[r] * W[3 * k + r, 3 * l + c]
                    J[3 * k, 3 * l + c] = gam * s
            for c in range(3):
                J[3 * k, 3 * k + c] += n[c]
            for row, t in ((1, ta[k]), (2, tb[k])):
                if mode[k] == STICK:
                    R[3 * k + row] = t @ wstar[k] + c2 * (t @ dk)
                    for l in range(nk):
                        for c in range(3):
                            s = 0.0
                            for r in range(3):
                                s += t[r] * W[3 * k + r, 3 * l + c]
                            J[3 * k + row, 3 * l + c] = c2 * s
                else:
                    st = sdir[k] @ t
                    R[3 * k + row] = Pk @ t + mu * N * st
                    for l in range(nk):
                        for c in range(3):
                            J[3 * k + row, 3 * l + c] = mu * st * J[3 * k, 3 * l + c] - (mu * st * n[c] if l == k else 0.0)
                    for c in range(3):
                        J[3 * k + row, 3 * k + c] += t[c]
        # minimum-norm step: a direction with no compliance (a contact at a clamped support node)
        # leaves its stick row empty, where any force is admissible and zero is taken
        dP = np.linalg.lstsq(J, -R, rcond=1e-12)[0]
        P += dP
        scale = 1e-30
        for i in range(3 * nk):
            scale = max(scale, abs(P[i]))
        if np.max(np.abs(dP)) <= 1e-12 * scale:
            converged = True
            break
    # final forces consistent with P
    d = W @ P
    for k in range(nk):
        n = nrm[k]
        g = gstar[k] + n @ d[3 * k:3 * k + 3]
        gd = gdstar[k] + c2 * (n @ d[3 * k:3 * k + 3])
        Ne[k] = contact_law(g, law, k_lin, k_hertz)[0]
        Nd[k] = c_n * gd if (g > 0.0 and gd > 0.0) else 0.0
    return P, Ne, Nd, converged


# ------------------------------------------------------------------------------------------------
# Newmark (average acceleration, gamma = 1/2, beta = 1/4) for one body


@njit(cache=True)
def _predict(Mb, Kb, Lf, Lb, f0, nf, alpha, beta, U, V, A, pres, pchan, up, vp, ap, dt, y1, y2, r):
    """Contact-free Newmark predictor: prescribe the supports at t+dt and solve
    (K + 2/dt C + 4/dt^2 M)_ff u_f = RHS for the free DOFs; U[free] holds the result."""
    b = (Mb.shape[1] - 1) // 2
    c0 = 4.0 / (dt * dt)
    c1 = 2.0 / dt
    for j in range(Mb.shape[0]):
        y1[j] = c0 * U[j] + 2 * c1 * V[j] + A[j] + alpha * (c1 * U[j] + V[j])
        y2[j] = beta * (c1 * U[j] + V[j])
    for q in range(len(pres)):
        j = pres[q]
        ch = pchan[q]
        u, v, a = (up[ch], vp[ch], ap[ch]) if ch >= 0 else (0.0, 0.0, 0.0)
        U[j], V[j], A[j] = u, v, a
        y1[j] = -(a + alpha * v)
        y2[j] = -(u + beta * v)
    band_rhs(Mb, Kb, y1, y2, f0, nf, b, r)
    band_cho_solve(Lf, Lb, r, r)
    for i in range(nf):
        U[f0 + i] = r[i]


@njit(cache=True)
def _finish(f0, nf, U, V, A, Uo, Vo, Ao, dt):
    c0 = 4.0 / (dt * dt)
    for i in range(f0, f0 + nf):
        A[i] = c0 * (U[i] - Uo[i]) - 2.0 * 2.0 / dt * Vo[i] - Ao[i]
        V[i] = Vo[i] + 0.5 * dt * (Ao[i] + A[i])


@njit(cache=True)
def _reactions(Mb, Kb, alpha, beta, U, V, A, fc, pres, pslot, x1, x2, out, off):
    """Force the body exerts on each support DOF: -(M a + C v + K u - f_contact) at the
    prescribed DOFs (Eq. 13). Written into out[off + slot]."""
    b = (Mb.shape[1] - 1) // 2
    for j in range(len(U)):
        x1[j] = A[j] + alpha * V[j]
        x2[j] = U[j] + beta * V[j]
    for q in range(len(pres)):
        i = pres[q]
        out[off + pslot[q]] = -(band_row(Mb, Kb, x1, x2, i, b) - fc[i])


@njit(cache=True)
def _node_kinematics(X, T0, U, V, i):
    """Deformed position, unit tangent, velocity and angular velocity of cable node i."""
    x = X[i] + U[6 * i:6 * i + 3]
    th = U[6 * i + 3:6 * i + 6]
    t = T0[i] + _cross(th, T0[i])
    t /= np.sqrt(t @ t)
    return x, t, V[6 * i:6 * i + 3].copy(), V[6 * i + 3:6 * i + 6].copy()


@njit(cache=True)
def _apply(H, v6, out, e, sign, P, arm):
    """out[element e DOFs] += sign * H^T [P; arm x P]."""
    m = _cross(arm, P)
    for c in range(12):
        s = 0.0
        for r in range(3):
            s += H[r, c] * P[r] + H[3 + r, c] * m[r]
        out[6 * e + c] += sign * s


@njit(cache=True)
def _compliance_block(Kinv, f0, nf, dof_k, Bk, dof_l, Bl, blk):
    """blk += Bk^T Kinv[dofs_k, dofs_l] Bl: one body's part of a 3x3 Delassus block. Bk, Bl map a
    contact force to generalized forces on the DOFs from dof_k, dof_l; only the free DOFs
    (f0 .. f0+nf-1, Kinv is their effective compliance) respond."""
    for p in range(Bk.shape[0]):
        dp = dof_k + p - f0
        if dp < 0 or dp >= nf:
            continue
        for q in range(Bl.shape[0]):
            dq = dof_l + q - f0
            if dq < 0 or dq >= nf:
                continue
            kv = Kinv[dp, dq]
            for r in range(3):
                for c in range(3):
                    blk[r, c] += Bk[p, r] * kv * Bl[q, c]


@njit(cache=True)
def contact_step(Xc, Tc, Uc, Vc, Xs, Rs, Ls, Us, Vs, Kc, fc0, nfc, Ks, fs0, nfs,
                 gap, r_in, law, k_lin, k_hertz, c_n, mu, v_stick, dt,
                 state, elem, xi_arr, Pn, vrel, Nout, gout, fcc, fcs, diag):
    """Contact of the cable nodes with the casing at the end of a step, from the predicted
    (contact-free) state. Writes the generalized contact forces on the cable (fcc) and the casing
    (fcs), the per-node state (OPEN/STICK/SLIP: the mode the forces were solved in), normal force,
    penetration and tangential relative speed at the end of the step (vrel, m/s: the next step sticks
    when it lies inside the band +-v_stick, Section 2.1). Returns the number
    of active contacts. diag[0] = max penetration (m), diag[1] = 1 if Newton failed, diag[2] and
    diag[3] = power dissipated (W) by contact damping (N_d g_dot) and by friction (-P_t . w_t)."""
    nn = Xc.shape[0]
    H = np.zeros((6, 12))
    idx = np.empty(nn, np.int64)
    nk = 0
    gst = np.empty(nn)
    gdst = np.empty(nn)
    wst = np.empty((nn, 3))
    nrm = np.empty((nn, 3))
    arm_c = np.empty((nn, 3))
    arm_s = np.empty((nn, 3))
    Hs = np.empty((nn, 6, 12))
    c2 = 2.0 / dt
    for i in range(nn):
        Nout[i] = 0.0
        gout[i] = 0.0
        x1, t1, v1, om1 = _node_kinematics(Xc, Tc, Uc, Vc, i)
        e, xi, far = search_casing(x1, t1, Xs, Rs, Ls, Us, elem[i], H, gap)
        if e >= 0:
            elem[i] = e
        if e < 0 or far:
            state[i] = OPEN
            continue
        elem[i] = e
        xi_arr[i] = xi
        xs = casing_point(Xs, Rs, Ls, Us, e, xi, H)
        rv = x1 - xs
        h = np.sqrt(rv @ rv)
        g = h - gap                                   # Eqs. (14), (30)-(31)
        if g <= 0.0 or h == 0.0:
            state[i] = OPEN
            continue
        n = rv / h
        cpt = xs + r_in * n                           # contact point on the casing wall
        vs = np.zeros(3)
        oms = np.zeros(3)
        for r in range(3):
            for c in range(12):
                vs[r] += H[r, c] * Vs[6 * e + c]
                oms[r] += H[3 + r, c] * Vs[6 * e + c]
        w = (v1 + _cross(om1, cpt - x1)) - (vs + _cross(oms, cpt - xs))
        idx[nk] = i
        gst[nk] = g
        gdst[nk] = n @ w
        wst[nk] = w
        nrm[nk] = n
        arm_c[nk] = cpt - x1
        arm_s[nk] = cpt - xs
        Hs[nk] = H
        nk += 1
    for i in range(len(fcc)):
        fcc[i] = 0.0
    for i in range(len(fcs)):
        fcs[i] = 0.0
    if nk == 0:
        diag[0] = 0.0
        diag[2] = 0.0
        diag[3] = 0.0
        return 0
    # Delassus matrix W = Bc^T Kc^-1 Bc + Gs^T Ks^-1 Gs (only free DOFs respond)
    Bc = np.zeros((nk, 6, 3))
    Gs = np.zeros((nk, 12, 3))
    for k in range(nk):
        for r in range(3):
            Bc[k, r, r] = 1.0
        a = arm_c[k]
        # moment (a x P): rows 3..5
        Bc[k, 3, 1], Bc[k, 3, 2] = -a[2], a[1]
        Bc[k, 4, 0], Bc[k, 4, 2] = a[2], -a[0]
        Bc[k, 5, 0], Bc[k, 5, 1] = -a[1], a[0]
        sk = arm_s[k]
        Ax = np.zeros((6, 3))
        for r in range(3):
            Ax[r, r] = -1.0
        Ax[3, 1], Ax[3, 2] = sk[2], -sk[1]
        Ax[4, 0], Ax[4, 2] = -sk[2], sk[0]
        Ax[5, 0], Ax[5, 1] = sk[1], -sk[0]
        Gs[k] = Hs[k].T @ Ax
    W = np.zeros((3 * nk, 3 * nk))
    for k in range(nk):
        ik = idx[k]
        ek = elem[ik]
        for l in range(nk):
            il = idx[l]
            el = elem[il]
            blk = np.zeros((3, 3))
            _compliance_block(Kc, fc0, nfc, 6 * ik, Bc[k], 6 * il, Bc[l], blk)   # cable
            _compliance_block(Ks, fs0, nfs, 6 * ek, Gs[k], 6 * el, Gs[l], blk)   # casing
            W[3 * k:3 * k + 3, 3 * l:3 * l + 3] = blk
    ta = np.empty((nk, 3))
    tb = np.empty((nk, 3))
    mode = np.empty(nk, np.int64)
    sdir = np.zeros((nk, 3))
    Pinit = np.zeros(3 * nk)
    for k in range(nk):
        ta[k], tb[k] = tangent_basis(nrm[k])
        i = idx[k]
        wt = wst[k] - (wst[k] @ nrm[k]) * nrm[k]
        sp = np.sqrt(wt @ wt)
        speed = sp if state[i] == OPEN else vrel[i]
        if speed < v_stick:
            mode[k] = STICK
        else:
            mode[k] = SLIP
        if sp > 0.0:
            sdir[k] = wt / sp
        if state[i] != OPEN:
            Pinit[3 * k:3 * k + 3] = Pn[i]
    active = np.ones(nk, np.bool_)
    P = Pinit
    Ne = np.zeros(nk)
    Nd = np.zeros(nk)
    for outer in range(8):
        # solve on the active subset
        sel = np.nonzero(active)[0]
        m = len(sel)
        if m == 0:
            break
        Wsub = np.empty((3 * m, 3 * m))
        for a_ in range(m):
            for b_ in range(m):
                Wsub[3 * a_:3 * a_ + 3, 3 * b_:3 * b_ + 3] = W[3 * sel[a_]:3 * sel[a_] + 3, 3 * sel[b_]:3 * sel[b_] + 3]
        Pi = np.empty(3 * m)
        for a_ in range(m):
            Pi[3 * a_:3 * a_ + 3] = P[3 * sel[a_]:3 * sel[a_] + 3]
        Psub, Nes, Nds, ok = solve_contact_forces(Wsub, gst[sel], gdst[sel], wst[sel], nrm[sel], ta[sel], tb[sel],
                                                  mode[sel], sdir[sel], Pi, law, k_lin, k_hertz, c_n, mu, dt)
        if not ok:
            diag[1] = 1.0
        P = np.zeros(3 * nk)
        for a_ in range(m):
            P[3 * sel[a_]:3 * sel[a_] + 3] = Psub[3 * a_:3 * a_ + 3]
            Ne[sel[a_]] = Nes[a_]
            Nd[sel[a_]] = Nds[a_]
        changed = False
        d = W @ P
        for a_ in range(m):
            k = sel[a_]
            N = Ne[k] + Nd[k]
            if N <= 0.0:
                active[k] = False
                changed = True
                continue
            Pk = P[3 * k:3 * k + 3]
            Pt = Pk - (Pk @ nrm[k]) * nrm[k]
            ft = np.sqrt(Pt @ Pt)
            if mode[k] == STICK and ft > mu * N * (1 + 1e-12):
                mode[k] = SLIP
                sdir[k] = -Pt / ft
                changed = True
            elif mode[k] == SLIP:
                w = wst[k] + c2 * d[3 * k:3 * k + 3]
                wt = w - (w @ nrm[k]) * nrm[k]
                if wt @ sdir[k] < 0.0:      # friction would reverse the slip: it sticks instead
                    if v_stick > 0.0 and outer < 4:
                        mode[k] = STICK
                    else:
                        spd = np.sqrt(wt @ wt)
                        if spd > 0.0:
                            sdir[k] = wt / spd
                    changed = True
        if not changed:
            break
    gmax = 0.0
    diag[2] = 0.0
    diag[3] = 0.0
    d = W @ P
    for k in range(nk):
        i = idx[k]
        Pk = P[3 * k:3 * k + 3]
        if not active[k] or Ne[k] + Nd[k] <= 0.0:
            state[i] = OPEN
            Pn[i, :] = 0.0
            continue
        g = gst[k] + nrm[k] @ d[3 * k:3 * k + 3]
        gout[i] = g
        Nout[i] = Ne[k] + Nd[k]
        gmax = max(gmax, g)
        w = wst[k] + c2 * d[3 * k:3 * k + 3]
        wt = w - (w @ nrm[k]) * nrm[k]
        state[i] = mode[k]
        vrel[i] = np.sqrt(wt @ wt)
        diag[2] += Nd[k] * (w @ nrm[k])                  # damping acts only while compressing
        Pt = Pk - (Pk @ nrm[k]) * nrm[k]
        diag[3] -= Pt @ wt
        Pn[i] = Pk
        # generalized forces: +P at the cable node (with its moment), -P on the casing element
        for r in range(6):
            s = 0.0
            for c in range(3):
                s += Bc[k, r, c] * Pk[c]
            fcc[6 * i + r] += s
        e = elem[i]
        for r in range(12):
            s = 0.0
            for c in range(3):
                s += Gs[k, r, c] * Pk[c]
            fcs[6 * e + r] += s
    for i in range(nn):
        if Nout[i] == 0.0:
            state[i] = OPEN
            Pn[i, :] = 0.0
    diag[0] = gmax
    return nk


@njit(cache=True)
def run_steps(t0, dt, up, vp, ap,
              s_on, sMb, sKb, sLf, sLb, sf0, snf, salpha, sbeta, sU, sV, sA, spres, spchan, spslot, sKinv,
              c_on, cMb, cKb, cLf, cLb, cf0, cnf, calpha, cbeta, cU, cV, cA, cpres, cpchan, cpslot, cKinv,
              contact_on, Xc, Tc, Xs, Rs, Ls, gap, r_in, r_cable, law, k_lin, k_hertz, c_n, mu, v_stick,
              state, elem, xi_arr, Pn, vrel, Nn, gn, fcs, fcc, reac, ledger, ledger_on,
              rec_on, rec_F, rec_state, rec_N, rec_g, rec_off, info):
    """Advance both bodies by len(up) Newmark steps of size dt (s) from time t0 (s).

    up, vp, ap: (n, 12) support channel displacement (m), velocity (m/s), acceleration (m/s2) at
    t0 + (k+1) dt. reac (24): force each body exerts on each support, N and N.m, in the order
    casing A, casing B, cable A, cable B, each [Fx Fy Fz Mx My Mz]. ledger (J): [work of the
    supports, Rayleigh dissipation, energy at the start (set by the engine), friction dissipation,
    work of the contact forces, contact-damping dissipation, last friction power (W), last damping
    power (W)]; the dissipations integrate the powers by the trapezoidal rule. Returns a status code (OK or ERR_*); info = [time, node, value] of a failure.
    """
    nsteps = up.shape[0]
    ns = sU.shape[0]
    nc = cU.shape[0]
    sUo, sVo, sAo = sU.copy(), sV.copy(), sA.copy()
    cUo, cVo, cAo = cU.copy(), cV.copy(), cA.copy()
    sy1, sy2, sr = np.zeros(ns), np.zeros(ns), np.zeros(max(snf, 1))
    cy1, cy2, cr = np.zeros(nc), np.zeros(nc), np.zeros(max(cnf, 1))
    fcs_new, fcc_new = np.zeros(ns), np.zeros(nc)
    reac_new = np.zeros(24)
    diag = np.zeros(4)
    nn = Xc.shape[0]
    Ne_prev = Nn.copy()
    for k in range(nsteps):
        t = t0 + (k + 1) * dt
        if s_on:
            sUo[:] = sU
            sVo[:] = sV
            sAo[:] = sA
            _predict(sMb, sKb, sLf, sLb, sf0, snf, salpha, sbeta, sU, sV, sA, spres, spchan,
                     up[k], vp[k], ap[k], dt, sy1, sy2, sr)
        if c_on:
            cUo[:] = cU
            cVo[:] = cV
            cAo[:] = cA
            _predict(cMb, cKb, cLf, cLb, cf0, cnf, calpha, cbeta, cU, cV, cA, cpres, cpchan,
                     up[k], vp[k], ap[k], dt, cy1, cy2, cr)
        nact = 0
        if contact_on:
            # predicted velocities of the free DOFs (Newmark: v = 2/dt (u - u_old) - v_old)
            for i in range(sf0, sf0 + snf):
                sV[i] = 2.0 / dt * (sU[i] - sUo[i]) - sVo[i]
            for i in range(cf0, cf0 + cnf):
                cV[i] = 2.0 / dt * (cU[i] - cUo[i]) - cVo[i]
            nact = contact_step(Xc, Tc, cU, cV, Xs, Rs, Ls, sU, sV, cKinv, cf0, cnf, sKinv, sf0, snf,
                                gap, r_in, law, k_lin, k_hertz, c_n, mu, v_stick, dt,
                                state, elem, xi_arr, Pn, vrel, Nn, gn, fcc_new, fcs_new, diag)
            if nact > 0:
                for i in range(snf):
                    sr[i] = fcs_new[sf0 + i]
                band_cho_solve(sLf, sLb, sr, sr)
                for i in range(snf):
                    sU[sf0 + i] += sr[i]
                for i in range(cnf):
                    cr[i] = fcc_new[cf0 + i]
                band_cho_solve(cLf, cLb, cr, cr)
                for i in range(cnf):
                    cU[cf0 + i] += cr[i]
            if diag[0] > r_cable:
                info[0], info[2] = t, diag[0]
                for i in range(nn):
                    if gn[i] == diag[0]:
                        info[1] = i
                return ERR_PENETRATION
        if s_on:
            _finish(sf0, snf, sU, sV, sA, sUo, sVo, sAo, dt)
            _reactions(sMb, sKb, salpha, sbeta, sU, sV, sA, fcs_new, spres, spslot, sy1, sy2, reac_new, 0)
        if c_on:
            _finish(cf0, cnf, cU, cV, cA, cUo, cVo, cAo, dt)
            _reactions(cMb, cKb, calpha, cbeta, cU, cV, cA, fcc_new, cpres, cpslot, cy1, cy2, reac_new, 12)
        # blow-up check on the cheap aggregates
        tot = 0.0
        for i in range(24):
            tot += reac_new[i]
        if not np.isfinite(tot):
            info[0], info[1], info[2] = t, -1, tot
            return ERR_NAN
        # energy ledger (trapezoidal rule, consistent with the average-acceleration scheme)
        if s_on:
            for q in range(len(spres)):
                j = spres[q]
                ledger[0] += -0.5 * (reac[spslot[q]] + reac_new[spslot[q]]) * (sU[j] - sUo[j])
            for i in range(ns):
                ledger[4] += 0.5 * (fcs[i] + fcs_new[i]) * (sU[i] - sUo[i])
            if ledger_on:
                for i in range(ns):
                    sy1[i] = sVo[i] + sV[i]
                ledger[1] += 0.25 * dt * band_quadratic(sMb, sKb, salpha, sbeta, sy1, (sMb.shape[1] - 1) // 2)
        if c_on:
            for q in range(len(cpres)):
                j = cpres[q]
                ledger[0] += -0.5 * (reac[12 + cpslot[q]] + reac_new[12 + cpslot[q]]) * (cU[j] - cUo[j])
            for i in range(nc):
                ledger[4] += 0.5 * (fcc[i] + fcc_new[i]) * (cU[i] - cUo[i])
            if ledger_on:
                for i in range(nc):
                    cy1[i] = cVo[i] + cV[i]
                ledger[1] += 0.25 * dt * band_quadratic(cMb, cKb, calpha, cbeta, cy1, (cMb.shape[1] - 1) // 2)
        if contact_on:
            ledger[3] += 0.5 * dt * (ledger[6] + diag[3])
            ledger[5] += 0.5 * dt * (ledger[7] + diag[2])
            ledger[6] = diag[3]
            ledger[7] = diag[2]
        reac[:] = reac_new
        fcs[:] = fcs_new
        fcc[:] = fcc_new
        if rec_on:
            r = rec_off + k
            rec_F[r, :] = reac
            for i in range(nn):
                rec_state[r, i] = state[i]
                rec_N[r, i] = Nn[i]
                rec_g[r, i] = gn[i]
    info[0] = t0 + nsteps * dt
    return OK
