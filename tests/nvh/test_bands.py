"""Octave-band RMS (Section 4.4, Table 3) against theory: tones, Parseval, white noise, IEC edges."""

import numpy as np
import pytest

from cablecasing_core.errors import ModelError
from cablecasing_core.nvh.bands import TABLE3_LOWER, TABLE3_UPPER, Bands, octave_bands, octave_rms, window_options

RECT = window_options("boxcar")  # the rectangular window, no detrending: Parseval exact

FS = 20000.0  # Hz; with n = FS samples (1 s) the bins fall on whole hertz


def test_table3_edges():
    # the paper's Table 3 ("The limit values of the octave bands"), written out here, not taken
    # from the module: f_lo and f_up (Hz) of bands 1..9; each band's upper edge is the next one's lower
    f_lo = [11, 22, 44, 88, 177, 355, 710, 1420, 2840]
    f_up = [22, 44, 88, 177, 355, 710, 1420, 2840, 5680]
    b = octave_bands()
    assert b.labels == tuple(f"oct{i}" for i in range(1, 10))
    np.testing.assert_array_equal(b.lower, f_lo)
    np.testing.assert_array_equal(b.upper, f_up)
    np.testing.assert_array_equal(TABLE3_LOWER, f_lo)  # (the module's constants, which the docs quote)
    np.testing.assert_array_equal(TABLE3_UPPER, f_up)
    np.testing.assert_allclose(b.centre, np.sqrt(np.array(f_lo, float) * f_up), rtol=1e-15)  # geometric centre


def test_sum_of_sines_lands_in_bands():
    # one tone per band on a bin centre >= df/2 away from every edge: band RMS = A/sqrt(2) exactly
    # (rounding only: 1e-9 relative), every other band empty (leakage-free, rectangular window).
    t = np.arange(int(FS)) / FS
    freqs = [15, 30, 60, 120, 250, 500, 1000, 2000, 4000]
    amps = [1.0, 0.5, 2.0, 0.1, 3.0, 0.7, 1.3, 0.05, 0.9]
    x = 7.0 + sum(a * np.sin(2 * np.pi * f * t + 0.3 * k) for k, (f, a) in enumerate(zip(freqs, amps)))
    r = octave_rms(x, FS)
    np.testing.assert_allclose(r.rms, np.array(amps) / np.sqrt(2), rtol=1e-9)
    # the 7.0 mean stays in bin 0, outside Table 3
    assert r.as_dict()["oct1"] == pytest.approx(1 / np.sqrt(2), rel=1e-9)


def test_two_tones_in_one_band_add_in_power():
    t = np.arange(int(FS)) / FS
    x = 3 * np.sin(2 * np.pi * 400 * t) + 4 * np.cos(2 * np.pi * 600 * t)  # both in 355-710 Hz
    r = octave_rms(x, FS).as_dict()
    assert r["oct6"] == pytest.approx(np.sqrt((9 + 16) / 2), rel=1e-9)  # 5/sqrt(2)


def test_tone_on_an_edge_bin_is_split_half_and_half():
    # bin 22 covers [21.5, 22.5] Hz; the 22 Hz edge splits it proportionally: A^2/4 to each band
    t = np.arange(int(FS)) / FS
    r = octave_rms(2.0 * np.sin(2 * np.pi * 22 * t), FS)
    np.testing.assert_allclose(r.mean_square[:2], [1.0, 1.0], rtol=1e-9)


def test_off_bin_tone_with_hann_window():
    # a tone between bins, mid-band; Hann main lobe (+-2 bins) stays inside 710-1420 Hz and the
    # power normalisation by mean(w^2) is exact up to a 1/(number of periods) ripple: 1 % is ample.
    t = np.arange(int(FS)) / FS
    r = octave_rms(1.5 * np.sin(2 * np.pi * 1000.37 * t), FS, window="hann")
    assert r.as_dict()["oct7"] == pytest.approx(1.5 / np.sqrt(2), rel=1e-2)
    assert r.rms[[5, 7]].max() < 1e-3 * r.rms[6]


@pytest.mark.parametrize("n", [4096, 4097])
def test_parseval_over_bands_covering_zero_to_nyquist(n):
    # bands that tile [0, fs/2] with edges off the bin grid: through the rectangular window, sum of
    # band mean squares = mean(x^2), exactly up to rounding (1e-12), for even and odd n (Nyquist bin or not).
    rng = np.random.default_rng(0)
    fs = 1000.0
    x = 2.5 + rng.standard_normal(n) + np.sin(2 * np.pi * 123.4 * np.arange(n) / fs)
    edges = np.array([0.0, 0.3, 7.77, 50.05, 123.45, 300.0, 480.01, fs / 2])
    r = octave_rms(x, fs, Bands(edges[:-1], edges[1:], tuple(f"b{i}" for i in range(7))), **RECT)
    assert r.mean_square.sum() == pytest.approx(np.mean(x**2), rel=1e-12)
    np.testing.assert_allclose(r.bins.sum(), n // 2 + 1, rtol=1e-12)


def test_parseval_table3_plus_complement():
    rng = np.random.default_rng(1)
    x = rng.standard_normal(int(FS))
    b = octave_bands()
    lo = np.r_[0.0, b.lower, b.upper[-1]]
    up = np.r_[b.lower[0], b.upper, FS / 2]
    r = octave_rms(x, FS, Bands(lo, up, tuple(f"b{i}" for i in range(lo.size))), **RECT)
    assert r.mean_square.sum() == pytest.approx(np.mean(x**2), rel=1e-12)


@pytest.mark.parametrize("window", ["boxcar", "hann"])
def test_white_noise_mean_square_proportional_to_bandwidth(window):
    # Gaussian white noise of variance s2: band mean square -> s2 * bw / (fs/2) through either window
    # (Hann's power-normalised). Through the rectangular one each one-sided bin is s2 (2/n) times a
    # unit exponential, so a band of K bins has relative std 1/sqrt(K); Hann's neighbouring bins are
    # correlated, which raises the variance of their sum by n sum(w^4) / sum(w^2)^2 = 35/18: allow 4
    # standard deviations per band (chance of a false failure < 1e-3 over 9 bands; seed fixed).
    rng = np.random.default_rng(2)
    s2 = 0.04
    n = 2**20
    fs = 16384.0
    x = np.sqrt(s2) * rng.standard_normal(n)
    r = octave_rms(x, fs, **window_options(window))
    expected = s2 * (r.upper - r.lower) / (fs / 2)
    rel = r.mean_square / expected - 1
    sd = np.sqrt((1.0 if window == "boxcar" else 35 / 18) / r.bins)
    assert np.all(np.abs(rel) < 4 * sd), (rel, sd)


def test_the_rectangular_windows_leakage_swamps_a_weak_band_and_hanns_does_not():
    """Why the band levels take Hann's window: a strong 10 N tone at 50.5 Hz (50.5 periods in a 1 s
    record, so its periodic extension jumps by J = x(T) - x(0) = -20 sin(0.3) N at the record's end)
    beside a weak 0.01 N tone at 4000 Hz, on its bin, alone in octave 9. Through the rectangular
    window the jump puts |X_k|^2 ~ (J n / (2 pi k))^2 in bin k far above the tone (a sawtooth's
    spectrum), so octave 9's bins k = 2840 .. 5680 hold J^2 / (2 pi^2) (1/2840 - 1/5680) = 3.1e-4 N^2
    beside the tone's own 5e-5 N^2: octave 9 reads 0.019 N for 0.0071 N (within 10 %: 1/k for the two
    images' 1/(k -+ 50.5), the sum taken as its integral). Hann's tail falls as 1/m^6 and its main
    lobe keeps the on-bin tone in its band: octave 9 reads 0.01/sqrt 2 within 1e-6 of itself."""
    t = np.arange(int(FS)) / FS
    x = 10.0 * np.sin(2 * np.pi * 50.5 * t + 0.3) + 0.01 * np.sin(2 * np.pi * 4000.0 * t + 1.1)
    J = 10.0 * (np.sin(2 * np.pi * 50.5 + 0.3) - np.sin(0.3))
    leak = J**2 / (2 * np.pi**2) * (1 / 2840 - 1 / 5680)
    rect = octave_rms(x, FS, **RECT).rms[8]
    assert rect == pytest.approx(np.sqrt(leak + 0.01**2 / 2), rel=0.1)
    assert octave_rms(x, FS).rms[8] == pytest.approx(0.01 / np.sqrt(2), rel=1e-6)


def test_the_mean_is_removed_before_hanns_window():
    """Hann's window spreads a record's mean into bin 1 as well as bin 0: with a mean of 100 N over
    0.1 s, bin 1 (10 Hz, standing for 5-15 Hz) puts 4 of its 10 Hz into octave 1 (11-22 Hz), which
    would read sqrt(0.4 * 2 (100/4)^2 / (3/8)) = 36.5 N (Hann's window is 1/2 - cos / 2: bin 1 holds
    a quarter of the mean's amplitude; power-normalised by mean(w^2) = 3/8, one-sided twice). The
    default removes the mean first, so octave 1 holds nothing but the record's own content: a 0.5 N
    tone at 100 Hz (octave 4) on its bin leaves it empty, the tone's main lobe ending at 110 Hz."""
    t = np.arange(2000) / FS
    x = 100.0 + 0.5 * np.sin(2 * np.pi * 100.0 * t)
    kept = octave_rms(x, FS, detrend=None).rms[0]
    assert kept == pytest.approx(np.sqrt(0.4 * 2 * 25.0**2 / 0.375), rel=1e-9)
    assert octave_rms(x, FS).rms[0] < 1e-9


def test_iec_base10_edges():
    G = 10**0.3
    o = octave_bands("octave")
    k = o.labels.index("1000Hz")
    assert o.lower[k] == pytest.approx(1000 * G**-0.5, rel=1e-14)
    assert o.upper[k] == pytest.approx(1000 * G**0.5, rel=1e-14)
    np.testing.assert_allclose(o.upper[:-1], o.lower[1:], rtol=1e-14)  # contiguous
    np.testing.assert_allclose(o.centre[1:] / o.centre[:-1], G, rtol=1e-14)
    th = octave_bands("third")
    k = th.labels.index("1000Hz")
    assert (th.lower[k], th.upper[k]) == pytest.approx((1000 * G ** (-1 / 6), 1000 * G ** (1 / 6)), rel=1e-14)
    assert th.centre[0] == pytest.approx(10.0, rel=1e-12) and len(th) == 34  # 10 Hz .. 19.95 kHz
    np.testing.assert_allclose(th.centre[1:] / th.centre[:-1], G ** (1 / 3), rtol=1e-14)
    sel = octave_bands("third", f_min=100, f_max=1000)
    assert sel.labels[0] == "100Hz" and sel.labels[-1] == "1000Hz"


def test_third_octave_tone():
    t = np.arange(int(FS)) / FS
    r = octave_rms(np.sin(2 * np.pi * 1000 * t), FS, "third", beyond_nyquist="drop").as_dict()
    assert r["1000Hz"] == pytest.approx(1 / np.sqrt(2), rel=1e-9)


def test_detrend_linear_removes_a_ramp():
    t = np.arange(int(FS)) / FS
    x = 50 * t + np.sin(2 * np.pi * 300 * t)
    r = octave_rms(x, FS, detrend="linear")
    # the ramp's spectrum (1/f) would dominate oct1; after detrending only the 300 Hz tone is left
    # (plus the tiny projection of the tone on the ramp, < 1e-3 of its level)
    assert r.as_dict()["oct5"] == pytest.approx(1 / np.sqrt(2), rel=1e-3)
    assert r.rms[0] < 1e-2


def test_nyquist_rules():
    x = np.random.default_rng(3).standard_normal(10000)
    with pytest.raises(ModelError) as e:
        octave_rms(x, 10000.0)  # 2840-5680 Hz above fs/2 = 5000 Hz
    assert e.value.key == "fs" and "oct9" in e.value.allowed
    with pytest.raises(ModelError) as e:
        octave_rms(x, 5000.0)  # oct8 and oct9 above 2500 Hz: the rate named is the one that holds both
    assert "at least 2 x 5680 Hz = 11360 Hz so that bands 'oct8' to 'oct9'" in e.value.allowed, e.value.allowed
    r = octave_rms(x, 10000.0, beyond_nyquist="drop")
    assert r.labels == tuple(f"oct{i}" for i in range(1, 9))
    r = octave_rms(x, 10000.0, beyond_nyquist="nan")
    assert np.isnan(r.rms[8]) and np.all(np.isfinite(r.rms[:8]))
    assert octave_rms(x, 1000.0, beyond_nyquist="drop").labels[-1] == "oct5"  # 177-355 Hz < 500 Hz
    with pytest.raises(ModelError) as e:
        octave_rms(x, 30.0, beyond_nyquist="drop")  # even oct1 (22 Hz) is above 15 Hz
    assert e.value.key == "fs"


def test_a_decimated_records_passband_bounds_the_bands_as_nyquist_does():
    """A 5000 Hz tone (RMS 1/sqrt 2) decimated from 120 kHz to 12 kHz lies in oct9 (2840-5680 Hz),
    below the new Nyquist frequency 6000 Hz but above the filter's flat passband, 0.7 x 6000 =
    4200 Hz: oct9 reads it low, so with the record's passband the band is handled as beyond Nyquist
    (refused, dropped or nan) and the bands below keep their levels exactly."""
    from cablecasing_core.timedomain.simulation import decimate

    fs0, m = 120000.0, 10
    t = np.arange(240000) / fs0
    x = decimate(np.sin(2 * np.pi * 5000 * t) + np.sin(2 * np.pi * 1000 * t), m)[20:-20]  # (off the ends)
    fs, passband = fs0 / m, 0.7 * fs0 / m / 2
    blind = octave_rms(x, fs)  # (no passband: oct9 taken as measured)
    assert blind.as_dict()["oct9"] < 0.9 / np.sqrt(2)  # more than 1 dB low through the filter's edge
    with pytest.raises(ModelError) as e:
        octave_rms(x, fs, passband=passband)
    assert e.value.key == "fs" and "band 'oct9'" in e.value.allowed and "passband 4200 Hz" in e.value.allowed
    dropped = octave_rms(x, fs, beyond_nyquist="drop", passband=passband)
    assert dropped.labels == tuple(f"oct{i}" for i in range(1, 9))
    assert dropped.as_dict()["oct7"] == pytest.approx(1 / np.sqrt(2), rel=1e-3)  # (flat to 0.01 dB: 1.2e-3)
    assert np.isnan(octave_rms(x, fs, beyond_nyquist="nan", passband=passband).rms[8])
    with pytest.raises(ModelError, match="passband"):
        octave_rms(x, fs, passband=-1.0)


@pytest.mark.parametrize(
    "kwargs, key",
    [
        (dict(x=np.ones((4, 4)), fs=100.0), "x"),
        (dict(x=np.ones(100), fs=-1.0), "fs"),
        (dict(x=np.ones(100), fs=1e4, bands="decade"), "bands"),
        (dict(x=np.ones(100), fs=2e4), "x"),  # 5 ms: oct1 (11 Hz) < one 200 Hz bin
        (dict(x=np.ones(20000), fs=2e4, window="nope"), "window"),
        (dict(x=np.ones(20000), fs=2e4, detrend="quadratic"), "detrend"),
        (dict(x=np.ones(20000), fs=2e4, beyond_nyquist="ignore"), "beyond_nyquist"),
    ],
)
def test_bad_input_names_the_field(kwargs, key):
    with pytest.raises(ModelError) as e:
        octave_rms(**kwargs)
    assert e.value.key == key


def test_bad_bands():
    with pytest.raises(ModelError):
        Bands(np.array([10.0, 20.0]), np.array([20.0, 15.0]), ("a", "b"))
    with pytest.raises(ModelError):
        Bands(np.array([10.0]), np.array([20.0]), ("a", "b"))


def test_the_earlier_module_name_still_imports_every_name_of_the_band_library():
    # scripts and saved dask task paths may name cablecasing_core.studies.octave (the library's home
    # before nvh.bands): each public name of nvh.bands, and the bin sums of nvh.spectra, must be
    # there and be the very same object, so that results through either name are identical
    import cablecasing_core.nvh.bands as bands
    import cablecasing_core.studies.octave as old
    from cablecasing_core.nvh.spectra import band_sums, bin_edges

    public = [
        n
        for n, v in vars(bands).items()
        if not n.startswith("_")
        and getattr(v, "__module__", bands.__name__) == bands.__name__
        and not isinstance(v, type(bands))
    ]
    assert "octave_rms" in public and "bands_of" in public
    for n in public:
        assert getattr(old, n) is getattr(bands, n), n
    assert old.band_sums is band_sums and old.bin_edges is bin_edges
