"""Review AM: identification from exporters' UFF and CSV files (zero lines, truncated files, repeated names,
a CSV's --channel, the Rayleigh misfit, zero padding, unit labels). The measurements are the conftest's modal sums
and noise, written by the package's writers or by hand (pyuff's dict writer) where a file must be broken."""

import argparse
import warnings
from pathlib import Path

import numpy as np
import pytest

from cablecasing_core.cli.identify import add_parser
from cablecasing_core.errors import ModelWarning
from cablecasing_core.identification import find_resonances, loss_factor_circle, read_frf, write_uff_frf
from cablecasing_core.identification.uff_io import write_csv_frf

F = np.array([23.7, 61.3, 142.9])  # Hz, the review's modes
ETA = np.array([0.024, 0.040, 0.016])
AMP = np.array([1.0, -0.6, 0.35])
FREQ = np.arange(0.0, 256.0 + 1e-9, 0.0625)  # 4097 lines, 0 Hz first (an analyser's export)
MODEL = Path(__file__).resolve().parents[2] / "examples" / "straight_casing.toml"


def run(argv):
    p = argparse.ArgumentParser(prog="cablecasing")
    sub = p.add_subparsers(dest="command", required=True)
    add_parser(sub)
    args = p.parse_args(argv)
    return args.func(args)


def accelerance(synth, seed=30, noise=0.002, f_n=F):
    """The review's accelerance (m/s2/N): structural modes, complex noise of ``noise`` times the largest |H|."""
    H = -((2 * np.pi * FREQ) ** 2) * synth.receptance(FREQ, f_n, eta=ETA, A=AMP)
    return H + synth.cnoise(seed, FREQ.size, noise * np.abs(H).max())


def rows(out):
    return [line.split() for line in out.splitlines() if line[:4].strip().isdigit()]


# ------------------------------------------------------------------ H1: an exact-zero line of a measured FRF


def test_an_exact_zero_line_leaves_the_peak_search_as_it_was(synth):
    """One zero line at 200 Hz (a dropout far from every mode) sent find_resonances to its noise-free branch,
    where every noise wiggle of the displacement form at low frequency outranked the modes (0.25 Hz, 1.125 Hz)."""
    H = accelerance(synth)
    Hz = H.copy()
    Hz[FREQ == 200.0] = 0.0
    clean = find_resonances(FREQ, H, count=3, kind="acceleration")
    np.testing.assert_allclose(clean, F, atol=0.07)  # (the peak line: within a line spacing, 0.0625 Hz)
    np.testing.assert_array_equal(find_resonances(FREQ, Hz, count=3, kind="acceleration"), clean)
    # a block of zeros and zeroed lines above 220 Hz (a masked band) too
    Hb = H.copy()
    Hb[(FREQ > 100) & (FREQ < 101)] = 0.0
    Hb[FREQ > 220] = 0.0
    np.testing.assert_array_equal(find_resonances(FREQ, Hb, count=3, kind="acceleration"), clean)


def test_an_exact_zero_line_inside_a_circle_is_left_out_of_the_fit(synth):
    """A zero line at the second mode's peak is a missing point of its circle, not a point at the origin: the
    fit equals the fit of the FRF without that line (the same lines otherwise)."""
    H = accelerance(synth)
    k = int(np.argmin(np.abs(FREQ - 61.3)))
    Hz = H.copy()
    Hz[k] = 0.0
    keep = np.arange(FREQ.size) != k
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)  # (the leakage note of 9 lines per bandwidth)
        a = loss_factor_circle(FREQ, Hz, F, kind="acceleration")
        b = loss_factor_circle(FREQ[keep], H[keep], F, kind="acceleration")
    np.testing.assert_array_equal([r.eta for r in a], [r.eta for r in b])
    np.testing.assert_array_equal([r.f_r_hz for r in a], [r.f_r_hz for r in b])


@pytest.mark.parametrize("suffix", [".uff", ".csv"])
def test_the_readers_name_zero_lines(tmp_path, synth, suffix):
    """The readers warn of exact-zero lines above 0 Hz as they refuse nan lines: the file, the function, the first
    zero line's frequency and point, how many more; a 0 Hz line of 0 (the DC line an export zeroes) is not named."""
    H = accelerance(synth)
    H[0] = 0.0
    H[FREQ == 200.0] = 0.0
    H[FREQ == 210.0] = 0.0
    p = tmp_path / f"z{suffix}"
    (write_uff_frf if suffix == ".uff" else write_csv_frf)(p, FREQ, H, name="H41", kind="acceleration")
    with pytest.warns(ModelWarning) as caught:
        f, Hr = read_frf(p)
    said = [str(w.message) for w in caught if "exactly 0" in str(w.message)]
    assert len(said) == 1, [str(w.message) for w in caught]
    k = int(np.argmax(FREQ == 200.0))
    assert str(p) in said[0] and "H41" in said[0]
    assert f"at 200 Hz (point {k + 1} of {FREQ.size}, and 1 more)" in said[0]
    assert "leave these lines out" in said[0]
    np.testing.assert_array_equal(Hr, H)  # (read as it is; the fits leave the lines out)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # (no zero line, no word)
        q = tmp_path / f"clean{suffix}"
        Hc = accelerance(synth)
        Hc[0] = 0.0
        (write_uff_frf if suffix == ".uff" else write_csv_frf)(q, FREQ, Hc, name="H41", kind="acceleration")
        read_frf(q)


def _modulus(path, capsys):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        argv = ["identify", "modulus", str(path), "--modes", "1", "3", "5", "--model", str(MODEL), "--degree", "-1"]
        code = run(argv)
    out = capsys.readouterr()
    assert code == 0, out.err
    r = rows(out.out)
    return np.array([[float(x) for x in row[1:6]] for row in r])  # f_meas, f_unc, f_comp, E, E_unc_%


def test_modulus_of_an_frf_with_a_zero_line_is_that_of_the_frf_without_it(tmp_path, synth, capsys):
    """The review's repro: identify modulus took 0.25 and 1.125 Hz as modes 1 and 3 (E 1000 times too low,
    exit 0) for one zero line at 200 Hz. Now E equals the E without the zero within its printed uncertainty."""
    H = accelerance(synth)
    clean, zero = tmp_path / "clean.uff", tmp_path / "zero.uff"
    write_uff_frf(clean, FREQ, H, kind="acceleration")
    H[FREQ == 200.0] = 0.0
    write_uff_frf(zero, FREQ, H, kind="acceleration")
    a, b = _modulus(clean, capsys), _modulus(zero, capsys)
    np.testing.assert_allclose(a[:, 0], F, atol=0.01)  # (the circle fits' f_r: f_unc is 0.0005..0.002 Hz)
    # (E within one printed E_unc_% of the run without the zero; the 200 Hz line is in no circle's window)
    assert np.all(np.abs(b[:, 3] / a[:, 3] - 1) <= a[:, 4] / 100), (a, b)
