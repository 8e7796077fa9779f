"""Rayleigh (proportional viscous) damping from identified modal damping ratios.

The paper's Eqs. (40)-(44): ``C = alpha M + beta K`` gives the i-th damping ratio
``zeta_i = alpha / (2 omega_i) + beta omega_i / 2`` (Eq. 41); stacking the identified modes gives
``Z = A c`` (Eqs. 42-43), solved in the least-squares sense ``c = A^+ Z`` (Eq. 44).

The pseudo-inverse is applied through ``numpy.linalg.lstsq`` (SVD) rather than by forming
``(A^T A)^-1 A^T`` literally: the two columns ``1/(2 omega)`` and ``omega/2`` differ by ``omega^2`` in
scale, so the normal equations square an already large condition number. Columns are scaled to
unit norm before solving for the same reason. With ``nonnegative=True`` the model file's
constraint ``alpha, beta >= 0`` is imposed by ``scipy.optimize.nnls`` (Lawson-Hanson).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import nnls

from ..errors import ModelError
from ..model.validators import array_1d, frequencies, number


@dataclass(frozen=True)
class RayleighFit:
    """Rayleigh factors ``alpha`` (1/s) and ``beta`` (s) of Eq. (40), with the data and the fit.

    ``residuals = zeta - zeta_fit`` (dimensionless), one per mode, in the input order.
    """

    alpha: float
    beta: float
    freqs_hz: np.ndarray
    zeta: np.ndarray
    zeta_fit: np.ndarray
    residuals: np.ndarray

    @property
    def rms_residual(self):
        return float(np.sqrt(np.mean(self.residuals**2)))


def rayleigh_zeta(freqs_hz: ArrayLike, alpha: float, beta: float) -> np.ndarray:
    """Damping ratios (dimensionless) of Rayleigh damping at natural frequencies ``freqs_hz`` (Hz), Eq. (41),
    with ``alpha`` (1/s) and ``beta`` (s)."""
    w = 2.0 * np.pi * frequencies("freqs_hz", freqs_hz)
    alpha, beta = number("alpha", alpha, unit="1/s"), number("beta", beta, unit="s")
    return alpha / (2.0 * w) + beta * w / 2.0


def rayleigh_matrix(freqs_hz: ArrayLike) -> np.ndarray:
    """The matrix ``A`` of Eqs. (42)-(43): rows ``[1 / (2 omega_i), omega_i / 2]`` (omega in rad/s) at
    natural frequencies ``freqs_hz`` (Hz)."""
    w = 2.0 * np.pi * frequencies("freqs_hz", freqs_hz)
    return np.column_stack([1.0 / (2.0 * w), w / 2.0])


def rayleigh_fit(
    freqs_hz: ArrayLike, zetas: ArrayLike, weights: ArrayLike | None = None, nonnegative: bool = False
) -> RayleighFit:
    """Least-squares Rayleigh factors from identified (natural frequency, damping ratio) pairs.

    Solves Eq. (42) ``zeta_i = alpha / (2 omega_i) + beta omega_i / 2`` for ``alpha`` (1/s) and
    ``beta`` (s) by Eq. (44) (pseudo-inverse; exact for two modes or for exactly Rayleigh data).

    Parameters
    ----------
    freqs_hz : array (m,)
        Natural frequencies (Hz), m >= 2, distinct.
    zetas : array (m,)
        Damping ratios (dimensionless).
    weights : array (m,) or None
        Optional positive weights of the residuals (e.g. 1 / standard error of each zeta).
    nonnegative : bool
        Constrain ``alpha, beta >= 0`` (what the model file accepts).

    Returns
    -------
    :class:`RayleighFit` with the factors and the residuals ``zeta - zeta_fit``.
    """
    f = array_1d("freqs_hz", freqs_hz, min_len=2)
    z = array_1d("zetas", zetas, min_len=2)
    if z.size != f.size:
        raise ModelError("zetas", f"{z.size} values", f"must have one damping ratio per frequency ({f.size})")
    if np.any(f <= 0):
        raise ModelError("freqs_hz", float(f[f <= 0][0]), "natural frequencies must be positive (Hz)")
    if np.unique(f).size < 2:
        raise ModelError("freqs_hz", f.tolist(), "needs at least two distinct natural frequencies")
    w = np.ones_like(f) if weights is None else array_1d("weights", weights, min_len=f.size)
    if w.size != f.size or np.any(w <= 0):
        raise ModelError("weights", weights, "must be one positive weight per frequency")
    A = rayleigh_matrix(f) * w[:, None]
    b = z * w
    scale = np.linalg.norm(A, axis=0)
    As = A / scale
    if nonnegative:
        c, _ = nnls(As, b)
    else:
        c = np.linalg.lstsq(As, b, rcond=None)[0]
    alpha, beta = c / scale
    zfit = rayleigh_zeta(f, alpha, beta)
    return RayleighFit(alpha=float(alpha), beta=float(beta), freqs_hz=f, zeta=z, zeta_fit=zfit, residuals=z - zfit)
