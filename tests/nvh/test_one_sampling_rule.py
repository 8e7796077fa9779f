"""One rule of an evenly sampled record (``Records.fs``) for every command that reads one: a CSV whose
time column an analyser printed ``%.6g`` gives ``spectrum``, ``bands`` and ``identify damping`` one
rate, the true one to the least squares' accuracy; one with a sample missing is refused by all three
with one message naming the time column and what is allowed. (``identify damping`` accepted such a
file by its own rule, which ``spectrum`` and ``bands`` refused, and computed its rate another way.)"""

import warnings

import numpy as np
import pytest

import cablecasing_core.identification as identification
import cablecasing_core.nvh as nvh
import cablecasing_core.nvh.bands as bands
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelError
from cablecasing_core.records import Records, read_records

FS = 2048.0
F_N, ZETA = (115.8, 301.7), (0.01, 0.008)  # two viscous modes (Hz, damping ratio)


def _decay(t):
    """The two modes' free decay from t = 0, computed independently of the package."""
    w = 2 * np.pi * np.array(F_N)
    return sum(np.exp(-z * wk * t) * np.sin(wk * np.sqrt(1 - z * z) * t) for wk, z in zip(w, ZETA))


def _csv(path, drop=()):
    """1.2 s at 2048 Hz, the time printed %.6g as analysers export it (6 digits: 1e-6 s below 1 s,
    1e-5 s from 1 s on, so its steps differ by up to 2 % of themselves), ``drop`` the samples left out."""
    t = np.arange(int(1.2 * FS) + 1) / FS
    keep = np.setdiff1d(np.arange(t.size), drop)
    path.write_text("time [s],acc [m/s2]\n" + "".join(f"{a:.6g},{b:.6g}\n" for a, b in zip(t[keep], _decay(t)[keep])))
    return path


def _spy(monkeypatch, module, name, seen):
    """Wrap ``module.name`` (a function called as ``f(x, fs, ...)``) to note the rate it is given."""
    real = getattr(module, name)

    def spy(x, fs, *args, **kwargs):
        seen.append((name, fs))
        return real(x, fs, *args, **kwargs)

    monkeypatch.setattr(module, name, spy)


COMMANDS = {
    "spectrum": ["spectrum", "{path}", "--column", "acc", "--skip", "0"],
    "bands": ["bands", "{path}", "--column", "acc", "--skip", "0", "--kind", "octave", "--fmax", "500"],
    "identify damping": ["identify", "damping", "{path}", "--channel", "acc", "--freqs", "115.8", "301.7"],
}


def test_a_csv_printed_g6_gives_spectrum_bands_and_identify_one_rate(tmp_path, capsys, monkeypatch):
    path = _csv(tmp_path / "g6.csv")
    steps = np.diff(read_records(path).time)
    assert np.ptp(steps) > 1e-2 * steps.mean()  # (the printing's rounding, far beyond exact times' 1e-6)
    seen = []
    _spy(monkeypatch, nvh, "psd", seen)  # spectrum's PSD
    _spy(monkeypatch, bands, "octave_rms", seen)  # bands' band levels
    _spy(monkeypatch, identification, "wavelet_damping", seen)  # identify damping's ridges
    for argv in COMMANDS.values():
        assert main([a.format(path=path) for a in argv]) == 0, capsys.readouterr().err
    capsys.readouterr()
    assert [name for name, _ in seen] == ["psd", "octave_rms", "wavelet_damping"]
    rates = {fs for _, fs in seen}
    assert len(rates) == 1  # one rate, to the last bit
    # least squares over 2458 times rounded to at most 5e-6 s: for independent roundings its error is
    # sqrt(12) 5e-6 / sqrt(3) / (sqrt(n) T) = 1.7e-7 of fs (rms); 1e-6 is 6 of those. The ends alone,
    # (n - 1) / (t[-1] - t[0]), are 2.5e-6 off here: the last time 1.19970703 s prints 1.19971.
    assert rates.pop() == pytest.approx(FS, rel=1e-6)


def test_a_csv_with_a_sample_missing_is_refused_by_all_three_with_one_message(tmp_path, capsys):
    path = _csv(tmp_path / "gap.csv", drop=[1000])
    errors = {}
    for what, argv in COMMANDS.items():
        assert main([a.format(path=path) for a in argv]) == 2
        errors[what] = capsys.readouterr().err.strip().splitlines()
    # (one message, the file named as each command's --help names it: RECORD, identify's file)
    said = [
        errors["spectrum"],
        errors["bands"],
        [e.replace("error: file = ", "error: RECORD = ") for e in errors["identify damping"]],
    ]
    assert said[0] == said[1] == said[2], errors
    (line,) = errors["spectrum"]
    assert line.startswith(f"cablecasing: error: RECORD = '{path}': must be evenly sampled: its time column 'time [s]'")
    # what is allowed: the grid through the first and last time, to 1e-6 of a step plus the printing's
    # rounding (half the last digit, 5e-7 s below 1 s); the sample after the gap, 1001/2048 s, departs most
    assert "no sample missing" in line and "to within 1e-06 of a step (" in line and "plus the rounding" in line
    assert "(5e-07 s there" in line and "sample 1001 of 2457 (t = 0.48877 s)" in line  # (as printed)


def test_the_rule_allows_exact_times_1e_6_of_a_step_and_what_summing_the_steps_adds():
    """A record made in Python, its times exact (no rounding stated): off the grid by 0.9e-6 of a step
    it is read, by 2e-6 refused (summing 30000 steps could add n eps max|t| = 2e-7 of a step); fs is 1 /
    the least-squares slope, the grid's step for exact times. Times a host sums step by step (t += h)
    over 1e6 steps drift 1e-5 of a step off the grid (3.4e-10 s), within n eps max|t| (7.4e-9 s)."""
    dt = 1 / 30000
    t = dt * np.arange(30001)
    x = np.zeros(t.size)
    assert Records(t, {"x": x}).fs == pytest.approx(30000, rel=1e-12)  # (exact times: to rounding)
    near, far = t.copy(), t.copy()
    near[15000] += 0.9e-6 * dt
    far[15000] += 2e-6 * dt
    assert Records(near, {"x": x}).fs == pytest.approx(30000, rel=1e-12)
    with pytest.raises(ModelError, match=r"to within 1e-06 of a step \(4e-11 s with .*\); sample 15001 of 30001"):
        _ = Records(far, {"x": x}).fs
    summed = np.r_[0.0, np.cumsum(np.full(10**6, dt))]
    assert np.abs(summed - dt * np.arange(summed.size)).max() > 5e-6 * dt  # (beyond 1e-6 of a step alone)
    # the summed times' own slope: they drift from k dt by 3.4e-10 s over 33 s, 1e-11 of fs
    assert Records(summed, {"x": np.zeros(summed.size)}).fs == pytest.approx(30000, rel=1e-10)
    # the same time stated rounded to 5e-6 of a step is read: the rounding is allowed
    assert Records(far, {"x": x}, time_rounding=5e-6 * dt).fs == pytest.approx(30000, rel=1e-9)


def test_times_printed_too_coarsely_to_resolve_the_step_are_refused_unless_on_the_grid(tmp_path):
    """Times printed to 0.1 s at a step of 0.1 s cannot show a missing sample: read when they lie on
    the grid as printed, refused off it, saying the digits do not resolve the step."""
    ok = tmp_path / "ok.csv"
    ok.write_text("time_s,x\n0,1\n0.1,2\n0.2,3\n0.3,4\n")
    assert read_records(ok).fs == pytest.approx(10.0, rel=1e-12)
    bad = tmp_path / "bad.csv"
    bad.write_text("time_s,x\n0,1\n0.1,2\n0.3,3\n0.4,4\n")
    with pytest.raises(ModelError, match=r"too coarse to resolve its step to 10 %"):
        _ = read_records(bad).fs


def test_a_time_rounding_that_is_no_rounding_is_refused_by_name():
    t = np.arange(8) / 8.0
    for bad in ([1e-6, 1e-6], -1e-6, np.nan, "5e-7"):
        with pytest.raises(ModelError, match=r"^time_rounding = "):
            Records(t, {"x": np.zeros(8)}, time_rounding=bad)
    assert Records(t, {"x": np.zeros(8)}, time_rounding=np.full(8, 1e-6)).fs == pytest.approx(8.0, rel=1e-12)


@pytest.mark.parametrize("fs, seconds", [(10000.0, 1.0), (25600.0, 2.0)])
def test_a_float32_time_axis_is_read_within_its_own_rounding(tmp_path, fs, seconds):
    """Review X D1: a time vector stored as float32 (MATLAB single, DAQ exports) was refused as not
    evenly sampled, its times off the grid by up to half a float32 spacing (4.6e-8 s at 1 s, 0.00046
    of a step at 10 kHz), and its magnitude check warned of an overflow. It is read now, without a
    warning, fs to the float32 times' accuracy (their rounding, 3e-8 s over the record's length,
    moves the slope by ~1e-10: 1e-9 leaves room); a sample missing is still refused, naming the
    dtype; a float32 time far from 0, whose spacing does not resolve the step (or merges two times, at
    25.6 kHz), is refused so."""
    n = int(fs * seconds)
    t = (np.arange(n) / fs).astype(np.float32)
    path = tmp_path / "f32.npz"
    np.savez(path, time=t, table=np.sin(np.arange(n) / fs * 600.0)[:, None], names=np.array(["acc"]),
             units=np.array(["m/s2"]))  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert read_records(path).fs == pytest.approx(fs, rel=1e-9)
    gap = np.delete(t, n // 2)
    with pytest.raises(ModelError, match=r"its time \(stored as float32\) must increase .*\(0.5 of a step\)"):
        _ = Records(gap, {"x": np.zeros(gap.size)}).fs
    late = (1000.0 + np.arange(n) / fs).astype(np.float32)  # (spacing 6e-5 s at 1000 s: above a step's 10 %)
    with pytest.raises(ModelError, match=r"stored as float32.*(too coarse to resolve its step to 10 %|does not come)"):
        _ = Records(late, {"x": np.zeros(n)}).fs
