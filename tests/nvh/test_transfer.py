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
        "cablecasing: error: --resolution = 1.0: must be at least 2 Hz for the 1 s of record after --skip (3 averages "
        "of half-overlapping segments of a power of two samples; from one the coherence is 1 whatever the signals)"
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
