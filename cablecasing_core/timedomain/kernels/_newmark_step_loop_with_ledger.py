"""The Newmark step loop (average acceleration, gamma = 1/2, beta = 1/4; Eq. 18 with
C = alpha M + beta K) with the supports prescribed (Eq. 13), the implicit contact forces, the
support reactions and the energy ledger: :func:`run_steps`, the one kernel the engine calls. The
per-body kernels it calls are in ``_newmark_per_body.py``."""

from __future__ import annotations

import numpy as np
from numba import njit

from ._banded_products_and_block_solve import copy_into, dia_quadratic, fill
from ._compile_options import FM, NO_RT
from ._contact_forces_with_active_set import contact_parameters, solve_contact_forces
from ._newmark_per_body import (
    add_into,
    finish,
    load_reactions,
    mount_forces,
    mount_ledger,
    predict,
    predicted_velocity,
    reactions,
    respond_by_block_solve,
)
from ._quintic_support_motion import quintic_coefficients, quintic_values
from ._step_loop_contract import (
    DIAG_ACTIVE_SET_PASSES,
    DIAG_DAMPING_POWER,
    DIAG_FRICTION_POWER,
    DIAG_MAX_PENETRATION,
    DIAG_NEWTON_FAILED,
    DIAG_NEWTON_ITERATIONS,
    DIAG_SLIP_REVERSED,
    DIAG_SLOW_SLIP,
    ERR_INPUT,
    ERR_NAN,
    ERR_PENETRATION,
    EVENT_TURN,
    INFO_ACTIVE_SET_PASSES,
    INFO_INPUT_CHANNEL,
    INFO_INPUT_KIND,
    INFO_INPUT_ROW,
    INFO_MAX_LOCAL_ERROR,
    INFO_NEWTON_ITERATIONS,
    INFO_NODE,
    INFO_REFINED_STEPS,
    INFO_TIME,
    INFO_TOLERANCE_STEPS,
    INFO_UNCONVERGED_STEPS,
    INFO_VALUE,
    LEDGER_CONTACT_WORK,
    LEDGER_DAMPING_DISSIPATION,
    LEDGER_DAMPING_POWER,
    LEDGER_FRICTION_DISSIPATION,
    LEDGER_FRICTION_POWER,
    LEDGER_MOUNT_DISSIPATION,
    LEDGER_RAYLEIGH_DISSIPATION,
    LEDGER_SUPPORT_WORK,
    OK,
    OPEN,
)


@njit(cache=True, fastmath=FM, error_model="numpy")
def _work(U, Uo, f, fn, lo, hi):
    """Trapezoidal work (J) of the forces f (old) and fn (new) over U - Uo on DOFs lo..hi-1 (four
    partial sums, as in :func:`dot`)."""
    u, uo, a, an = U[lo:hi], Uo[lo:hi], f[lo:hi], fn[lo:hi]
    s0 = s1 = s2 = s3 = 0.0
    n = hi - lo
    i = 0
    while i + 4 <= n:
        s0 += (a[i] + an[i]) * (u[i] - uo[i])
        s1 += (a[i + 1] + an[i + 1]) * (u[i + 1] - uo[i + 1])
        s2 += (a[i + 2] + an[i + 2]) * (u[i + 2] - uo[i + 2])
        s3 += (a[i + 3] + an[i + 3]) * (u[i + 3] - uo[i + 3])
        i += 4
    for i in range(i, n):
        s0 += (a[i] + an[i]) * (u[i] - uo[i])
    return 0.5 * ((s0 + s1) + (s2 + s3))


@njit(**NO_RT)
def _body_ledger(
    Md,
    Kd,
    alpha,
    beta,
    U,
    Uo,
    V,
    Vo,
    pres,
    pslot,
    reac,
    reac_new,
    off,
    fc,
    fc_new,
    contact_on,
    ledger_on,
    y,
    t,
    dt,
    ledger,
):
    """One body's share of a step in the energy ledger (J), trapezoidal rule: work of its supports
    (reactions at slots off + pslot), work of the contact forces fc -> fc_new and, with ledger_on,
    the Rayleigh dissipation (y: padded scratch, t: scratch (2, n))."""
    for q in range(len(pres)):
        j = pres[q]
        ledger[LEDGER_SUPPORT_WORK] += -0.5 * (reac[off + pslot[q]] + reac_new[off + pslot[q]]) * (U[j] - Uo[j])
    n = U.shape[0]
    if contact_on:
        ledger[LEDGER_CONTACT_WORK] += _work(U, Uo, fc, fc_new, 0, n)
    if ledger_on:
        b = (Md.shape[0] - 1) // 2
        z = y[b : b + n]
        for i in range(n):
            z[i] = Vo[i] + V[i]
        ledger[LEDGER_RAYLEIGH_DISSIPATION] += 0.25 * dt * dia_quadratic(Md, Kd, alpha, beta, y, t)


@njit(cache=True, fastmath=FM, error_model="numpy")
def local_error_estimate(f0, nf, A, Ao, h):
    """Zienkiewicz and Xie's estimate of the local error (m) of a Newmark step of h (s) with
    beta = 1/4: (beta - 1/6) h^2 max |a_(n+1) - a_n| = h^2 / 12 max |A - Ao| over the free
    translations (DOFs 0-2 of each node's six) among the free DOFs f0 .. f0 + nf - 1. The step's
    local error in displacement is (beta - 1/6) h^3 d3u/dt3 + O(h^4), and (A - Ao) / h is d3u/dt3
    to O(h) (O. C. Zienkiewicz, Y. M. Xie, Earthquake Eng. Struct. Dyn. 20 (1991) 871-887)."""
    m = 0.0
    for i in range(f0, f0 + nf):
        if i % 6 < 3:
            d = abs(A[i] - Ao[i])
            if d > m:
                m = d
    return h * h / 12.0 * m


@njit(**NO_RT)
def _friction_event(state0, state):
    """True when a cable node in contact at both ends of a step switched between stick and slip in
    it (the step is then recomputed in sub-steps, ``ContactLaw.nsub``)."""
    for i in range(state.shape[0]):
        a, b = state0[i], state[i]
        if a != OPEN and b != OPEN and a != b:
            return True
    return False


@njit(**NO_RT)
def _copy_contact_memory(
    state, elem, xi, vrel, N, g, P, Pp, state_to, elem_to, xi_to, vrel_to, N_to, g_to, P_to, Pp_to
):  # fmt: skip
    """The contact's memory per cable node (state, element and coordinate found, relative speed,
    normal force, penetration, force vector at the step's end and the one before) into the *_to
    arrays: kept at a step's start, put back when the step is recomputed in sub-steps."""
    for i in range(state.shape[0]):
        state_to[i], elem_to[i], xi_to[i], vrel_to[i], N_to[i], g_to[i] = state[i], elem[i], xi[i], vrel[i], N[i], g[i]
        P_to[i, 0], P_to[i, 1], P_to[i, 2] = P[i, 0], P[i, 1], P[i, 2]
        Pp_to[i, 0], Pp_to[i, 1], Pp_to[i, 2] = Pp[i, 0], Pp[i, 1], Pp[i, 2]


@njit(**NO_RT)
def _copy_mounts(bo, Fo, b, F):
    """bo, Fo = b, F: the mounts' support motion (nm x 2 x 6) and forces (nm x 6), as plain loops
    (an array assignment would want numba's runtime, which run_steps is compiled without)."""
    for m in range(b.shape[0]):
        for s in range(b.shape[1]):
            for i in range(b.shape[2]):
                bo[m, s, i] = b[m, s, i]
        for i in range(F.shape[1]):
            Fo[m, i] = F[m, i]


@njit(**NO_RT)
def _zero_scratch(sq, cq, subrows, subc, subt, subm):
    """The step loop's 2- and 3-D scratch set to zero, as run_steps made it (plain loops)."""
    for q in (sq, cq, subrows):
        for i in range(q.shape[0]):
            for j in range(q.shape[1]):
                q[i, j] = 0.0
    for q in (subc, subm):
        for i in range(q.shape[0]):
            for j in range(q.shape[1]):
                for k in range(q.shape[2]):
                    q[i, j, k] = 0.0
    for i in range(subt.shape[0]):
        subt[i] = 0.0


@njit(**NO_RT)
def _restore_step_start(U, V, A, Uo, Vo, Ao, mb, mbo, on):
    """A body back to the start of its step: U, V, A from their copies Uo, Vo, Ao, the mounts'
    supports mb from mbo (the predictor wrote both)."""
    if on:
        copy_into(U, Uo)
        copy_into(V, Vo)
        copy_into(A, Ao)
        for m in range(mb.shape[0]):
            for q in range(2):
                for i in range(6):
                    mb[m, q, i] = mbo[m, q, i]


@njit(cache=True, fastmath=FM, error_model="numpy")
def _substep_motion(chan, up, vp, ap, k, G, rows, c, times, motion, dt, hf, nsub):
    """motion (3 x nsub x channels): the supports' u, v, a (m, m/s, m/s2) at the ends of the nsub
    sub-steps of hf (s) of step k (dt s), which starts with the supports in the state chan:
    the quintic Hermite (``support_motion``, G its coefficient matrix for dt) from chan to row k of
    up, vp, ap. rows, c and times are scratch."""
    for j in range(chan.shape[1]):
        rows[0, j], rows[1, j], rows[2, j] = chan[0, j], chan[1, j], chan[2, j]
        rows[3, j], rows[4, j], rows[5, j] = up[k, j], vp[k, j], ap[k, j]
    quintic_coefficients(G, rows, c)
    for i in range(nsub):  # (from the step's start, so that its rounding does not enter)
        times[i] = (i + 1) * hf
    quintic_values(c, 0.0, dt, times, motion)


@njit(nogil=True, **NO_RT)
def run_steps(t0, dt, up, vp, ap, casing, cable, law, contact, reac, ledger, ledger_on, scratch, rec, info):
    """Advance both bodies by len(up) Newmark steps of size dt (s) from time t0 (s). Each step:
    contact-free predictor of both bodies, contact search and implicit contact forces
    (:func:`solve_contact_forces`), the bodies' response to them, Newmark update, reactions.

    up, vp, ap: (n, 12) support channel displacement (m), velocity (m/s), acceleration (m/s2) at
    t0 + (k+1) dt. casing, cable: :class:`BodyArrays`; law: :class:`ContactLaw`; contact:
    :class:`ContactArrays` (its memory is updated, its ``time`` accumulates each cable node's time
    in contact, s); reac (24): force each body exerts on each support, N and N.m, in the order
    casing A, casing B, cable A, cable B, each [Fx Fy Fz Mx My Mz]; ledger (LEDGER_SIZE, J): the
    LEDGER_* slots, the Rayleigh dissipation only with ledger_on; scratch: :class:`StepScratch`
    (``step_scratch``; set here as if made anew); rec: :class:`Recording`. Returns a
    status code (OK or ERR_*) with the INFO_* slots of info: what failed, and the running totals of
    the contact solve. Non-finite support motion is refused before any step is taken (ERR_INPUT,
    info = [row, channel, 0/1/2 for up/vp/ap]), so nothing is half-written.

    Events inside the step (docs/time_domain.md): with law.nsub > 1, a step in which a contact that
    is closed at both of its ends switches between stick and slip, or in which a slipping contact's
    friction could reverse its slip while its direction turns by more than EVENT_TURN (the contact
    solve's DIAG_SLOW_SLIP), or in which a slip reversed (it slips again with its friction turned by
    more than pi/2, DIAG_SLIP_REVERSED), is taken back and recomputed as
    law.nsub sub-steps of dt / nsub with the fine factors of the bodies (``BodyArrays.f*``), the
    supports following the quintic Hermite from their state at the step's start (contact.chan) to
    row k; everything else (records, the contact histogram, the ledger) sees the sub-steps as parts
    of the step. info[INFO_REFINED_STEPS] counts the steps so recomputed.

    With rec.on, step k writes row rec.off + k of rec.F (the reactions, then the forces through
    the casing's clips when rec.F has the columns) and, sparse, the cable
    nodes in contact at its end: entries rec.ptr[r] .. rec.ptr[r + 1] - 1 (r = rec.off + k;
    rec.ptr[rec.off] set by the caller) of rec.node, rec.state, rec.N (N) and rec.g (m). Capacity:
    one entry per cable node and step.

    The records are unpacked once here, outside the loop, and the kernels the loop calls take
    plain arrays. It allocates nothing (its scratch is the engine's) and is compiled without numba's
    runtime (``NO_RT``): no reference counts of the ~100 arrays of its records, at any call (see
    the package docstring). It runs outside the interpreter's lock (``nogil``): it touches no Python
    object and writes only its engine's arrays, so runs on several threads step in parallel.
    """
    nsteps = up.shape[0]
    for q, x in enumerate((up, vp, ap)):
        for k in range(nsteps):
            for j in range(x.shape[1]):
                if not np.isfinite(x[k, j]):
                    info[INFO_INPUT_ROW], info[INFO_INPUT_CHANNEL], info[INFO_INPUT_KIND] = k, j, q
                    return ERR_INPUT
    # s: casing, c: cable
    s_on, sMd, sKd, sDi, sL, sLT = casing.on, casing.Md, casing.Kd, casing.Dinv, casing.L, casing.LT
    sg0, sng, sf0, snf, salpha, sbeta = casing.g0, casing.ng, casing.f0, casing.nf, casing.alpha, casing.beta
    sU, sV, sA, spres, spchan, spslot = casing.U, casing.V, casing.A, casing.pres, casing.pchan, casing.pslot
    sKinv, ssup, ssup_lo, scpl_i, scpl_v, fcs = (
        casing.Kinv,
        casing.sup,
        casing.sup_lo,
        casing.cpl_i,
        casing.cpl_v,
        casing.fc,
    )
    c_on, cMd, cKd, cDi, cL, cLT = cable.on, cable.Md, cable.Kd, cable.Dinv, cable.L, cable.LT
    cg0, cng, cf0, cnf, calpha, cbeta = cable.g0, cable.ng, cable.f0, cable.nf, cable.alpha, cable.beta
    cU, cV, cA, cpres, cpchan, cpslot = cable.U, cable.V, cable.A, cable.pres, cable.pchan, cable.pslot
    cKinv, csup, csup_lo, ccpl_i, ccpl_v, fcc = cable.Kinv, cable.sup, cable.sup_lo, cable.cpl_i, cable.cpl_v, cable.fc
    smi, smKC, smb, smF = casing.mi, casing.mKC, casing.mb, casing.mF
    cmi, cmKC, cmb, cmF = cable.mi, cable.mKC, cable.mb, cable.mF
    sUo, sVo, sAo, cUo, cVo, cAo = scratch.sUo, scratch.sVo, scratch.sAo, scratch.cUo, scratch.cVo, scratch.cAo
    smbo, smFo, cmbo, cmFo = scratch.smbo, scratch.smFo, scratch.cmbo, scratch.cmFo
    _copy_mounts(smbo, smFo, smb, smF)
    _copy_mounts(cmbo, cmFo, cmb, cmF)
    s_loaded, sfext, suext = casing.loaded, casing.fext, casing.uext
    c_loaded, cfext, cuext = cable.loaded, cable.fext, cable.uext
    contact_on, r_cable = law.on, law.r_cable
    Xc, Tc, Xs, Rs, Ls, ws = contact.Xc, contact.Tc, contact.Xs, contact.Rs, contact.Ls, contact.ws
    state, elem, xi_arr, Pn, Pp, vrel = contact.state, contact.elem, contact.xi, contact.Pn, contact.Pp, contact.vrel
    Nn, gn, contact_time, share = contact.N, contact.g, contact.time, contact.share
    rec_on, rec_F, rec_ptr, rec_node, rec_state, rec_N, rec_g, rec_off = rec
    for x, y in ((sUo, sU), (sVo, sV), (sAo, sA), (cUo, cU), (cVo, cV), (cAo, cA)):
        copy_into(x, y)
    sy1, sr, cy1, cr, sq, cq = scratch.sy1, scratch.sr, scratch.cy1, scratch.cr, scratch.sq, scratch.cq
    fcs_new, fcc_new, reac_new, diag = scratch.fcs_new, scratch.fcc_new, scratch.reac_new, scratch.diag
    for x in (sy1, sr, cy1, cr, fcs_new, fcc_new, reac_new, diag):
        fill(x, 0.0)
    cpar = contact_parameters(law, dt, False, EVENT_TURN)  # (DIAG_SLOW_SLIP is read only with refine, below)
    nn = Xc.shape[0]
    # sub-steps of a step with a stick-slip event (law.nsub; docs/time_domain.md, "Events inside
    # the step"): the fine level's factors, the contact memory
    # at the step's start, and the sub-steps' support motion (quintic Hermite from chan to the row)
    nsub = law.nsub
    refine = contact_on and nsub > 1
    # the switch law's stick-slip events; the regularised law has none (its STICK/SLIP are a label)
    switch_events = refine and law.vreg == 0.0
    # the tolerance on the local error (ContactLaw.tol): a step whose estimate exceeds it is recomputed
    tol = law.tol if refine else 0.0
    hf = dt / max(nsub, 1)
    turnf = EVENT_TURN / max(nsub, 1)  # the turn a sub-step allows (rad)
    cparf = contact_parameters(law, hf, False, turnf)
    # the sub-steps after the first keep the Delassus matrix while the contacts stay (law.reuse)
    cparr = contact_parameters(law, hf, law.reuse, turnf)
    sDif, sLf, sLTf, sKinvf, suextf = casing.fDinv, casing.fL, casing.fLT, casing.fKinv, casing.fuext
    cDif, cLf, cLTf, cKinvf, cuextf = cable.fDinv, cable.fL, cable.fLT, cable.fKinv, cable.fuext
    chan, subG, cagain = contact.chan, contact.subG, contact.again
    nch = up.shape[1]
    state0, elem0, xi0, Pn0, Pp0 = scratch.state0, scratch.elem0, scratch.xi0, scratch.Pn0, scratch.Pp0
    vrel0, Nn0, gn0 = scratch.vrel0, scratch.Nn0, scratch.gn0
    _copy_contact_memory(state, elem, xi_arr, vrel, Nn, gn, Pn, Pp, state0, elem0, xi0, vrel0, Nn0, gn0, Pn0, Pp0)
    subrows, subc, subt, subm = scratch.subrows, scratch.subc, scratch.subt, scratch.subm
    _zero_scratch(sq, cq, subrows, subc, subt, subm)
    t = t0
    again = cagain[0] != 0  # the previous step ended in sub-steps with an event on
    for k in range(nsteps):
        t_start = t0 + k * dt
        if refine:
            _copy_contact_memory(
                state, elem, xi_arr, vrel, Nn, gn, Pn, Pp, state0, elem0, xi0, vrel0, Nn0, gn0, Pn0, Pp0
            )  # fmt: skip
        lev = 0  # 0: the step dt; 1: its nsub sub-steps
        nrep = 1
        j = 0
        if refine and again:
            # the last step ended in its sub-steps with an event still on: this one starts in them
            # (its coarse trial would be taken back, docs/time_domain.md)
            _substep_motion(chan, up, vp, ap, k, subG, subrows, subc, subt, subm, dt, hf, nsub)
            info[INFO_REFINED_STEPS] += 1
            lev, nrep = 1, nsub
        again = False
        while j < nrep:
            if lev == 0:
                h, cp, mu_, mv_, ma_, row = dt, cpar, up, vp, ap, k
                sDc, sLc, sLTc, sKc, suc = sDi, sL, sLT, sKinv, suext
                cDc, cLc, cLTc, cKc, cuc = cDi, cL, cLT, cKinv, cuext
            else:
                h, cp, mu_, mv_, ma_, row = hf, (cparf if j == 0 else cparr), subm[0], subm[1], subm[2], j
                sDc, sLc, sLTc, sKc, suc = sDif, sLf, sLTf, sKinvf, suextf
                cDc, cLc, cLTc, cKc, cuc = cDif, cLf, cLTf, cKinvf, cuextf
            t = t_start + (j + 1) * h if lev == 1 else t0 + (k + 1) * dt
            if s_on:
                copy_into(sUo, sU)
                copy_into(sVo, sV)
                copy_into(sAo, sA)
                _copy_mounts(smbo, smFo, smb, smF)
                predict(
                    sMd, sDc, sLc, sLTc, sg0, sng, sf0, snf, salpha, sbeta, sU, sV, sA, spres, spchan, scpl_i,
                    scpl_v, mu_, mv_, ma_, row, h, sy1, sr, smi, smKC, smb,
                )  # fmt: skip
            if c_on:
                copy_into(cUo, cU)
                copy_into(cVo, cV)
                copy_into(cAo, cA)
                _copy_mounts(cmbo, cmFo, cmb, cmF)
                predict(
                    cMd, cDc, cLc, cLTc, cg0, cng, cf0, cnf, calpha, cbeta, cU, cV, cA, cpres, cpchan, ccpl_i,
                    ccpl_v, mu_, mv_, ma_, row, h, cy1, cr, cmi, cmKC, cmb,
                )  # fmt: skip
            back = False  # the step taken back and recomputed in sub-steps
            # the constant loads at rest (an installed model): the predictor's response to them
            if s_on and s_loaded:
                add_into(sU, suc)
            if c_on and c_loaded:
                add_into(cU, cuc)
            if contact_on:
                predicted_velocity(sf0, snf, sU, sUo, sV, sVo, h)
                predicted_velocity(cf0, cnf, cU, cUo, cV, cVo, h)
                diag[DIAG_NEWTON_FAILED] = 0.0
                nact = solve_contact_forces(
                    Xc, Tc, cU, cV, Xs, Rs, Ls, sU, sV, cKc, sKc, cp, state, elem, xi_arr, Pn, Pp, vrel, Nn, gn,
                    fcc_new, fcs_new, diag, ws, share,
                )  # fmt: skip
                event = False
                if switch_events and (lev == 0 or j == nrep - 1):
                    event = (
                        diag[DIAG_SLOW_SLIP] > 0.0 or diag[DIAG_SLIP_REVERSED] > 0.0 or _friction_event(state0, state)
                    )
                if lev == 1 and j == nrep - 1:
                    again = event
                back = lev == 0 and event
                if not back:
                    if nact > 0:
                        if s_on:
                            respond_by_block_solve(sDc, sLc, sLTc, sg0, sng, sf0, snf, spres, fcs_new, sr, sU)
                        if c_on:
                            respond_by_block_solve(cDc, cLc, cLTc, cg0, cng, cf0, cnf, cpres, fcc_new, cr, cU)
                    if diag[DIAG_MAX_PENETRATION] > r_cable:
                        info[INFO_TIME], info[INFO_VALUE] = t, diag[DIAG_MAX_PENETRATION]
                        for i in range(nn):
                            if gn[i] == diag[DIAG_MAX_PENETRATION]:
                                info[INFO_NODE] = i
                        return ERR_PENETRATION
            if not back:
                if s_on:
                    finish(sf0, snf, sU, sV, sA, sUo, sVo, sAo, h)
                if c_on:
                    finish(cf0, cnf, cU, cV, cA, cUo, cVo, cAo, h)
                if tol > 0.0:
                    est = 0.0
                    if s_on:
                        est = local_error_estimate(sf0, snf, sA, sAo, h)
                    if c_on:
                        est = max(est, local_error_estimate(cf0, cnf, cA, cAo, h))
                    if lev == 0 and est > tol:
                        back = True
                        info[INFO_TOLERANCE_STEPS] += 1
                    else:
                        info[INFO_MAX_LOCAL_ERROR] = max(info[INFO_MAX_LOCAL_ERROR], est)
            if back:
                # recompute the step in nsub sub-steps (an event, or a local error above the
                # tolerance): back to its start (the bodies' state is in the *o copies, the
                # supports' in smbo, cmbo), the contact memory from its copy, the sub-steps' motion
                _restore_step_start(sU, sV, sA, sUo, sVo, sAo, smb, smbo, s_on)
                _restore_step_start(cU, cV, cA, cUo, cVo, cAo, cmb, cmbo, c_on)
                _copy_contact_memory(
                    state0, elem0, xi0, vrel0, Nn0, gn0, Pn0, Pp0, state, elem, xi_arr, vrel, Nn, gn, Pn, Pp
                )
                _substep_motion(chan, up, vp, ap, k, subG, subrows, subc, subt, subm, dt, hf, nsub)
                info[INFO_REFINED_STEPS] += 1
                lev, nrep, j = 1, nsub, 0
                continue
            if contact_on:
                info[INFO_UNCONVERGED_STEPS] += diag[DIAG_NEWTON_FAILED]
                for i in range(nn):
                    if state[i] != OPEN:
                        contact_time[i] += h
            if s_on:
                reactions(ssup, ssup_lo, salpha, sbeta, sU, sV, sA, fcs_new, spres, spslot, reac_new, 0)
                if s_loaded:
                    load_reactions(sfext, spres, spslot, reac_new, 0)
                mount_forces(smi, smKC, smb, sU, sV, smF, reac_new, 0)
            if c_on:
                reactions(csup, csup_lo, calpha, cbeta, cU, cV, cA, fcc_new, cpres, cpslot, reac_new, 12)
                if c_loaded:
                    load_reactions(cfext, cpres, cpslot, reac_new, 12)
                mount_forces(cmi, cmKC, cmb, cU, cV, cmF, reac_new, 12)
            # blow-up check on the cheap aggregates
            tot = 0.0
            for i in range(24):
                tot += reac_new[i]
            if not np.isfinite(tot):
                info[INFO_TIME], info[INFO_NODE], info[INFO_VALUE] = t, -1, tot
                return ERR_NAN
            # energy ledger (trapezoidal rule, consistent with the average-acceleration scheme)
            if s_on:
                _body_ledger(
                    sMd, sKd, salpha, sbeta, sU, sUo, sV, sVo, spres, spslot, reac, reac_new, 0, fcs, fcs_new,
                    contact_on, ledger_on, sy1, sq, h, ledger,
                )  # fmt: skip
            if c_on:
                _body_ledger(
                    cMd, cKd, calpha, cbeta, cU, cUo, cV, cVo, cpres, cpslot, reac, reac_new, 12, fcc, fcc_new,
                    contact_on, ledger_on, cy1, cq, h, ledger,
                )  # fmt: skip
            if s_on:
                w, d = mount_ledger(smi, smKC, smb, smbo, sU, sUo, sV, sVo, smF, smFo)
                ledger[LEDGER_SUPPORT_WORK] += w
                ledger[LEDGER_MOUNT_DISSIPATION] += d
            if c_on:
                w, d = mount_ledger(cmi, cmKC, cmb, cmbo, cU, cUo, cV, cVo, cmF, cmFo)
                ledger[LEDGER_SUPPORT_WORK] += w
                ledger[LEDGER_MOUNT_DISSIPATION] += d
            if contact_on:
                ledger[LEDGER_FRICTION_DISSIPATION] += (
                    0.5 * h * (ledger[LEDGER_FRICTION_POWER] + diag[DIAG_FRICTION_POWER])
                )
                ledger[LEDGER_DAMPING_DISSIPATION] += (
                    0.5 * h * (ledger[LEDGER_DAMPING_POWER] + diag[DIAG_DAMPING_POWER])
                )
                ledger[LEDGER_FRICTION_POWER] = diag[DIAG_FRICTION_POWER]
                ledger[LEDGER_DAMPING_POWER] = diag[DIAG_DAMPING_POWER]
            copy_into(reac, reac_new)
            if contact_on:
                copy_into(fcs, fcs_new)
                copy_into(fcc, fcc_new)
            j += 1
        cagain[0] = 1 if again else 0
        for c in range(nch):  # the supports' state at the step's end: where the next one starts
            chan[0, c], chan[1, c], chan[2, c] = up[k, c], vp[k, c], ap[k, c]
        if rec_on:
            r = rec_off + k
            for i in range(24):
                rec_F[r, i] = reac[i]
            jr = 24  # then the forces through the casing's clips (mounts without a reaction slot)
            for m in range(smi.shape[0]):
                if smi[m, 4] < 0 and jr + 6 <= rec_F.shape[1]:
                    for i in range(6):
                        rec_F[r, jr + i] = smF[m, i]
                    jr += 6
            jr = rec_ptr[r]
            for i in range(nn):  # only the nodes in contact (a few of them)
                if state[i] != OPEN or Nn[i] != 0.0 or gn[i] != 0.0:
                    rec_node[jr] = i
                    rec_state[jr] = state[i]
                    rec_N[jr] = Nn[i]
                    rec_g[jr] = gn[i]
                    jr += 1
            rec_ptr[r + 1] = jr
    info[INFO_TIME] = t
    info[INFO_NEWTON_ITERATIONS] += diag[DIAG_NEWTON_ITERATIONS]
    info[INFO_ACTIVE_SET_PASSES] += diag[DIAG_ACTIVE_SET_PASSES]
    return OK
