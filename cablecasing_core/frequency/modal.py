"""Natural frequencies and mode shapes of one body with its supports.

The undamped eigenproblem K_ff phi = omega^2 M_ff phi on the free DOFs of Eq. (13), solved densely
with LAPACK (scipy.linalg.eigh; a body has a few hundred DOFs, where a dense solver is faster than
a sparse iterative one and returns every mode). Modes are mass-normalised. K is the tangent
stiffness K_E + K_G of a prestressed body (an installed model: the cable's tension stiffens it, the
casing's compression softens it; structure/assembly.py), with the springs K6 of its isolators and
clips. A frequency-dependent modulus E(f) or mount stiffness k_scale(f) makes K depend on the
frequency: each mode then solves its own frequency (:func:`natural_frequencies`).

The frequency domain (these modes and the TRFAM) is of each body alone on its supports and mounts:
the contact between the cable and the casing belongs to the time domain. An installed model's
bodies carry the axial prestress of ``loads.cable_tension`` (K_G) about their route, not its static
state: gravity's sag, a straight cable's bending into the route and the contact forces on the wall
(``static_state``) are not in it. :func:`frequency_domain_scope` says so in one line for a model.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from scipy.linalg import eigh, eigvalsh
from scipy.optimize import brentq

from ..errors import NOT_SHOWN, ModelError, ModelWarning
from ..model.limits import check_dense_eigenproblem
from ..model.model import at_frequency
from ..model.validators import Choice, check_model, contact_in_force, integer, number
from ..structure.assembly import assemble_body

if TYPE_CHECKING:
    from ..model import Model
    from ..structure.assembly import BodySystem


@dataclass(frozen=True)
class ModalBasis:
    """Eigenvalues ``lam`` (rad^2/s^2, ascending) and mass-normalised modes ``phi`` on the free DOFs
    of a body assembled with modulus ``E`` (Pa)."""

    system: object
    lam: np.ndarray
    phi: np.ndarray

    @property
    def frequencies_hz(self):
        """The natural frequencies (Hz, ascending), sqrt(lam) / (2 pi); a negative round-off
        eigenvalue of a rigid-body mode gives 0."""
        return np.sqrt(np.clip(self.lam, 0.0, None)) / (2.0 * np.pi)


#: The shift of the inverted eigenproblem, rad^2/s^2: (2 pi 1 Hz)^2, below the lowest flexible mode
#: of a cable system and far above the round-off of its rigid-body modes (see :func:`modal_basis`).
SHIFT = (2.0 * np.pi) ** 2


def modal_basis(system: BodySystem) -> ModalBasis:
    """Full :class:`ModalBasis` of an assembled :class:`~cablecasing_core.structure.assembly.BodySystem`.

    Solved inverted and shifted, M_ff psi = mu (K_ff + s M_ff) psi, lambda = 1/mu - s (s =
    :data:`SHIFT`): a dense eigensolver gives each eigenvalue to about eps times the largest, and
    the largest of (K, M) grows with the stiffest spring (an isolator of 1e12 N.m/rad on an end
    node's small rotary inertia: ~1e20 rad^2/s^2, which moved the casing's first modes by up to
    27 %), while the largest of the inverted pencil is 1/s: the low modes, those a user reads, come
    to relative accuracy (eps lambda_i / s). Where K_ff + s M_ff is not positive definite (a
    prestress beyond buckling, which the callers refuse), the direct pencil (K_ff, M_ff)."""
    Kff, Mff = system.K_blocks[0], system.M_blocks[0]
    check_dense_eigenproblem(Kff.shape[0], system.ndof // 6 - 1)  # (before the work: model/limits.py)
    try:
        mu, psi = eigh(Mff, Kff + SHIFT * Mff)
    except np.linalg.LinAlgError:
        lam, phi = eigh(Kff, Mff)
        return ModalBasis(system=system, lam=lam, phi=phi)
    mu, psi = mu[::-1], psi[:, ::-1]  # (ascending lambda)
    return ModalBasis(system=system, lam=1.0 / mu - SHIFT, phi=psi / np.sqrt(mu))


def frequency_domain_scope(model: Model) -> str | None:
    """One line on what the frequency domain (modes, TRFAM) leaves out of ``model``, or None when it
    leaves out nothing the model has: the contact between the cable and the casing (a model with
    both bodies and ``contact.enabled``: each body is alone on its supports and mounts), and an
    installed model's static state (its bodies carry the axial prestress of ``loads.cable_tension``
    about their route; the static deflection and contact forces are not in it)."""
    check_model(model)
    contact = contact_in_force(model)
    installed = model.installed and "cable" in model.bodies
    if not (contact or installed):
        return None
    text = "each body alone on its supports and mounts" + (": no contact between the cable and the casing" * contact)
    if installed:
        T = model.loads["cable_tension"]
        text += (
            f"; with the prestress of loads.cable_tension = {T:g} N about the route" if T > 0 else "; about the route"
        )
        text += f", not the static state's deflection{' and contact forces' * contact} (cablecasing static)"
    return text


def natural_frequencies(model: Model, body: str, count: int | None = None) -> np.ndarray:
    """Natural frequencies (Hz, ascending) of ``body`` ("casing" or "cable") of ``model`` (a
    :class:`~cablecasing_core.Model`; anything else, a dict or a file's name, raises a ModelError
    naming ``model``) with its supports: the undamped eigenproblem of Eq. (13) on the free DOFs.

    The body alone: no contact with the other body (that is the time domain's). An installed
    model's body carries the axial prestress of ``loads.cable_tension`` (K = K_E + K_G: the cable
    stiffened by its tension, the casing softened by its compression) about its route; gravity's
    sag, a straight cable's bending into the route and the static state's contact forces are not
    in it (:func:`frequency_domain_scope`).

    ``count`` (None: all) is the number of modes wanted; a body has one mode per free degree of
    freedom (:func:`mode_count`), and a larger ``count`` returns all of them with a
    :class:`~cablecasing_core.errors.ModelWarning` that says how many there are.

    With a frequency-dependent stiffness, a modulus table E(f) (the dynamic modulus E_d(omega) of
    the paper's complex modulus, Section 2, identified against frequency in Section 3.1, Figs. 8-9)
    or a mount's table k_scale(f) (``structure/mount_element.py``), mode i solves its own fixed
    point f_i = g_i(f_i), g_i(f) the i-th frequency of (K(f), M) on the free DOFs of Eq. (13) with

        K(f) = E(f) / E_ref K_E + K_G + sum over the mounts of k_scale(f) K6

    (K_E is linear in E, Eq. 6; the geometric stiffness K_G of a prestress and the mounts' springs
    are not; k_scale = 1 for a mount without a table): the frequency at which the undamped TRFAM
    (damping "none", which applies E(f) and k_scale(f) at each frequency) has its resonance. It is
    solved by the secant method from the reference frequency (Brent's method on the bracket of the
    tables' extreme values if the secant fails) until a step changes f_i by less than 1e-10 f_i, or
    changes f_i^2 by less than the eigensolver's round-off (16 eps lambda_max); a ModelError naming
    the table if it does not converge. Without a prestress or mounts K(f) = E(f) / E_ref K, so each
    frequency is f_ref sqrt(E(f) / E_ref) (no eigenproblem per step). A constant modulus with mounts
    without tables needs no iteration: those frequencies are the reference eigenproblem's.
    """
    return _modes(model, body, count)[0]


def modes(model: Model, body: str, count: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(frequencies in Hz, as :func:`natural_frequencies`, and mode shapes) of ``body`` (Eq. 13's
    free DOFs; ``model`` a :class:`~cablecasing_core.Model`, else a ModelError naming it); shapes are
    (ndof, count) arrays over all DOFs (zero at prescribed DOFs), the mass-normalised modes (phi^T M
    phi = 1: m kg^-1/2 at a translation DOF, rad kg^-1/2 at a rotation DOF) of the reference
    stiffness (the reference modulus E_ref, the mounts' ``stiffness`` K6). A ``count`` beyond the
    body's modes returns all of them and warns (:class:`ModelWarning`)."""
    return _modes(model, body, count)


def _modes(model, body, count):
    """:func:`modes`, called by it and by :func:`natural_frequencies` (its warning points at their caller)."""
    check_model(model)
    Choice(*model.bodies)("body", body)
    if count is not None:
        integer("count", count, 1)
    basis = modal_basis(assemble_body(model, body))
    n = len(basis.lam) if count is None else min(count, len(basis.lam))
    if count is not None and count > n:
        warnings.warn(
            ModelWarning(
                f"count = {count}: the {body} of {model.source} has only {n} modes (one per free degree of "
                f"freedom of its {model.geometry['n_elements']} elements); all {n} are returned"
            ),
            stacklevel=3,
        )
    return _first_modes(basis, n)


def _first_modes(basis, n):
    """(frequencies in Hz, shapes on all DOFs) of the first ``n`` modes of a :class:`ModalBasis`, each
    at its own frequency where the modulus or a mount's stiffness depends on it."""
    system = basis.system
    spec = system.spec
    f = basis.frequencies_hz[:n].copy()
    tabled = any(m.table is not None for m in system.mounts)
    if spec.frequency_dependent and not system.prestressed and not system.mounts:
        f = _scaled_frequencies(system, f)
    elif spec.frequency_dependent or tabled:
        f = _own_frequencies(system, basis.lam, n)
    shapes = np.zeros((system.ndof, n))
    shapes[system.free] = basis.phi[:, :n]
    return f, shapes


def mode_count(model: Model, body: str) -> int:
    """The number of modes of ``body``: its free degrees of freedom with its supports (and its
    mounts' nodes), the most that :func:`natural_frequencies` returns (no eigenproblem solved)."""
    Choice(*model.bodies)("body", body)
    return len(assemble_body(model, body).free)


def modes_up_to(model: Model, body: str, f_max: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`modes` of ``body`` whose frequency is at most ``f_max`` (Hz): (frequencies in Hz, shapes).
    Asks for modes in growing counts until one lies above ``f_max`` or the body has no more."""
    return _modes_up_to(model, body, f_max)[:2]


def _modes_up_to(model, body, f_max):
    """:func:`modes_up_to` and the assembled body (frequencies in Hz, shapes, BodySystem): one
    eigenproblem; the modes' own frequencies (E(f), mount tables) are found for growing counts
    until one lies above ``f_max`` or the body has no more."""
    number("f_max", f_max, gt=0, unit="Hz")
    Choice(*model.bodies)("body", body)
    basis = modal_basis(assemble_body(model, body))
    n_all = len(basis.lam)
    count = 16
    while True:
        f, shapes = _first_modes(basis, min(count, n_all))
        if len(f) == n_all or f[-1] > f_max:
            keep = f <= f_max
            return f[keep], shapes[:, keep], basis.system
        count *= 4


def frequencies_up_to(model: Model, body: str, f_max: float) -> np.ndarray:
    """The natural frequencies (Hz, as :func:`natural_frequencies`) of ``body`` up to ``f_max`` Hz."""
    return modes_up_to(model, body, f_max)[0]


#: Convergence of a mode's frequency: a step of the iteration changes f_i by less than RTOL f_i.
RTOL = 1e-10
#: The round-off of a computed eigenvalue, in units of eps lambda_max (steps within it have converged).
ROUNDOFF = 16.0
MAX_SECANT = 30
MAX_BRENT = 200


def _scaled_frequencies(system, f_ref):
    """Frequencies (Hz) of a body whose whole stiffness is E(f) / E_ref K: f_i = f_ref,i sqrt(E(f_i) /
    E_ref), a scalar equation per mode."""
    spec = system.spec
    E = np.asarray(spec.E, dtype=float)[:, 1]
    bracket = np.sqrt(np.array([E.min(), E.max()]) / system.E)
    out = np.empty_like(f_ref)
    for i, fr in enumerate(f_ref):
        g = lambda x, fr=fr: fr * np.sqrt(float(spec.modulus(x)) / system.E)  # noqa: E731
        out[i] = _fixed_point(g, fr, lambda fr=fr: tuple(fr * bracket), 0.0, lambda i=i: _not_converged(system, i))
    return out


def _own_frequencies(system, lam_ref, n):
    """The first ``n`` frequencies (Hz) of a body with a prestress or mounts and a frequency table:
    f_i = g_i(f_i), g_i(f) the i-th frequency of (K(f), M) (see :func:`natural_frequencies`), each
    from its reference value sqrt(lam_ref[i]) / 2 pi. K(f) = K_0 + sum_j c_j(f) K_j on the free
    DOFs, each pencil solved inverted and shifted as :func:`modal_basis` does (M psi = mu (K(f) +
    s M) psi), so that a stiff mount's largest eigenvalue does not swamp the low ones."""
    spec = system.spec
    Mff = system.M_blocks[0]

    def springs(selected):  # the free-free block of the springs K6 of the mounts ``selected``
        K6 = [mt.K6 if j in selected else np.zeros((6, 6)) for j, mt in enumerate(system.mounts)]
        return system.blocks(system.augmented(np.zeros((system.ndof, system.ndof)), K6))[0]

    tabled = [j for j, mt in enumerate(system.mounts) if mt.table is not None]
    others = [j for j in range(len(system.mounts)) if j not in tabled]
    K0 = system.blocks(system.K_G)[0] + springs(others) + SHIFT * Mff  # the part that does not scale
    parts = []  # (c_j(f), (min c_j, max c_j), K_j)
    if spec.frequency_dependent:
        E = np.asarray(spec.E, dtype=float)[:, 1] / system.E
        parts.append((lambda x: float(spec.modulus(x)) / system.E, (E.min(), E.max()), system.blocks(system.K_E)[0]))
    else:
        K0 = K0 + system.blocks(system.K_E)[0]
    for j in tabled:
        t = system.mounts[j].table
        scale = lambda x, t=t: float(at_frequency(t, x))  # noqa: E731 (the k_scale of Mount.dynamic_stiffness)
        parts.append((scale, (t[:, 1].min(), t[:, 1].max()), springs([j])))
    c_max = max([1.0] + [hi for _, (_, hi), _ in parts])
    tol_lam = ROUNDOFF * np.finfo(float).eps * max(lam_ref[-1], 0.0) * c_max

    cache = {}  # scales -> every eigenvalue: the modes above the tables' last rows share one matrix

    def frequency(i, c):  # the i-th frequency (Hz) at the scales c
        key = tuple(c)
        if key not in cache:
            K = K0 + sum(cj * Kj for cj, (_, _, Kj) in zip(c, parts))
            cache[key] = 1.0 / eigvalsh(Mff, K, check_finite=False)[::-1] - SHIFT
        return np.sqrt(max(cache[key][i], 0.0)) / (2.0 * np.pi)

    f = np.sqrt(np.clip(lam_ref[:n], 0.0, None)) / (2.0 * np.pi)
    for i in range(n):
        f[i] = _fixed_point(
            lambda x, i=i: frequency(i, [c(x) for c, _, _ in parts]),
            f[i],
            lambda i=i: tuple(frequency(i, [r[k] for _, r, _ in parts]) for k in (0, 1)),
            tol_lam,
            lambda i=i: _not_converged(system, i),
        )
    return f


def _fixed_point(g, x0, bracket, tol_lam, fail):
    """The solution f >= 0 of f = g(f) near ``x0`` (Hz): the secant method on g(f) - f, or, when it
    does not converge in MAX_SECANT steps, Brent's method on ``bracket()`` = (lo, hi), g's values at
    the tables' extremes (g(f) lies between them for every f, as the scales multiply positive
    semi-definite parts: so g(lo) >= lo and g(hi) <= hi). A step has converged when it changes f by
    less than RTOL f or (2 pi f)^2 by less than ``tol_lam`` (the eigenvalue's round-off, rad^2/s^2).
    ``fail()`` raises the error of a solution not found."""

    def close(a, b):
        return abs(a - b) <= RTOL * max(a, b) or (2.0 * np.pi) ** 2 * abs(a * a - b * b) <= tol_lam

    x1 = g(x0)
    if close(x0, x1):
        return x1
    r0 = x1 - x0
    for _ in range(MAX_SECANT):
        r1 = g(x1) - x1
        x2 = x1 - r1 * (x1 - x0) / (r1 - r0) if r1 != r0 else x1 + r1
        if not np.isfinite(x2) or x2 < 0.0:
            break
        x0, x1, r0 = x1, x2, r1
        if close(x0, x1):
            return x1
    lo, hi = bracket()
    h = lambda x: g(x) - x  # noqa: E731
    if h(lo) <= 0.0:  # g(lo) >= lo but for round-off: lo is the solution
        return lo
    if h(hi) >= 0.0:
        return hi
    try:
        root, res = brentq(h, lo, hi, xtol=1e-12, rtol=RTOL, maxiter=MAX_BRENT, full_output=True, disp=False)
    except (ValueError, RuntimeError):
        res = None
    if res is None or not res.converged:
        fail()
    return root


def _not_converged(system, i):
    """Raise the ModelError of mode ``i`` (0-based) of ``system`` whose frequency was not found,
    naming its frequency tables."""
    keys = [f"{system.name}.E"] if system.spec.frequency_dependent else []
    for mt in system.mounts:
        if mt.table is not None:
            where = f"isolator.{mt.support}" if mt.support else f"clip[{mt.label[4:]}]"
            keys.append(f"{system.name}.{where}.table")
    raise ModelError(
        keys[0],
        NOT_SHOWN,
        f"mode {i + 1} of the {system.name}: no frequency f found at which the mode's frequency, with the "
        f"frequency tables ({', '.join(keys)}) at f, is f (to a relative {RTOL:g}); make the tables less steep",
    )
