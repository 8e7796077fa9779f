"""One FMU communication step in one compiled call: the support motion from the reconstruction
(Taylor target of the inputs, quintic Hermite from the supports' state, ``_quintic_support_motion``),
the Newmark steps with contact (:func:`run_steps`) and the outputs after them
(:func:`step_outputs`).

It is what ``Engine.advance(h, SupportReconstruction.motion(...))`` followed by
``SupportReconstruction.accept`` and ``Engine.output_values`` computes, with the same kernels in the
same order on the same numbers, so the results are the same to the bit; it exists because those
are about ten Python-level calls per communication step (motion set-up and evaluation, the engine's
chunking and records, four numba dispatches) that cost as much as the ten Newmark steps of a 1e-4 s
step themselves (docs/performance.md, FMU).

:func:`communication_step_in_context` takes every array of a communication step in one
:class:`CommunicationContext` (a numba structref, made once per engine, step size and buffers by
:func:`new_communication_context`): numba unboxes a structref as one pointer, where the ~60 arrays
of the records cost ~0.15 us each to unbox at every call.
"""

from __future__ import annotations

from numba import njit, types
from numba.core.extending import overload
from numba.experimental import structref

from ._compile_options import FM, NO_RT
from ._contact_search_and_law import contact_potential
from ._newmark_step_loop_with_ledger import run_steps
from ._quintic_support_motion import accept_rows, quintic_coefficients, quintic_values, taylor_rows
from ._step_loop_contract import INFO_NEWTON_ITERATIONS, LEDGER_CONTACT_WORK


@njit(cache=True, fastmath=FM, error_model="numpy")
def step_outputs(reac, cstate, gn, ledger, law, k_lin, k_hertz, share, pot0, out):
    """The engine's outputs (``model.schema.OUTPUTS``) into ``out``: the 24 support reactions (N,
    N.m), the cable nodes in contact, the largest penetration (m, 0 without contact) and the energy
    dissipated in the contacts (J: their work less the change of the energy they store since the
    start, ``pot0`` J the energy stored in the static state's contacts)."""
    for i in range(24):
        out[i] = reac[i]
    active = 0
    for i in range(cstate.shape[0]):
        if cstate[i] != 0:  # OPEN == 0
            active += 1
    out[24] = active
    g = 0.0
    for i in range(gn.shape[0]):
        if i == 0 or gn[i] > g:
            g = gn[i]
    out[25] = g
    # (0.0 - x: +0 where nothing was dissipated, not -0; the same bits as -x otherwise)
    out[26] = 0.0 - ledger[LEDGER_CONTACT_WORK] - (contact_potential(gn, law, k_lin, k_hertz, share) - pot0)


@njit(cache=True, fastmath=FM, error_model="numpy")
def clip_force_outputs(mi, mF, out, first):
    """The force and moment through each clip of a body (N, N.m, global axes: the mounts without a
    support end, ``mi[m, 4] < 0``; ``mF`` the forces through the mounts) into ``out[first:]``, six
    per clip in file order (``model.schema.clip_outputs``), as many clips as ``out`` has room for.
    (``run_steps`` writes the same columns of its record inline: a row view per step would bring
    reference counting into the step loop.)"""
    o = first
    for m in range(mi.shape[0]):
        if mi[m, 4] < 0 and o + 6 <= out.shape[0]:
            for i in range(6):
                out[o + i] = mF[m, i]
            o += 6


@njit(**NO_RT)
def communication_step(
    t0, dt, h, pot0, G, state, u, v, a, rows, coeffs, times, motion, base, use_base, casing, cable, law, contact,
    reac, ledger, ledger_on, scratch, rec, info, out, fbuf, ibuf, snap_f, snap_i,
):  # fmt: skip
    """Advance from ``t0`` by m = len(``times``) steps of ``dt`` (s), ``m dt`` = ``h``, with the support motion
    of the communication step ``[t0, t0 + h]``: the quintic Hermite (power-basis matrix ``G`` of
    ``support_motion``) from ``state`` (5 x n: u, v, a of the n support channels at t0, the engine's
    ``channels``: 12, and 3 per excited clip, then the previous inputs' acceleration and time, as
    :func:`taylor_rows` reads them) to the Taylor target of the inputs ``u, v, a`` (n
    each, m, m/s, m/s2), plus ``base`` (3 x m x n: u, v, a at the m step ends) when ``use_base``.
    ``rows`` (6 x n), ``coeffs`` (3 x 6 x n), ``times`` (m) and ``motion`` (3 x m x n) are scratch;
    ``out`` receives the outputs (``OUTPUTS``, then the casing's clip forces as far as it is long).
    ``fbuf`` and ``ibuf`` are the engine's state buffers, copied into ``snap_f`` and ``snap_i``
    first (the engine rolls back from them after a failed step); ``info``'s per-call slots are
    zeroed. Returns run_steps' status; only if it is OK are ``out`` written and ``state``
    replaced by the supports' state at t0 + h (:func:`accept_rows`) (``pot0``: as :func:`step_outputs`).
    Thirty arguments at most: a call with more is compiled as a call with a built tuple, whose
    every array numba reference-counts around the call (the package docstring)."""
    m = times.shape[0]
    for i in range(fbuf.shape[0]):
        snap_f[i] = fbuf[i]
    for i in range(ibuf.shape[0]):
        snap_i[i] = ibuf[i]
    for i in range(INFO_NEWTON_ITERATIONS):
        info[i] = 0.0
    taylor_rows(state, u, v, a, t0, h, rows)
    quintic_coefficients(G, rows, coeffs)
    for i in range(m):
        times[i] = t0 + dt * (i + 1)
    quintic_values(coeffs, t0, h, times, motion)
    if use_base:
        for d in range(3):
            for i in range(m):
                for j in range(motion.shape[2]):
                    motion[d, i, j] += base[d, i, j]
    status = run_steps(t0, dt, motion[0], motion[1], motion[2], casing, cable, law, contact, reac, ledger,
                       ledger_on, scratch, rec, info)  # fmt: skip
    if status == 0:  # OK: a failed step leaves out and state alone (the engine rolls the step back)
        step_outputs(reac, contact.state, contact.g, ledger, law.law, law.k_lin, law.k_hertz, contact.share, pot0, out)
        clip_force_outputs(casing.mi, casing.mF, out, 27)  # (27 = len(OUTPUTS), step_outputs' share)
        accept_rows(state, rows, a, t0)
    return status


@structref.register
class CommunicationContextType(types.StructRef):
    """The numba type of :class:`CommunicationContext` (its fields typed by what it is made of)."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(t)) for name, t in fields)


class CommunicationContext(structref.StructRefProxy):
    """Every array of :func:`communication_step` but the step's numbers, held by the engine."""


structref.define_boxing(CommunicationContextType, CommunicationContext)

CONTEXT_FIELDS = (
    "G", "state", "u", "v", "a", "rows", "coeffs", "times", "motion", "base", "use_base", "casing", "cable", "law",
    "contact", "reac", "ledger", "ledger_on", "scratch", "rec", "info", "out", "fbuf", "ibuf", "snap_f", "snap_i",
)  # fmt: skip


def _new_context(*fields):
    raise NotImplementedError  # (compiled only, through the overload below)


@overload(_new_context)
def _new_context_overload(*fields):
    ty = CommunicationContextType(list(zip(CONTEXT_FIELDS, fields)))

    def build(*fields):
        ctx = structref.new(ty)
        (ctx.G, ctx.state, ctx.u, ctx.v, ctx.a, ctx.rows, ctx.coeffs, ctx.times, ctx.motion, ctx.base, ctx.use_base,
         ctx.casing, ctx.cable, ctx.law, ctx.contact, ctx.reac, ctx.ledger, ctx.ledger_on, ctx.scratch, ctx.rec,
         ctx.info, ctx.out, ctx.fbuf, ctx.ibuf, ctx.snap_f, ctx.snap_i) = fields  # fmt: skip
        return ctx

    return build


@njit(cache=True)
def new_communication_context(
    G, state, u, v, a, rows, coeffs, times, motion, base, use_base, casing, cable, law, contact, reac, ledger,
    ledger_on, scratch, rec, info, out, fbuf, ibuf, snap_f, snap_i,
):  # fmt: skip
    """The :class:`CommunicationContext` of these arrays (the arguments of :func:`communication_step`
    in its order, without t0, dt, h and pot0); it refers to them, it does not copy them."""
    return _new_context(
        G, state, u, v, a, rows, coeffs, times, motion, base, use_base, casing, cable, law, contact, reac, ledger,
        ledger_on, scratch, rec, info, out, fbuf, ibuf, snap_f, snap_i,
    )  # fmt: skip


@njit(cache=True, fastmath=FM, error_model="numpy", nogil=True)
def communication_step_in_context(ctx, t0, dt, h, pot0):
    """:func:`communication_step` with its arrays from ``ctx`` (its steps: ``ctx.times``' length).
    It runs outside the interpreter's lock (``nogil``): it touches no Python object, and every array
    it writes is its engine's own, so the FMU's instances on a master's threads step in parallel."""
    return communication_step(
        t0, dt, h, pot0, ctx.G, ctx.state, ctx.u, ctx.v, ctx.a, ctx.rows, ctx.coeffs, ctx.times, ctx.motion,
        ctx.base, ctx.use_base, ctx.casing, ctx.cable, ctx.law, ctx.contact, ctx.reac, ctx.ledger, ctx.ledger_on,
        ctx.scratch, ctx.rec, ctx.info, ctx.out, ctx.fbuf, ctx.ibuf, ctx.snap_f, ctx.snap_i,
    )  # fmt: skip
