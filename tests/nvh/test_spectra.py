"""PSD (Welch) and levels against Parseval and known levels: a sum of sines and white noise; band
levels in dB re a documented reference."""

import numpy as np
import pytest

from cablecasing_core import ModelError
from cablecasing_core.nvh import REFERENCES, level_db, psd, reference
from cablecasing_core.studies import octave_rms

FS = 8192.0


def test_psd_of_a_sum_of_sines_is_parseval_and_puts_each_tone_at_its_power():
    nper = 1024  # df = 8 Hz
    df = FS / nper
    tones = [(3.0, 50 * df, 0.3), (0.5, 100 * df, 1.1), (1.5, 333 * df, 2.0)]  # N, Hz (bin centres), rad
    t = np.arange(64 * nper) / FS
    x = sum(A * np.sin(2 * np.pi * f * t + ph) for A, f, ph in tones)
    p = psd(x, FS, nperseg=nper, unit="N", name="x")
    assert p.fs / p.nperseg == df and p.n_averages == 127
    # Parseval: on bin centres the Hann window's power has no component at twice a tone's frequency,
    # so the integral of the density is the mean square exactly (to round-off)
    assert p.mean_square() == pytest.approx(np.mean(x**2), rel=1e-10)
    assert p.mean_square() == pytest.approx(sum(A * A / 2 for A, _, _ in tones), rel=1e-10)
    for A, f, _ in tones:  # each tone in its bin and the two beside it (Hann's main lobe): A^2 / 2
        assert p.mean_square(f - 1.5 * df, f + 1.5 * df) == pytest.approx(A * A / 2, rel=1e-10)
        k = int(round(f / df))
        assert p.level_db()[k] == pytest.approx(10 * np.log10(p.density[k] / 1.0))  # dB re 1 N^2/Hz
    # the window's equivalent noise bandwidth is 1.5 bins: the peak density is the power / ENBW / ...
    assert p.enbw == pytest.approx(1.5 * df, rel=1e-3)
    assert p.density[50] == pytest.approx(3.0**2 / 2 / p.enbw, rel=1e-10)


def test_psd_of_white_noise_is_flat_at_its_known_level():
    rng = np.random.default_rng(5)
    sigma = 2.0  # m/s2
    x = sigma * rng.standard_normal(2**20)
    p = psd(x, FS, nperseg=2048, unit="m/s2")
    level = 2 * sigma**2 / FS  # one-sided density of white noise of variance sigma^2, (m/s2)^2/Hz
    inner = p.density[1:-1]
    # each bin's estimate scatters by ~1/sqrt(averages) (1023 segments, 50 % overlap: ~1/27); the
    # mean over 1023 bins by ~1/sqrt(1023 * 1023 / 1.1) ~ 1e-3: 5e-3 is five standard deviations
    assert np.mean(inner) == pytest.approx(level, rel=5e-3)
    assert np.std(inner / level) < 1.3 / np.sqrt(p.n_averages)  # (overlap raises it by < 10 %)
    assert p.mean_square() == pytest.approx(np.var(x), rel=5e-3)  # Parseval within the same scatter
    # its level: dB re (1e-6 m/s2)^2/Hz (ISO 1683)
    assert reference("m/s2") == 1e-6
    np.testing.assert_allclose(p.level_db(), 10 * np.log10(p.density / 1e-12))
    # and octave bands of the same record: band RMS sqrt(level * bandwidth), in dB re 1e-6 m/s2
    b = octave_rms(x, FS, "octave", beyond_nyquist="drop")
    np.testing.assert_allclose(b.rms, np.sqrt(level * (b.upper - b.lower)), rtol=0.1)  # >= 11 Hz bands
    np.testing.assert_allclose(b.level_db(1e-6), 20 * np.log10(b.rms / 1e-6))


def test_level_references_and_errors():
    # ISO 1683:2015's references of the motions, 1 N for forces (vehicle NVH), 1 for a count (contact.active)
    assert REFERENCES == {"N": 1.0, "N.m": 1.0, "m/s2": 1e-6, "m/s": 1e-9, "m": 1e-12, "1": 1.0}
    assert level_db(10.0, 1.0) == pytest.approx(20.0) and level_db(10.0, 1.0, power=True) == pytest.approx(10.0)
    assert reference("Pa", 2e-5) == 2e-5
    with pytest.raises(ModelError, match="^ref = None: must be given for a quantity in 'Pa'"):
        reference("Pa")  # (the library names its argument; the command line renames it --ref)
    with pytest.raises(ModelError, match="nperseg"):
        psd(np.ones(100), FS, nperseg=200)
    with pytest.raises(ModelError, match="window"):
        psd(np.ones(100), FS, window="no-such-window")


@pytest.mark.parametrize("overlap", [0.0, 0.75])
def test_psd_uses_the_overlap_asked_for_as_a_hand_welch(overlap):
    """Welch written out by hand (segments every (1 - overlap) nperseg samples, mean removed, periodic
    Hann, |FFT|^2 / (fs sum w^2), doubled except at 0 and Nyquist, averaged): the same numbers to
    round-off (1e-10: the same sums in another order), and the number of segments it averaged."""
    rng = np.random.default_rng(11)
    fs, nper, n = 1000.0, 128, 128 * 40
    x = rng.standard_normal(n) + np.sin(2 * np.pi * 62.5 * np.arange(n) / fs)
    p = psd(x, fs, nperseg=nper, overlap=overlap)
    hop = nper - int(round(overlap * nper))
    starts = np.arange(0, n - nper + 1, hop)
    w = 0.5 - 0.5 * np.cos(2 * np.pi * np.arange(nper) / nper)  # periodic Hann
    segs = np.array([x[s : s + nper] - x[s : s + nper].mean() for s in starts])
    G = np.mean(np.abs(np.fft.rfft(segs * w, axis=1)) ** 2, axis=0) / (fs * np.sum(w**2))
    G[1:-1] *= 2
    assert p.n_averages == len(starts)
    np.testing.assert_allclose(p.density, G, rtol=1e-10, atol=1e-12 * G.max())


def test_a_hann_windowed_tone_on_a_bin_centre_keeps_its_mean_square_to_round_off():
    """With the periodic (DFT-even) Hann window the cross term of sin^2 w^2 vanishes for a tone on a
    bin centre, so the band mean square over 0..fs/2 is A^2/2 to round-off (1e-12), for a short record
    as well (64 samples); the symmetric window is 1e-6 off there."""
    from cablecasing_core.nvh.bands import Bands

    n, fs = 64, 64.0
    t = np.arange(n) / fs
    x = 1.7 * np.sin(2 * np.pi * 8 * t + 0.4)
    r = octave_rms(x, fs, Bands([0.0], [fs / 2], ("all",)), window="hann")
    assert r.mean_square[0] == pytest.approx(1.7**2 / 2, rel=1e-12)


def test_a_psd_without_a_unit_has_levels_re_1_as_band_levels_do():
    """Review X D3: ``psd(x, fs).level_db()`` of a signal without a unit raised (a reference asked
    for), while ``octave_rms(...).level_db()`` of the same signal gives dB re 1 (docs/nvh.md, "Levels
    and references"): both take the reference 1 now, so the level is 10 log10 of the density."""
    x = np.sin(2 * np.pi * 100.0 * np.arange(8192) / FS)
    p = psd(x, FS, nperseg=1024)
    np.testing.assert_allclose(p.level_db(), 10 * np.log10(p.density), rtol=1e-14)
    np.testing.assert_allclose(p.level_db(ref=2.0), 10 * np.log10(p.density / 4.0), rtol=1e-14)


def test_the_default_resolution_counts_only_the_lines_below_nyquist():
    """Review X D4: with f_max above fs / 2 (1000-1800 Hz at 2048 Hz) the default segment counted 16
    lines over 1000-1800 Hz, of which only 1000-1024 Hz exist: one line (df = 32 Hz). The lines above
    fs / 2 are no longer counted: 16 lines or more within 1000-1024 Hz (df <= 1.5 Hz)."""
    fs = 2048.0
    x = np.random.default_rng(1).standard_normal(int(60 * fs))
    p = psd(x, fs, f_min=1000.0, f_max=1800.0)
    within = (p.f_hz >= 1000.0) & (p.f_hz <= fs / 2)
    assert within.sum() >= 16, (fs / p.nperseg, within.sum())


def test_a_resolution_coarser_than_the_least_segment_is_refused_by_its_name():
    """Review X D2: --resolution 1000 at 2048 Hz was refused naming ``nperseg = 2``, and
    ``apparent_mass(..., resolution_hz=1000)`` at 5 kHz raised the segment to 16 samples without a
    word. Both refuse it naming the resolution and the coarsest allowed: fs / 8 for a PSD, fs / 16 for
    a transfer function."""
    from cablecasing_core.nvh.spectra import segment_for_resolution
    from cablecasing_core.nvh.transfer import MIN_AVERAGES, MIN_SEGMENT

    # (the nearest power of two: 8 samples from fs / 8 sqrt 2 up, so the limit is 256 sqrt 2 = 362 Hz at 2048 Hz)
    with pytest.raises(ModelError, match=r"^--resolution = 1000.0: must be below 362 Hz at 2048 Hz sampling"):
        segment_for_resolution("--resolution", 1000.0, 2048.0, 4096)
    assert segment_for_resolution("--resolution", 256.0, 2048.0, 4096) == 8
    assert segment_for_resolution("--resolution", 360.0, 2048.0, 4096) == 8
    with pytest.raises(ModelError, match=r"^--resolution = 363.0: must be below 362 Hz"):
        segment_for_resolution("--resolution", 363.0, 2048.0, 4096)
    with pytest.raises(ModelError, match=r"^resolution_hz = 1000.0: must be below 441.9 Hz at 5000 Hz"):
        segment_for_resolution("resolution_hz", 1000.0, 5000.0, 5000, MIN_AVERAGES, MIN_SEGMENT)
    with pytest.raises(ModelError, match=r"^--resolution = 5e-324: must be at least"):  # (was an OverflowError)
        segment_for_resolution("--resolution", 5e-324, 2048.0, 4096)
