"""The buckling load of a body as built: the lowest compression its supports, isolators and clips
carry, and the refusal of a tension above it.

The casing's compression P (the cable's tension) softens it by its geometric stiffness,
K = K_E - P K_G1 (K_G1 the geometric stiffness of a unit tension, element_beam.py). On the
constrained structure, K_E is the beam's elastic stiffness on its free DOFs plus the static
stiffness K6 of every isolator and clip joining a node to its (prescribed) support node
(structure/mount_element.py, the same augmented system the modes and the time domain see). The
body buckles at the smallest P that makes K singular: the generalised eigenproblem

    K_G1 phi = mu K_E phi,        P_cr = 1 / mu_max  (mu_max > 0; none: P_cr = inf).

For a straight body this is Euler's load of its supports (clamped-clamped 4 pi^2 EI / L^2,
clamped-free pi^2 EI / (4 L^2), pinned-pinned pi^2 EI / L^2, to the discretisation's h^4 error);
for the routed casing in its isolators and clips it is the linearised buckling load of the curved,
elastically supported casing, which no closed form gives.

K_E is positive definite only when the supports hold every rigid motion of the body. A body held
by springs alone can leave some free (a mount of zero stiffness in a direction): the rigid motions
are the null space of K_E, found exactly and explicitly from the mounts' stiffness on the six
rigid motions (structure/support_check.py). When the compression does work on one of them
(K_G1 Phi not 0: a rotation about an axis across the body) it is a mechanism, P_cr = 0: any
compression moves it, reported as one. When it does none (K_G1 Phi = 0 to rounding, UNDRIVEN: a
twist about a straight body's own axis, a translation) both K_E and K_G1 vanish on Phi and the
pencil is solved on the complement of Phi (Q^T K_E Q, Q^T K_G1 Q, Q an orthonormal basis of it),
where K_E is positive definite: the load of the other motions, every free one named beside it. Then
LAPACK's
symmetric-definite solver (scipy.linalg.eigh, a Cholesky factor of K_E) gives the pencil; should
that factor fail on rounding (mounts soft beside the beam), the general QZ solver
(scipy.linalg.eig on (K_E, K_G1)) gives its finite positive eigenvalues instead.

Below P_cr, and only below it, K is positive definite, which is what the check at every assembly
tests (a banded Cholesky factorisation, ~0.2 ms); the load itself, where its mode is largest and
the supports assumed, are computed for the refusal's message and for ``cablecasing static`` and
``cablecasing geometry`` (:func:`buckling`). The load of a model's body (at its reference
modulus) is ``cc.body_buckling`` (``timedomain.body_storage.body_buckling``): this module takes
the assembled body.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.linalg import cholesky_banded, eig, eigh

from ..errors import ModelError, plain
from ..model.model import Model
from .element_beam import geometric_stiffness, transformation


@dataclass(frozen=True)
class Buckling:
    """A body's lowest buckling load under the compression it carries (SI units).

    body: "casing" or "cable"; load: the critical compression P_cr (N; inf when no compression
    buckles it, 0 for a mechanism that any compression moves); at: the arc length (m from end A)
    where the buckling mode's lateral displacement is largest (None without a mode); supports: the
    supports, isolators and clips assumed, in words; mechanism: the rigid motion the supports leave
    free and the compression drives, in words, or None; undriven: the rigid motions the supports
    leave free when the compression drives none of them (a twist about a straight body's own axis;
    the three translations of rotation-only isolators), every one in words (the basis
    ``support_check.free_motions`` names, joined: "a translation along [1, 0, 0], a translation
    along [0, 1, 0] and a translation along [0, 0, 1]"), or None (the load is then that of the
    other motions)."""

    body: str
    load: float
    at: float | None
    supports: str
    mechanism: str | None = None
    undriven: str | None = None

    def as_dict(self) -> dict:
        """The JSON form: ``load_N`` (None for inf, 0 for a mechanism), ``at_m``, ``supports``,
        ``mechanism``, and ``free_motion`` (the rigid motions left free that the compression does not
        drive, every one in words, as ``undriven``) only when there are some."""
        load = None if not np.isfinite(self.load) else float(self.load)
        out = {"load_N": load, "at_m": self.at, "supports": self.supports, "mechanism": self.mechanism}
        if self.undriven:
            out["free_motion"] = self.undriven
        return out

    def text(self) -> str:
        """One line: the load, where its mode is, the supports assumed."""
        if self.mechanism:
            return (
                f"{self.body}: buckles under any compression (buckling load 0 N), {self.mechanism} "
                f"(supports: {self.supports})"
            )
        free = (
            f"; free in {self.undriven}, on which the compression does no work (the load is that of the other motions)"
            if self.undriven
            else ""
        )
        if not np.isfinite(self.load):
            return f"{self.body}: no compression buckles it (supports: {self.supports}){free}"
        return (
            f"{self.body}: buckles under a compression of {self.load:.4g} N, its mode largest at s = {self.at:.4g} m "
            f"(supports: {self.supports}){free}"
        )


def unit_geometric_stiffness(system) -> sp.csr_matrix:
    """K_G1 (N/m, N, N.m per unit of axial force) of ``system``: its geometric stiffness of a unit
    tension, K_G / N0 of a prestressed body, built element by element otherwise."""
    if system.N0 != 0.0:
        return system.K_G / system.N0
    cl, sec = system.centerline, system.section
    n = system.ndof
    rows, cols, vals = [], [], []
    for e in range(cl.n_elements):
        T = transformation(cl.frames[e])
        G = T.T @ geometric_stiffness(cl.lengths[e], 1.0, sec.A, sec.Ip) @ T
        dofs = np.arange(6 * e, 6 * e + 12)
        r, c = np.meshgrid(dofs, dofs, indexing="ij")
        rows.append(r.ravel())
        cols.append(c.ravel())
        vals.append(G.ravel())
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))


def supports_text(system) -> str:
    """The supports of ``system`` in words: each end clamped, free or an isolator with its
    translational (N/m) and rotational (N.m/rad) stiffness [axial, lateral_1, lateral_2], then the
    clips' arc lengths (m) and translational stiffness."""
    parts = []
    for s in ("A", "B"):
        m = system.mount_of_support(s)
        if m is None:
            parts.append(f"{s} {system.spec.supports[s]}")
        else:
            k, kr = system.mounts[m].local_stiffness()
            parts.append(f"{s} isolator k = {_short(k)} N/m, k_rot = {_short(kr)} N.m/rad")
    clips = [m for m in system.mounts if m.support is None]
    if clips:
        ks = {_short(m.local_stiffness()[0]) for m in clips}
        stiff = f", k = {ks.pop()} N/m" if len(ks) == 1 else ""
        parts.append(f"clips at s = {', '.join(f'{m.at:.4g}' for m in clips)} m{stiff}")
    return "; ".join(parts)


def _short(v):
    """A stiffness as given: one number when its three agree (to rounding), else the three."""
    v = np.atleast_1d(np.asarray(v, dtype=float))
    if np.allclose(v, v[0], rtol=1e-9, atol=0.0):
        return f"{v[0]:.3g}"
    return "[" + ", ".join(f"{x:.3g}" for x in v) + "]"


def _free_blocks(system):
    """(K_E, K_G1) on the free DOFs of the augmented system, K_E with the mounts' static K6."""
    KE = system.augmented(system.K_E if system.K_E is not None else system.K, [m.K6 for m in system.mounts])
    KG = system.augmented(unit_geometric_stiffness(system))
    f = system.free
    return KE[np.ix_(f, f)], KG[np.ix_(f, f)]


def buckling(system) -> Buckling:
    """The lowest buckling load of ``system`` (an assembled
    :class:`~cablecasing_core.structure.assembly.BodySystem`, any prestress) with its real
    supports, isolators and clips: the generalised eigenproblem K_G1 phi = mu K_E phi on the
    constrained structure (module docstring), P_cr = 1 / mu_max (N). Anything else (a
    :class:`~cablecasing_core.Model`: ``cc.body_buckling`` takes one) raises :class:`ModelError`
    naming ``system``."""
    from .assembly import BodySystem
    from .support_check import free_rigid

    if not isinstance(system, BodySystem):
        source = getattr(system, "source", None)
        raise ModelError(
            "system",
            plain(f"<Model {source}>") if isinstance(system, Model) else system,
            "must be an assembled body (structure.assembly.assemble_body(model, 'casing')); for a model, "
            "cc.body_buckling(model, 'casing') gives its buckling load",
        )

    text = supports_text(system)
    free, Phi, words = free_rigid(system)  # (Phi orthonormal: the null space of K_E)
    KE, KG = _free_blocks(system)  # (dense: BodySystem.augmented)
    undriven, Q = None, None
    if free is not None:
        if _drives(KG, Phi):
            # named: the free motion the compression drives most (K_G1's largest response among them),
            # not the first free one (a translation along the axis, on which it does no work)
            driven = np.linalg.svd(KG @ Phi)[2][0]
            return Buckling(system.name, 0.0, None, text, mechanism=f"it is free to move: {words(driven)}")
        # The compression does no work on the free motions (a twist about a straight body's own axis,
        # a translation): K_E and K_G1 both vanish on them, and the pencil is solved on the rest.
        undriven = free
        Q = np.linalg.qr(Phi, mode="complete")[0][:, Phi.shape[1] :]
        KE, KG = Q.T @ KE @ Q, Q.T @ KG @ Q
    try:
        mu, phi = eigh(KG, KE, check_finite=False)  # (all of them: LAPACK's subset driver is slower here)
        k = int(np.argmax(mu))
        mu_max, mode = float(mu[k]), phi[:, k]
    except np.linalg.LinAlgError:  # K_E positive definite but its Cholesky factor fails on rounding
        w, v = eig(KE, KG, check_finite=False)  # QZ: P = alpha / beta, infinite where K_G1 is singular
        ok = np.isfinite(w) & (np.abs(w.imag) <= 1e-8 * np.abs(w.real)) & (w.real > 0.0)
        if not ok.any():
            return Buckling(system.name, float("inf"), None, text, undriven=undriven)
        k = np.flatnonzero(ok)[np.argmin(w.real[ok])]
        mu_max, mode = 1.0 / float(w.real[k]), v[:, k].real
    if not mu_max > 0.0:
        return Buckling(system.name, float("inf"), None, text, undriven=undriven)
    if Q is not None:
        mode = Q @ mode
    return Buckling(system.name, 1.0 / mu_max, _largest_lateral(system, mode), text, undriven=undriven)


#: |K_G1 Phi| below this fraction of max|K_G1| (Phi's columns of unit norm) is no work of the
#: compression on the free rigid motions Phi: exact rigid motions leave rounding alone (~1e-15 of
#: the entries), a rotation about an axis across the body ~1e-2 or more (1 / (number of elements)).
UNDRIVEN = 1e-8


def _drives(KG, Phi):
    """Whether the geometric stiffness KG (free DOFs) does work on any of the free rigid motions
    Phi (orthonormal columns): |KG Phi| above UNDRIVEN of max|KG|."""
    scale = np.abs(KG).max(initial=0.0)
    return bool(np.abs(KG @ Phi).max(initial=0.0) > UNDRIVEN * scale)


def buckling_load(system) -> float:
    """The critical compression P_cr (N) of ``system`` as built: :func:`buckling`'s load (inf when
    no compression buckles it, 0 for a mechanism)."""
    return buckling(system).load


def _largest_lateral(system, mode):
    """Arc length (m) of the node where the mode's (free DOFs, augmented) displacement normal to
    the centerline's tangent is largest."""
    u = np.zeros(system.n_augmented)
    u[system.free] = mode
    d = u[: system.ndof].reshape(-1, 6)[:, :3]
    t = system.centerline.tangents
    lateral = d - np.einsum("ij,ij->i", d, t)[:, None] * t
    return float(system.centerline.s[int(np.argmax(np.linalg.norm(lateral, axis=1)))])


def is_positive_definite(system) -> bool:
    """Whether the tangent stiffness of ``system`` on its free DOFs, with its mounts' K6, is
    positive definite (its compression below the buckling load): a banded Cholesky factorisation
    (half-bandwidth 11: a mount joins a node to its prescribed support) succeeds, ~0.2 ms instead
    of an eigenproblem."""
    A = system.K_blocks[0]
    n, b = A.shape[0], 11
    ab = np.zeros((b + 1, n))
    for k in range(b + 1):  # upper form: ab[b - k, j] = A[j - k, j]
        j = np.arange(k, n)
        ab[b - k, j] = A[j - k, j]
    try:
        cholesky_banded(ab, check_finite=False)
    except np.linalg.LinAlgError:
        return False
    return True


def check_compression(system) -> None:
    """Refuse (ModelError naming loads.cable_tension) a body whose compression -N0 reaches its
    buckling load as built; the message gives the load, where its mode is largest and the supports
    assumed. A mechanism has none (it says what moves); a load of 0 N or none found on a body
    whose tangent stiffness is not positive definite comes of a bending stiffness too small for
    double precision (casing.E = 5e-324 Pa: K_E underflows): the message then names that stiffness
    (``<body>.E``, and ``<body>.I`` when set) and its value."""
    P = -system.N0
    if P <= 0.0 or is_positive_definite(system):
        return
    b = buckling(system)
    name = system.name
    if b.mechanism:
        allowed = (
            f"must be below the {name}'s buckling load, but it has none: {b.mechanism}, so any compression moves it "
            f"(supports: {b.supports})"
        )
    elif b.undriven and P < b.load:  # (refused before by check_supported; a system assembled by hand)
        allowed = (
            f"needs the {name} held against every rigid motion: it is free in {b.undriven}, on which the compression "
            f"does no work (its buckling load {b.load:.4g} N is that of the other motions), but its tangent "
            f"stiffness is singular there; give the isolators a stiffness in that direction, however small "
            f"(supports: {b.supports})"
        )
    elif np.isfinite(b.load) and b.load > 0.0:
        allowed = (
            f"must be below the {name}'s buckling load {b.load:.4g} N (the compression it carries, equal to the "
            f"cable's tension, at which its tangent stiffness K_E + K_G turns singular; its mode largest at "
            f"s = {b.at:.4g} m; supports: {b.supports})"
        )
    else:
        found = "it is 0 N" if b.load == 0.0 else "none is found"
        allowed = (
            f"must be below the {name}'s buckling load, but {found} for its bending stiffness "
            f"({_stiffness(system)}): its tangent stiffness K_E + K_G is singular under any compression, as a "
            f"stiffness too small for double precision makes it; give {name}.E the {name}'s modulus "
            f"(supports: {b.supports})"
        )
    raise ModelError("loads.cable_tension", P, allowed)


def _stiffness(system) -> str:
    """The keys that set ``system``'s bending stiffness EI, with their values: ``<body>.E = … Pa``
    (a table by its first value), and ``<body>.I = … m4`` when the model sets the second moment."""
    spec, name = system.spec, system.name
    text = f"{name}.E = {_number(spec.E_ref)} Pa" + (" (its table's first value)" if spec.frequency_dependent else "")
    if spec.I_override is not None:
        text += f", {name}.I = {_number(spec.I_override)} m4"
    return text


def _number(x) -> str:
    """``x`` in the shortest of its %.6g and repr forms that gives it back (5e-324, 5e+09)."""
    x = float(x)
    forms = [f for f in (f"{x:.6g}", repr(x)) if float(f) == x]
    return min(forms, key=len) if forms else repr(x)
