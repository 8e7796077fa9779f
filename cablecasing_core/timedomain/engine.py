"""The single time-stepping engine: Newmark average acceleration of casing and cable coupled by
frictional contact (Section 2.1, Eqs. 14-39). Used by :func:`simulate`, the CLI and the FMU.

Each step (gamma = 1/2, beta = 1/4, Eq. 18 with C = alpha M + beta K) first predicts both bodies
without contact forces (the supports prescribed at the new time, Eq. 13), then searches every cable
node's normal plane for the casing axis, and solves the contact forces at the new time implicitly
in the small space of active contacts (see ``kernels.solve_contact_forces``); the bodies respond
to them through their effective compliance, exactly, because the structure is linear. The
reactions (Eq. 13) follow from the partitioned equations at the prescribed DOFs.

The engine can advance from any time by any step (a step that is not a multiple of ``dt`` ends
with one shorter sub-step, whose factorisation is cached) and can copy out and restore its
complete state (:meth:`Engine.get_state`, :meth:`Engine.set_state`).
"""

from __future__ import annotations

import io
import math

import numpy as np
from scipy.linalg import cho_factor, cho_solve

from ..errors import ModelError, SimulationError
from ..model.schema import BODY_NAMES, CHANNELS, OUTPUTS, lookup
from ..model.validators import seconds
from ..structure.assembly import assemble_body
from . import kernels as K


def hertz_constant(model):
    """4/3 E* r^1/2 of Eq. (29) in N/m^1.5: E* from both moduli and Poisson ratios (Eq. 28), r from
    the cable radius (convex, r1 = d/2) and the casing's inner radius (concave, r2 = -d_inner/2),
    1/r = 1/r1 + 1/r2 (Eq. 27). Hertz's point-contact law; a wire lying in a tube is closer to a line
    contact, so the law is a stiffness model for the penalty method, as in the paper (Fig. 19)."""
    ca, cb = model.bodies["casing"], model.bodies["cable"]
    Es = 1.0 / ((1 - cb.nu**2) / cb.E_ref + (1 - ca.nu**2) / ca.E_ref)
    r1, r2 = cb.d_outer / 2.0, -ca.d_inner / 2.0
    r = 1.0 / (1.0 / r1 + 1.0 / r2)
    return 4.0 / 3.0 * Es * np.sqrt(r)


def block_ldl(A):
    """Block LDL^T factor of a symmetric positive definite block-tridiagonal matrix A (6 x 6 node
    blocks), A = L D L^T with unit block diagonal in L, in the form ``kernels.block_solve`` uses:
    Dinv[i] = D_i^-1, L[i] = L_i,i-1 (L[0] = 0) and LT[i] = L_i+1,i^T (LT[-1] = 0), each (nb, 6, 6).
    D_0 = A_00, L_i,i-1 = A_i,i-1 D_i-1^-1, D_i = A_ii - L_i,i-1 A_i-1,i (the Schur complements,
    SPD, so no pivoting is needed)."""
    n = A.shape[0]
    nb = n // 6
    blk = lambda i, j: A[6 * i : 6 * i + 6, 6 * j : 6 * j + 6]  # noqa: E731
    for i in range(nb):
        if np.any(A[6 * i : 6 * i + 6, 6 * (i + 2) :]):
            raise AssertionError("the effective stiffness must be block tridiagonal in node blocks")
    Dinv = np.zeros((nb, 6, 6))
    L = np.zeros((nb, 6, 6))
    LT = np.zeros((nb, 6, 6))
    for i in range(nb):
        D = blk(i, i).copy()
        if i:
            L[i] = blk(i, i - 1) @ Dinv[i - 1]
            LT[i - 1] = L[i].T
            D -= L[i] @ blk(i - 1, i)
        inv = cho_solve(cho_factor(0.5 * (D + D.T)), np.eye(6))
        Dinv[i] = 0.5 * (inv + inv.T)
    return Dinv, L, LT


def diagonal_storage(A, b):
    """Diagonals of a square matrix of half-bandwidth b: D[k, i] = A[i, i + k - b] (zero outside)."""
    n = A.shape[0]
    D = np.zeros((2 * b + 1, n))
    for k in range(-b, b + 1):
        i = np.arange(max(0, -k), min(n, n - k))
        D[b + k, i] = A[i, i + k]
    return D


def support_rows(M, K, pres, b):
    """Rows of M and K (dense, half-bandwidth b) of the prescribed DOFs over their band, for the
    reactions (Eq. 13): sup[q, 0] = M[pres[q], lo[q]:lo[q] + w], sup[q, 1] the same of K, w = 2b + 1
    (at most n), lo[q] = pres[q] - b moved inside the matrix. Returns (sup, lo)."""
    n = M.shape[0]
    w = min(2 * b + 1, n)
    lo = np.clip(np.asarray(pres, np.int64) - b, 0, n - w)
    sup = np.zeros((len(pres), 2, w))
    for q, (p, j0) in enumerate(zip(pres, lo)):
        sup[q, 0] = M[p, j0 : j0 + w]
        sup[q, 1] = K[p, j0 : j0 + w]
    return sup, lo


def coupling_triplets(K, pres, free):
    """The nonzero entries of K_fp, the stiffness between the free DOFs and the prescribed ones
    (N/m): (idx, val) with idx[0] the free row, idx[1] the prescribed DOF's index into pres."""
    sub = K[np.ix_(free, pres)]
    r, q = np.nonzero(sub)
    return np.array([np.asarray(free)[r], q], np.int64).reshape(2, -1), sub[r, q].copy()


class _Body:
    """Matrices in diagonal storage, factorisations and state of one body (plain arrays for the
    kernels)."""

    def __init__(self, model, name):
        spec = model.bodies[name]
        sysm = assemble_body(model, name)
        if spec.frequency_dependent:
            from ..frequency.modal import natural_frequencies

            f1 = natural_frequencies(model, name, 1)[0]
            sysm = assemble_body(model, name, E=float(spec.modulus(f1)))
        self.system = sysm
        self.alpha, self.beta = spec.alpha, spec.beta
        Kd, Md = sysm.K.toarray(), sysm.M.toarray()
        rows, cols = np.nonzero(Kd + Md)
        self.b = b = int(np.max(np.abs(rows - cols)))
        n = sysm.ndof
        self.Md = diagonal_storage(Md, b)
        self.Kd = diagonal_storage(Kd, b)
        self.K_full, self.M_full = Kd, Md
        free = sysm.free
        self.f0, self.nf = (int(free[0]), len(free)) if len(free) else (0, 0)
        if self.nf and not np.array_equal(free, np.arange(self.f0, self.f0 + self.nf)):
            raise AssertionError("free DOFs must be contiguous (supports sit at the ends)")
        # the node blocks holding the free DOFs (the block solve works on whole nodes)
        self.g0 = 6 * (self.f0 // 6)
        self.ng = 6 * -(-(self.f0 + self.nf) // 6) - self.g0 if self.nf else 0
        self.pres = sysm.prescribed.astype(np.int64)
        bi = BODY_NAMES.index(name)
        pchan, pslot = [], []
        for j in self.pres:
            node, comp = divmod(int(j), 6)
            s = 0 if node == sysm.support_nodes["A"] else 1
            pslot.append(6 * s + comp)
            pchan.append(6 * bi + 3 * s + comp if comp < 3 else -1)
        self.pchan = np.array(pchan, np.int64)
        self.pslot = np.array(pslot, np.int64)
        self.sup, self.sup_lo = support_rows(Md, Kd, self.pres, b)
        self.cpl_i, self.cpl_v = coupling_triplets(Kd, self.pres, free)
        self._factors = {}
        self.U = np.zeros(n)
        self.V = np.zeros(n)
        self.A = np.zeros(n)

    def factors(self, dt, need_inverse):
        """Block LDL^T factor (Dinv, L, LT) of the effective stiffness K + 2/dt C + 4/dt^2 M over
        the free node blocks (prescribed DOFs among them as identity rows) and, for contact, the
        dense inverse (m/N) of its free part, placed in an all-DOF matrix that is zero on the
        prescribed DOFs; cached per dt."""
        key = (dt, need_inverse)
        if key not in self._factors:
            g = slice(self.g0, self.g0 + self.ng)
            Keff = (1 + 2 * self.beta / dt) * self.K_full[g, g] + (4 / dt**2 + 2 * self.alpha / dt) * self.M_full[g, g]
            inner = [j - self.g0 for j in self.pres if self.g0 <= j < self.g0 + self.ng]
            Keff[inner, :] = 0.0
            Keff[:, inner] = 0.0
            Keff[inner, inner] = 1.0
            Dinv, L, LT = block_ldl(Keff)
            if need_inverse:
                f = slice(self.f0 - self.g0, self.f0 - self.g0 + self.nf)
                # columns of Keff^-1 from the block factor by the step loop's own solve (the identity
                # rows of the prescribed DOFs keep the free part equal to inv(Keff[f, f])). Not LAPACK:
                # a threaded BLAS rounds differently with each thread count, and the contact response
                # is chaotic, so a record would depend on OMP_NUM_THREADS (a dask worker, an FMU host).
                cols = np.eye(self.ng)[f]  # e_j of the free DOFs, one per row
                for x in cols:
                    K.block_solve(Dinv, L, LT, x)  # -> column j of Keff^-1, stored as row j
                inv_ff = cols[:, f]
                # over all DOFs, zero on the prescribed ones (they do not respond), and exactly
                # symmetric: the contact kernels read its rows as columns
                n = len(self.U)
                inv = np.zeros((n, n))
                inv[self.f0 : self.f0 + self.nf, self.f0 : self.f0 + self.nf] = 0.5 * (inv_ff + inv_ff.T)
            else:
                inv = np.zeros((1, 1))
            self._factors[key] = (Dinv, L, LT, inv)
        return self._factors[key]

    def energy(self):
        """(kinetic, strain) energy in J."""
        return 0.5 * self.V @ self.M_full @ self.V, 0.5 * self.U @ self.K_full @ self.U


def compiled_entry(dispatcher, args):
    """The compiled entry point of the numba ``dispatcher`` for the types of ``args``, or the
    dispatcher itself when there is none. Calling it skips numba's type dispatch, which types the
    arrays in tuples in Python (~100 arrays in run_steps' records: ~20 us per call, more than ten
    steps cost the FMU at its 1e-4 s step). The engine builds every argument of run_steps itself,
    with fixed dtypes and dimensions (the support motion as C-contiguous float64, shape (n, 12)), so
    the types of later calls are those of the first one."""
    try:
        return dispatcher.overloads[tuple(dispatcher.typeof_pyval(a) for a in args)].entry_point
    except (AttributeError, KeyError):  # (another numba, or not compiled for these types)
        return dispatcher


_DUMMY_BLOCK = np.zeros((0, 6, 6))


class Engine:
    """Newmark stepping engine for a :class:`~cablecasing_core.model.Model`.

    Parameters
    ----------
    model : Model
    dt : float, time step in s (default ``model.scenario["dt"]``).
    contact : bool, contact between cable and casing (default ``model.contact["enabled"]``; needs
        both bodies).
    ledger : bool, accumulate the Rayleigh dissipation each step (one extra matrix product).
    record : bool, keep per-step histories (support forces, contact state, normal force,
        penetration) for :meth:`history`.
    """

    def __init__(self, model, dt=None, contact=None, ledger=True, record=False):
        dt = model.scenario["dt"] if dt is None else dt
        lookup("scenario.dt").check(dt, "dt")
        self.model = model
        self.dt = float(dt)
        self.bodies = {n: _Body(model, n) for n in model.bodies}
        both = "casing" in self.bodies and "cable" in self.bodies
        contact = model.contact["enabled"] if contact is None else bool(contact)
        self.contact = contact and both
        self.ledger_on = bool(ledger)
        self.record = bool(record)
        c = model.contact
        if both:
            cab, cas = self.bodies["cable"].system, self.bodies["casing"].system
            self.Xc = cab.centerline.nodes.copy()
            self.Tc = cab.centerline.tangents.copy()
            self.Xs = cas.centerline.nodes.copy()
            self.Rs = cas.centerline.frames.copy()
            self.Ls = cas.centerline.lengths.copy()
            self.gap = model.radial_gap
            self.r_in = cas.section.r_inner
            self.r_cable = cab.section.r_outer
            self.k_hertz = hertz_constant(model)
        else:
            self.Xc = np.zeros((0, 3))
            self.Tc = self.Xs = np.zeros((0, 3))
            self.Rs = np.zeros((0, 3, 3))
            self.Ls = np.zeros(0)
            self.gap = self.r_in = self.r_cable = self.k_hertz = 0.0
        self.law = 0 if c["law"] == "hertz" else 1
        self.k_lin, self.c_n, self.mu, self.v_stick = c["stiffness"], c["damping"], c["friction"], c["stick_velocity"]
        self._hist = []
        self._snap = None  # roll-back buffer of advance (see snapshot)
        self._ws = K.contact_workspace(len(self.Xc))
        self._allocate_state()
        self._call_args = {}  # (dt, settings) -> the step loop's arguments and entry point (see _run)
        self._no_record = K.Recording(
            False,
            np.zeros((1, 24)),
            np.zeros(2, np.int64),
            np.zeros(1, np.int32),
            np.zeros(1, np.int8),
            np.zeros(1),
            np.zeros(1),
            0,
        )
        self.reset()

    def _allocate_state(self):
        """All state arrays as views into two flat buffers (floats, integers), so that a snapshot is
        two copies (:meth:`snapshot`); the arrays are never rebound, only written."""
        nn = len(self.Xc)
        ns = self.bodies["casing"].system.ndof if "casing" in self.bodies else 1
        nc = self.bodies["cable"].system.ndof if "cable" in self.bodies else 1
        floats = [(b, k, (len(b.U),)) for b in self.bodies.values() for k in "UVA"]
        floats += [
            (self, k, shape)
            for k, shape in (
                ("cxi", (nn,)),
                ("Pn", (nn, 3)),
                ("vrel", (nn,)),
                ("Nn", (nn,)),
                ("gn", (nn,)),
                ("fcs", (ns,)),
                ("fcc", (nc,)),
                ("reac", (24,)),
                ("ledger", (K.LEDGER_SIZE,)),
                ("contact_time", (nn,)),
                ("_info", (K.INFO_SIZE,)),
            )
        ]
        ints = [(self, "cstate", (nn,)), (self, "celem", (nn,))]
        for items, dtype, name in ((floats, float, "_fbuf"), (ints, np.int64, "_ibuf")):
            buf = np.zeros(sum(int(np.prod(shape)) for _, _, shape in items), dtype)
            o = 0
            for owner, key, shape in items:
                size = int(np.prod(shape))
                setattr(owner, key, buf[o : o + size].reshape(shape))
                o += size
            setattr(self, name, buf)
        # the step loop's info array (K.INFO_*): what failed, then the solver counters: contact Newton
        # iterations, stick/slip passes, unconverged steps
        self.solver_counts = self._info[K.INFO_NEWTON_ITERATIONS : K.INFO_UNCONVERGED_STEPS + 1]

    # -------------------------------------------------------------------------------- state
    def reset(self):
        """Back to t = 0 with both bodies at rest in their reference configuration."""
        self.time = 0.0
        self._fbuf[:] = 0.0
        self._ibuf[:] = 0
        self.celem[:] = np.clip(np.arange(len(self.celem)) - 1, 0, max(len(self.Ls) - 1, 0))
        self._hist = []

    _ARRAYS = ("cstate", "celem", "cxi", "Pn", "vrel", "Nn", "gn", "fcs", "fcc", "reac", "ledger", "contact_time")

    def get_state(self):
        """The complete state as ``{name: array}`` (copies): time, U/V/A of each body, contact
        memory (state, element, forces), last reactions and the energy ledger."""
        s = {"time": np.array([self.time])}
        for n, b in self.bodies.items():
            s[f"{n}.U"], s[f"{n}.V"], s[f"{n}.A"] = b.U.copy(), b.V.copy(), b.A.copy()
        for a in self._ARRAYS:
            s[a] = getattr(self, a).copy()
        return s

    def snapshot(self, into=None):
        """The complete state (what :meth:`get_state` holds, and the solver counters) as an opaque
        list, cheaply: two buffer copies, written into ``into`` (an earlier snapshot of this engine)
        when given. For roll-back (:meth:`restore`); recorded histories are not part of it."""
        if into is None:
            return [self.time, self._fbuf.copy(), self._ibuf.copy()]
        into[0] = self.time
        np.copyto(into[1], self._fbuf)
        np.copyto(into[2], self._ibuf)
        return into

    def restore(self, snap):
        """Return to a :meth:`snapshot` of this engine (continuation is bit-identical)."""
        self.time = snap[0]
        np.copyto(self._fbuf, snap[1])
        np.copyto(self._ibuf, snap[2])

    def set_state(self, state):
        """Restore a state from :meth:`get_state` (continuation is bit-identical). Every entry is
        checked before any is written, so a bad state leaves the engine as it was."""
        targets = [(f"{n}.{k}", getattr(b, k)) for n, b in self.bodies.items() for k in "UVA"]
        targets += [(a, getattr(self, a)) for a in self._ARRAYS]
        try:
            time = float(np.asarray(state["time"]).reshape(-1)[0])
            new = [(dst, np.asarray(state[key], dst.dtype)) for key, dst in targets]
        except KeyError as exc:
            raise ModelError("state", str(exc), "is missing from the state") from None
        for (key, dst), (_, arr) in zip(targets, new):
            if arr.shape != dst.shape:
                raise ModelError(f"state.{key}", arr.shape, f"must have shape {dst.shape}")
        for dst, arr in new:
            dst[...] = arr
        self.time = time

    # -------------------------------------------------------------------------------- stepping
    def _body_arrays(self, name, dt):
        """The step loop's record of body ``name`` (:class:`kernels.BodyArrays`); a body that is
        absent, or has no free DOF, is off (its arrays are placeholders of the right types)."""
        b = self.bodies.get(name)
        fc = self.fcs if name == "casing" else self.fcc
        if b is None or b.nf == 0:
            z = np.zeros(1)
            i0 = np.zeros(0, np.int64)
            return K.BodyArrays(
                False,
                np.zeros((1, 1)),
                np.zeros((1, 1)),
                _DUMMY_BLOCK,
                _DUMMY_BLOCK,
                _DUMMY_BLOCK,
                0,
                0,
                0,
                0,
                0.0,
                0.0,
                b.U if b else z,
                b.V if b else z.copy(),
                b.A if b else z.copy(),
                b.pres if b else i0,
                b.pchan if b else i0,
                b.pslot if b else i0,
                np.zeros((len(b.U), len(b.U))) if b else np.zeros((1, 1)),  # nothing responds
                np.zeros((0, 2, 1)),
                i0,
                np.zeros((2, 0), np.int64),
                np.zeros(0),
                fc,
            )
        Dinv, L, LT, inv = b.factors(dt, self.contact)
        return K.BodyArrays(
            True,
            b.Md,
            b.Kd,
            Dinv,
            L,
            LT,
            b.g0,
            b.ng,
            b.f0,
            b.nf,
            b.alpha,
            b.beta,
            b.U,
            b.V,
            b.A,
            b.pres,
            b.pchan,
            b.pslot,
            inv,
            b.sup,
            b.sup_lo,
            b.cpl_i,
            b.cpl_v,
            fc,
        )

    def _run(self, dt, up, vp, ap, times):
        n = len(up)
        if self.record:
            # contact histories sparse (the nodes in contact, ~2 of 36): np.empty of the worst case
            # is only address space until written; the used part is copied out below
            cap = n * len(self.Xc)
            rec = K.Recording(
                True,
                np.zeros((n, 24)),
                np.zeros(n + 1, np.int64),
                np.empty(cap, np.int32),
                np.empty(cap, np.int8),
                np.empty(cap),
                np.empty(cap),
                0,
            )
        else:
            rec = self._no_record
        # the arrays are never rebound (see _allocate_state), so the arguments are built once per
        # time step and setting (a changed attribute, e.g. contact, builds them anew)
        key = (
            dt,
            self.contact,
            self.ledger_on,
            self.record,
            self.law,
            self.k_lin,
            self.k_hertz,
            self.c_n,
            self.mu,
            self.v_stick,
            self.gap,
            self.r_in,
            self.r_cable,
        )
        args, step_loop = self._call_args.get(key, (None, None))
        if args is None:
            law = K.ContactLaw(
                self.contact,
                self.gap,
                self.r_in,
                self.r_cable,
                self.law,
                self.k_lin,
                self.k_hertz,
                self.c_n,
                self.mu,
                self.v_stick,
            )
            contact = K.ContactArrays(
                self.Xc,
                self.Tc,
                self.Xs,
                self.Rs,
                self.Ls,
                self.cstate,
                self.celem,
                self.cxi,
                self.Pn,
                self.vrel,
                self.Nn,
                self.gn,
                self.contact_time,
                self._ws,
            )
            args = (
                self._body_arrays("casing", dt),
                self._body_arrays("cable", dt),
                law,
                contact,
                self.reac,
                self.ledger,
                self.ledger_on,
            )
        info = self._info  # info[K.INFO_NEWTON_ITERATIONS:] are the solver counters (a view)
        info[: K.INFO_NEWTON_ITERATIONS] = 0.0
        if step_loop is None:
            status = K.run_steps(self.time, dt, up, vp, ap, *args, rec, info)  # compiles or loads it
            self._call_args[key] = (args, compiled_entry(K.run_steps, (self.time, dt, up, vp, ap, *args, rec, info)))
        else:
            status = step_loop(self.time, dt, up, vp, ap, *args, rec, info)
        if status == K.ERR_INPUT:
            r, c, q = (int(info[i]) for i in (K.INFO_INPUT_ROW, K.INFO_INPUT_CHANNEL, K.INFO_INPUT_KIND))
            name = ("displacement", "velocity", "acceleration")[q]
            raise ModelError(
                f"{CHANNELS[c]} {name}", float((up, vp, ap)[q][r, c]), f"must be finite (at t = {times[r]:.6g} s)"
            )
        if status != K.OK:
            what = {
                K.ERR_NAN: "the solution is no longer finite (NaN/inf): the step is unstable or the input is",
                K.ERR_PENETRATION: f"penetration {info[K.INFO_VALUE]:.4g} m exceeds the cable radius "
                f"{self.r_cable:.4g} m (contact too soft for this load, or the time step too "
                "large)",
            }[status]
            node = info[K.INFO_NODE]
            where = f"cable node {int(node)}" if node >= 0 else "the support forces"
            raise SimulationError(f"at t = {info[K.INFO_TIME]:.6g} s, {where}: {what}")
        if self.record:
            m = int(rec.ptr[-1])
            self._hist.append((rec.F, rec.ptr) + tuple(x[:m].copy() for x in (rec.node, rec.state, rec.N, rec.g)))
        self.time = float(info[K.INFO_TIME])

    CHUNK = 2048  # steps per evaluation of the support motion (see advance)

    def advance(self, h, motion):
        """Integrate from ``self.time`` to ``self.time + h`` (s) with the support ``motion``
        (callable t -> (u, v, a), each (len(t), 12), in m, m/s, m/s2 over ``CHANNELS``; a function
        of t alone, evaluated in chunks of :attr:`CHUNK` steps).

        The motion is evaluated chunk by chunk, so its arrays stay small and in cache whatever the
        duration (1 s at dt = 1e-5 in one piece would be 29 MB of motion alone, and faulting them
        in cost ~10 % of the step loop's time). Bad input (a non-finite or misshaped motion, or an
        error raised by ``motion``) in any chunk leaves the engine as it was before the call: a
        later chunk's error restores the state (:meth:`snapshot`) and drops that call's recorded
        history. So does a blow-up (:class:`SimulationError`, whose message says when, where and
        what): the engine is then as it was before the call, and can be advanced again (e.g. by
        a smaller step, or after :meth:`set_state`)."""
        seconds("h", h)
        n = math.floor(h / self.dt * (1 + 1e-12))  # (math: numpy's scalar calls cost ~1 µs each)
        rest = h - n * self.dt
        segments = []
        if n:
            segments.append((self.dt, n))
        if rest > 1e-9 * self.dt:
            segments.append((rest, 1))
        # roll-back for a blow-up, or for bad input in a later chunk (the shorter last substep is a
        # chunk of its own); the snapshot buffer is reused (two buffer copies per call)
        self._snap = snap = self.snapshot(self._snap)
        nhist = len(self._hist)
        try:
            if self.time == 0.0 and not self.ledger.any():
                kin, strain = (sum(x) for x in zip(*(b.energy() for b in self.bodies.values())))
                self.ledger[K.LEDGER_START_ENERGY] = kin + strain + self.contact_potential()
            for dt, m in segments:
                t = self.time
                for j0 in range(0, m, self.CHUNK):
                    j1 = min(m, j0 + self.CHUNK)
                    times = t + dt * np.arange(j0 + 1, j1 + 1)  # as if evaluated in one piece
                    u, v, a = (np.ascontiguousarray(x, dtype=float) for x in motion(times))
                    for x in (u, v, a):
                        if x.shape != (j1 - j0, len(CHANNELS)):
                            raise ModelError(
                                "motion", x.shape, f"must return arrays of shape ({j1 - j0}, {len(CHANNELS)})"
                            )
                    self._run(dt, u, v, a, times)  # (non-finite motion is refused there, before any step)
                self.time = float(t + m * dt)
        except BaseException:
            self.restore(snap)
            del self._hist[nhist:]
            raise

    # -------------------------------------------------------------------------------- outputs
    def contact_potential(self):
        """Elastic energy stored in the contacts (J), from the penetrations at the current time."""
        return K.contact_potential(self.gn, self.law, self.k_lin, self.k_hertz)

    def energies(self):
        """Energy ledger in J: kinetic, strain, contact potential, work done by the supports,
        dissipated by Rayleigh damping, dissipated in the contacts (damping and friction together:
        the work of the contact forces less the stored contact energy), and the balance residual
        (energy now minus the energy at the start plus supplied work less dissipation)."""
        kin = sum(b.energy()[0] for b in self.bodies.values())
        strain = sum(b.energy()[1] for b in self.bodies.values())
        pot = self.contact_potential()
        w_sup, d_ray, e_start, d_fric, w_con, d_damp = (
            self.ledger[i]
            for i in (
                K.LEDGER_SUPPORT_WORK,
                K.LEDGER_RAYLEIGH_DISSIPATION,
                K.LEDGER_START_ENERGY,
                K.LEDGER_FRICTION_DISSIPATION,
                K.LEDGER_CONTACT_WORK,
                K.LEDGER_DAMPING_DISSIPATION,
            )
        )
        d_con = -w_con - pot
        residual = kin + strain + pot - (e_start + w_sup - d_ray - d_con)
        return {
            "kinetic": kin,
            "strain": strain,
            "contact_potential": pot,
            "support_work": w_sup,
            "rayleigh_dissipation": d_ray if self.ledger_on else np.nan,
            "contact_dissipation": d_con,
            "contact_damping_dissipation": d_damp,
            "friction_dissipation": d_fric,
            "residual": residual,
        }

    def output_values(self, out=None):
        """The values of :meth:`outputs` as an array in the order of :data:`OUTPUTS` (written into
        ``out`` when given): one call instead of a dict, for the FMU's per-step reads."""
        out = np.empty(len(OUTPUTS)) if out is None else out
        out[:24] = self.reac
        out[24] = np.count_nonzero(self.cstate)  # OPEN == 0 (no comparison array)
        out[25] = self.gn.max() if len(self.gn) else 0.0
        out[26] = -self.ledger[K.LEDGER_CONTACT_WORK] - self.contact_potential()
        return out

    def outputs(self):
        """Current outputs ``{name: value}`` for the names in :data:`OUTPUTS` (N, N.m, m, J)."""
        out = dict(zip(OUTPUTS, self.output_values().tolist()))
        out["contact.active"] = int(out["contact.active"])
        return out

    def history(self, sparse=False):
        """Recorded histories (``record=True``) over all steps so far: ``support_forces`` (n x 24,
        N and N.m, :data:`SUPPORT_OUTPUTS`) and, per cable node, ``contact_state`` (0 open, 1 stick,
        2 slip), ``normal_force`` (N) and ``penetration`` (m), each n x nodes.

        The engine stores the contact histories sparse (the nodes in contact at the end of each
        step: about 2 of 36 in the default scenario, some 40 bytes per step instead of 600);
        ``sparse=True`` returns them so, as ``contact_step``, ``contact_node`` (row and column of
        each entry) with ``contact_state``, ``normal_force`` and ``penetration`` of that entry."""
        if not self._hist:
            return {}
        F = np.concatenate([h[0] for h in self._hist])
        rows = np.concatenate([np.repeat(np.arange(len(h[0])), np.diff(h[1])) for h in self._hist])
        rows += np.repeat(np.cumsum([0] + [len(h[0]) for h in self._hist[:-1]]), [len(h[2]) for h in self._hist])
        node, state, N, g = (np.concatenate([h[i] for h in self._hist]) for i in range(2, 6))
        if sparse:
            return {
                "support_forces": F,
                "contact_step": rows,
                "contact_node": node,
                "contact_state": state,
                "normal_force": N,
                "penetration": g,
            }
        shape = (len(F), len(self.Xc))
        out = {
            "support_forces": F,
            "contact_state": np.zeros(shape, np.int8),
            "normal_force": np.zeros(shape),
            "penetration": np.zeros(shape),
        }
        for key, v in (("contact_state", state), ("normal_force", N), ("penetration", g)):
            out[key][rows, node] = v
        return out


def state_to_bytes(state):
    """Serialise a state dict of arrays (np.savez, no pickle)."""
    buf = io.BytesIO()
    np.savez(buf, **state)
    return buf.getvalue()


def state_from_bytes(data):
    """Inverse of :func:`state_to_bytes`."""
    with np.load(io.BytesIO(bytes(data)), allow_pickle=False) as z:
        return {k: z[k] for k in z.files}
