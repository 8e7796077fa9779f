"""Review AT: the apparent-mass CSV names its sign (AT1), Welch's segments span the whole record
(AT2), and the report says how many lines its median coherence is taken over (AT4)."""

import csv
import re

import numpy as np
import pytest
from scipy import signal

from cablecasing_core.cli import main
from cablecasing_core.errors import ModelWarning
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


def scipy_segments(n, nperseg, noverlap):
    """(segments, samples after the last one) of Welch's segmenting as scipy takes it, read from scipy itself:
    scipy.signal.spectrogram segments a record as welch does (its densities are welch's segment for segment, checked
    in tests/identification/test_frf.py) and returns each segment's centre, (start + nperseg / 2) / fs."""
    _, t, _ = signal.spectrogram(np.zeros(n), fs=1.0, window="hann", nperseg=nperseg, noverlap=noverlap)
    assert t[0] == nperseg / 2  # (the first starts at sample 0)
    return t.size, n - round(t[-1] + nperseg / 2)


@pytest.mark.parametrize("least", [0.5, 0.0, 0.75])
def test_welch_segments_span_the_record_to_its_last_few_samples(least):
    """For segment lengths 8 to 8192 and records of one to 40 segments: the overlap is at least the
    one asked for, scipy's segments at it (counted by scipy.signal.spectrogram, not by the code's own
    formula) are as many as welch_averages says, the first starts at sample 0 and the last ends fewer
    than ``averages`` samples before the record's end; at 50 % Welch's own tail (n - nperseg) % (nperseg / 2)
    may reach half a segment less one. (800 records each: scipy's count costs an FFT a segment.)"""
    rng = np.random.default_rng(0)
    for _ in range(800):
        nper = int(2 ** rng.integers(3, 14))
        n = int(rng.integers(nper, 40 * nper))
        want = int(round(least * nper))
        nov = welch_overlap(n, nper, want)
        k, tail = scipy_segments(n, nper, nov)
        assert nov >= want and k == welch_averages(n, nper, nov), (n, nper, nov, k)
        assert 0 <= tail <= k - 1, (n, nper, nov, k, tail)
    assert welch_overlap(44000, 8192) == 4214 and welch_averages(44000, 8192) == 10  # (the 0.44 s of a 0.5 s run)
    assert scipy_segments(44000, 8192, 4214) == (10, 6) and scipy_segments(44000, 8192, 4096) == (9, 3040)


def test_the_least_overlap_is_at_least_the_fraction_asked_for():
    """Review AX3: the least overlap in samples is the fraction asked for rounded up (a record of one
    segment keeps it: no segment to add): an odd segment overlaps by at least 50 % (513 of 1025, not
    512; welch_overlap's default alike), and a product whole but for its last bit is not rounded
    up (0.55 * 100 = 55.00000000000001: 55)."""
    x = np.random.default_rng(2).standard_normal(1025)
    with pytest.warns(ModelWarning, match="averages only 1 segment"):
        assert psd(x, 1.0, nperseg=1025).noverlap == 513 == welch_overlap(1025, 1025)
    with pytest.warns(ModelWarning, match="averages only 1 segment"):
        assert psd(x[:100], 1.0, nperseg=100, overlap=0.55).noverlap == 55


def test_spectrum_s_psd_header_says_the_overlap_and_tail_of_scipys_segments(tmp_path, capsys):
    """Review AX5: the PSD's header line states the segments' overlap and the samples after the last
    one; read here from scipy on a record of 44000 samples (0.44 s at 100 kHz, the docs' example:
    51.4 %, 10 averages, 6 samples left). The overlap the header's rounded percentage allows (0.1 %
    of 8192: a few samples) that reproduces the written PSD with scipy.signal.welch, to the 9 digits
    written (1e-7 relative; white noise: another overlap changes the lines by up to percents), is the
    one used; scipy's own segmenting at it (scipy.signal.spectrogram) gives the averages and the
    tail the header states."""
    fs, n = 1e5, 44000
    x = np.random.default_rng(5).standard_normal(n)
    rec = Records(np.arange(n) / fs, {"casing.B.Fz": x})
    rec.units["casing.B.Fz"] = "N"
    write_records(tmp_path / "r.npz", rec)
    out_csv = tmp_path / "s.csv"
    assert main(["spectrum", str(tmp_path / "r.npz"), "--skip", "0", "--out", str(out_csv)]) == 0
    head = next(line for line in capsys.readouterr().out.splitlines() if "PSD (Welch" in line)
    said = re.search(
        r"overlapping by ([0-9.]+)%, at least 50 %.* to within (\d+) samples of its end\).*, (\d+) averages", head
    )
    assert said, head
    percent, tail, averages = float(said[1]), int(said[2]), int(said[3])
    table = np.loadtxt(out_csv, delimiter=",", skiprows=1)
    nperseg = round(fs / (table[1, 0] - table[0, 0]))  # (the default segment, from the lines written)
    line = np.round(table[:, 0] * nperseg / fs).astype(int)  # (the lines written, k df)
    fits = []
    for nov in range(nperseg // 2, nperseg):
        if round(100 * nov / nperseg, 1) == percent:
            _, G = signal.welch(x, fs=fs, nperseg=nperseg, noverlap=nov)
            if np.allclose(table[:, 1], G[line], rtol=1e-7, atol=0):
                fits.append(nov)
    assert len(fits) == 1, (percent, fits)
    assert scipy_segments(n, nperseg, fits[0]) == (averages, tail)
    assert (nperseg, percent, averages, tail) == (8192, 51.4, 10, 6)  # (docs/nvh.md's figures)


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


def test_a_median_over_exactly_min_median_lines_is_given_and_one_line_fewer_is_not():
    """Review AX5: the boundary itself, MIN_MEDIAN_LINES (5: the middle line of at least 2 below and
    2 above) lines give a median, 4 do not; in the sentence and in the bare figure."""
    from cablecasing_core.report.figures import MIN_MEDIAN_LINES
    from cablecasing_core.report.page import apparent_mass_note

    assert MIN_MEDIAN_LINES == 5
    text = apparent_mass_note(_am(5, 41, 4, 10), "without the cable drive")
    assert "median 0.37 over 10-100 Hz (5 lines)" in text and "leaves 0.30 and 0.85" in text
    assert "no meaningful median over 10-100 Hz, which holds 4 lines (a median needs at least 5)" in text
    text = apparent_mass_note(_am(4, 41, 5, 10), "without the cable drive")
    assert "no meaningful median over 10-100 Hz, which holds 4 lines (" in text and "leaves no figure and 0.85" in text
    assert "median 0.11 over 10-100 Hz (5 lines)" in text


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
