"""A record's passband and its sampling, as the NVH commands read them: a filtered CSV states its
passband as its .npz does, a record that states none is noted as possibly aliased, the PSD's mean
square warns below the lines' coverage, and the coverage figures the docs quote are measured."""

import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from cablecasing_core import ModelError, load_model
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelWarning
from cablecasing_core.identification.uff_io import read_csv_time
from cablecasing_core.nvh import psd
from cablecasing_core.nvh.spectra import PSD
from cablecasing_core.records import Records, read_records, write_records
from cablecasing_core.timedomain.simulation import decimate

ROOT = Path(__file__).resolve().parents[2]
DT, M = 1e-5, 10  # a run's step and the decimation to S = 1e-4 s: Nyquist 5000 Hz, passband 3500 Hz
PASSBAND = 0.7 / (2 * DT * M)  # Hz, 0.7 of the new Nyquist frequency (docs/nvh.md)


def _flat(text):
    return " ".join(text.split())


def _tone_record(f0, passband=True):
    """A 1 N RMS tone at ``f0`` Hz decimated by M as SimulationResult.records(1e-4) does, with the
    passband that record states (or, ``passband=False``, none: as a host's CSV)."""
    t = np.arange(30000) * DT  # 0.3 s: a whole number of periods of the tones below
    x = decimate(np.sqrt(2) * np.sin(2 * np.pi * f0 * t), M)
    extra = {"passband_hz": np.array(PASSBAND)} if passband else {}
    return Records(t[::M], {"casing.B.Fz": x}, {"casing.B.Fz": "N"}, extra=extra)


def _rows(out):
    """The table rows of a command's output (its '#' notes left out)."""
    return [s for s in out.splitlines() if s and not s.startswith("#")]


# ------------------------------------------------------------- D3. a filtered CSV states its passband


def test_a_filtered_csv_states_its_passband_and_reads_as_its_npz(tmp_path, capsys):
    """The CSV of a filtered record holds '# passband_hz = 3500' after its header; read back, it
    has the .npz file's passband, and `bands` on the two prints the same table: the 4000 Hz third
    (3548-4467 Hz), above the passband, is left out of both (a tone at 0.85 of the Nyquist
    frequency, 4250 Hz, reads 6 dB low through the filter there)."""
    rec = _tone_record(4250.0)
    csv, npz = write_records(tmp_path / "r.csv", rec), write_records(tmp_path / "r.npz", rec)
    lines = Path(csv).read_text().splitlines()
    assert lines[0].startswith("time [s],casing.B.Fz [N]") and lines[1].startswith("# passband_hz = 3500 (")
    # 15 significant digits of 0.7 / (2 1e-4) against the npz's double
    assert read_records(csv).passband_hz == pytest.approx(read_records(npz).passband_hz, rel=1e-14)
    assert read_records(csv).passband_hz == pytest.approx(PASSBAND, rel=1e-14)
    tables = []
    for path in (csv, npz):
        assert main(["bands", path, "--kind", "third", "--fmin", "2500", "--skip", "0"]) == 0
        out = capsys.readouterr().out
        assert "up to 3500 Hz" in out and "the bands above it are left out" in out
        tables.append(_rows(out))
    # the same bands, the same levels to the CSV's 9 digits (a 1 N tone rounded to 1e-9 N: the empty
    # bands beside it read ~4e-9 N of that rounding through Hann's window)
    assert [r.split(",")[0] for r in tables[0]] == [r.split(",")[0] for r in tables[1]]
    rms = [np.array([float(r.split(",")[4]) for r in t[1:]]) for t in tables]
    np.testing.assert_allclose(rms[0], rms[1], rtol=1e-6, atol=1e-8)
    assert not any(r.startswith("4000Hz,") for r in tables[0])
    # every reader of these CSVs skips the comment line: the same numbers as read_records
    data = read_records(csv).columns["casing.B.Fz"]
    np.testing.assert_array_equal(np.loadtxt(csv, delimiter=",", skiprows=1)[:, 1], data)
    np.testing.assert_array_equal(np.genfromtxt(csv, delimiter=",", names=True)["casingBFz_N"], data)
    x, fs, name = read_csv_time(csv, "casing.B.Fz")  # (identification's CSV reader)
    np.testing.assert_array_equal(x, data)
    assert fs == pytest.approx(1 / (DT * M), rel=1e-9) and name == "casing.B.Fz"  # (1e-9: the 15-digit times)


def test_simulate_states_the_passband_of_the_record_it_filters(tmp_path, capsys):
    """`simulate --output-interval 1e-4` writes the passband, 0.7 / (2 1e-4) = 3500 Hz, into its
    CSV and its UFF file and says so; picked samples are said to alias."""
    base = ["simulate", "--duration", "0.01", "--output-interval", "1e-4", "--no-progress", "--out"]
    assert main([*base, str(tmp_path / "r.csv")]) == 0
    assert "flat within 0.01 dB up to its passband 3500 Hz, which the file states" in capsys.readouterr().out
    assert read_records(tmp_path / "r.csv").passband_hz == pytest.approx(3500.0, rel=1e-14)  # (15 digits)
    assert main([*base, str(tmp_path / "r.uff")]) == 0
    assert "passband 3500 Hz, which the file states" in capsys.readouterr().out
    assert read_records(tmp_path / "r.uff").passband_hz == pytest.approx(3500.0, rel=1e-14)  # (ID line 5)
    assert main([*base, str(tmp_path / "p.csv"), "--decimation", "pick"]) == 0
    assert "picked: content above the Nyquist frequency 5000 Hz aliases" in capsys.readouterr().out
    assert "passband_hz" not in read_records(tmp_path / "p.csv").extra  # (none stated)


@pytest.mark.parametrize("value", ["-1", "0", "nan", "", "3.5 kHz"])
def test_a_passband_line_that_is_not_a_positive_number_of_hz_is_refused(tmp_path, value):
    path = tmp_path / "r.csv"
    path.write_text(f"time [s],casing.B.Fz [N]\n# passband_hz = {value}\n0,1\n0.001,2\n0.002,3\n")
    with pytest.raises(ModelError) as e:
        read_records(path)
    assert e.value.key == "file" and "line 2 states passband_hz, but not as a positive number of Hz" in str(e.value)


def test_two_passband_lines_are_refused(tmp_path):
    path = tmp_path / "r.csv"
    path.write_text("# passband_hz = 3500\ntime [s],casing.B.Fz [N]\n# passband_hz = 3000\n0,1\n0.001,2\n0.002,3\n")
    with pytest.raises(ModelError, match="lines 1 and 3 both state passband_hz"):
        read_records(path)


@pytest.mark.parametrize("line", ["# PASSBAND_HZ: 3500", "# Passband_hz = 3500 (Hz)"])
def test_a_passband_line_in_another_spelling_is_read(tmp_path, line):
    """One parser for the CSV's statements (files.csv_statements; the FRF's kind line too): the
    name in any case, '=' or ':', a parenthesis after the value."""
    path = tmp_path / "r.csv"
    path.write_text(f"time [s],casing.B.Fz [N]\n{line}\n0,1\n0.001,2\n0.002,3\n")
    assert read_records(path).extra["passband_hz"] == 3500.0


# ------------------------------------------------------------------ D2. a record that states no passband


def test_bands_and_spectrum_note_that_a_record_without_a_passband_may_hold_aliases(tmp_path, capsys):
    """A tone at 6000 Hz sampled every 1e-4 s without a filter (as a host samples an FMU's outputs)
    folds to 10000 - 6000 = 4000 Hz: its samples equal those of a 4000 Hz tone of opposite phase
    (numpy by hand), so `bands` reads it in the 4000 Hz third at 0 dB re 1 N, and notes on such a
    record that content above its Nyquist frequency may have aliased; a filtered record gets no note."""
    t = np.arange(3000) * 1e-4
    x = np.sqrt(2) * np.sin(2 * np.pi * 6000.0 * t)
    np.testing.assert_allclose(x, -np.sqrt(2) * np.sin(2 * np.pi * 4000.0 * t), atol=1e-9)  # (sin's round-off)
    rec = Records(t, {"casing.B.Fz": x}, {"casing.B.Fz": "N"})
    host = write_records(tmp_path / "host.csv", rec)
    note = "host.csv states no passband: content above its Nyquist frequency 5000 Hz (dt = 0.0001 s) may have aliased"
    assert main(["bands", host, "--kind", "third", "--fmin", "2500", "--skip", "0"]) == 0
    out = capsys.readouterr().out
    assert f"{note} into the bands unless it was filtered before sampling" in out
    level = float(next(r for r in _rows(out) if r.startswith("4000Hz,")).split(",")[-1])
    assert level == pytest.approx(0.0, abs=0.01)  # (the whole tone in one band: Parseval, to round-off)
    assert main(["spectrum", host, "--fmin", "100", "--fmax", "4500", "--skip", "0"]) == 0
    assert f"{note} into the lines" in capsys.readouterr().out
    assert main(["spectrum", host, "--kind", "transmissibility", "--input", "casing.B.Fz", "--skip", "0"]) == 0
    assert f"{note} into the lines" in capsys.readouterr().out
    filtered = write_records(tmp_path / "filtered.csv", _tone_record(2500.0))
    assert main(["bands", filtered, "--kind", "third", "--fmin", "2500", "--skip", "0"]) == 0
    assert main(["spectrum", filtered, "--fmin", "100", "--skip", "0"]) == 0
    assert "states no passband" not in capsys.readouterr().out


def test_a_runs_every_step_states_its_nyquist_frequency_and_a_picked_record_none(tmp_path, capsys):
    """A run's record at every step holds the run's own samples (nothing above its Nyquist frequency
    to fold): its CSV states 1/(2 dt) and `bands` notes nothing; the same run picked every 10 steps
    states none, and is noted (what lay above 1/(20 dt) folded into it)."""
    base = ["simulate", "--duration", "0.06", "--no-progress"]
    assert main([*base, "--out", str(tmp_path / "every.csv")]) == 0
    assert main([*base, "--output-interval", "1e-4", "--decimation", "pick", "--out", str(tmp_path / "pick.csv")]) == 0
    assert read_records(tmp_path / "every.csv").passband_hz == pytest.approx(5e4, rel=1e-12)  # 1/(2 dt), dt = 1e-5 s
    assert "passband_hz" not in read_records(tmp_path / "pick.csv").extra
    capsys.readouterr()
    assert main(["bands", str(tmp_path / "every.csv"), "--kind", "third", "--fmin", "500", "--skip", "0"]) == 0
    assert "states no passband" not in capsys.readouterr().out
    assert main(["bands", str(tmp_path / "pick.csv"), "--kind", "third", "--fmin", "500", "--skip", "0"]) == 0
    assert "pick.csv states no passband" in capsys.readouterr().out


def test_a_loaded_run_picked_or_loaded_from_a_picked_record_states_no_passband(tmp_path):
    """A run saved every step states its Nyquist frequency; loaded and picked every 10 steps it
    states none (what lay above the new Nyquist frequency folds into it); a result loaded from a
    picked record states none however it is saved again, even every step; filtered, 0.7 of the new
    Nyquist frequency."""
    from cablecasing_core import simulate
    from cablecasing_core.timedomain.simulation import SimulationResult

    res = simulate(load_model(), duration=0.02)
    res.save(tmp_path / "every.npz")
    every = SimulationResult.load(tmp_path / "every.npz")
    assert every.records().extra["passband_hz"] == pytest.approx(5e4, rel=1e-12)  # 1/(2 dt)
    assert "passband_hz" not in every.records(1e-4, "pick").extra
    assert every.records(1e-4).extra["passband_hz"] == pytest.approx(3500.0, rel=1e-12)
    every.save(tmp_path / "picked.npz", 1e-4, "pick")
    picked = SimulationResult.load(tmp_path / "picked.npz")
    assert "passband_hz" not in picked.records().extra and "passband_hz" not in picked.records(2e-4).extra


# ------------------------------------------------------- D4. mean_square below the lines' coverage


def test_mean_square_warns_below_the_covered_range_and_not_within_it(tmp_path, capsys):
    """A 1 N RMS tone at 64 df (on a line): mean_square over a range reaching below 2 df warns,
    naming the covered range; over covered() it gives the tone's power, A^2/2 = 1 N^2 (Parseval,
    1e-9: the Hann window's leakage stays within the three lines around it); the whole spectrum
    warns not. The spectrum command, which cuts its range to covered(), warns not either."""
    fs, n, nperseg = 8192.0, 16384, 512  # df = 16 Hz, 2 df = 32 Hz
    t = np.arange(n) / fs
    p = psd(np.sqrt(2) * np.sin(2 * np.pi * 64 * 16.0 * t), fs, nperseg=nperseg, unit="N", name="casing.B.Fz")
    with pytest.warns(ModelWarning, match=r"casing.B.Fz: mean_square from f_low = 10 Hz .* 32-2000 Hz") as said:
        assert p.mean_square(10, 2000) == pytest.approx(1.0, rel=1e-9)
    assert len(said) == 1
    with pytest.warns(ModelWarning, match="from f_low = 0 Hz"):  # (from 0 Hz: f_low absent, f_high given)
        assert p.mean_square(f_high=2000) == pytest.approx(1.0, rel=1e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert p.covered(10, 2000) == (32.0, 2000.0)
        assert p.mean_square(*p.covered(10, 2000)) == pytest.approx(1.0, rel=1e-9)
        assert p.mean_square(2 * p.df, 2000) == pytest.approx(1.0, rel=1e-9)
        assert p.mean_square() == pytest.approx(1.0, rel=1e-9)
    rec = Records(t, {"casing.B.Fz": np.sqrt(2) * np.sin(2 * np.pi * 1024.0 * t)}, {"casing.B.Fz": "N"})
    path = write_records(tmp_path / "tone.csv", rec)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)
        assert main(["spectrum", path, "--fmin", "1", "--skip", "0", "--resolution", "16"]) == 0
    out, err = capsys.readouterr()
    assert "RMS 1 N in 32-2000 Hz" in out and "mean_square" not in err


# ------------------------------------------------- the coverage figures of PSD.covered and docs/nvh.md


def _held(k, n=16384, nperseg=1024, phases=8):
    """What the lines of the package's PSD (:func:`psd`: Hann, 50 % overlap, mean removed per
    segment), all of them summed (``PSD.mean_square()``), hold of a unit sine's power at ``k`` lines
    (k df), for ``phases`` phases over [0, pi) (the power's period)."""
    t = np.arange(n)
    return np.array(
        [psd(np.sin(2 * np.pi * k * t / nperseg + ph), 1.0, nperseg=nperseg).mean_square() / 0.5
         for ph in np.arange(phases) * np.pi / phases]
    )  # fmt: skip


def test_the_coverage_figures_quoted_are_those_measured():
    """docs/nvh.md and PSD.covered quote what the lines hold of a sine below 2 df, and from 2 df up,
    as measured here (nperseg 1024, 16384 samples, 8 phases): each figure to its 2 decimals."""
    low, one, mid = _held(0.6), _held(1.0), _held(1.5)
    assert np.ptp(low) < 0.005 and np.ptp(mid) < 0.02  # (little of a phase's effect left: segments average it)
    assert np.ptp(one) > 0.3 and one.mean() == pytest.approx(1.0, abs=1e-6)  # (at 1 df no segment averages it)
    ks = 2.0 + 0.025 * np.arange(160)  # 2 df to 6 df: each line's worst phase, once, for the three ranges
    off = np.array([np.abs(_held(k) - 1).max() for k in ks])
    worst = {a: off[ks >= a - 1e-9].max() for a in (2.0, 3.0, 4.0)}
    figures = [
        f"{low.mean():.2f} of a sine's power at 0.6 df",
        f"{one.min():.2f} to {one.max():.2f} at 1 df",
        f"{mid.mean():.2f} at 1.5 df",
        f"within {100 * worst[2.0]:.1f} %",
    ]
    assert figures == ["0.38 of a sine's power at 0.6 df", "0.83 to 1.17 at 1 df", "1.21 at 1.5 df", "within 1.2 %"]
    assert 100 * worst[3.0] < 0.85 and 100 * worst[4.0] < 0.505  # (quoted as 0.8 % from 3 df, 0.5 % from 4 df)
    doc, docstring = _flat((ROOT / "docs" / "nvh.md").read_text()), _flat(PSD.covered.__doc__)
    for text in [*figures, "0.5 % from 4 df"]:
        assert text in doc and text in docstring, text
    assert "0.8 % from 3 df" in doc


# ------------------------------------------------------------ D1. fmpy's output_interval in the docs


def test_every_simulate_fmu_call_in_the_docs_gives_the_output_interval():
    """fmpy's simulate_fmu steps a co-simulation FMU at output_interval, not step_size (without it,
    the DefaultExperiment's 1e-4 s doubled to at most 1000 steps): every call the README and
    docs/fmu.md show passes it."""
    calls = 0
    for doc in ("README.md", "docs/fmu.md"):
        for block in re.findall(r"```python\n(.*?)```", (ROOT / doc).read_text(), re.S):
            for call in re.findall(r"simulate_fmu\((.*?)\)\n", block, re.S):
                calls += 1
                assert "output_interval=" in call, (doc, call[:60])
    assert calls >= 2


def test_a_run_s_uff_record_keeps_its_passband_another_tool_s_states_none(tmp_path, capsys):
    """A run's UFF file states its passband (ID line 5), so `bands` notes no aliasing of it; the same
    functions without that statement (another tool's file) are noted as stating none."""
    import dataclasses

    from cablecasing_core.identification.uff_io import read_uff, write_uff

    assert main(["simulate", "--duration", "0.06", "--no-progress", "--out", str(tmp_path / "r.uff")]) == 0
    capsys.readouterr()
    args = ["--kind", "third", "--fmin", "500", "--skip", "0"]
    assert main(["bands", str(tmp_path / "r.uff"), *args]) == 0
    assert "passband" not in capsys.readouterr().out
    write_uff(tmp_path / "other.uff", [dataclasses.replace(r, stated={}) for r in read_uff(tmp_path / "r.uff")])
    assert main(["bands", str(tmp_path / "other.uff"), *args]) == 0
    assert "other.uff states no passband: content above" in capsys.readouterr().out
