"""One body's matrices in the storage of the step loop's kernels, its factorisations and its state
(plain arrays), and the kernels' record of it (:func:`body_arrays`).

M and K of a body (Eqs. 4-9 assembled, Eq. 13 partitioned; K the tangent stiffness K_E + K_G of a
prestressed body) go into diagonal storage; the effective stiffness K + 2/dt C + 4/dt^2 M of
Newmark's average acceleration (Eq. 18, C = alpha M + beta K) over the node blocks that hold the
free DOFs gets a block LDL^T factor; with contact, the dense effective compliance comes from that
factor, by the step loop's own solve; with a constant load at rest, the response to it too.

The body as the time domain assembles it (:func:`time_domain_system`: its modulus at its first
natural frequency) and its buckling load (:func:`body_buckling`, ``cc.body_buckling``: at its reference modulus).
"""

from __future__ import annotations

from collections import OrderedDict

import numpy as np
from scipy.linalg import cho_factor, cho_solve

from ..frequency.modal import natural_frequencies
from ..model.schema import BODY_NAMES, CHANNELS
from ..model.validators import Choice, check_model
from ..structure.assembly import assemble_body
from ..structure.buckling import Buckling, buckling
from . import kernels as K


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


# Factorisations (and the engine's step-loop arguments) are kept for the time steps used last: the
# step dt and the shorter last sub-steps of communication steps that are not multiples of dt. Each
# costs ~0.4 MB per body (the dense compliance for contact) and a few ms to build, so a master that
# varies its step size all the time pays a factorisation per step but no memory beyond this bound.
FACTOR_CACHE_SIZE = 8


class BoundedCache(OrderedDict):
    """A dict that keeps only the ``size`` entries used last (get and set both count as use).
    (functools.lru_cache caches a function's calls; here the cache belongs to each body and engine.)"""

    def __init__(self, size):
        super().__init__()
        self.size = size

    def get(self, key, default=None):
        if key in self:
            self.move_to_end(key)
            return self[key]
        return default

    def __setitem__(self, key, value):
        super().__setitem__(key, value)
        self.move_to_end(key)
        while len(self) > self.size:
            self.popitem(last=False)


def time_domain_system(model, name, check_buckling=True):
    """Body ``name`` of ``model`` assembled as the time domain uses it (``structure.assembly``'s
    system: M in kg, K in N/m, f in N, SI throughout): with its frequency-dependent modulus, if any,
    at its first natural frequency (one modulus, Pa, for the whole run); ``check_buckling``: refuse a
    compression at or above its buckling load, as :func:`~cablecasing_core.structure.assembly.assemble_body`."""
    spec = model.bodies[name]
    if spec.frequency_dependent:
        f1 = natural_frequencies(model, name, 1)[0]
        return assemble_body(model, name, E=float(spec.modulus(f1)), check_buckling=check_buckling)
    return assemble_body(model, name, check_buckling=check_buckling)


def body_buckling(model, body: str = "casing") -> Buckling:
    """The lowest buckling load of ``body`` ("casing", the default, or "cable") of ``model`` (a
    :class:`~cablecasing_core.Model`) at its reference modulus (Pa: the scalar ``E``, or a
    frequency-dependent modulus's first row, its quasi-static value, which the refusal of a tension
    at or above the load takes too: one load per model, whatever the tension), with its real
    supports, isolators and clips: :func:`~cablecasing_core.structure.buckling.buckling` of that
    body, P_cr in N (``Buckling.load``; inf when no compression buckles it, 0 for a mechanism). The
    compression the body carries does not enter it: the load of a casing whose tension exceeds it
    is given, not refused. (The time domain's single modulus of a frequency-dependent one, at the
    first natural frequency, :func:`time_domain_system`, falls with the compression, and a load from
    it would move with the tension.) A ``model`` that is no Model, or a ``body`` it does not have,
    raises :class:`~cablecasing_core.errors.ModelError` naming it. ``cc.body_buckling``."""
    check_model(model)
    Choice(*model.bodies)("body", body)
    return buckling(assemble_body(model, body, check_buckling=False))


class BodyStorage:
    """Matrices in diagonal storage, factorisations and state of one body (plain arrays for the
    kernels); ``f`` its constant load at rest (N, N.m, all DOFs; an installed model's).
    ``channels``: the engine's support channels (the mounts' supports are driven by theirs;
    default :data:`~cablecasing_core.model.schema.CHANNELS`).

    The mounts (isolators and clips) are springs and dampers from a node to its support: the
    node's DOFs stay free, K6 + 2/dt C6 joins the effective stiffness of its node block (so the
    factor stays block tridiagonal), the support's motion enters the predictor's right-hand side,
    and the force through the mount is the support's reaction (``kernels.mount_forces``). Their
    state, the supports' motion ``mb`` and the forces ``mF``, is the engine's (set by it)."""

    def __init__(self, model, name, system=None, channels=CHANNELS):
        sysm = time_domain_system(model, name) if system is None else system
        self.system = sysm
        self.f = np.asarray(sysm.f, dtype=float).copy()
        self.loaded = bool(np.any(self.f))
        self.alpha, self.beta = sysm.spec.alpha, sysm.spec.beta
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
        self.pres = sysm.prescribed[sysm.prescribed < n].astype(np.int64)  # (not the mounts' support nodes)
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
        self.mounts = sysm.mounts
        nm = len(self.mounts)
        self.mi = np.full((nm, 5), -1, np.int64)
        self.mKC = np.zeros((nm, 2, 6, 6))
        for m, mt in enumerate(self.mounts):
            self.mi[m, 0] = 6 * mt.node
            if mt.channels is not None:
                self.mi[m, 1:4] = [channels.index(c) for c in mt.channels]
            if mt.support is not None:
                self.mi[m, 4] = 6 * "AB".index(mt.support)
            self.mKC[m] = mt.K6, mt.C6
        self.mb = np.zeros((nm, 2, 6))  # (views into the engine's state buffer once it allocates)
        self.mF = np.zeros((nm, 6))
        self._factors = BoundedCache(FACTOR_CACHE_SIZE)
        self.U = np.zeros(n)
        self.V = np.zeros(n)
        self.A = np.zeros(n)

    def factors(self, dt, need_inverse):
        """Block LDL^T factor (Dinv, L, LT) of the effective stiffness K + 2/dt C + 4/dt^2 M over
        the free node blocks (prescribed DOFs among them as identity rows) and, for contact, the
        dense inverse (m/N) of its free part, placed in an all-DOF matrix that is zero on the
        prescribed DOFs; cached for the last FACTOR_CACHE_SIZE steps."""
        key = (dt, need_inverse)
        cached = self._factors.get(key)
        if cached is None:
            g = slice(self.g0, self.g0 + self.ng)
            # Keff = K + c1 C + c0 M, C = alpha M + beta K (Eq. 40, the element damping of Eq. 5
            # assembled), c0 = 4/dt^2 and c1 = 2/dt Newmark's coefficients (Eq. 18). The Rayleigh
            # factors are rounded as written, 1 + 2 beta/dt and 4/dt**2 + 2 alpha/dt, which for some dt
            # differ in the last bit from the predictor's ck = 1 + c1 beta and cm = c0 + c1 alpha: the
            # difference is below the solve's round-off, but a contact run is chaotic, and another
            # rounding here would change every record (and the figures measured with them) in its
            # last digits.
            _, c1 = K.newmark_coefficients(dt)
            Keff = (1 + 2 * self.beta / dt) * self.K_full[g, g] + (4 / dt**2 + 2 * self.alpha / dt) * self.M_full[g, g]
            inner = [j - self.g0 for j in self.pres if self.g0 <= j < self.g0 + self.ng]
            for mt in self.mounts:  # the mounts' springs and dampers on their node blocks
                j = slice(6 * mt.node - self.g0, 6 * mt.node - self.g0 + 6)
                Keff[j, j] += mt.K6 + c1 * mt.C6
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
            cached = self._factors[key] = (Dinv, L, LT, inv)
        return cached

    def set_load(self, f):
        """Set the constant load at rest (N, N.m, all DOFs; the static state's, whose cable tension
        is its pre-stretch force) and drop the cached responses to the old one."""
        self.f = np.asarray(f, dtype=float).copy()
        self.loaded = bool(np.any(self.f))
        for key in [k for k in self._factors if k[0] == "load"]:
            del self._factors[key]

    def load_response(self, dt):
        """uext = Keff^-1 f (m, rad): the free DOFs' share of a Newmark step of size dt (s) in the
        response to the constant load f (zero on the prescribed DOFs), by the step loop's own block
        solve (the same factor as :meth:`factors`); cached with the factors."""
        key = ("load", dt)
        cached = self._factors.get(key)
        if cached is None:
            Dinv, L, LT, _ = self.factors(dt, False)
            r = np.zeros(self.ng)
            r[self.f0 - self.g0 : self.f0 - self.g0 + self.nf] = self.f[self.f0 : self.f0 + self.nf]
            K.block_solve(Dinv, L, LT, r)
            cached = np.zeros(len(self.U))
            cached[self.f0 : self.f0 + self.nf] = r[self.f0 - self.g0 : self.f0 - self.g0 + self.nf]
            self._factors[key] = cached
        return cached

    def energy(self):
        """(kinetic, strain) energy in J; the strain energy includes the mounts' springs,
        1/2 r K6 r with r the node's displacement relative to its support."""
        strain = 0.5 * self.U @ self.K_full @ self.U
        for m, mt in enumerate(self.mounts):
            r = self.U[6 * mt.node : 6 * mt.node + 6] - self.mb[m, 0]
            strain += 0.5 * r @ mt.K6 @ r
        return 0.5 * self.V @ self.M_full @ self.V, strain


_DUMMY_BLOCK = np.zeros((0, 6, 6))


def body_arrays(body, dt, contact, fc, nsub=1):
    """The step loop's record of ``body`` (a :class:`BodyStorage`, or None for an absent body) at
    time step ``dt`` (s), with the dense compliance when ``contact``, and ``fc`` the array of its
    generalized contact forces (N, N.m): :class:`kernels.BodyArrays`, with the factors of the
    sub-step dt / nsub of a step recomputed around a contact event (the same arrays when nsub is 1).
    A body that is absent, or has no free DOF, is off (its arrays are placeholders of the right types)."""
    if body is None or body.nf == 0:
        z = np.zeros(1)
        i0 = np.zeros(0, np.int64)
        n = len(body.U) if body else 1
        return K.BodyArrays(
            on=False, Md=np.zeros((1, 1)), Kd=np.zeros((1, 1)), Dinv=_DUMMY_BLOCK, L=_DUMMY_BLOCK, LT=_DUMMY_BLOCK,
            g0=0, ng=0, f0=0, nf=0, alpha=0.0, beta=0.0,
            U=body.U if body else z, V=body.V if body else z.copy(), A=body.A if body else z.copy(),
            pres=body.pres if body else i0, pchan=body.pchan if body else i0, pslot=body.pslot if body else i0,
            Kinv=np.zeros((n, n)),  # nothing responds
            sup=np.zeros((0, 2, 1)), sup_lo=i0, cpl_i=np.zeros((2, 0), np.int64), cpl_v=np.zeros(0), fc=fc,
            mi=np.zeros((0, 5), np.int64), mKC=np.zeros((0, 2, 6, 6)), mb=np.zeros((0, 2, 6)), mF=np.zeros((0, 6)),
            loaded=False, fext=z, uext=z,
            fDinv=_DUMMY_BLOCK, fL=_DUMMY_BLOCK, fLT=_DUMMY_BLOCK, fKinv=np.zeros((n, n)), fuext=z,
        )  # fmt: skip
    Dinv, L, LT, inv = body.factors(dt, contact)
    uext = body.load_response(dt) if body.loaded else np.zeros(1)
    fine = (Dinv, L, LT, inv, uext)
    if nsub > 1:
        fine = (*body.factors(dt / nsub, contact), body.load_response(dt / nsub) if body.loaded else uext)
    return K.BodyArrays(
        on=True, Md=body.Md, Kd=body.Kd, Dinv=Dinv, L=L, LT=LT, g0=body.g0, ng=body.ng, f0=body.f0, nf=body.nf,
        alpha=body.alpha, beta=body.beta, U=body.U, V=body.V, A=body.A, pres=body.pres, pchan=body.pchan,
        pslot=body.pslot, Kinv=inv, sup=body.sup, sup_lo=body.sup_lo, cpl_i=body.cpl_i, cpl_v=body.cpl_v, fc=fc,
        mi=body.mi, mKC=body.mKC, mb=body.mb, mF=body.mF,
        loaded=body.loaded, fext=body.f if body.loaded else np.zeros(1), uext=uext,
        fDinv=fine[0], fL=fine[1], fLT=fine[2], fKinv=fine[3], fuext=fine[4],
    )  # fmt: skip
