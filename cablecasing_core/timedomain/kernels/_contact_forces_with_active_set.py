"""The implicit contact forces of a Newmark step (Eqs. 14-24, 29-39): every cable node's contact search,
the Delassus matrix of the active contacts from both bodies' effective compliance, the Newton of
``_contact_newton_for_fixed_modes.py`` inside passes that switch contacts between stick and slip
and in and out of the active set, and the generalized forces on both bodies.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ._banded_products_and_block_solve import fill
from ._compile_options import FM, NO_RT
from ._contact_newton_for_fixed_modes import (
    BAND,
    forces_from_unknowns,
    newton_for_fixed_modes,
    reduced_delassus,
    relative_displacement,
    unknowns_from_forces,
)
from ._contact_search_and_law import cable_node, far_from_wall, follow_cut, search_node, tangent_basis
from ._hermite_interpolation import hermite_matrix
from ._newmark_per_body import newmark_coefficients
from ._step_loop_contract import (
    DIAG_ACTIVE_SET_PASSES,
    DIAG_DAMPING_POWER,
    DIAG_FRICTION_POWER,
    DIAG_MAX_PENETRATION,
    DIAG_NEWTON_FAILED,
    DIAG_NEWTON_ITERATIONS,
    DIAG_SLIP_REVERSED,
    DIAG_SLOW_SLIP,
    OPEN,
    SLIP,
    STICK,
)


def contact_workspace(nn):
    """Scratch arrays of the contact solve for nn cable nodes (allocated once per run)."""
    m = 3 * max(nn, 1)
    z = lambda *s: np.zeros(s)  # noqa: E731
    return (
        np.zeros(max(nn, 1), np.int64),
        z(nn),
        z(nn),
        z(nn, 3),
        z(nn, 3),
        z(nn, 3),
        z(nn, 3),
        z(nn, 6, 12),
        z(nn, 6, 3),
        z(nn, 12, 3),
        z(m, m),
        z(m, m),
        z(m),
        z(m),
        z(m),
        z(m),
        z(nn, 3),
        z(nn, 3),
        np.zeros(max(nn, 1), np.int64),
        z(nn, 3),
        z(nn),
        z(nn),
        np.zeros(max(nn, 1), np.bool_),
        z(6),
        z(m),
        np.zeros(max(nn, 1), np.bool_),
        np.zeros(max(nn, 1), np.bool_),
        z(m, m),
        z(m),
        z(m),
        np.zeros(max(nn, 1) + 1, np.int64),
        z(nn),
        z(3 * SPAN),
        np.full(max(nn, 1) + 1, -1, np.int64),
        np.zeros(m, np.int64),
        z(nn),
    )


#: Columns of casing compliance one pass of :func:`_casing_compliance_row` takes (the stride of its
#: scratch: a constant, so that LLVM sees its three rows apart and vectorizes the pass).
SPAN = 256


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _span_rows(Kinv, r0, G, q0, lo, span, U, first):
    """U[a * SPAN + j] (+)= sum_p G[q0 + p, a] Kinv[r0 + p, lo + j] for p < 6 and j < span: six rows
    of compliance times six rows of G, over a contiguous span of columns (the loop over j is the
    one vectorized; lo, span unsigned so that no negative-index wraparound stops it)."""
    for j in range(span):
        c = lo + j
        if first:
            u0 = u1 = u2 = 0.0
        else:
            u0, u1, u2 = U[j], U[SPAN + j], U[2 * SPAN + j]
        for p in range(6):
            kv = Kinv[r0 + p][c]
            u0 += kv * G[q0 + p, 0]
            u1 += kv * G[q0 + p, 1]
            u2 += kv * G[q0 + p, 2]
        U[j], U[SPAN + j], U[2 * SPAN + j] = u0, u1, u2


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _casing_compliance_row(Ks, Gs, idx, elem, k, nk, W, U):
    """The casing's part of the Delassus blocks (k, l), l >= k: W[3k:3k+3, 3l:3l+3] += G_k^T
    Ks[dofs_k, dofs_l] G_l, G (12 x 3, ``Gs``) the map of a contact force to the generalized forces
    on the DOFs of its element. First U = G_k^T Ks[dofs_k, lo:hi] (3 x span) over the contiguous
    span of columns that the elements of contacts l touch (vectorized, two passes of six rows), then
    each block U[:, dofs_l] G_l. The contacts are taken in runs whose span fits SPAN columns (one
    run when the casing has at most SPAN DOFs)."""
    e6k = 6 * elem[idx[k]]
    Gk = Gs[k]
    l0 = k
    while l0 < nk:
        lo = 6 * elem[idx[l0]]
        hi = lo + 12
        l1 = l0 + 1
        while l1 < nk:
            e6 = 6 * elem[idx[l1]]
            if max(hi, e6 + 12) - min(lo, e6) > SPAN:
                break
            lo, hi = min(lo, e6), max(hi, e6 + 12)
            l1 += 1
        span, ulo = np.uint64(hi - lo), np.uint64(lo)
        _span_rows(Ks, e6k, Gk, 0, ulo, span, U, True)
        _span_rows(Ks, e6k + 6, Gk, 6, ulo, span, U, False)
        for l in range(l0, l1):
            _casing_block(U, 6 * elem[idx[l]] - lo, Gs[l], W, 3 * k, 3 * l)
        l0 = l1


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _casing_block(U, o, Gl, W, r0, c0):
    """W[r0:r0+3, c0:c0+3] += U[:, o:o+12] G_l (U: three rows at stride SPAN, see
    :func:`_casing_compliance_row`). The nine sums are named locals that advance together over the
    twelve terms: nine independent chains of multiply-adds instead of one chain of twelve after
    another, each waiting for the last (there is no re-association; the package docstring), ~2 x
    fewer cycles per block."""
    u0, u1, u2 = U[o : o + 12], U[SPAN + o : SPAN + o + 12], U[2 * SPAN + o : 2 * SPAN + o + 12]
    s00 = s01 = s02 = s10 = s11 = s12 = s20 = s21 = s22 = 0.0
    for q in range(12):
        g0, g1, g2 = Gl[q, 0], Gl[q, 1], Gl[q, 2]
        x0, x1, x2 = u0[q], u1[q], u2[q]
        s00 += x0 * g0
        s01 += x0 * g1
        s02 += x0 * g2
        s10 += x1 * g0
        s11 += x1 * g1
        s12 += x1 * g2
        s20 += x2 * g0
        s21 += x2 * g1
        s22 += x2 * g2
    W[r0, c0] += s00
    W[r0, c0 + 1] += s01
    W[r0, c0 + 2] += s02
    W[r0 + 1, c0] += s10
    W[r0 + 1, c0 + 1] += s11
    W[r0 + 1, c0 + 2] += s12
    W[r0 + 2, c0] += s20
    W[r0 + 2, c0 + 1] += s21
    W[r0 + 2, c0 + 2] += s22


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _cable_compliance_block(Kinv, dof_k, ak0, ak1, ak2, dof_l, al0, al1, al2, W, ok, ol):
    """The cable's part of a 3x3 Delassus block, B_k^T Kinv[dofs_k, dofs_l] B_l with B = [I; [a]x]
    (the force on the node and its moment a x P, a the arm from the node; the rows of ``Bc``),
    added to W[ok:ok+3, ol:ol+3]. Written out on the nonzero entries of B: 54 FMAs where
    the dense product B_k^T K B_l takes 162 (a zero term adds exactly nothing; the contraction into
    FMAs may differ from the dense loops', so the bits may differ at rounding level). The 18 values
    of K B_l are named locals, set by row p, so that they stay in registers once the loop over p
    is unrolled."""
    t00 = t01 = t02 = t03 = t04 = t05 = 0.0  # t_c[p] = (Kinv_kl B_l)[p, c]
    t10 = t11 = t12 = t13 = t14 = t15 = 0.0
    t20 = t21 = t22 = t23 = t24 = t25 = 0.0
    for p in range(6):
        row = Kinv[dof_k + p, dof_l : dof_l + 6]
        k0, k1, k2, k3, k4, k5 = row[0], row[1], row[2], row[3], row[4], row[5]
        u0 = k0 + k4 * al2 - k5 * al1  # B_l columns: e_c + [a_l]x rows 3..5
        u1 = k1 - k3 * al2 + k5 * al0
        u2 = k2 + k3 * al1 - k4 * al0
        if p == 0:
            t00, t10, t20 = u0, u1, u2
        elif p == 1:
            t01, t11, t21 = u0, u1, u2
        elif p == 2:
            t02, t12, t22 = u0, u1, u2
        elif p == 3:
            t03, t13, t23 = u0, u1, u2
        elif p == 4:
            t04, t14, t24 = u0, u1, u2
        else:
            t05, t15, t25 = u0, u1, u2
    W[ok, ol] += t00 + t04 * ak2 - t05 * ak1
    W[ok, ol + 1] += t10 + t14 * ak2 - t15 * ak1
    W[ok, ol + 2] += t20 + t24 * ak2 - t25 * ak1
    W[ok + 1, ol] += t01 - t03 * ak2 + t05 * ak0
    W[ok + 1, ol + 1] += t11 - t13 * ak2 + t15 * ak0
    W[ok + 1, ol + 2] += t21 - t23 * ak2 + t25 * ak0
    W[ok + 2, ol] += t02 + t03 * ak1 - t04 * ak0
    W[ok + 2, ol + 1] += t12 + t13 * ak1 - t14 * ak0
    W[ok + 2, ol + 2] += t22 + t23 * ak1 - t24 * ak0


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _delassus(Kc, Ks, Gs, idx, elem, arm_c, nk, W, Uspan):
    """The Delassus matrix W (3 nk x 3 nk, m/N) = Bc^T Kc Bc + Gs^T Ks Gs of the nk contacts: the
    cable's blocks on the nonzero entries of B (``_cable_compliance_block``), the casing's by rows
    (``_casing_compliance_row``), the lower triangle mirrored."""
    m = 3 * nk
    for i in range(m):
        for j in range(m):
            W[i, j] = 0.0
    for k in range(nk):
        ik = idx[k]
        ak0, ak1, ak2 = arm_c[k, 0], arm_c[k, 1], arm_c[k, 2]
        for l in range(k, nk):
            al0, al1, al2 = arm_c[l, 0], arm_c[l, 1], arm_c[l, 2]
            _cable_compliance_block(Kc, 6 * ik, ak0, ak1, ak2, 6 * idx[l], al0, al1, al2, W, 3 * k, 3 * l)
        _casing_compliance_row(Ks, Gs, idx, elem, k, nk, W, Uspan)
        for l in range(k + 1, nk):
            for r in range(3):
                for c in range(3):
                    W[3 * l + c, 3 * k + r] = W[3 * k + r, 3 * l + c]


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def contact_parameters(law, dt, reuse, max_turn):
    """The ``par`` tuple of :func:`solve_contact_forces` for a (sub-)step of dt (s) from the step
    loop's law record: reuse keeps the Delassus matrix while the same contacts hold, max_turn (rad)
    is the turn of the friction direction that makes a slow slip an event (stored as 1 - cos)."""
    turn = 1.0 - np.cos(max_turn)
    return (law.gap, law.r_in, law.law, law.k_lin, law.k_hertz, law.c_n, law.mu, law.v_stick, dt, reuse, turn, law.vreg)


@njit(**NO_RT)
def solve_contact_forces(
    Xc,
    Tc,
    Uc,
    Vc,
    Xs,
    Rs,
    Ls,
    Us,
    Vs,
    Kc,
    Ks,
    par,
    state,
    elem,
    xi_arr,
    Pn,
    Pp,
    vrel,
    Nout,
    gout,
    fcc,
    fcs,
    diag,
    ws,
    share,
):
    """Contact of the cable nodes with the casing at the end of a step, from the predicted
    (contact-free) state (Eqs. 14-24, 29-39). Writes the generalized contact forces on the cable (fcc, N
    and N.m) and the casing (fcs), the per-node state (OPEN/STICK/SLIP: the mode the forces were
    solved in), normal force (Nout, N), penetration (gout, m) and tangential relative speed at the
    end of the step (vrel, m/s: the next step sticks when it lies inside the band +-v_stick,
    Section 2.1). Pn, Pp (N, nn x 3): each node's contact force at the end of the last step and of
    the one before (zero where the node was not in contact); the regularised law's Newton starts
    from their linear extrapolation, 2 Pn - Pp, where both are nonzero (its forces move smoothly
    with the step; ~0.8 x the cost of starting from Pn, docs/performance-history.md), the switch law's from
    Pn. Kc, Ks: effective compliances (m/N) over all DOFs of each body (zero rows and
    columns on the prescribed DOFs). par = (gap, r_in, law, k_lin, k_hertz, c_n, mu, v_stick, dt,
    reuse, turn, vreg) (m, m, 0 Hertz / 1 linear / 2 Hunt-Crossley, N/m, N/m^1.5, kg/s or s/m, -, m/s, s,
    keep the Delassus matrix of the last solve when the same contacts hold, the 1 - cos of the
    friction direction's turn that marks a slow slip as an event, DIAG_SLOW_SLIP; m/s: 0 for the
    switch law of Section 2.1, > 0 for Coulomb's law regularised over that speed,
    f_t = -mu N v_t / sqrt(|v_t|^2 + vreg^2) at the end of the step, every contact then solved with
    three unknowns and reported STICK while |v_t| < vreg, else SLIP); ws: the scratch arrays of
    :func:`contact_workspace`; share (one per cable node, dimensionless): each node's share of the
    law, its stiffness and damper (``engine.contact_shares``). Returns the number of contacts
    examined (penetrating before the solve); the DIAG_* slots of diag (``_step_loop_contract.py``)
    say the largest penetration, a failed Newton, the damping and friction powers, the
    iterations and passes taken, and the events of the switch law's friction: a slow slip whose
    friction turned (DIAG_SLOW_SLIP) and a slip that reversed (DIAG_SLIP_REVERSED).

    At most 30 arguments on purpose: Python compiles a call with more than 30 positional
    arguments as a call with a built tuple (CALL_FUNCTION_EX), and numba then increments and
    decrements the reference count of every array in it around each call, ~100 atomic operations
    per step."""
    gap, r_in, law, k_lin, k_hertz, c_n, mu, v_stick, dt, reuse, turn, vreg = par
    (
        idx,
        gst,
        gdst,
        wst,
        nrm,
        arm_c,
        arm_s,
        Hs,
        Bc,
        Gs,
        W,
        J,
        R,
        dx,
        P,
        d,
        ta,
        tb,
        mode,
        sdir,
        Ne,
        Nd,
        active,
        tmp,
        xt,
        touch,
        skip,
        Q,
        x,
        y,
        off,
        wkk,
        Uspan,
        held,
        piv,
        sk,
    ) = ws
    nn = Xc.shape[0]
    nk = 0
    _, c2 = newmark_coefficients(dt)  # 2/dt (1/s): a velocity change per displacement change (Eq. 18)
    far_from_wall(Xc, Tc, Uc, Xs, Ls, Us, elem, gap, skip)
    for i in range(nn):
        Nout[i] = 0.0
        gout[i] = 0.0
        if skip[i]:
            state[i] = OPEN
            continue
        o = 6 * i
        # (kernels._contact_search_and_law.search_cable_node does the same; written out here because
        # calling it changes this kernel's FMA contraction, and so the bits of every record)
        x0, x1, x2, t0, t1, t2 = cable_node(Xc, Tc, Uc, i)
        tn = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
        t0, t1, t2 = t0 / tn, t1 / tn, t2 / tn
        found = False
        if reuse and state[i] != OPEN and 0.0 < xi_arr[i] < 1.0:
            # a sub-step after the first, the node in contact: its cut followed on its element
            e, far = elem[i], False
            found, xi, px, py, pz = follow_cut(x0, x1, x2, t0, t1, t2, Xs, Rs, Ls, Us, e, xi_arr[i])
        if not found:
            e, xi, far, px, py, pz = search_node(x0, x1, x2, t0, t1, t2, Xs, Rs, Ls, Us, elem[i], gap)
        if e >= 0:
            elem[i] = e
        if e < 0 or far:
            state[i] = OPEN
            continue
        xi_arr[i] = xi
        r0, r1, r2 = x0 - px, x1 - py, x2 - pz
        h = np.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
        g = h - gap  # Eqs. (14), (30)-(31)
        if g <= 0.0 or h == 0.0:
            state[i] = OPEN
            continue
        n0, n1, n2 = r0 / h, r1 / h, r2 / h
        c0, c1, c2_ = px + r_in * n0, py + r_in * n1, pz + r_in * n2  # contact point on the wall
        H = Hs[nk]
        hermite_matrix(xi, Ls[e], Rs[e], H)
        vs = tmp  # casing velocity and spin at xi
        for r in range(6):
            s = 0.0
            for c in range(12):
                s += H[r, c] * Vs[6 * e + c]
            vs[r] = s
        ac0, ac1, ac2 = c0 - x0, c1 - x1, c2_ - x2  # arm from the cable node
        as0, as1, as2 = c0 - px, c1 - py, c2_ - pz  # arm from the casing axis
        om0, om1, om2 = Vc[o + 3], Vc[o + 4], Vc[o + 5]
        w0 = Vc[o] + om1 * ac2 - om2 * ac1 - (vs[0] + vs[4] * as2 - vs[5] * as1)
        w1 = Vc[o + 1] + om2 * ac0 - om0 * ac2 - (vs[1] + vs[5] * as0 - vs[3] * as2)
        w2 = Vc[o + 2] + om0 * ac1 - om1 * ac0 - (vs[2] + vs[3] * as1 - vs[4] * as0)
        idx[nk] = i
        sk[nk] = share[i]
        gst[nk] = g
        gdst[nk] = n0 * w0 + n1 * w1 + n2 * w2
        wst[nk, 0], wst[nk, 1], wst[nk, 2] = w0, w1, w2
        nrm[nk, 0], nrm[nk, 1], nrm[nk, 2] = n0, n1, n2
        arm_c[nk, 0], arm_c[nk, 1], arm_c[nk, 2] = ac0, ac1, ac2
        arm_s[nk, 0], arm_s[nk, 1], arm_s[nk, 2] = as0, as1, as2
        nk += 1
    fill(fcc, 0.0)
    fill(fcs, 0.0)
    diag[DIAG_DAMPING_POWER] = 0.0
    diag[DIAG_FRICTION_POWER] = 0.0
    diag[DIAG_SLOW_SLIP] = 0.0
    diag[DIAG_SLIP_REVERSED] = 0.0
    if nk == 0:
        held[0] = -1  # (W was not formed: a later solve must not take the one in ws as this one's)
        diag[DIAG_MAX_PENETRATION] = 0.0
        for i in range(nn):
            Pn[i, 0], Pn[i, 1], Pn[i, 2] = 0.0, 0.0, 0.0
            Pp[i, 0], Pp[i, 1], Pp[i, 2] = 0.0, 0.0, 0.0
        return 0
    # Delassus matrix W = Bc^T Kc^-1 Bc + Gs^T Ks^-1 Gs (only free DOFs respond)
    for k in range(nk):
        B = Bc[k]
        G = Gs[k]
        H = Hs[k]
        B[:, :] = 0.0
        a0, a1, a2 = arm_c[k, 0], arm_c[k, 1], arm_c[k, 2]
        B[0, 0], B[1, 1], B[2, 2] = 1.0, 1.0, 1.0
        B[3, 1], B[3, 2] = -a2, a1  # moment a x P in rows 3..5
        B[4, 0], B[4, 2] = a2, -a0
        B[5, 0], B[5, 1] = -a1, a0
        s0, s1, s2 = arm_s[k, 0], arm_s[k, 1], arm_s[k, 2]
        for r in range(12):  # G = H^T [-I; -[s]x]: -P and -(s x P) on the axis
            G[r, 0] = -H[0, r] - (H[4, r] * s2 - H[5, r] * s1)
            G[r, 1] = -H[1, r] - (H[5, r] * s0 - H[3, r] * s2)
            G[r, 2] = -H[2, r] - (H[3, r] * s1 - H[4, r] * s0)
    m = 3 * nk
    # W of the last solve is kept when ``reuse`` and the same nodes are in contact on the same casing
    # elements (the sub-steps of a recomputed step: W moves with the contact points, by ~1e-4 of
    # itself over a step; docs/time_domain.md); ``held`` = [nk, (node, element) ...] of the W in ws
    same = reuse and held[0] == nk
    if same:
        for k in range(nk):
            if held[1 + k] != idx[k] * (Ls.shape[0] + 1) + elem[idx[k]]:
                same = False
                break
    if not same:
        _delassus(Kc, Ks, Gs, idx, elem, arm_c, nk, W, Uspan)
        held[0] = nk
        for k in range(nk):
            held[1 + k] = idx[k] * (Ls.shape[0] + 1) + elem[idx[k]]
    for k in range(nk):
        tangent_basis(nrm[k, 0], nrm[k, 1], nrm[k, 2], ta[k], tb[k])
        i = idx[k]
        wn = wst[k, 0] * nrm[k, 0] + wst[k, 1] * nrm[k, 1] + wst[k, 2] * nrm[k, 2]
        wt0, wt1, wt2 = wst[k, 0] - wn * nrm[k, 0], wst[k, 1] - wn * nrm[k, 1], wst[k, 2] - wn * nrm[k, 2]
        sp = np.sqrt(wt0 * wt0 + wt1 * wt1 + wt2 * wt2)
        speed = sp if state[i] == OPEN else vrel[i]
        mode[k] = STICK if speed < v_stick or vreg > 0.0 else SLIP
        sdir[k, 0], sdir[k, 1], sdir[k, 2] = (wt0 / sp, wt1 / sp, wt2 / sp) if sp > 0.0 else (0.0, 0.0, 0.0)
        extrapolate = vreg > 0.0 and state[i] != OPEN and (Pp[i, 0] != 0.0 or Pp[i, 1] != 0.0 or Pp[i, 2] != 0.0)
        for c in range(3):
            if extrapolate:
                P[3 * k + c] = 2.0 * Pn[i, c] - Pp[i, c]
            else:
                P[3 * k + c] = Pn[i, c] if state[i] != OPEN else 0.0
        active[k] = True
        touch[k] = False
    for k in range(nk):
        o = 3 * k
        wkk[k] = max(W[o, o], W[o + 1, o + 1], W[o + 2, o + 2])
    for outer in range(8):
        r = unknowns_from_forces(nk, nrm, ta, tb, mode, active, P, off, x)
        reduced_delassus(W, nk, nrm, ta, tb, sdir, mu, off, Q, J)  # (J: its scratch, before the Newton fills it)
        its = newton_for_fixed_modes(
            Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, x, law, k_lin, k_hertz, c_n, sk, dt, J, R, dx, y, Ne, Nd,
            xt, mu, vreg, piv, BAND,
        )  # fmt: skip
        forces_from_unknowns(nk, nrm, ta, tb, sdir, mu, off, x, P)
        relative_displacement(W, P, m, d)
        diag[DIAG_NEWTON_ITERATIONS] += abs(its)
        diag[DIAG_ACTIVE_SET_PASSES] += 1
        # the last pass's Newton decides (an earlier one that ran out, a stick that needed more than
        # mu N, is then switched to slip and solved again)
        diag[DIAG_NEWTON_FAILED] = 1.0 if its < 0 else 0.0
        changed = False
        for k in range(nk):
            if not active[k]:
                continue
            o = 3 * k
            N = Ne[k] + Nd[k]
            if N <= 0.0:
                active[k] = False
                P[o], P[o + 1], P[o + 2] = 0.0, 0.0, 0.0
                changed = True
                continue
            # the law holds for g > 0; at g <= 0 the damper alone would push the bodies apart past
            # the surface, so the step ends touching (g = 0, N <= c_n g_dot); a touching contact
            # whose force exceeds the damper's goes back to the law
            dn = nrm[k, 0] * d[o] + nrm[k, 1] * d[o + 1] + nrm[k, 2] * d[o + 2]
            if not touch[k] and law != 2 and gst[k] + dn <= 0.0:  # (Hunt-Crossley: no force at g = 0)
                touch[k] = True
                changed = True
            elif touch[k] and N > c_n * sk[k] * max(gdst[k] + c2 * dn, 0.0) * (1 + 1e-12):
                touch[k] = False
                changed = True
            pn = P[o] * nrm[k, 0] + P[o + 1] * nrm[k, 1] + P[o + 2] * nrm[k, 2]
            pt0, pt1, pt2 = P[o] - pn * nrm[k, 0], P[o + 1] - pn * nrm[k, 1], P[o + 2] - pn * nrm[k, 2]
            ft = np.sqrt(pt0 * pt0 + pt1 * pt1 + pt2 * pt2)
            if vreg > 0.0:
                continue  # the regularised law has no stick to break and no slip to reverse
            if mode[k] == STICK and ft > mu * N * (1 + 1e-12):
                mode[k] = SLIP
                sdir[k, 0], sdir[k, 1], sdir[k, 2] = -pt0 / ft, -pt1 / ft, -pt2 / ft
                changed = True
            elif mode[k] == SLIP:
                w0, w1, w2 = wst[k, 0] + c2 * d[o], wst[k, 1] + c2 * d[o + 1], wst[k, 2] + c2 * d[o + 2]
                wn = w0 * nrm[k, 0] + w1 * nrm[k, 1] + w2 * nrm[k, 2]
                wt0, wt1, wt2 = w0 - wn * nrm[k, 0], w1 - wn * nrm[k, 1], w2 - wn * nrm[k, 2]
                if wt0 * sdir[k, 0] + wt1 * sdir[k, 1] + wt2 * sdir[k, 2] < 0.0:
                    # friction would reverse the slip: it sticks instead
                    if v_stick > 0.0 and outer < 4:
                        mode[k] = STICK
                    else:
                        spd = np.sqrt(wt0 * wt0 + wt1 * wt1 + wt2 * wt2)
                        if spd > 0.0:
                            sdir[k, 0], sdir[k, 1], sdir[k, 2] = wt0 / spd, wt1 / spd, wt2 / spd
                    changed = True
        if not changed:
            break
    if changed:
        # the passes ran out with a change: a contact the last pass opened still counts in d
        relative_displacement(W, P, m, d)
    gmax = 0.0
    for k in range(nk):
        i = idx[k]
        o = 3 * k
        if not active[k] or Ne[k] + Nd[k] <= 0.0:
            continue
        n0, n1, n2 = nrm[k, 0], nrm[k, 1], nrm[k, 2]
        dn = n0 * d[o] + n1 * d[o + 1] + n2 * d[o + 2]
        g = 0.0 if touch[k] else gst[k] + dn
        gout[i] = g
        Nout[i] = Ne[k] + Nd[k]
        gmax = max(gmax, g)
        w0, w1, w2 = wst[k, 0] + c2 * d[o], wst[k, 1] + c2 * d[o + 1], wst[k, 2] + c2 * d[o + 2]
        wn = w0 * n0 + w1 * n1 + w2 * n2
        wt0, wt1, wt2 = w0 - wn * n0, w1 - wn * n1, w2 - wn * n2
        vrel[i] = np.sqrt(wt0 * wt0 + wt1 * wt1 + wt2 * wt2)
        slipped = state[i] == SLIP and mu > 0.0  # (the last solve's mode; without friction, no slip to reverse)
        state[i] = mode[k] if vreg == 0.0 else (STICK if vrel[i] < vreg else SLIP)
        slow = c2 * wkk[k] * mu * Nout[i] > vrel[i]
        if mode[k] == SLIP and (slow or slipped):
            # the friction's turn since the last solve (1 - cos of the angle between its tangential parts)
            pn = Pn[i, 0] * n0 + Pn[i, 1] * n1 + Pn[i, 2] * n2
            a0, a1, a2 = Pn[i, 0] - pn * n0, Pn[i, 1] - pn * n1, Pn[i, 2] - pn * n2
            pn = P[o] * n0 + P[o + 1] * n1 + P[o + 2] * n2
            b0, b1, b2 = P[o] - pn * n0, P[o + 1] - pn * n1, P[o + 2] - pn * n2
            ab = np.sqrt((a0 * a0 + a1 * a1 + a2 * a2) * (b0 * b0 + b1 * b1 + b2 * b2))
            if slow and (ab == 0.0 or 1.0 - (a0 * b0 + a1 * b1 + a2 * b2) / ab > turn):
                # the friction force alone changes the slip velocity by more than it is within the step,
                # and its direction turned by more than the step allows (1 - cos > turn) since the last
                # solve, or the contact is new: the slip is slow and not steady
                diag[DIAG_SLOW_SLIP] = 1.0
            if slipped and a0 * b0 + a1 * b1 + a2 * b2 < 0.0:
                # a contact that slipped at the last solve slips again with its friction turned by more
                # than pi/2: its slip reversed within the step (a stick the average-acceleration rule
                # could not hold, whatever the slip speed at the step's end; docs/time_domain.md)
                diag[DIAG_SLIP_REVERSED] = 1.0
        diag[DIAG_DAMPING_POWER] += Nd[k] * wn  # damping acts only while compressing
        pn = P[o] * n0 + P[o + 1] * n1 + P[o + 2] * n2
        diag[DIAG_FRICTION_POWER] -= (P[o] - pn * n0) * wt0 + (P[o + 1] - pn * n1) * wt1 + (P[o + 2] - pn * n2) * wt2
        Pp[i, 0], Pp[i, 1], Pp[i, 2] = Pn[i, 0], Pn[i, 1], Pn[i, 2]
        Pn[i, 0], Pn[i, 1], Pn[i, 2] = P[o], P[o + 1], P[o + 2]
        # generalized forces: +P at the cable node (with its moment), -P on the casing element
        for r in range(6):
            fcc[6 * i + r] += Bc[k, r, 0] * P[o] + Bc[k, r, 1] * P[o + 1] + Bc[k, r, 2] * P[o + 2]
        e = elem[i]
        for r in range(12):
            fcs[6 * e + r] += Gs[k, r, 0] * P[o] + Gs[k, r, 1] * P[o + 1] + Gs[k, r, 2] * P[o + 2]
    for i in range(nn):
        if Nout[i] == 0.0:
            state[i] = OPEN
            Pn[i, 0], Pn[i, 1], Pn[i, 2] = 0.0, 0.0, 0.0
            Pp[i, 0], Pp[i, 1], Pp[i, 2] = 0.0, 0.0, 0.0
    diag[DIAG_MAX_PENETRATION] = gmax
    return nk
