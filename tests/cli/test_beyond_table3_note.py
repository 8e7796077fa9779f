"""`cablecasing bands`' note on a model output's bands above the paper's Table 3 quotes Newmark's period
error at the step of the run the record holds (cli/nvh.py, ``_beyond_table3_note``), not at 1e-5 s."""

from pathlib import Path

import numpy as np
import pytest

from cablecasing_core.cli import main

ROOT = Path(__file__).resolve().parents[2]
MODEL = str(ROOT / "examples" / "straight_casing.toml")  # (no contact: 0.1 s of 4e-6 s steps run in a second)
DT = 4e-6  # s: not the default 1e-5


def _error(f, dt):
    """Newmark's relative period error (%) at f (Hz) and step dt (s), by hand: (2 pi f dt)^2 / 12."""
    return 100 * (2 * np.pi * f * dt) ** 2 / 12


def _note(capsys, record):
    assert main(["bands", str(record), "--column", "casing.B.Fy", "--kind", "third", "--fmin", "100"]) == 0
    notes = [line for line in capsys.readouterr().out.splitlines() if "beyond the paper's Table 3" in line]
    assert len(notes) == 1
    return notes[0]


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    """The example run at 4e-6 s for 0.1 s, written at every step (.csv), decimated by the filter to
    2e-5 s (.npz: passband 17.5 kHz) and picked at 2e-5 s (.csv, which states no passband)."""
    d = tmp_path_factory.mktemp("beyond")
    base = ["simulate", MODEL, "--dt", str(DT), "--duration", "0.1", "--no-progress"]
    assert main([*base, "--out", str(d / "full.csv")]) == 0
    assert main([*base, "--out", str(d / "dec.npz"), "--output-interval", "2e-5"]) == 0
    assert main([*base, "--out", str(d / "pick.csv"), "--output-interval", "2e-5", "--decimation", "pick"]) == 0
    return d


def test_a_record_of_every_step_gives_its_run_s_step(records, capsys):
    """At every step the record's sample interval is the run's step (it states its Nyquist frequency as
    its passband): 4e-6 s, 2.6 % at the top third's edge 22 387 Hz, 0.17 % at 5680 Hz; the note at the
    hard-coded 1e-5 s said 16 % and 1.1 %."""
    note = _note(capsys, records / "full.csv")
    assert f"at the run's step, {DT:g} s (the record holds every step)" in note
    assert f"period error is {_error(22387, DT):.2g} % at 22387 Hz ({_error(5680, DT):.2g} % at 5680 Hz)" in note
    assert "16 %" not in note


def test_a_decimated_record_bounds_the_step(records, capsys):
    """A record decimated by the filter holds at least two steps per sample and does not say how many:
    the step is at most half its 2e-5 s, and the error at most its value there (the bands end at the
    passband, 17.5 kHz: the top third's edge is 14 125 Hz)."""
    note = _note(capsys, records / "dec.npz")
    assert "does not state the run's step, at most half its sample interval, 1e-05 s" in note
    assert f"at most {_error(14125, 1e-5):.2g} % at 14125 Hz" in note


def test_a_record_that_states_no_passband_leaves_the_step_unknown(records, capsys):
    """Picked samples (or an FMU's outputs written by its host) say nothing of the step: "unknown", and
    the error at the default step as what it would be there."""
    note = _note(capsys, records / "pick.csv")
    assert "the run's step is unknown" in note
    assert f"at the default step, 1e-05 s, it would be {_error(22387, 1e-5):.2g} % at 22387 Hz" in note


def test_a_derived_column_read_back_from_a_file_is_a_model_output_s(records, capsys, tmp_path):
    """net.B.Fy, derived and then written with the record (Records.resolve adds it to the columns), is a
    plain column of the file read back: still the sum of two model outputs, so it gets the note."""
    from cablecasing_core.records import read_records, write_records

    rec = read_records(records / "full.csv")
    rec.column("net.B.Fy")
    write_records(tmp_path / "net.csv", rec)
    assert "net.B.Fy" in read_records(tmp_path / "net.csv").columns
    assert main(["bands", str(tmp_path / "net.csv"), "--column", "net.B.Fy", "--kind", "third", "--fmin", "100"]) == 0
    assert "beyond the paper's Table 3" in capsys.readouterr().out


def test_what_a_record_says_of_its_run_s_step(records):
    """Records.run_step, which the note quotes: the step of the run (DT) for the record of every step,
    at most half the 2e-5 s interval for the decimated one, nothing for picked samples."""
    from cablecasing_core.records import read_records

    step, how = read_records(records / "full.csv").run_step()
    assert how == "every step" and step == pytest.approx(DT, rel=1e-9)  # (fs from 15-digit times)
    step, how = read_records(records / "dec.npz").run_step()
    assert how == "decimated" and step == pytest.approx(1e-5, rel=1e-9)
    assert read_records(records / "pick.csv").run_step() is None
