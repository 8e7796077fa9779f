"""Rayleigh (proportional viscous) damping from identified modal damping ratios.

The paper's Eqs. (40)-(44): ``C = alpha M + beta K`` gives the i-th damping ratio
``zeta_i = alpha / (2 omega_i) + beta omega_i / 2`` (Eq. 41); stacking the identified modes gives
``Z = A c`` (Eqs. 42-43), solved in the least-squares sense ``c = A^+ Z`` (Eq. 44).

The pseudo-inverse is applied through ``numpy.linalg.lstsq`` (SVD) rather than by forming
``(A^T A)^-1 A^T`` literally: the two columns ``1/(2 omega)`` and ``omega/2`` differ by ``omega^2`` in
scale, so the normal equations square an already large condition number. Columns are scaled to
unit norm before solving for the same reason. With ``nonnegative=True`` the model file's
constraint ``alpha, beta >= 0`` is imposed by ``scipy.optimize.nnls`` (Lawson-Hanson).

Close frequencies cannot separate ``alpha`` (the ``1/omega`` trend) from ``beta`` (the ``omega``
trend): for two modes at the ratio ``r = omega_2 / omega_1`` the scaled columns meet at an angle
whose cosine is ``2 r / (r^2 + 1)``, and the scaled matrix's condition number is
``sqrt((1 + cos) / (1 - cos)) = (r + 1) / (r - 1)`` (3 at r = 2, 21 at 1.1). A relative error of
the damping ratios reaches ``alpha`` and ``beta`` multiplied by up to that number, so above
:data:`MAX_CONDITION` (100: damping ratios identified to 1 % then leave the factors uncertain by up
to 100 %; two modes within 2 % of each other) a ModelWarning says so.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import nnls

from ..errors import ModelError, ModelWarning
from ..model.validators import array_1d, frequencies, number

#: Condition number of the scaled least-squares matrix above which alpha and beta are not separated
#: (module docstring: a 1 % error of the damping ratios may then change them by 100 %).
MAX_CONDITION = 100.0
#: Upper-tail probability of the residuals' chi-square (against ``zeta_sd``, on ``n - 2`` degrees of freedom)
#: below which :func:`rayleigh_fit` says the damping is not of Rayleigh form: exactly Rayleigh damping
#: ratios with honest standard deviations (the wavelet's are, 0.8-1.1 of the scatter) are warned about in
#: 1 % of records; the reduced chi-square it takes is 6.6 for 3 modes, 4.6 for 4, 3.0 for 7 (about the
#: "reduced chi-square above 4" of practice, but not a warning every twentieth exact record of 3 modes).
MISFIT_PROBABILITY = 0.01
#: Damping ratios above this are warned about: a fraction of critical damping this large is rare in a
#: structure, and damping given in per cent (1.2 for 1.2 %) makes alpha and beta 100 times too large.
ZETA_WARN = 0.3


@dataclass(frozen=True)
class RayleighFit:
    """Rayleigh factors ``alpha`` (1/s) and ``beta`` (s) of Eq. (40), with the data and the fit.

    ``residuals = zeta - zeta_fit`` (dimensionless), one per mode, in the input order. ``alpha_sd`` (1/s) and
    ``beta_sd`` (s) are the factors' standard deviations propagated from the damping ratios' (``zeta_sd`` of
    :func:`rayleigh_fit`; nan without them, and for a factor the nonnegative fit holds at its bound 0).
    ``reduced_chi2`` is the least ``sum(((zeta - zeta_R) / zeta_sd)^2) / (n - 2)`` any Rayleigh damping
    ``zeta_R`` leaves (the zeta_sd-weighted fit's): about 1 when the damping is of Rayleigh form within the
    damping ratios' noise, far above when it is not (nan without ``zeta_sd``, or for two modes, which any
    alpha and beta fit exactly).
    """

    alpha: float
    beta: float
    freqs_hz: np.ndarray
    zeta: np.ndarray
    zeta_fit: np.ndarray
    residuals: np.ndarray
    alpha_sd: float = float("nan")
    beta_sd: float = float("nan")
    reduced_chi2: float = float("nan")

    @property
    def rms_residual(self):
        """The RMS of ``residuals``, the fit's damping-ratio residuals (dimensionless)."""
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
    freqs_hz: ArrayLike,
    zetas: ArrayLike,
    weights: ArrayLike | None = None,
    nonnegative: bool = False,
    zeta_sd: ArrayLike | None = None,
) -> RayleighFit:
    """Least-squares Rayleigh factors from identified (natural frequency, damping ratio) pairs.

    Solves Eq. (41), stacked over the modes (Eq. 42), ``zeta_i = alpha / (2 omega_i) + beta omega_i / 2``
    for ``alpha`` (1/s) and ``beta`` (s) by Eq. (44) (pseudo-inverse; exact for two modes or for exactly Rayleigh data).

    Parameters
    ----------
    freqs_hz : array (m,)
        Natural frequencies (Hz), m >= 2, distinct.
    zetas : array (m,)
        Damping ratios (dimensionless fractions of critical damping), each in (0, 1); above
        :data:`ZETA_WARN` (0.3) a warning asks whether they are per cent.
    weights : array (m,) or None
        Optional positive weights of the residuals (e.g. 1 / standard error of each zeta).
    nonnegative : bool
        Constrain ``alpha, beta >= 0`` (what the model file accepts).
    zeta_sd : array (m,) or None
        Standard deviations of the damping ratios (e.g. ``RidgeResult.zeta_sd``), independent: propagated
        linearly to ``alpha_sd``, ``beta_sd`` (the factors are ``P zeta`` with ``P`` the weighted
        pseudo-inverse, so their covariance is ``P diag(zeta_sd^2) P^T``; a factor the nonnegative fit holds
        at 0 stays there and the other is the one-column fit's).

    Returns
    -------
    :class:`RayleighFit` with the factors and the residuals ``zeta - zeta_fit``.

    Warns
    -----
    ModelWarning
        Frequencies too close to separate ``alpha`` and ``beta`` (the scaled matrix's condition
        number above :data:`MAX_CONDITION`; module docstring); a damping ratio above :data:`ZETA_WARN`;
        with ``zeta_sd`` and three modes or more, residuals whose chi-square against ``zeta_sd`` exceeds
        its ``1 - MISFIT_PROBABILITY`` quantile (:data:`MISFIT_PROBABILITY`: the damping is not of
        Rayleigh form, ``RayleighFit.reduced_chi2`` says how far).
    """
    f = array_1d("freqs_hz", freqs_hz, min_len=2)
    z = array_1d("zetas", zetas, min_len=2)
    if z.size != f.size:
        raise ModelError("zetas", f"{z.size} values", f"must have one damping ratio per frequency ({f.size})")
    if np.any((z <= 0) | (z >= 1)):
        k = int(np.argmax((z <= 0) | (z >= 1)))
        raise ModelError(
            "zetas",
            float(z[k]),
            f"damping ratios are fractions of critical damping, 0 < zeta < 1 (mode {k + 1}, at {f[k]:g} Hz; damping "
            "in per cent, 1.2 for 1.2 %, is 0.012)",
        )
    if np.any(z > ZETA_WARN):
        warnings.warn(
            f"zetas: {', '.join(f'{v:g}' for v in z[z > ZETA_WARN])} above {ZETA_WARN:g}: damping ratios are fractions "
            "of critical damping; if these are per cent, divide them by 100 (alpha and beta scale with them)",
            ModelWarning,
            stacklevel=2,
        )
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
    cond = np.linalg.cond(As)
    if cond > MAX_CONDITION:
        warnings.warn(
            f"freqs_hz: the natural frequencies ({f.min():.6g} .. {f.max():.6g} Hz, spread {f.max() / f.min() - 1:.2g} "
            "of the lowest) are too close to separate alpha (the 1/omega trend) from beta (the omega trend): "
            f"the scaled least-squares matrix has condition number {cond:.3g} (above {MAX_CONDITION:g}), which "
            "multiplies the relative error of the damping ratios in alpha and beta (1 % becomes up to "
            f"{cond:.3g} %); use modes further apart (a frequency ratio of 2 gives 3)",
            ModelWarning,
            stacklevel=2,
        )
    if nonnegative:
        c, _ = nnls(As, b)
    else:
        c = np.linalg.lstsq(As, b, rcond=None)[0]
    alpha, beta = c / scale
    zfit = rayleigh_zeta(f, alpha, beta)
    sd = [float("nan")] * 2
    chi2_r = float("nan")
    if zeta_sd is not None:
        u = array_1d("zeta_sd", zeta_sd, min_len=f.size)
        if u.size != f.size or np.any(u < 0):
            raise ModelError("zeta_sd", zeta_sd, "must be one standard deviation >= 0 per frequency")
        free = [k for k in (0, 1) if not (nonnegative and c[k] == 0.0)]  # (a factor at its bound 0 stays there)
        P = np.linalg.pinv(As[:, free]) * w[None, :] / scale[free, None]  # (factors = P zeta)
        for k, row in zip(free, P):
            sd[k] = float(np.sqrt(np.sum((row * u) ** 2)))
        if f.size > 2 and np.all(u > 0):
            chi2_r = _warn_misfit(f, z, zfit, u, sd)
    return RayleighFit(
        alpha=float(alpha),
        beta=float(beta),
        freqs_hz=f,
        zeta=z,
        zeta_fit=zfit,
        residuals=z - zfit,
        alpha_sd=sd[0],
        beta_sd=sd[1],
        reduced_chi2=chi2_r,
    )


def _warn_misfit(f, z, zfit, zeta_sd, sd):
    """The reduced chi-square of the damping ratios ``z`` against Rayleigh damping (n > 2 modes): the least any
    alpha, beta leave, ``min sum(((z - zeta_R) / zeta_sd)^2) / (n - 2)``, the zeta_sd-weighted fit's (whatever
    fit the caller asked for: the statistic of whether the form fits at all, chi-square on n - 2 degrees of
    freedom for Rayleigh damping with honest zeta_sd), with a ModelWarning when its upper-tail probability is
    below :data:`MISFIT_PROBABILITY`: the damping is not of Rayleigh form (or the damping ratios err beyond
    their noise), and alpha, beta (``zfit`` their damping ratios) are a compromise whose +- (``sd``: alpha's,
    beta's, for noise alone) understates it. (The residuals of the unweighted fit against zeta_sd warned of an
    exactly Rayleigh record at 3 % noise in 5-20 % of 40 draws, the weighted fit's in none: largest 5.1.)"""
    from scipy.stats import chi2

    dof = f.size - 2
    Aw = rayleigh_matrix(f) / zeta_sd[:, None]
    Aw_scale = np.linalg.norm(Aw, axis=0)
    best = np.linalg.lstsq(Aw / Aw_scale, z / zeta_sd, rcond=None)[0]
    chi_square = float(np.sum((z / zeta_sd - (Aw / Aw_scale) @ best) ** 2))
    reduced = chi_square / dof
    if chi2.sf(chi_square, dof) >= MISFIT_PROBABILITY:
        return reduced
    off = ", ".join(f"{100 * (zf / zm - 1):+.0f} %" for zm, zf in zip(z, zfit))
    scaled = np.sqrt(reduced)
    widened = ", ".join(f"{name} +- {v * scaled:.2g}" for name, v in zip(("alpha", "beta"), sd) if np.isfinite(v))
    at = ", ".join(f"{v:.6g}" for v in f)
    limit = chi2.isf(MISFIT_PROBABILITY, dof) / dof
    warnings.warn(
        f"zetas: the damping is not of Rayleigh form: the Rayleigh damping ratios at {at} Hz are off the measured "
        f"ones by {off}, and no alpha, beta fit them within their standard deviations (zeta_sd): the least "
        f"reduced chi-square any leave is {reduced:.3g} on {dof} degree(s) of freedom, where Rayleigh damping "
        f"would give about 1 (above "
        f"{limit:.3g} in {100 * MISFIT_PROBABILITY:g} % of records); alpha and beta describe a compromise, and "
        "their +- covers the noise only"
        + (f" (scaled by sqrt of the reduced chi-square: {widened})" if widened else "")
        + "; a model of other damping (a loss factor per mode) fits such damping",
        ModelWarning,
        stacklevel=3,
    )
    return reduced
