"""Newmark's average acceleration for one body (Eq. 18 with the Rayleigh damping C = alpha M + beta K
of Eq. 40, the element damping of Eq. 5 assembled; the supports prescribed at the new time, Eq. 13):
the contact-free predictor, the response to the contact forces and to a constant load at rest, the
update of acceleration and velocity, and the reactions at the prescribed DOFs."""

from __future__ import annotations

from numba import njit

from ._banded_products_and_block_solve import block_solve, dia_product
from ._compile_options import FM, NO_RT

TINY = 1e-200  # m, m/s, m/s2: states below this are flushed to zero (see finish)


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def newmark_coefficients(dt):
    """Newmark's average-acceleration coefficients for a step of dt s (Eq. 18): c0 = 4/dt^2 (1/s^2)
    and c1 = 2/dt (1/s), as a tuple (c0, c1). With them a = c0 (u - u_old) - 2 c1 v_old - a_old,
    v = c1 (u - u_old) - v_old, and the effective stiffness is S = K + c1 C + c0 M."""
    return 4.0 / (dt * dt), 2.0 / dt


@njit(**NO_RT)
def predict(
    Md, Dinv, L, LT, g0, ng, f0, nf, alpha, beta, U, V, A, pres, pchan, cpl_i, cpl_v, up, vp, ap, step, dt, y1, r,
    mi, mKC, mb,
):  # fmt: skip
    """Contact-free Newmark predictor: prescribe the supports at t+dt (Eq. 13) and solve
    S_ff u_f = [M (c0 u + 2 c1 v + a) + C (c1 u + v)]_f - (coupling to the prescribed DOFs) for the
    free DOFs, S = K + c1 C + c0 M = ck K + cm M, C = alpha M + beta K (Eq. 40; alpha in 1/s, beta
    in s), c0 = 4/dt^2, c1 = 2/dt (:func:`newmark_coefficients`), ck = 1 + c1 beta, cm = c0 + c1 alpha;
    U[free] holds the result (m, rad; U, V, A the body's state, m, m/s, m/s2 and rad, rad/s, rad/s2;
    dt in s).

    One matrix product instead of two: with z = beta (c1 u + v) on the free DOFs the stiffness part
    is K z = (S z - cm M z) / ck, so u_f = z_f / ck + S_ff^-1 ([M w]_f - [K_fp (u_p + beta v_p)]),
    w = c0 u + 2 c1 v + a + alpha (c1 u + v) - (cm / ck) z (free), -(a_p + alpha v_p) (prescribed).
    The stiffness enters only through K_fp, the few free rows next to the supports, given as
    triplets: row cpl_i[0, m], support cpl_i[1, m] (index into pres), value cpl_v[m] (N/m). The
    solve runs over the node blocks g0 .. g0+ng-1 that hold the free DOFs (prescribed DOFs among
    them are identity rows with zero right-hand side). The supports move as row ``step`` of up, vp,
    ap (m, m/s, m/s2, by channel). y1 is a padded scratch vector, r has ng.

    Mounts (isolators, clips; rows of mi, mKC, mb, see ``BodyArrays``): a spring K6 and damper C6
    from the node to its support, whose motion (u_b, v_b) at t+dt is set into mb here. Their part of
    S, K6 + c1 C6 = D6, is in the factor; on the right-hand side they add C6 (c1 u + v) and the
    support's K6 u_b + C6 v_b at the node, less D6 z / ck (the z/ck split above assumed S = ck K + cm M)."""
    b = (Md.shape[0] - 1) // 2
    n = U.shape[0]
    c0, c1 = newmark_coefficients(dt)
    ck = 1.0 + c1 * beta
    q = (c0 + c1 * alpha) / ck
    z1 = y1[b : b + n]
    cu = c0 + c1 * alpha - q * beta * c1
    cv = 2 * c1 + alpha - q * beta
    for j in range(n):
        z1[j] = cu * U[j] + cv * V[j] + A[j]
    for k in range(len(pres)):
        j = pres[k]
        ch = pchan[k]
        u, v, a = (up[step, ch], vp[step, ch], ap[step, ch]) if ch >= 0 else (0.0, 0.0, 0.0)
        U[j], V[j], A[j] = u, v, a
        y1[b + j] = -(a + alpha * v)
    for i in range(ng):
        r[i] = 0.0
    dia_product(Md, y1, g0, ng, r)
    # - K_fp (u_p + beta v_p); the triplets come row by row, and each row's terms are subtracted in a
    # register (in the same order as one at a time from r[row], so the same result): through memory,
    # each term would wait for the previous one's store
    m = 0
    nm = cpl_v.shape[0]
    while m < nm:
        row = cpl_i[0, m]
        acc = r[row - g0]
        while m < nm and cpl_i[0, m] == row:
            j = pres[cpl_i[1, m]]
            acc -= cpl_v[m] * (U[j] + beta * V[j])
            m += 1
        r[row - g0] = acc
    bk = beta / ck
    for m in range(mi.shape[0]):
        for i in range(3):
            ch = mi[m, 1 + i]
            mb[m, 0, i] = up[step, ch] if ch >= 0 else 0.0
            mb[m, 1, i] = vp[step, ch] if ch >= 0 else 0.0
        j0 = mi[m, 0]
        for i in range(6):
            acc = 0.0
            for j in range(6):
                kij, cij = mKC[m, 0, i, j], mKC[m, 1, i, j]
                w = c1 * U[j0 + j] + V[j0 + j]
                acc += (cij - bk * (kij + c1 * cij)) * w + kij * mb[m, 0, j] + cij * mb[m, 1, j]
            r[j0 + i - g0] += acc
    for k in range(len(pres)):
        if g0 <= pres[k] < g0 + ng:
            r[pres[k] - g0] = 0.0
    block_solve(Dinv, L, LT, r)
    u, v, rf = U[f0 : f0 + nf], V[f0 : f0 + nf], r[f0 - g0 : f0 - g0 + nf]
    for i in range(nf):
        u[i] = rf[i] + bk * (c1 * u[i] + v[i])


@njit(**NO_RT)
def respond_by_block_solve(Dinv, L, LT, g0, ng, f0, nf, pres, fc, r, U):
    """U += Keff^-1 fc: the body's exact response to the contact forces fc (N, N.m; the structure is
    linear, Eq. 18) by one solve with the step's block LDL^T factor (:func:`block_solve`) over the
    node blocks g0 .. g0+ng-1 that hold the free DOFs, the prescribed DOFs' forces going into the
    supports (zero right-hand side there, as in :func:`predict`). r: scratch of ng.

    A solve, not the sum of the loaded compliance rows: with 13 contacts the rows are ~190 x n
    multiply-adds read from memory (9 µs per step of the installed specimen's two bodies, in a
    compiled loop), the solve two sweeps of one 6 x 6 product per node (~1 µs)."""
    for i in range(ng):
        r[i] = fc[g0 + i]
    for k in range(len(pres)):
        if g0 <= pres[k] < g0 + ng:
            r[pres[k] - g0] = 0.0
    block_solve(Dinv, L, LT, r)
    u, rf = U[f0 : f0 + nf], r[f0 - g0 : f0 - g0 + nf]
    for i in range(nf):
        u[i] += rf[i]


@njit(cache=True, fastmath=FM, error_model="numpy")
def finish(f0, nf, U, V, A, Uo, Vo, Ao, dt):
    """Newmark update (Eq. 18) of the free DOFs f0 .. f0+nf-1: their acceleration (m/s2, rad/s2)
    and velocity (m/s, rad/s) from the new displacement U (m, rad), the old state Uo, Vo, Ao and the
    step dt (s), into V and A; states below TINY are flushed to zero."""
    c0, c1 = newmark_coefficients(dt)
    c2 = 2.0 * c1  # 4/dt (1/s), exactly: doubling does not round
    u, v, a = U[f0 : f0 + nf], V[f0 : f0 + nf], A[f0 : f0 + nf]
    uo, vo, ao = Uo[f0 : f0 + nf], Vo[f0 : f0 + nf], Ao[f0 : f0 + nf]
    # Far from the excitation the response decays towards zero through subnormal numbers, where
    # every operation costs ~100 times more (10-50x slower steps were measured at the start of a
    # run). States below TINY (in SI units, physically nothing) are set to zero, by selects in the
    # same pass (branches in a second pass cost a third more).
    for i in range(nf):
        ui = u[i]
        ai = c0 * (ui - uo[i]) - c2 * vo[i] - ao[i]
        vi = vo[i] + 0.5 * dt * (ao[i] + ai)
        u[i] = 0.0 if abs(ui) < TINY else ui  # (NaN stays NaN, for the blow-up check)
        v[i] = 0.0 if abs(vi) < TINY else vi
        a[i] = 0.0 if abs(ai) < TINY else ai


@njit(cache=True, fastmath=FM, error_model="numpy")
def reactions(sup, sup_lo, alpha, beta, U, V, A, fc, pres, pslot, out, off):
    """Force the body exerts on each support DOF (N, N.m): -(M a + C v + K u - f_contact) at the
    prescribed DOFs (Eq. 13), C = alpha M + beta K (Eq. 40; alpha in 1/s, beta in s), from the state
    U, V, A (m, m/s, m/s2; rad, rad/s, rad/s2) and the contact forces fc (N, N.m). sup[q, 0] and
    sup[q, 1] are the rows of M and K of DOF pres[q] over the columns sup_lo[q] .. sup_lo[q] + w - 1
    (its band), contiguous, so each reaction is one short dot product. Written into
    out[off + pslot[q]]."""
    w = sup.shape[2]
    for q in range(len(pres)):
        j0 = sup_lo[q]
        mr, kr = sup[q, 0], sup[q, 1]
        u, v, a = U[j0 : j0 + w], V[j0 : j0 + w], A[j0 : j0 + w]
        sm = 0.0
        sk = 0.0
        for k in range(w):
            sm += mr[k] * (a[k] + alpha * v[k])
            sk += kr[k] * (u[k] + beta * v[k])
        out[off + pslot[q]] = fc[pres[q]] - (sm + sk)


@njit(cache=True, fastmath=FM, error_model="numpy")
def predicted_velocity(f0, nf, U, Uo, V, Vo, dt):
    """Newmark velocity (m/s, rad/s) of the free DOFs from the predicted displacement U (m, rad):
    v = 2/dt (u - u_old) - v_old (Eq. 18; dt in s), into V."""
    _, c1 = newmark_coefficients(dt)
    u, uo, v, vo = U[f0 : f0 + nf], Uo[f0 : f0 + nf], V[f0 : f0 + nf], Vo[f0 : f0 + nf]
    for i in range(nf):
        v[i] = c1 * (u[i] - uo[i]) - vo[i]


@njit(cache=True, fastmath=FM, error_model="numpy")
def add_into(U, dU):
    """U += dU: a body's response to its constant load at rest (the predictor is linear, so a
    constant load fext adds Keff^-1 fext to it, Eq. 18; dU is zero on the prescribed DOFs)."""
    for i in range(U.shape[0]):
        U[i] += dU[i]


@njit(cache=True, fastmath=FM, error_model="numpy")
def load_reactions(fext, pres, pslot, out, off):
    """The constant load's share of the force the body exerts on each support DOF: fext at the
    prescribed DOFs (N, N.m) goes straight into the supports (added to :func:`reactions`' out)."""
    for q in range(len(pres)):
        out[off + pslot[q]] += fext[pres[q]]


@njit(cache=True, fastmath=FM, error_model="numpy")
def mount_forces(mi, mKC, mb, U, V, mF, out, off):
    """Force each mount passes to its support, F = K6 (u - u_b) + C6 (v - v_b) (N, N.m, global
    axes; the node's state U, V, the support's mb), into mF and, for an isolator, into
    out[off + slot .. off + slot + 5] (the support's six reactions)."""
    for m in range(mi.shape[0]):
        j0 = mi[m, 0]
        for i in range(6):
            acc = 0.0
            for j in range(6):
                acc += mKC[m, 0, i, j] * (U[j0 + j] - mb[m, 0, j]) + mKC[m, 1, i, j] * (V[j0 + j] - mb[m, 1, j])
            mF[m, i] = acc
        slot = mi[m, 4]
        if slot >= 0:
            for i in range(6):
                out[off + slot + i] = mF[m, i]


@njit(cache=True, fastmath=FM, error_model="numpy")
def mount_ledger(mi, mKC, mb, mbo, U, Uo, V, Vo, mF, mFo):
    """(work of the mounts' supports, dissipation of their dampers) over a step, J: the supports do
    -1/2 (F_old + F_new) . (u_b,new - u_b,old) (the trapezoidal rule of the support work); the
    dampers take 1/2 C6 (w_old + w_new) . (r_new - r_old), r and w the node's displacement and
    velocity relative to the support. With the springs' energy 1/2 r K6 r this closes the ledger to
    round-off whatever the support motion (K6 (r_old + r_new) / 2 . (r_new - r_old) is the spring
    energy's change exactly)."""
    work = 0.0
    diss = 0.0
    for m in range(mi.shape[0]):
        j0 = mi[m, 0]
        for i in range(6):
            work -= 0.5 * (mF[m, i] + mFo[m, i]) * (mb[m, 0, i] - mbo[m, 0, i])
            cw = 0.0
            for j in range(6):
                cw += mKC[m, 1, i, j] * ((V[j0 + j] - mb[m, 1, j]) + (Vo[j0 + j] - mbo[m, 1, j]))
            diss += 0.5 * cw * ((U[j0 + i] - mb[m, 0, i]) - (Uo[j0 + i] - mbo[m, 0, i]))
    return work, diss
