"""Natural frequencies and mode shapes of one body with its supports.

The undamped eigenproblem K_ff phi = omega^2 M_ff phi on the free DOFs of Eq. (13), solved densely
with LAPACK (scipy.linalg.eigh; a body has a few hundred DOFs, where a dense solver is faster than
a sparse iterative one and returns every mode). Modes are mass-normalised.
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
    (K scales with E), iterated to a relative change below 1e-12.
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
    if spec.frequency_dependent:
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
