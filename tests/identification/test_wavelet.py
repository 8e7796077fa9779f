"""Wavelet-ridge damping identification (Section 3.2.1, Table 1) against theory and mwdi."""

import warnings

import numpy as np
import pytest

from cablecasing_core.errors import ModelError
from cablecasing_core.identification import cwt_morlet, edge_length, wavelet_damping, wavelet_time_spread

# Table 1 of the paper: natural frequencies (Hz) and damping ratios of the numerical example
F_TABLE1 = np.array([115.8, 182.0, 254.1])
ZETA_TABLE1 = np.array([0.0359, 0.0263, 0.0216])
FS = 2048.0  # Hz, eight times the highest mode
DURATION = 1.0  # s


def impulse_response(fs=FS, duration=DURATION, amps=(1.0, 1.0, 1.0)):
    """Free response of three viscously damped modes, exp(-zeta wn t) sin(wd t), from t = 0."""
    t = np.arange(int(round(duration * fs))) / fs
    x = np.zeros_like(t)
    for f, z, a in zip(F_TABLE1, ZETA_TABLE1, amps):
        wn = 2 * np.pi * f
        x += a * np.exp(-z * wn * t) * np.sin(wn * np.sqrt(1 - z * z) * t)
    return x


def test_cwt_normalisation_and_closed_form():
    # |W| of a*exp(-sigma t)cos(wd t) is a exp(-sigma u) exp((sigma^2-(wd-wc)^2) gamma^2/(2 wc^2)) away from
    # the edges (module docstring); FFT with 8-sigma_t padding reproduces it to ~1e-6 (discrete sums of a
    # smooth Gaussian)
    fs, gamma, a, fd, sigma = 1000.0, 12.0, 2.5, 50.0, 3.0
    t = np.arange(4000) / fs
    x = a * np.exp(-sigma * t) * np.cos(2 * np.pi * fd * t + 0.3)
    fc = np.array([46.0, 49.0, 50.0, 52.0, 55.0])
    W = cwt_morlet(x, fs, fc, gamma)
    assert W.shape == (t.size, fc.size)
    mid = slice(1500, 2500)
    wc, wd = 2 * np.pi * fc, 2 * np.pi * fd
    theory = a * np.exp(-sigma * t[mid, None]) * np.exp((sigma**2 - (wd - wc) ** 2) * gamma**2 / (2 * wc**2))
    np.testing.assert_allclose(np.abs(W[mid]), theory, rtol=1e-6)
    # undamped harmonic: |W| equals the amplitude on the ridge
    y = 0.7 * np.cos(2 * np.pi * 80.0 * t)
    np.testing.assert_allclose(np.abs(cwt_morlet(y, fs, [80.0])[mid, 0]), 0.7, rtol=1e-9)


def test_three_modes_clean_within_1_percent():
    res = wavelet_damping(impulse_response(), FS, F_TABLE1)
    zeta = np.array([r.zeta for r in res])
    fn = np.array([r.f_natural_hz for r in res])
    # spec: 1 % on clean data (the method's bias here is < 0.1 %)
    np.testing.assert_allclose(zeta, ZETA_TABLE1, rtol=0.01)
    # ridge-frequency correction gives the undamped natural frequency; residual interference < 0.02 %
    np.testing.assert_allclose(fn, F_TABLE1, rtol=2e-4)
    for r in res:
        t0, t1 = r.t_fit
        assert t0 >= r.edge_s and t1 <= DURATION - r.edge_s
        assert np.all(np.isnan(r.ridge_hz[r.t < r.edge_s]))


def test_ridge_frequency_correction_single_mode():
    # one strongly damped mode (zeta = 0.08): the raw ridge lies at wd - sigma^2/wd and the corrected
    # damped/natural frequencies match the signal; with edge_factor = 5 the leftover edge effect
    # (Gaussian tail ~3e-7) is negligible, so 1e-6 holds; the default edge (3 sigma_t) leaves ~3e-4 in zeta
    fs, f, z = 4096.0, 200.0, 0.08
    t = np.arange(4096) / fs
    wn = 2 * np.pi * f
    wd = wn * np.sqrt(1 - z * z)
    sigma = z * wn
    x = np.exp(-sigma * t) * np.cos(wd * t)
    (r,) = wavelet_damping(x, fs, [f], edge_factor=5.0)
    assert r.f_ridge_hz == pytest.approx((wd - sigma**2 / wd) / (2 * np.pi), rel=1e-6)
    assert r.f_damped_hz == pytest.approx(wd / (2 * np.pi), rel=1e-6)
    assert r.f_natural_hz == pytest.approx(f, rel=1e-6)
    assert r.zeta == pytest.approx(z, rel=1e-6)
    (r3,) = wavelet_damping(x, fs, [f])
    assert r3.zeta == pytest.approx(z, rel=1e-3)


def test_three_modes_with_one_percent_noise_within_2_percent():
    # 1 % noise = white noise of standard deviation 1 % of the clean record's (40 dB SNR)
    x = impulse_response()
    rng = np.random.default_rng(20030101)
    for _ in range(3):
        xn = x + 0.01 * np.std(x) * rng.standard_normal(x.size)
        zeta = np.array([r.zeta for r in wavelet_damping(xn, FS, F_TABLE1)])
        np.testing.assert_allclose(zeta, ZETA_TABLE1, rtol=0.02)


def test_agrees_with_mwdi_within_2_percent():
    import mwdi

    x = impulse_response()
    ours = np.array([r.zeta for r in wavelet_damping(x, FS, F_TABLE1)])
    ident = mwdi.MorletWave(free_response=x, fs=FS)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # exact (Newton) form: the closed form assumes light damping and is 7 % low at zeta = 0.036
        theirs = np.array(
            [ident.identify_damping(2 * np.pi * f, n_1=8, n_2=12, k=30, root_finding="Newton") for f in F_TABLE1]
        )
    np.testing.assert_allclose(ours, theirs, rtol=0.02)


def test_scalogram_reuse_shape_and_dtype():
    x = impulse_response(duration=0.25)
    f = np.linspace(50, 500, 37)
    W = cwt_morlet(x, FS, f, gamma=8.0, max_block_bytes=1e5)  # several blocks give the same as one
    W1 = cwt_morlet(x, FS, f, gamma=8.0)
    assert W.dtype == complex and W.shape == (x.size, f.size)
    np.testing.assert_allclose(W, W1, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    "freqs, key", [([0.0], "freqs_hz"), ([1024.0], "freqs_hz"), ([-5.0], "freqs_hz"), ([2000.0], "freqs_hz")]
)
def test_frequency_outside_band(freqs, key):
    with pytest.raises(ModelError) as e:
        cwt_morlet(np.ones(64), FS, freqs)
    assert e.value.key == key and "fs/2" in e.value.allowed
    with pytest.raises(ModelError):
        wavelet_damping(impulse_response(), FS, freqs)


def test_record_too_short():
    x = impulse_response(duration=0.05)  # 50 ms: the edges at 115.8 Hz (3 sigma_t ~ 52 ms each) swallow it
    with pytest.raises(ModelError) as e:
        wavelet_damping(x, FS, [115.8])
    assert e.value.key == "x" and "too short" in e.value.allowed


def test_no_ridge_near_requested_frequency():
    with pytest.raises(ModelError) as e:
        wavelet_damping(impulse_response(), FS, [148.0])  # between modes: |W| has a valley, no ridge
    assert e.value.key == "freqs_hz" and e.value.value == 148.0


def test_mode_below_noise_floor():
    rng = np.random.default_rng(1)
    x = impulse_response() + 3.0 * rng.standard_normal(int(FS * DURATION))
    with pytest.raises(ModelError) as e:
        wavelet_damping(x, FS, [254.1], search=0.02)
    assert e.value.key in ("x", "freqs_hz")


def test_bad_parameters():
    with pytest.raises(ModelError) as e:
        cwt_morlet(np.ones(64), FS, [100.0], gamma=1.0)
    assert e.value.key == "gamma"
    with pytest.raises(ModelError) as e:
        cwt_morlet(np.ones(64), -1.0, [100.0])
    assert e.value.key == "fs"
    with pytest.raises(ModelError) as e:
        cwt_morlet(np.ones((4, 4)), FS, [100.0])
    assert e.value.key == "x"
    with pytest.raises(ModelError) as e:
        wavelet_damping(np.r_[np.nan, np.ones(100)], FS, [100.0])
    assert e.value.key == "x"


def test_lightly_damped_record_that_never_reaches_the_noise():
    # zeta = 0.001 at 100 Hz decays only e^-0.6 over the 1 s record: the tail is signal, not noise, so
    # no floor may cut the fit (a tail-median floor would leave nothing); clean data: 0.1 %
    fs = 1000.0
    t = np.arange(1000) / fs
    z = 0.001
    x = np.exp(-z * 2 * np.pi * 100 * t) * np.sin(2 * np.pi * 100 * np.sqrt(1 - z * z) * t)
    (r,) = wavelet_damping(x, fs, [100.0])
    assert r.zeta == pytest.approx(z, rel=1e-3)
    assert r.t_fit[1] == pytest.approx(1.0 - r.edge_s, abs=2 / fs)


def test_two_requests_of_one_ridge_are_refused():
    """113 and 118 Hz both settle on the 115.8 Hz mode's ridge: refused naming both (a Rayleigh fit
    of the two took them as two modes at rc 0: alpha = 0, beta 12 times the true one)."""
    with pytest.raises(ModelError, match=r"found the same ridge \(115.79") as e:
        wavelet_damping(impulse_response(), FS, [113.0, 118.0])
    assert e.value.key == "freqs_hz"


@pytest.mark.parametrize(
    "call, key",
    [
        (lambda: edge_length(0.0), "f_hz"),  # (gave inf)
        (lambda: edge_length(10.0, gamma=-1.0), "gamma"),  # (gave a negative time)
        (lambda: edge_length(10.0, edge_factor=float("nan")), "edge_factor"),
        (lambda: wavelet_time_spread("x"), "f_hz"),
    ],
)
def test_the_wavelet_s_time_helpers_refuse_bad_input_by_name(call, key):
    with pytest.raises(ModelError) as e:
        call()
    assert e.value.key == key
    assert edge_length(10.0) == pytest.approx(3 * 12 / (2 * np.pi * 10.0))  # (a float for a float)


def test_heavy_damping_outside_the_default_search_names_search():
    """zeta = 0.2: the ridge lies at omega_d - sigma^2 / omega_d = (1 - 2 zeta^2) / sqrt(1 - zeta^2) omega_n
    (module docstring; 108.7 Hz for 115.8 Hz), 6 % below, outside the default +-5 % band (review t10b: the
    error said to give a mode present in the record)."""
    fn, z = 115.8, 0.2
    wn = 2 * np.pi * fn
    t = np.arange(2048) / FS
    x = np.exp(-z * wn * t) * np.sin(wn * np.sqrt(1 - z * z) * t)
    with pytest.raises(ModelError) as e:
        wavelet_damping(x, FS, [fn])
    assert e.value.key == "freqs_hz" and e.value.value == fn
    assert "lower edge" in e.value.allowed and "--search" in e.value.allowed and "e.g. 0.1" in e.value.allowed
    (r,) = wavelet_damping(x, FS, [fn], search=0.1)  # the suggested band
    # clean record: the edge bias (3e-4 at zeta = 0.08, docs) and the real record's mirror leave ~1e-4
    assert r.zeta == pytest.approx(z, rel=1e-3)
    assert r.f_ridge_hz == pytest.approx((1 - 2 * z * z) / np.sqrt(1 - z * z) * fn, rel=1e-3)
    assert r.f_natural_hz == pytest.approx(fn, rel=1e-3)


def test_the_damping_uncertainty_and_the_rayleigh_factors_are_the_scatter_over_noise_draws(synth):
    """Review Q: zeta, alpha and beta were printed to 5-6 digits with no uncertainty. Three viscous modes
    (100.23, 143.7, 260.11 Hz; zeta of alpha = 6 1/s, beta = 2e-5 s: 1.1, 1.2, 1.8 %), 2 s at 2048 Hz, white
    noise 3 % of the record's peak, 20 draws: the errors of zeta over RidgeResult.zeta_sd, and of alpha and beta
    over the propagated RayleighFit.alpha_sd, beta_sd, have an rms near 1 (measured over 30 draws: zeta 1.17,
    1.41, 0.74 per mode, alpha 0.72, beta 0.74). The scatter itself is what the review measured: zeta 1.8, 2.9,
    10 %, alpha 23 %, beta 13 %."""
    from cablecasing_core.identification import rayleigh_fit

    f_n, alpha, beta = np.array([100.23, 143.7, 260.11]), 6.0, 2e-5
    zeta = alpha / (4 * np.pi * f_n) + beta * np.pi * f_n
    t = np.arange(0, 2.0, 1 / FS)
    x0 = synth.impulse(t, f_n, zeta, [1.0, 0.7, 0.5])
    z_norm, ab_norm = [], []
    for seed in range(20):
        x = x0 + 0.03 * np.abs(x0).max() * np.random.default_rng(seed).standard_normal(t.size)
        res = wavelet_damping(x, FS, f_n)
        z_norm += [(r.zeta - z) / r.zeta_sd for r, z in zip(res, zeta)]
        fit = rayleigh_fit([r.f_natural_hz for r in res], [r.zeta for r in res], zeta_sd=[r.zeta_sd for r in res])
        ab_norm += [(fit.alpha - alpha) / fit.alpha_sd, (fit.beta - beta) / fit.beta_sd]
    # 60 and 40 normalised errors: their rms estimates 1 to +-0.1 (1/sqrt(2 n)); the bounds allow that three
    # times over and the per-mode spread measured (0.74-1.41: the window's end, where the noise floor stops it,
    # is itself random and biases zeta low by up to 2 % there)
    assert 0.6 < np.sqrt(np.mean(np.square(z_norm))) < 1.6, z_norm
    assert 0.45 < np.sqrt(np.mean(np.square(ab_norm))) < 1.5, ab_norm


def test_close_modes_are_refused_naming_the_gamma_that_separates_them(synth):
    """Review Q: 100 and 104 Hz at zeta 1 % beat at gamma 12 and are refused; the message suggested t_max,
    measuring again or skipping the check, which gives wrong numbers (100 and 115 Hz: f_n 101.17 and 110.68 Hz).
    It now names gamma >= 4 f / df = 104 (the higher mode over the gap) and the record's length that needs,
    and says the check is skipped only for a slower neighbour's late leakage; at gamma 104 both modes come
    out within 0.1 % (measured 0.02 % at 100), the closed form's zeta and f_n."""
    t = np.arange(0, 2.0, 1 / FS)
    x = synth.impulse(t, [100.0, 104.0], [0.01, 0.01], [1.0, 1.0])
    with pytest.raises(ModelError) as e:
        wavelet_damping(x, FS, [100.0, 104.0])
    text = e.value.allowed
    assert "the request at 104 Hz, 4 Hz away, is closer than gamma = 12 resolves" in text
    assert "give a larger gamma (the CLI's --gamma), 104 or more (4 f / df" in text and "about 1.02 s long" in text
    assert "Skipping the check (max_departure None, --max-departure off) is only for a clean record" in text
    res = wavelet_damping(x, FS, [100.0, 104.0], gamma=104)
    np.testing.assert_allclose([r.zeta for r in res], 0.01, rtol=1e-3)
    np.testing.assert_allclose([r.f_natural_hz for r in res], [100.0, 104.0], rtol=1e-4)


def test_a_force_pulse_is_not_taken_for_a_clipped_decay(synth):
    """Review Q: the first channel of an impact test, the hammer's 1 ms half-sine and then zeros, was diagnosed
    as clipped (its zeros at the record's minimum) and too short. It is refused as a pulse, not a decay, naming
    its samples; a heavily damped decay (zeta 0.2, within 1 % of its peak in 37 ms) is no pulse."""
    t = np.arange(-0.02, 2.0, 1 / FS)
    force = np.where((t >= 0) & (t < 1e-3), np.sin(np.pi * t / 1e-3), 0.0) * 100
    with pytest.raises(ModelError, match=r"not a decay: .* a pulse of 3 samples .* pick the response channel") as e:
        wavelet_damping(force, FS, [100.0], t0=-0.02)
    assert e.value.key == "x"
    (r,) = wavelet_damping(synth.impulse(t, [100.0], [0.2], [1.0]), FS, [100.0], t0=-0.02, search=0.1)
    assert r.zeta == pytest.approx(0.2, rel=0.01)  # (the heavy-damping case of section 1: within 0.2 %)
