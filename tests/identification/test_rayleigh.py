"""Rayleigh factors by least squares (Eqs. 41-44)."""

import warnings

import numpy as np
import pytest

from cablecasing_core.errors import ModelError, ModelWarning
from cablecasing_core.identification import rayleigh_fit, rayleigh_matrix, rayleigh_zeta

F = np.array([115.8, 182.0, 254.1, 410.0])


def eq41(f_hz, alpha, beta):
    """The paper's Eq. (41), written out: zeta_i = alpha / (2 omega_i) + beta omega_i / 2."""
    w = 2 * np.pi * np.asarray(f_hz, float)
    return alpha / (2 * w) + beta * w / 2


def eq42(f_hz):
    """The paper's Eq. (42) matrix, written out: rows [1 / (2 omega_i), omega_i / 2]."""
    w = 2 * np.pi * np.asarray(f_hz, float)
    return np.column_stack([1 / (2 * w), w / 2])


def test_helpers_are_eqs_41_and_42():
    # the module's helpers against the equations as printed (same arithmetic: rounding only, 1e-15)
    for alpha, beta in ((35.0, 2.2e-5), (11.1, 4.23e-5), (0.0, 1e-4), (60.0, 0.0)):
        np.testing.assert_allclose(rayleigh_zeta(F, alpha, beta), eq41(F, alpha, beta), rtol=1e-15)
    np.testing.assert_allclose(rayleigh_matrix(F), eq42(F), rtol=1e-15)
    # the paper's casing (alpha = 11.1 1/s, beta = 4.23e-5 s, Fig. 16a) at 115.8 Hz, by hand:
    # omega = 727.593 1/s: 11.1 / (2 omega) + 4.23e-5 omega / 2 = 0.0076279 + 0.0153886 = 0.0230165
    assert rayleigh_zeta([115.8], 11.1, 4.23e-5)[0] == pytest.approx(0.0230165, abs=1e-7)


def test_exact_rayleigh_data_recovered():
    alpha, beta = 35.0, 2.2e-5
    fit = rayleigh_fit(F, eq41(F, alpha, beta))
    # exactly Rayleigh data: the solution is exact up to rounding (condition number ~1e1 after scaling)
    assert fit.alpha == pytest.approx(alpha, rel=1e-12)
    assert fit.beta == pytest.approx(beta, rel=1e-12)
    np.testing.assert_allclose(fit.residuals, 0.0, atol=1e-15)


def test_least_squares_matches_lstsq_and_normal_equations():
    zeta = np.array([0.0359, 0.0263, 0.0216, 0.0190])
    fit = rayleigh_fit(F, zeta)
    A = eq42(F)
    c_lstsq = np.linalg.lstsq(A, zeta, rcond=None)[0]
    c_pinv = np.linalg.solve(A.T @ A, A.T @ zeta)  # Eq. (44) literally
    # same minimiser; 1e-9 allows for the conditioning of the unscaled normal equations
    np.testing.assert_allclose([fit.alpha, fit.beta], c_lstsq, rtol=1e-9)
    np.testing.assert_allclose([fit.alpha, fit.beta], c_pinv, rtol=1e-9)
    np.testing.assert_allclose(fit.residuals, zeta - A @ c_lstsq, atol=1e-14)
    assert abs(A.T @ fit.residuals).max() < 1e-12 * np.abs(A.T @ zeta).max()  # normal equations hold


def test_table1_values_and_nonnegative_option():
    zeta = np.array([0.0359, 0.0263, 0.0216])  # Table 1
    fit = rayleigh_fit(F[:3], zeta)
    assert fit.alpha > 0 and fit.beta > 0
    assert fit.rms_residual < 5e-4  # Table 1 is close to Rayleigh damping
    # damping falling faster than 1/omega: least squares wants beta < 0, which the model file rejects
    zeta_fast = np.array([0.04, 0.02, 0.01, 0.005])
    assert rayleigh_fit(F, zeta_fast).beta < 0
    nn = rayleigh_fit(F, zeta_fast, nonnegative=True)
    assert nn.beta == 0.0 and nn.alpha > 0
    # with beta = 0 the best alpha is the 1-D least squares a = <A1, z> / <A1, A1>
    a1 = 1 / (4 * np.pi * F)  # Eq. (42)'s first column, 1 / (2 omega)
    assert nn.alpha == pytest.approx(a1 @ zeta_fast / (a1 @ a1), rel=1e-12)


def test_weights():
    zeta = np.array([0.0359, 0.0263, 0.0216, 0.0190])
    w = np.array([1.0, 2.0, 3.0, 0.5])
    fit = rayleigh_fit(F, zeta, weights=w)
    c = np.linalg.lstsq(eq42(F) * w[:, None], zeta * w, rcond=None)[0]
    np.testing.assert_allclose([fit.alpha, fit.beta], c, rtol=1e-9)


def test_errors():
    with pytest.raises(ModelError) as e:
        rayleigh_fit([100.0], [0.01])
    assert e.value.key == "freqs_hz"
    with pytest.raises(ModelError) as e:
        rayleigh_fit([100.0, 200.0], [0.01])
    assert e.value.key == "zetas"
    with pytest.raises(ModelError) as e:
        rayleigh_fit([100.0, 100.0], [0.01, 0.02])
    assert e.value.key == "freqs_hz"
    with pytest.raises(ModelError) as e:
        rayleigh_fit([-1.0, 100.0], [0.01, 0.02])
    assert e.value.key == "freqs_hz"


@pytest.mark.parametrize(
    "call, key",
    [
        (lambda: rayleigh_zeta([0.0], 1.0, 1e-5), "freqs_hz"),  # (0 Hz gave inf)
        (lambda: rayleigh_zeta([10.0], float("nan"), 1e-5), "alpha"),  # (gave NaN)
        (lambda: rayleigh_zeta([10.0], 1.0, "x"), "beta"),
        (lambda: rayleigh_matrix([-5.0, 10.0]), "freqs_hz"),  # (accepted)
    ],
)
def test_rayleigh_helpers_refuse_bad_input_by_name(call, key):
    with pytest.raises(ModelError) as e:
        call()
    assert e.value.key == key


def test_close_frequencies_warn_that_alpha_and_beta_are_not_separated():
    """Two modes at the ratio r: the scaled matrix's condition number is (r + 1) / (r - 1) (module
    docstring), 100 at r = 1.0202 (review t08: 1e-6 apart gave alpha = -1.26e6, beta = 3.18 silently)."""
    with pytest.warns(ModelWarning, match="too close to separate alpha"):
        rayleigh_fit([100.0, 100.0 * (1 + 1e-6)], [0.010, 0.012])
    with pytest.warns(ModelWarning, match="too close"):
        rayleigh_fit([100.0, 101.9], [0.010, 0.012])  # (r + 1) / (r - 1) = 106
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)
        rayleigh_fit([100.0, 102.1], [0.010, 0.012])  # 96
        rayleigh_fit(F[:3], [0.0359, 0.0263, 0.0216])  # Table 1


@pytest.mark.parametrize("freqs", [[True, 20.0], np.array([True, False])])
def test_a_bool_is_not_a_frequency(freqs):
    # True would read as 1 Hz: damping ratios at a frequency nobody gave.
    with pytest.raises(ModelError, match=r"freqs_hz = .*not True or False"):
        rayleigh_zeta(freqs, 1.0, 1e-4)


def test_the_factors_uncertainty_is_the_damping_ratios_carried_through_eq_44():
    """Review Q: alpha and beta carry the damping ratios' standard deviations linearly. Two modes: the factors
    are A^-1 zeta (Eq. 42 solved), so their covariance is A^-1 diag(sd^2) A^-T; four modes: the least-squares
    (A^T A)^-1 A^T in place of A^-1 (both by numpy here); the nonnegative fit with beta at its bound: alpha is
    the one-column fit a1.zeta / a1.a1 and beta has none (nan). To rounding (1e-9)."""
    sd = np.array([2e-4, 3e-4, 1e-3, 5e-4])
    zeta = np.array([0.0359, 0.0263, 0.0216, 0.0190])
    A = eq42(F)
    for n in (2, 4):
        P = np.linalg.solve(A[:n].T @ A[:n], A[:n].T)  # (A^-1 for n = 2)
        expect = np.sqrt(np.diag(P @ np.diag(sd[:n] ** 2) @ P.T))
        fit = rayleigh_fit(F[:n], zeta[:n], zeta_sd=sd[:n])
        np.testing.assert_allclose([fit.alpha_sd, fit.beta_sd], expect, rtol=1e-9)
    nn = rayleigh_fit(F, [0.04, 0.02, 0.01, 0.005], nonnegative=True, zeta_sd=sd)
    a1 = A[:, 0]
    assert nn.beta == 0.0 and np.isnan(nn.beta_sd)
    assert nn.alpha_sd == pytest.approx(np.sqrt(np.sum((a1 * sd) ** 2)) / (a1 @ a1), rel=1e-9)
    assert np.isnan(rayleigh_fit(F, zeta).alpha_sd)  # (no zeta_sd given: none)
    with pytest.raises(ModelError, match=r"zeta_sd = .*one standard deviation >= 0 per frequency"):
        rayleigh_fit(F, zeta, zeta_sd=[1e-3, -1e-3, 1e-3, 1e-3])


def test_damping_ratios_outside_0_1_are_refused_and_large_ones_warned():
    """Review Q: rayleigh_fit took negative damping ratios and ratios >= 1 (damping in per cent gave alpha 100
    times too large) without a word. A ratio <= 0 or >= 1 is refused naming zetas, the value and the mode;
    above 0.3 a warning asks whether they are per cent, and the fit is Eq. (42) solved as before."""
    for zeta, k in (([-0.01, 0.01], 1), ([0.01, 0.0], 2), ([1.0, 0.8], 1)):
        with pytest.raises(ModelError, match=rf"0 < zeta < 1 \(mode {k}, at .* per cent, 1.2 for 1.2 %") as e:
            rayleigh_fit(F[:2], zeta)
        assert e.value.key == "zetas" and e.value.value == zeta[k - 1]
    with pytest.warns(ModelWarning, match=r"zetas: 0.35 above 0.3: .* if these are per cent, divide them by 100"):
        fit = rayleigh_fit(F[:2], [0.35, 0.01])
    np.testing.assert_allclose([fit.alpha, fit.beta], np.linalg.solve(eq42(F[:2]), [0.35, 0.01]), rtol=1e-9)
