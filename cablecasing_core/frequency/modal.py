"""Natural frequencies and mode shapes of one body with its supports.

The undamped eigenproblem K_ff phi = omega^2 M_ff phi on the free DOFs of Eq. (13), solved densely
with LAPACK (scipy.linalg.eigh; a body has a few hundred DOFs, where a dense solver is faster than
a sparse iterative one and returns every mode). Modes are mass-normalised. K is the tangent
stiffness K_E + K_G of a prestressed body (an installed model: the cable's tension stiffens it, the
casing's compression softens it; structure/assembly.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from scipy.linalg import eigh

from ..model.limits import check_dense_eigenproblem
from ..model.validators import Choice, integer
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
        return np.sqrt(np.clip(self.lam, 0.0, None)) / (2.0 * np.pi)


def modal_basis(system: BodySystem) -> ModalBasis:
    """Full :class:`ModalBasis` of an assembled :class:`~cablecasing_core.structure.assembly.BodySystem`."""
    Kff, Mff = system.K_blocks[0], system.M_blocks[0]
    check_dense_eigenproblem(Kff.shape[0], system.ndof // 6 - 1)  # (before the work: model/limits.py)
    lam, phi = eigh(Kff, Mff)
    return ModalBasis(system=system, lam=lam, phi=phi)


def natural_frequencies(model: Model, body: str, count: int | None = None) -> np.ndarray:
    """Natural frequencies (Hz, ascending) of ``body`` ("casing" or "cable") with its supports.

    With a frequency-dependent modulus E(f) each frequency solves f = f_ref sqrt(E(f) / E_ref)
    (K scales with E), iterated to a relative change below 1e-12; for a prestressed body, whose
    geometric stiffness does not scale with E, mode i solves f_i = i-th frequency of
    (E(f_i) / E_ref K_E + K_G, M), iterated alike.
    """
    return modes(model, body, count)[0]


def modes(model: Model, body: str, count: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(frequencies in Hz, mode shapes) of ``body``; shapes are (ndof, count) arrays over all DOFs
    (zero at prescribed DOFs), mass-normalised for the reference modulus."""
    Choice(*model.bodies)("body", body)
    if count is not None:
        integer("count", count, 1)
    basis = modal_basis(assemble_body(model, body))
    spec = basis.system.spec
    n = len(basis.lam) if count is None else min(count, len(basis.lam))
    f = basis.frequencies_hz[:n].copy()
    if spec.frequency_dependent and basis.system.prestressed:
        f = _prestressed_frequencies(basis.system, f)
    elif spec.frequency_dependent:
        f_ref = f.copy()
        for _ in range(200):
            f_new = f_ref * np.sqrt(spec.modulus(f) / spec.E_ref)
            done = np.allclose(f_new, f, rtol=1e-12, atol=0.0)
            f = f_new
            if done:
                break
    shapes = np.zeros((basis.system.ndof, n))
    shapes[basis.system.free] = basis.phi[:, :n]
    return f, shapes


def _prestressed_frequencies(system, f):
    """Frequencies (Hz) of a prestressed body with E(f): mode i at the modulus of its own frequency,
    f_i = g_i(f_i), g_i(f) = the i-th frequency of (E(f)/E K_E + K_G, M), solved from the reference
    ``f`` by the secant method on g_i(f) - f (|g_i'| is small, ~f E'/(2 E): a few eigenproblems per
    mode instead of a fixed-point iteration's dozen), to a relative change below 1e-12."""
    spec = system.spec
    f = f.copy()
    KE, KG, M = (system.blocks(A)[0] for A in (system.K_E, system.K_G, system.M))

    def g(i, fi):
        s = float(spec.modulus(fi)) / system.E
        lam = eigh(s * KE + KG, M, eigvals_only=True)[i]  # (all: LAPACK's subset driver is slower here)
        return np.sqrt(max(lam, 0.0)) / (2.0 * np.pi)

    for i in range(len(f)):
        x0, x1 = f[i], g(i, f[i])
        r0 = x1 - x0
        for _ in range(50):
            if abs(x1 - x0) <= 1e-12 * abs(x1):
                break
            r1 = g(i, x1) - x1
            x0, x1, r0 = x1, (x1 - r1 * (x1 - x0) / (r1 - r0)) if r1 != r0 else x1 + r1, r1
        f[i] = x1
    return f
