"""Review AT: the apparent-mass CSV names its sign (AT1), Welch's segments span the whole record
(AT2), and the report says how many lines its median coherence is taken over (AT4)."""

import csv

import numpy as np
import pytest
from scipy import signal

from cablecasing_core.cli import main
from cablecasing_core.identification.frf import frf_estimate, welch_averages, welch_overlap
from cablecasing_core.nvh import psd
from cablecasing_core.records import Records, write_records

# ---------------------------------------------------------------- AT1: the apparent mass's sign


def test_the_apparent_mass_csv_header_names_the_negated_force_its_values_hold(tmp_path, capsys):
    """The recorded force is -m a plus noise (m = 0.3 kg: what a rigid mass of 0.3 kg exerts on its
    support): the TRFAM-convention apparent mass is +0.3 kg. The file's header must name what its
    values are the ratio of, so that H1 of the columns it names, with the sign it names, computed
    independently (scipy.signal.csd / welch over the file's segment), equals the file's values to the
    9 digits written (1e-7 relative). Before, the header said casing.B.Fz/casing.A.az over values of
    about +0.3, the negative of that ratio."""
    rng = np.random.default_rng(3)
    fs, n = 4096.0, 4096 * 8
    t = np.arange(n) / fs
    a = rng.standard_normal(n)
    F = -0.3 * a + 0.01 * rng.standard_normal(n)
    rec = Records(t, {"casing.A.az": a, "casing.B.Fz": F})
    rec.units.update({"casing.A.az": "m/s2", "casing.B.Fz": "N"})
    write_records(tmp_path / "r.npz", rec)
    out = tmp_path / "am.csv"
    assert (
        main(["spectrum", str(tmp_path / "r.npz"), "--kind", "apparent-mass", "--skip", "0"] + ["--out", str(out)]) == 0
    )
    said = capsys.readouterr().out
    assert "(-casing.B.Fz)/casing.A.az: the TRFAM's sign convention" in said
    with open(out) as f:
        header = next(csv.reader(f))
    assert header[1] == "re (-casing.B.Fz)/casing.A.az [kg]" and header[2] == "im (-casing.B.Fz)/casing.A.az [kg]"
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    nper = round(fs / (table[1, 0] - table[0, 0]))
    noverlap = welch_overlap(n, nper)
    kw = dict(fs=fs, nperseg=nper, noverlap=noverlap)
    f, Gaa = signal.welch(a, **kw)
    _, GaF = signal.csd(a, -F, **kw)  # (the ratio the header names: the recorded force negated)
    H = np.interp(table[:, 0], f, (GaF / Gaa).real)
    np.testing.assert_allclose(table[:, 1], H, rtol=1e-7)
    assert np.median(table[:, 1]) == pytest.approx(0.3, rel=0.01)  # (positive: the header's sign)


# ---------------------------------------------------------------- AT2: segments that span the record


@pytest.mark.parametrize("least", [0.5, 0.0, 0.75])
def test_welch_segments_span_the_record_to_its_last_few_samples(least):
    """For segment lengths 8 to 8192 and records of one to 40 segments: the overlap is at least the
    one asked for, the first segment starts at sample 0 and scipy's last one (counted as
    scipy.signal.welch counts them, 1 + (n - nperseg) // step) ends fewer than ``averages`` samples
    before the record's end; at 50 % Welch's own tail (n - nperseg) % (nperseg / 2) may reach half a
    segment less one."""
    rng = np.random.default_rng(0)
    for _ in range(3000):
        nper = int(2 ** rng.integers(3, 14))
        n = int(rng.integers(nper, 40 * nper))
        want = int(round(least * nper))
        nov = welch_overlap(n, nper, want)
        step = nper - nov
        k = 1 + (n - nper) // step
        assert nov >= want and k == welch_averages(n, nper, nov)
        end = (k - 1) * step + nper
        assert end <= n and n - end <= max(k - 1, 0), (n, nper, nov, k)
    assert welch_overlap(44000, 8192) == 4214 and welch_averages(44000, 8192) == 10  # (the 0.44 s of a 0.5 s run)


def test_the_psd_weighs_a_tone_in_the_last_7_percent_of_the_record_as_one_in_the_first():
    """A tone only in the last 7 % of 44000 samples (3080, the review's tail) over weak noise: the
    PSD integrates its power as it does the same tone in the first 7 % (the segments span the record
    and both ends of it lie under the falling or rising half of a Hann window alike): within 1 %
    (the periodic Hann window is one sample off symmetric and the last segment ends up to 9 samples
    before the record's end: 3 % of a tail weighted by w^2 ~ (pi t / N)^4, well under 1 % of the
    tone's power read). An independent check of the integral: the Welch weights summed in the time
    domain, sum_t x(t)^2 w^2(t - s_k) / (K sum w^2), over the segments starting at s_k = k step (the
    PSD's own Parseval, exact per segment, 1e-9 for the mean removed per segment). With 50 % overlap
    Welch left the last 3040 samples out and read 2 % of the tail's power (its 40 first samples)."""
    fs, n, nper = 1e5, 44000, 8192
    t = np.arange(n) / fs
    noise = 1e-3 * np.random.default_rng(1).standard_normal(n)
    tail = (t >= t[-1] * 0.93).astype(float)  # (the last 7 %)
    tone = np.sin(2 * np.pi * 1000.0 * t)
    late, early = noise + tone * tail, noise + tone * tail[::-1]
    pl, pe = psd(late, fs, nperseg=nper), psd(early, fs, nperseg=nper)
    tail_ms = np.mean((tone * tail) ** 2)  # (the tone's share of the record's mean square)
    read_l, read_e = pl.mean_square() - np.var(noise), pe.mean_square() - np.var(noise)
    assert read_l == pytest.approx(read_e, rel=0.01)
    assert 0.2 * tail_ms < read_l < tail_ms  # (the end's half window weighs it, but does not leave it out)
    # the integral as the Welch weights in the time domain: the segments the PSD says it averaged
    step = nper - pl.noverlap
    w = signal.get_window("hann", nper)
    ms = np.mean(
        [np.sum(w**2 * (s - s.mean()) ** 2) for s in (late[k * step : k * step + nper] for k in range(pl.n_averages))]
    )
    assert pl.mean_square() == pytest.approx(ms / np.sum(w**2), rel=1e-9)
    # what 50 % overlap read: Welch over whole steps only
    f, G = signal.welch(late, fs=fs, nperseg=nper, noverlap=nper // 2)
    assert np.sum(G) * f[1] - np.var(noise) < 0.05 * read_l


def test_transfer_estimates_share_the_psds_segments():
    """One segmentation: frf_estimate's input density is psd()'s of the same samples to round-off,
    with the same number of averages (44000 samples, 8192 per segment: 10, not the 9 of 50 %)."""
    rng = np.random.default_rng(2)
    x, y = rng.standard_normal(44000), rng.standard_normal(44000)
    est = frf_estimate(x, y, 1e5, nperseg=8192)
    p = psd(x, 1e5, nperseg=8192)
    assert est.n_averages == p.n_averages == 10
    np.testing.assert_allclose(est.Gxx, p.density, rtol=1e-12)


# ---------------------------------------------------------------- AT4: the median's line count


def _am(lines_100, lines_1000, coarse_100, coarse_1000):
    return {
        "input": "casing.A.az",
        "n_averages": 5,
        "n_effective": 4.24,
        "df": 24.41,
        "median_coherence": {"10-100": 0.371, "10-1000": 0.861},
        "median_lines": {"10-100": lines_100, "10-1000": lines_1000},
        "expected_coherence": {"10-100": 0.30, "10-1000": 0.85},
        "input_bands": [(10.0, 1000.0)],
        "other_inputs": [],
        "contact": False,
        "narrow_modes": [],
        "coarser": {
            "df": 97.66,
            "n_averages": 26,
            "median_coherence": {"10-100": 0.110, "10-1000": 0.119},
            "median_lines": {"10-100": coarse_100, "10-1000": coarse_1000},
        },
    }


def test_the_report_gives_the_lines_of_each_median_and_no_median_of_too_few():
    """The review's 0.45 s report: 4 lines of 24.4 Hz in 10-100 Hz, 1 of 97.7 Hz; 41 and 10 in
    10-1000 Hz. A median of fewer than MIN_MEDIAN_LINES (5) lines is not given as one; the others
    carry their line count."""
    from cablecasing_core.report.figures import MIN_MEDIAN_LINES
    from cablecasing_core.report.page import apparent_mass_note

    assert MIN_MEDIAN_LINES == 5
    text = apparent_mass_note(_am(4, 41, 1, 10), "without the cable drive")
    assert "no meaningful median over 10-100 Hz, which holds 4 lines (a median needs at least 5)" in text
    assert "median 0.86 over 10-1000 Hz (41 lines)" in text and "0.37" not in text
    assert "no meaningful median over 10-100 Hz, which holds 1 line (" in text
    assert "median 0.12 over 10-1000 Hz (10 lines)" in text and "0.11" not in text
    assert "leaves no figure and 0.85" in text
    text = apparent_mass_note(_am(15, 163, 4, 41), "without the cable drive")
    assert "median 0.37 over 10-100 Hz (15 lines)" in text and "leaves 0.30 and 0.85" in text


def test_the_transfer_s_random_error_counts_the_independent_averages_of_its_overlapping_segments():
    """Transfer.error is Bendat & Piersol's random error with the averages its segments are worth
    (FRFEstimate.n_effective: they overlap by at least 50 %, so fewer than the segments), as
    identification.frf's test of H1's scatter measures it; with the segments' count it would be
    smaller by sqrt(n_effective / n_averages)."""
    from cablecasing_core.identification.frf import random_error
    from cablecasing_core.nvh import transmissibility

    rng = np.random.default_rng(3)
    t = np.arange(40_000) / 10_000.0  # s, at 10 kHz
    a = rng.standard_normal(t.size)
    rec = Records(t, {"casing.A.Fz": a, "casing.B.Fz": a + 0.5 * rng.standard_normal(t.size)}, {})
    tr = transmissibility(rec, skip=0.0, nperseg=2048)
    est = frf_estimate(a, rec.column("casing.B.Fz"), 10_000.0, nperseg=2048)
    assert tr.n_averages == est.n_averages and est.n_effective < 0.96 * est.n_averages
    np.testing.assert_allclose(tr.error, random_error(tr.coherence, est.n_effective), rtol=1e-12)
