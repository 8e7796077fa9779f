"""H1/H2 FRF estimation and coherence on a known SDOF system with noise."""

import numpy as np
import pytest
from scipy import signal

from cablecasing_core.errors import ModelError
from cablecasing_core.identification import frf_estimate

FS = 500.0  # Hz
NPERSEG = 2048  # df = 0.244 Hz; Hann resolution bias at the resonance ~ (1/3)(B_e/B_r)^2 ~ 1 %
N = NPERSEG * 65  # 129 averages with 50 % overlap


def sdof():
    """m = 1 kg, f_n = 50 Hz, zeta = 0.02 (receptance m/N), discretised by the bilinear transform; the
    reference FRF is the exact response of the *discrete* filter (scipy.signal.freqz)."""
    m, fn, z = 1.0, 50.0, 0.02
    k, c = m * (2 * np.pi * fn) ** 2, 2 * z * m * 2 * np.pi * fn
    b, a = signal.bilinear([1.0], [m, c, k], fs=FS)
    return b, a


def band(f):
    """10..200 Hz without +-5 Hz around the resonance, where window bias is below 0.1 %."""
    return (f > 10) & (f < 200) & (np.abs(f - 50.0) > 5.0)


def test_h1_with_output_noise_and_h2_bias():
    b, a = sdof()
    rng = np.random.default_rng(5)
    u = rng.standard_normal(N)  # force, N (white, sigma_u = 1)
    v = signal.lfilter(b, a, u)  # displacement, m
    sigma_n = 0.3 * np.std(v)
    y = v + sigma_n * rng.standard_normal(N)  # output noise
    est = frf_estimate(u, y, FS, nperseg=NPERSEG)
    _, H = signal.freqz(b, a, worN=est.f_hz, fs=FS)
    # H2 = H (1 + Gnn/Gvv): white noises give Gnn/Gvv = sigma_n^2 / (sigma_u^2 |H|^2) (theory)
    bias = sigma_n**2 / np.abs(H) ** 2
    sel = band(est.f_hz) & (bias < 1.0)  # where the true coherence 1/(1+bias) exceeds 0.5
    bias = bias[sel]
    # H1 is unbiased, with the random error of Bendat & Piersol: magnitude and phase (rad) standard
    # deviations eps = sqrt(1-g^2)/(|g| sqrt(2 n_d)), so rms(|H1/H - 1| / (sqrt(2) eps)) = 1; ~100
    # independent bins estimate it to +-7 % (1 sigma): accept 0.85..1.15
    g2 = 1 / (1 + bias)
    eps = np.sqrt(1 - g2) / np.sqrt(g2) / np.sqrt(2 * est.n_averages)
    e = np.abs(est.H1[sel] / H[sel] - 1)
    assert 0.85 < np.sqrt(np.mean((e / (np.sqrt(2) * eps)) ** 2)) < 1.15
    # the complex mean of H1/H is 1 within 1.5 % (2.5 standard errors of a ~100-bin mean of ~4 % errors)
    assert abs(np.mean(est.H1[sel] / H[sel]) - 1) < 0.015
    np.testing.assert_allclose(np.mean(np.abs(est.H2[sel] / H[sel]) / (1 + bias)), 1.0, atol=0.01)
    # ordinary coherence gamma^2 = 1 / (1 + Gnn/Gvv)
    np.testing.assert_allclose(np.mean(est.coherence[sel] * (1 + bias)), 1.0, atol=0.01)
    assert est.n_averages == 129


def test_the_averages_overlapping_segments_are_worth_are_welchs():
    """Welch's variance of a PSD from overlapping segments (Welch 1967): 4000 white-noise records of 16
    Hann segments of 64 samples; the variance over the records of each line's estimate, relative to
    its mean squared, is 1 / n_effective (a chi-square of 2 n_effective degrees of freedom). Measured
    over 24 lines: within 3 % at 75 % overlap (8.6 averages, where counting the 16 segments would be
    86 % off) and at 50 % (15.2); the pooled estimate's scatter is about 1 %."""
    from cablecasing_core.identification.frf import welch_effective_averages

    rng = np.random.default_rng(1)
    for noverlap in (48, 32):
        n = 64 + 15 * (64 - noverlap)
        _, P = signal.welch(rng.standard_normal((4000, n)), nperseg=64, noverlap=noverlap, axis=-1)
        lines = P[:, 4:-4]  # (away from 0 Hz and fs / 2, where a line is a chi-square of 1 degree)
        measured = 1.0 / np.mean(lines.var(axis=0) / lines.mean(axis=0) ** 2)
        assert measured == pytest.approx(welch_effective_averages(64, noverlap, 16), rel=0.03), noverlap
    assert welch_effective_averages(64, 48, 16) < 0.55 * 16


def test_h1_scatter_from_overlapping_segments_is_the_random_error_of_the_averages_they_are_worth():
    """The same SDOF with output noise as above, its segments overlapping by 75 %: H1's scatter is
    Bendat & Piersol's random error with the independent averages the segments are worth
    (n_effective, 0.52 of the 257 segments), where with the segments' count it would read 1.4 times
    too small; the nvh layer's random error takes the same."""
    from cablecasing_core.identification.frf import random_error

    b, a = sdof()
    rng = np.random.default_rng(5)
    u = rng.standard_normal(N)
    v = signal.lfilter(b, a, u)
    y = v + 0.3 * np.std(v) * rng.standard_normal(N)
    est = frf_estimate(u, y, FS, nperseg=NPERSEG, noverlap=3 * NPERSEG // 4)
    _, H = signal.freqz(b, a, worN=est.f_hz, fs=FS)
    bias = (0.3 * np.std(v)) ** 2 / np.abs(H) ** 2
    sel = band(est.f_hz) & (bias < 1.0)
    eps = random_error(1 / (1 + bias[sel]), est.n_effective)
    e = np.abs(est.H1[sel] / H[sel] - 1)
    # (the same bound as above: ~100 bins estimate the rms to +-7 %)
    assert 0.85 < np.sqrt(np.mean((e / (np.sqrt(2) * eps)) ** 2)) < 1.15
    assert est.n_averages == 257 and 0.5 * 257 < est.n_effective < 0.55 * 257


def test_h2_with_input_noise_and_h1_bias():
    b, a = sdof()
    rng = np.random.default_rng(6)
    u = rng.standard_normal(N)
    y = signal.lfilter(b, a, u)
    x = u + 0.3 * rng.standard_normal(N)  # noise on the measured input
    est = frf_estimate(x, y, FS, nperseg=NPERSEG)
    _, H = signal.freqz(b, a, worN=est.f_hz, fs=FS)
    sel = band(est.f_hz)
    # H2 unbiased; H1 = H / (1 + Gmm/Guu) = H / 1.09 (white input noise of 0.3 sigma_u)
    assert abs(np.mean(np.abs(est.H2[sel] / H[sel])) - 1) < 0.01
    assert abs(np.mean(np.abs(est.H1[sel] / H[sel])) - 1 / 1.09) < 0.01
    # phase is not biased by either noise: within 1 degree on average
    assert abs(np.degrees(np.mean(np.angle(est.H1[sel] / H[sel])))) < 1.0


def test_resonance_peak_within_window_bias():
    b, a = sdof()
    rng = np.random.default_rng(7)
    u = rng.standard_normal(N)
    y = signal.lfilter(b, a, u)
    est = frf_estimate(u, y, FS, nperseg=NPERSEG)
    _, H = signal.freqz(b, a, worN=est.f_hz, fs=FS)
    j = np.argmax(np.abs(H))
    # noise-free: only the Hann resolution bias, -(1/3)(B_e/B_r)^2 = -(1/3)(0.37/2)^2 ~ -1.1 %, remains
    assert np.abs(est.H1[j]) / np.abs(H[j]) == pytest.approx(1 - 0.011, abs=0.006)
    # no noise: H1 = H2 and coherence 1 up to leakage of the Hann window where |H| is steep (< 0.5 %)
    sel = band(est.f_hz)
    np.testing.assert_allclose(est.H1[sel], est.H2[sel], rtol=5e-3)
    assert np.min(est.coherence[sel]) > 0.995


def test_the_apparent_mass_of_a_rigid_mass_is_h1_of_acceleration_to_force():
    rng = np.random.default_rng(8)
    acc = rng.standard_normal(2**15)  # m/s^2
    force = 0.35 * acc + 0.01 * rng.standard_normal(acc.size)  # N, a 0.35 kg mass plus force noise
    est = frf_estimate(acc, force, FS, nperseg=1024)
    M, coh = est.H1, est.coherence
    # H1 with noise on the force only: unbiased; random error sqrt(1-g^2)/(g sqrt(2*63)) ~ 0.3 %
    assert abs(np.mean(M[1:-1].real) - 0.35) < 0.35 * 0.005
    assert np.max(np.abs(M[1:-1].imag)) < 0.35 * 0.02
    assert coh[1:-1].min() > 0.99


def test_frf_errors():
    with pytest.raises(ModelError) as e:
        frf_estimate(np.ones(100), np.ones(99), FS)
    assert e.value.key == "y"
    with pytest.raises(ModelError) as e:
        frf_estimate(np.ones(100), np.ones(100), FS, nperseg=500)
    assert e.value.key == "nperseg"
    with pytest.raises(ModelError) as e:
        frf_estimate(np.ones(100), np.ones(100), 0.0)
    assert e.value.key == "fs"


def _tail(n, nperseg, noverlap):
    """(samples after scipy's last segment, segments) at this overlap: segments every nperseg - noverlap samples
    from sample 0 while a whole one fits (``scipy.signal.welch``'s rule, checked below against its own output)."""
    step = nperseg - noverlap
    k = 1 + (n - nperseg) // step
    return n - ((k - 1) * step + nperseg), k


def test_welch_overlap_is_the_least_overlap_whose_segments_span_the_record():
    """Review AX3: welch_overlap(n, nperseg, least) is the smallest overlap of at least ``least`` whose segments leave
    at most their number less one samples after the last (its guarantee), found here by trying every overlap from
    ``least`` up; over segment lengths odd and even, records of one to 12 segments and ``least`` from 0 to
    nperseg - 1. It added a segment whenever the tail at ``least`` was not 0: 45057 samples at 8192 leave 1 sample
    at 50 %, where it took 55 % and left 5; 17409 at 1024 with no overlap leave 1, where it took 61 samples and left
    14. The default least is half a segment rounded up: at least 50 % (4 of 9 samples would be 44 %)."""
    from cablecasing_core.identification.frf import welch_overlap

    for nper in [*range(8, 41), 63, 64, 127, 128]:
        for n in range(nper, 12 * nper + 3, max(1, nper // 16)):
            for least in sorted({0, nper // 3, nper // 2, -(-nper // 2), (3 * nper) // 4, nper - 1}):
                want = next(o for o in range(least, nper) if _tail(n, nper, o)[0] <= _tail(n, nper, o)[1] - 1)
                assert welch_overlap(n, nper, least) == want, (n, nper, least)
            assert welch_overlap(n, nper) == welch_overlap(n, nper, -(-nper // 2)) >= nper / 2
    assert welch_overlap(45057, 8192) == 4096 and _tail(45057, 8192, 4096) == (1, 10)  # (kept at 50 %)
    assert welch_overlap(17409, 1024, 0) == 0 and _tail(17409, 1024, 0) == (1, 17)
    assert welch_overlap(44000, 8192) == 4214 and _tail(44000, 8192, 4214) == (6, 10)  # (raised: 3040 left at 50 %)
    assert welch_overlap(44000, 16384) == 9480 and _tail(44000, 16384, 9480) == (0, 5)  # (the report's 58 %)


@pytest.mark.parametrize(
    ("n", "nperseg", "least"),
    [(45057, 8192, None), (44000, 8192, None), (17409, 1024, 0), (1000, 9, None), (5003, 127, 40)],
)
def test_welch_overlap_segments_as_scipy_takes_them(n, nperseg, least):
    """The segments scipy itself takes at welch_overlap's overlap (scipy.signal.spectrogram, Welch's segmenting with
    each segment's spectrum kept: its segment times are their centres): as many as welch_averages counts, the
    first from sample 0, the last ending within their number less one samples of the record's end; and welch's
    density is the mean of those segments' (to round-off, 1e-12)."""
    from cablecasing_core.identification.frf import welch_averages, welch_overlap

    nov = welch_overlap(n, nperseg, least)
    x = np.random.default_rng(0).standard_normal(n)
    kw = dict(fs=1.0, window="hann", nperseg=nperseg, noverlap=nov)  # (spectrogram's default window is not welch's)
    _, t, S = signal.spectrogram(x, **kw)
    starts = t - nperseg / 2  # (samples, at fs = 1 Hz)
    assert starts[0] == 0 and t.size == welch_averages(n, nperseg, nov)
    assert 0 <= n - (starts[-1] + nperseg) <= t.size - 1 and n - (starts[-1] + nperseg) == _tail(n, nperseg, nov)[0]
    _, G = signal.welch(x, **kw)
    np.testing.assert_allclose(G, S.mean(axis=-1), rtol=1e-12)
    assert nov >= (nperseg / 2 if least is None else least)
