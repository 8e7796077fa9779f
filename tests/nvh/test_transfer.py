"""The apparent mass estimated from a simulated record (H1, through identification.frf) against the
frequency domain's TRFAM, within the coherence-based bound; and the transmissibility's definition."""

import numpy as np
import pytest
from scipy.signal import get_window

import cablecasing_core as cc
from cablecasing_core import ModelError
from cablecasing_core.nvh import apparent_mass, transmissibility


@pytest.fixture(scope="module")
def linear_run():
    """3 s of the built-in scenario with contact off: the casing is a linear system driven at A in
    z (the cable's drive moves only the cable), recorded with its support inputs."""
    model = cc.load_model()
    return model, cc.simulate(model, duration=3.0, contact=False).records()


def _window_smoothed_trfam(model, f, fs, nperseg, oversample=16, half_width=8):
    """The expectation of a Welch H1 estimate of a linear system under a flat input spectrum: the
    TRFAM averaged over the Hann window's spectral window |W(f' - f)|^2 (Bendat & Piersol 11.4:
    E[G_xy] = integral |W|^2 H G_xx), on a grid of df / oversample over +-half_width bins."""
    df = fs / nperseg
    w2 = np.abs(np.fft.fft(get_window("hann", nperseg), oversample * nperseg)) ** 2
    m = half_width * oversample
    kernel = np.concatenate([w2[-m:], w2[: m + 1]])
    offsets = np.arange(-m, m + 1) * df / oversample
    H = cc.trfam(model, "casing.A.z", "casing.B.z", (f[:, None] + offsets).ravel(), "viscous")
    return (H.reshape(len(f), -1) * kernel).sum(axis=1) / kernel.sum()


@pytest.mark.slow  # a 3 s run and 27 000 TRFAM frequencies
def test_h1_of_a_linear_run_is_the_trfam_within_the_coherence_bound(linear_run):
    model, rec = linear_run
    tr = apparent_mass(rec, "casing.A.az", "casing.B.Fz", resolution_hz=4.0)
    fs, nper = rec.fs, 2 * (len(tr.f_hz) - 1)
    assert tr.unit == "kg" and tr.n_averages >= 15
    k = np.nonzero((tr.f_hz >= 30) & (tr.f_hz <= 975))[0][::3]  # every third bin of the band, 160
    f = tr.f_hz[k]
    expected = _window_smoothed_trfam(model, f, fs, nper)
    # the bound: |H1 - E[H1]| <= (4 eps + 0.01) |E[H1]|, eps = sqrt(1 - g^2) / (|g| sqrt(2 n_d)) the
    # normalized random error of Bendat & Piersol Eq. 9.90 from the coherence g^2 and the n_d averages
    # (4 standard deviations: exceeded with probability 6e-5 per frequency), 0.01 for Newmark's period
    # error ((w dt)^2 / 12 <= 3.3e-4 at 1 kHz) amplified by the resonances' Q ~ 25
    rel = np.abs(tr.H1[k] - expected) / np.abs(expected)
    bound = 4 * tr.error[k] + 0.01
    assert np.all(rel <= bound), (f[rel > bound], rel[rel > bound], bound[rel > bound])
    # ... and the bound is not loose: the errors are the random error's size (median |z| ~ 1), and
    # a casing 3 % stiffer than the one simulated (its resonances 1.5 % higher) is found out
    assert 0.3 < np.median(rel / tr.error[k]) < 3
    stiffer = model.with_overrides({"casing.E": 1.03 * model.bodies["casing"].E_ref})
    other = _window_smoothed_trfam(stiffer, f, fs, nper)
    assert np.sum(np.abs(tr.H1[k] - other) / np.abs(other) > bound) > 10


def test_transmissibility_is_the_ratio_of_the_support_forces_and_checks_its_signals(linear_run):
    model, rec = linear_run
    T = transmissibility(rec, "casing.A.Fz", "casing.B.Fz", resolution_hz=8.0)
    M_A = apparent_mass(rec, "casing.A.az", "casing.A.Fz", resolution_hz=8.0)
    M_B = apparent_mass(rec, "casing.A.az", "casing.B.Fz", resolution_hz=8.0)
    band = (T.f_hz > 20) & (T.f_hz < 900)
    # for a linear system the force ratio B/A is the ratio of the two apparent masses, to the random
    # errors of the three estimates (Bendat & Piersol Eq. 9.90 each; 4 standard deviations of their sum)
    ratio = M_B.H1 / M_A.H1
    tol = 4 * (T.error + M_A.error + M_B.error)
    assert np.all((np.abs(T.H1 - ratio) / np.abs(ratio))[band] <= tol[band])
    assert T.unit == "1"
    with pytest.raises(ModelError, match="acceleration"):
        apparent_mass(rec, "casing.A.Fz", "casing.B.Fz")
    with pytest.raises(ModelError, match="one unit"):
        transmissibility(rec, "casing.A.az", "casing.B.Fz")


def test_a_transfer_estimate_of_fewer_than_three_averages_is_refused(tmp_path, capsys):
    """From one Welch average the coherence is 1 whatever the signals (|G_xy|^2 = G_xx G_yy for one
    segment), so an estimate that would average fewer than three is refused, by the API naming
    nperseg and by ``spectrum`` naming --resolution with the finest one the record allows; at three
    the coherence of two independent noises is already well below 1."""
    from cablecasing_core.cli import main
    from cablecasing_core.records import Records

    rng = np.random.default_rng(1)
    n, fs = 4096, 4096.0
    t = np.arange(n) / fs
    rec = Records(t, {"casing.A.az": rng.normal(size=n), "casing.B.Fz": rng.normal(size=n)})
    rec.units.update({"casing.A.az": "m/s2", "casing.B.Fz": "N"})
    with pytest.raises(ModelError, match=r"nperseg = 4096: must leave at least 3 Welch averages .* at most 2048"):
        apparent_mass(rec, skip=0.0, nperseg=4096)
    three = apparent_mass(rec, skip=0.0, nperseg=2048)
    assert three.n_averages == 3 and np.median(three.coherence[1:]) < 0.6
    cc.records.write_records(tmp_path / "r.npz", rec)
    args = ["spectrum", str(tmp_path / "r.npz"), "--kind", "apparent-mass", "--skip", "0", "--fmin", "4"]
    assert main(args + ["--resolution", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (
        "cablecasing: error: --resolution = 1.0: must be at least 2 Hz for the 1 s of record after the skip "
        "(3 averages of half-overlapping segments of a power of two samples; from one the coherence is 1 whatever "
        "the signals)"
    ), err
    assert main(args + ["--resolution", "2"]) == 0 and "3 averages" in capsys.readouterr().out


def test_transfer_and_level_helpers_refuse_bad_input_by_name():
    """nperseg, resolution_hz and a level's reference are checked (0 gave ZeroDivisionError, NaN a
    ValueError, a reference of 0 inf), a NaN in a column is named by the column, and a constant
    input is refused before Gxx = 0 makes H1 and the coherence 0/0."""
    from cablecasing_core.identification import frf_estimate
    from cablecasing_core.nvh import level_db
    from cablecasing_core.records import Records

    rng = np.random.default_rng(2)
    t = np.arange(2048) / 1024.0
    acc, force = rng.normal(size=t.size), rng.normal(size=t.size)
    rec = Records(t, {"casing.A.az": acc, "casing.B.Fz": force}, {"casing.A.az": "m/s2", "casing.B.Fz": "N"})
    for kwargs, key in (({"nperseg": 0}, "nperseg"), ({"resolution_hz": float("nan")}, "resolution_hz")):
        with pytest.raises(ModelError) as e:
            apparent_mass(rec, skip=0.0, **kwargs)
        assert e.value.key == key
    bad = Records(t, {"casing.A.az": np.where(t > 1, np.nan, acc), "casing.B.Fz": force}, rec.units)
    with pytest.raises(ModelError, match=r"casing.A.az = 'array with nan/inf'"):
        apparent_mass(bad, skip=0.0)
    with pytest.raises(ModelError) as e:
        level_db([1.0], 0.0)
    assert e.value.key == "ref"
    with pytest.raises(ModelError, match=r"x = 'a constant signal': must vary"):
        frf_estimate(np.zeros(256), force[:256], 1024.0)


def _records(x, y, fs, names=("casing.A.az", "casing.B.Fz"), units=("m/s2", "N")):
    from cablecasing_core.records import Records

    t = np.arange(x.size) / fs
    return Records(t, {names[0]: x, names[1]: y}, dict(zip(names, units)))


def test_the_random_error_of_h1_is_the_scatter_of_h1_over_independent_records():
    """Bendat & Piersol Eq. 9.90: the normalized random error eps = sqrt(1 - g^2) / (|g| sqrt(2 n_d))
    is the standard deviation of |H1| / |H| - 1. y = -2 x + noise of twice x's RMS: H = 2 kg
    (apparent_mass negates the force), g^2 = 4 / (4 + 4) = 0.5; 300 records of n_d = 31 averages
    (eps = 0.127). The measured scatter over 300 x 29 lines is known to ~2 %, and Hann's 50 % overlap
    raises the variance by ~6 % over independent averages (Welch): 15 % covers both, and a factor
    sqrt(2) in eps (n_d for 2 n_d, or 2 n_d for n_d) is 41 % off."""
    rng = np.random.default_rng(7)
    fs, nper = 1024.0, 64
    rel, eps = [], []
    for _ in range(300):
        x = rng.standard_normal(1024)
        y = -2.0 * x + 2.0 * rng.standard_normal(1024)
        tr = apparent_mass(_records(x, y, fs), skip=0.0, nperseg=nper)
        assert tr.n_averages == 31
        k = slice(2, 31)  # lines away from 0 Hz and Nyquist (real-valued there)
        rel.append(np.abs(tr.H1[k]) / 2.0 - 1)
        eps.append(tr.error[k])
    ratio = np.std(np.concatenate(rel)) / np.median(np.concatenate(eps))
    assert abs(ratio - 1) < 0.15, ratio


@pytest.mark.parametrize("estimator, expected", [("H1", 1 / 1.25), ("H2", 1.0)])
def test_the_estimator_asked_for_is_the_one_returned(estimator, expected):
    """Input noise of half the input's RMS (Gmm / Guu = 0.25) on a pure gain of 2 with one sample of
    delay: H2 is unbiased (H), H1 = H / 1.25 (Bendat & Piersol 9.2), both with H's phase -2 pi f / fs.
    2^16 samples, 511 averages: the mean over 100 lines scatters by ~0.2 % (eps ~ 1.6 % per line),
    the one-sample delay biases |H| by 1/256 (B&P 9.3.1): 2 % is ample, the H1-H2 gap is 20 %; a
    conjugate lost in H2 = Gyy / Gyx turns its phase to +2 pi f / fs, up to 2.6 rad off here."""
    rng = np.random.default_rng(3)
    fs, n = 1024.0, 2**16
    u = rng.standard_normal(n)
    x = u + 0.5 * rng.standard_normal(n)
    y = 2.0 * np.roll(u, 1)
    rec = _records(x, y, fs, ("casing.A.Fz", "casing.B.Fz"), ("N", "N"))
    T = transmissibility(rec, estimator=estimator, skip=0.0, nperseg=256)
    assert T.estimator == estimator
    k = (T.f_hz > 20) & (T.f_hz < 420)
    H = 2.0 * np.exp(-2j * np.pi * T.f_hz[k] / fs)
    assert np.mean(np.abs(T.H[k])) / 2.0 == pytest.approx(expected, abs=0.02)
    phase = np.angle(T.H[k] / H)  # each line's phase error scatters by ~eps = 0.016 rad
    assert abs(np.mean(phase)) < 0.01 and np.max(np.abs(phase)) < 0.1  # 5 and 6 standard deviations


def test_the_default_resolution_keeps_at_least_15_averages():
    """The docstring's default: 1 Hz, but segments of at most an eighth of the record, so at least
    15 averages (a 4 s record at 4096 Hz: 2048-sample segments, 2 Hz, 15 averages); a 16 s one
    resolves 1 Hz (31 averages). Counted, not estimated: exact."""
    rng = np.random.default_rng(0)
    fs = 4096.0
    for seconds, df, averages in ((4, 2.0, 15), (16, 1.0, 31)):
        x = rng.standard_normal(int(seconds * fs))
        tr = apparent_mass(_records(x, -x + rng.standard_normal(x.size), fs), skip=0.0)
        assert tr.f_hz[1] == df and tr.n_averages == averages


def _record_with_a_line(fs=10000.0, duration=0.5):
    """Noise through a simple linear filter with a 50 Hz line, stating the line (lines_hz) as a
    run's record does: its default skip is 0.06 s (whole periods of 50 Hz in the rest), not 0.05 s."""
    from cablecasing_core.records import Records

    rng = np.random.default_rng(3)
    t = np.arange(int(round(duration * fs)) + 1) / fs
    a = rng.normal(size=t.size) + np.sin(2 * np.pi * 50 * t)
    f = np.convolve(a, [0.5, 0.3, 0.2], mode="same") + 0.1 * rng.normal(size=t.size)
    cols = {"casing.A.az": a, "casing.A.Fz": a + 0.2 * rng.normal(size=t.size), "casing.B.Fz": f}
    units = {"casing.A.az": "m/s2", "casing.A.Fz": "N", "casing.B.Fz": "N"}
    return Records(t, cols, units, extra={"lines_hz": np.array([50.0])})


def test_a_resolution_finer_than_the_record_allows_is_refused_by_the_api_as_by_spectrum(tmp_path, capsys):
    """One rule for ``resolution_hz`` and ``spectrum --resolution``: a segment that leaves fewer than
    3 averages after the skip is refused naming the value and the finest resolution the record allows
    (the API used to coarsen it silently); one it allows is kept, rounded to the nearest power of two
    of samples (6 Hz and 4.9 Hz both give 2048 samples at 10 kHz)."""
    from cablecasing_core.cli import main
    from cablecasing_core.nvh.transfer import finest_resolution

    rec = _record_with_a_line()  # 0.44 s after the default skip of 0.06 s: 4400 samples, at most 2048
    finest = finest_resolution(rec)
    assert finest == pytest.approx(10000.0 / 2048)
    for fn, inp in ((apparent_mass, "casing.A.az"), (transmissibility, "casing.A.Fz")):
        with pytest.raises(ModelError) as e:
            fn(rec, inp, "casing.B.Fz", resolution_hz=3.0)  # (4096 samples: one average of 4400)
        assert e.value.key == "resolution_hz"
        assert str(e.value).startswith("resolution_hz = 3.0: must be at least 4.883 Hz for the 0.44 s of record")
    assert np.diff(apparent_mass(rec, resolution_hz=finest).f_hz)[0] == pytest.approx(finest)
    assert np.diff(apparent_mass(rec, resolution_hz=6.0).f_hz)[0] == pytest.approx(finest)  # (2048 samples)
    cc.records.write_records(tmp_path / "r.npz", rec)
    assert main(["spectrum", str(tmp_path / "r.npz"), "--kind", "apparent-mass", "--resolution", "3"]) == 2
    cli = capsys.readouterr().err.strip()
    api = str(e.value).split(": ", 1)[1]
    assert cli == f"cablecasing: error: --resolution = 3.0: {api}", (cli, api)


def test_the_api_and_spectrum_take_the_same_samples_by_default(tmp_path, capsys):
    """skip=None (the default) is the record's default_skip(), as ``spectrum`` and ``bands`` take
    it: 0.06 s of a 0.5 s record stating a 50 Hz line, so the API's estimate and the command's table
    of one record are the same numbers (the API took a bare 0.05 s)."""
    from cablecasing_core.cli import main
    from cablecasing_core.records import read_records

    rec = _record_with_a_line()
    path = tmp_path / "r.npz"
    cc.records.write_records(path, rec)
    rec = read_records(path)
    assert rec.default_skip() == pytest.approx(0.06)
    for kind, fn, inp in (
        ("apparent-mass", apparent_mass, "casing.A.az"),
        ("transmissibility", transmissibility, "casing.A.Fz"),
    ):
        out = tmp_path / f"{kind}.csv"
        assert main(["spectrum", str(path), "--kind", kind, "--input", inp, "--out", str(out)]) == 0
        assert "after 0.06 s" in capsys.readouterr().out
        table = np.loadtxt(out, delimiter=",", skiprows=1)
        tr = fn(rec, inp, "casing.B.Fz")
        assert tr.n_averages == fn(rec, inp, "casing.B.Fz", skip=0.06).n_averages
        k = np.searchsorted(tr.f_hz, table[:, 0])
        np.testing.assert_allclose(tr.f_hz[k], table[:, 0])
        # (the command's table keeps 9 significant digits: 5e-9; atol for values near 0)
        np.testing.assert_allclose(tr.H.real[k], table[:, 1], rtol=1e-8, atol=1e-12)
        np.testing.assert_allclose(tr.coherence[k], table[:, 3], rtol=1e-8)
        np.testing.assert_array_equal(fn(rec, inp, "casing.B.Fz", skip=0.06).H, tr.H)
        assert not np.array_equal(fn(rec, inp, "casing.B.Fz", skip=0.05).H, tr.H)
