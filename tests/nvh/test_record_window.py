"""The samples after ``skip`` are a whole number of steps (``records.after_skip``): t = k dt computed
in floating point lands a hair above skip (6000 * 1e-5 > 0.06), and keeping the sample at skip
made the record one step longer than whole periods of a line on its bins, which then leaked
through the rectangular window into the bands below it (the installed specimen's octave 2 moved by
5 % with dt for that reason alone: docs/time_domain.md, "The record's length")."""

import warnings

import numpy as np
import pytest

from cablecasing_core.cli import main
from cablecasing_core.nvh.bands import window_options
from cablecasing_core.records import after_skip, passband_line
from cablecasing_core.studies import octave_rms

DTS = (3.125e-5, 2.5e-5, 2e-5, 1e-5, 5e-6, 1.25e-6, 3.125e-7)


@pytest.mark.parametrize("dt", DTS)
def test_after_skip_keeps_the_steps_after_it_whatever_the_rounding(dt):
    """A run's time axis (the ends of its steps, dt .. 1 s) and a file's (its start row, then the
    steps, from t0 = 0.3 s): after 0.06 s exactly (1 - 0.06) / dt samples stay, the sample at
    0.06 s itself left out; a skip a third of a step either side of 0.06 s keeps the samples
    strictly after it (the same count, and one more)."""
    n, kept = round(1.0 / dt), round(0.94 / dt)
    run = dt * np.arange(1, n + 1)
    assert after_skip(run, 0.06).sum() == kept
    assert after_skip(run, 0.06 + dt / 3).sum() == kept
    assert after_skip(run, 0.06 - dt / 3).sum() == kept + 1
    file = 0.3 + dt * np.arange(n + 1)
    assert after_skip(file, 0.06, file[0]).sum() == kept
    assert after_skip(file, 0.0, file[0]).sum() == n + 1  # skipping nothing keeps every row
    assert after_skip(file, dt / 2, file[0]).sum() == n  # and half a step leaves out the start row


def test_a_line_on_the_records_bins_stays_in_its_band():
    """A 50 Hz line of 27 N RMS (the installed specimen's drive in octave 3) over 1 s at 1e-5 s,
    0.06 s left out: 47 whole periods, so the line sits on a bin of the rectangular window and
    octaves 1-2 hold nothing of it (DFT orthogonality: 1e-9 N bounds the round-off of 94 000
    samples of 38 N). Kept with the sample at 0.06 s (the selection t > 0.06 gave) the line lies
    d = 5e-4 of a bin off (47.0005 periods) and leaks into bin 47 - m about A d / m (the tail of
    the Dirichlet kernel, A = 27 N RMS): over octave 2's bins m = 6 .. 26 that is A d (sum 1/m^2)^1/2
    = 5.1e-3 N, a third of the specimen's own octave-2 level (0.014 N); 20 % for the bins the
    band's edges split, which the sum counts whole."""
    dt = 1e-5
    t = dt * np.arange(1, 100_001)
    F = 27.0 * np.sqrt(2.0) * np.sin(2 * np.pi * 50.0 * t + 0.4)
    rect = window_options("boxcar")  # (the window of the leakage's closed form)
    whole = octave_rms(F[after_skip(t, 0.06)], 1 / dt, **rect).rms
    assert np.all(whole[:2] < 1e-9) and whole[2] == pytest.approx(27.0, rel=1e-12)
    one_more = octave_rms(F[t > 0.06], 1 / dt, **rect).rms  # (what the selection was)
    m = np.arange(6, 27)
    assert one_more[1] == pytest.approx(27.0 * 5e-4 * np.sqrt(np.sum(1.0 / m**2)), rel=0.2)


def test_the_bands_command_takes_the_samples_after_skip(tmp_path, capsys):
    """`cablecasing bands` on a file with its start row (t = 0 .. 1 s at 1e-5 s): octave 2 of the
    line above stays empty after --skip 0.06 (the level of 1e-9 N, below -180 dB re 1 N)."""
    dt = 1e-5
    t = dt * np.arange(100_001)
    F = 27.0 * np.sqrt(2.0) * np.sin(2 * np.pi * 50.0 * t + 0.4)
    path = tmp_path / "tone.npz"
    np.savez(path, time=t, table=F[:, None], names=np.array(["casing.B.Fz"]), units=np.array(["N"]))
    assert main(["bands", str(path), "--skip", "0.06"]) == 0
    rows = {r.split(",")[0]: r.split(",") for r in capsys.readouterr().out.splitlines() if r.startswith("oct")}
    assert float(rows["oct2"][4]) < 1e-9 and float(rows["oct3"][4]) == pytest.approx(27.0, rel=1e-9)


def test_the_bands_of_a_runs_file_are_the_studies_bands(tmp_path, capsys):
    """A run saved with its start row (t = 0 .. T, `simulate --out`) and read back by `cablecasing
    bands --skip 0.05` gives the band levels a study computes from the run itself (dt .. T, the
    same 0.05 s left out): the same 10 000 samples, to the 6 digits printed."""
    import cablecasing_core as cc
    from cablecasing_core.studies.evaluators import default_evaluate

    model = cc.load_model()
    cc.simulate(model, duration=0.15).save(tmp_path / "run.npz")
    study = default_evaluate({}, duration=0.15, skip=0.05, model=model)
    assert main(["bands", str(tmp_path / "run.npz"), "--skip", "0.05"]) == 0
    rows = {r.split(",")[0]: r.split(",") for r in capsys.readouterr().out.splitlines() if r.startswith("oct")}
    for band, level in study.items():
        assert float(rows[band][4]) == pytest.approx(level, rel=5e-6), band


def test_a_short_record_s_messages_say_which_skip_took_it(tmp_path, capsys):
    """A record too short after the default skip is named by that skip, not an --skip nobody gave;
    a record that states no fade-in and no lines (a host's CSV) is not said to state them."""
    t = 1e-4 * np.arange(1, 3001)  # 0.3 s at 1e-4 s
    path = tmp_path / "host.csv"
    np.savetxt(
        path, np.column_stack([t, np.sin(2 * np.pi * 100 * t)]), delimiter=",", header="time,casing.B.Fz", comments=""
    )
    assert main(["bands", str(path), "--kind", "third", "--fmin", "16"]) == 2
    err = capsys.readouterr().err
    assert "(the record after the default skip, 0.05 s) = '0.2499 s': is too short for band 16Hz" in err, err
    assert main(["bands", str(path), "--kind", "third", "--fmin", "16", "--skip", "0.1"]) == 2
    assert "(the record after --skip, 0.1 s) = '0.1999 s'" in capsys.readouterr().err
    short = tmp_path / "short.csv"
    np.savetxt(short, np.column_stack([t[:300], t[:300]]), delimiter=",", header="time,casing.B.Fz", comments="")
    assert main(["bands", str(short)]) == 2
    err = capsys.readouterr().err
    assert "it is the default (0.05 s): give a shorter one" in err and "ramp_s" not in err, err


def test_hann_s_band_levels_weight_the_middle_of_a_record_whose_level_drifts():
    """docs/nvh.md: through Hann's window the band levels estimate the mean square weighted by w^2,
    which falls to zero at both ends; the rectangular window weights the record evenly. A 100 Hz
    tone (on the bins of the 1 s record) whose amplitude rises from 1 to 3 along it: the octave
    holding it reads sqrt(sum w^2 x^2 / sum w^2) through Hann's window and the plain RMS through the
    rectangular one, each to 3e-3 (the drift's sidebands, which fall off as 1/f through the
    rectangular window, put 1.4e-3 of the level outside the 89-178 Hz octave), and the two differ
    by the drift (1.428 against 1.472 N)."""
    fs, n = 10_000.0, 10_000
    t = np.arange(n) / fs
    x = (1 + 2 * t) * np.sin(2 * np.pi * 100 * t)
    w = np.hanning(n)
    expected = {"hann": np.sqrt(np.sum(w**2 * x**2) / np.sum(w**2)), "boxcar": np.sqrt(np.mean(x**2))}
    for window, rms in expected.items():
        got = octave_rms(x, fs, "octave", beyond_nyquist="drop", **window_options(window)).as_dict()["125Hz"]
        assert got == pytest.approx(rms, rel=3e-3), window
    # the two expectations lie 3 % apart, ten times the tolerance: a window not applied fails one check above
    assert expected["hann"] / expected["boxcar"] == pytest.approx(0.970, abs=0.002)


def test_a_model_output_s_bands_beyond_table_3_carry_a_note(tmp_path, capsys):
    """Third-octave bands of a model output up to 20 kHz (top edge 22 387 Hz) are noted as beyond the
    paper's Table 3, with the trapezoidal rule's period error (ω Δt)² / 12 at Δt = 1e-5 s: 16 % at
    22 387 Hz, 1.1 % at 5680 Hz (the record of every step, which states its Nyquist frequency as its
    passband, gives its run's step); a measurement's column and Table 3's bands carry no such note."""
    t = 1e-5 * np.arange(1, 100_001)  # 1 s at 1e-5 s, the specimens' full-rate record
    x = np.sin(2 * np.pi * 300 * t) + 0.01 * np.sin(2 * np.pi * 9000 * t)
    for col in ("casing.B.Fz", "accel"):
        path = tmp_path / f"{col}.csv"
        header = f"time,{col}\n{passband_line(0.5 / 1e-5)}"
        np.savetxt(path, np.column_stack([t, x]), delimiter=",", header=header, comments="")
        assert main(["bands", str(path), "--column", col, "--kind", "third", "--fmin", "25"]) == 0
        out = capsys.readouterr().out
        noted = "# the bands above 5680 Hz lie beyond the paper's Table 3" in out
        assert noted == (col == "casing.B.Fz"), out
        if noted:
            assert "period error is 16 % at 22387 Hz (1.1 % at 5680 Hz)" in out, out
    assert main(["bands", str(tmp_path / "casing.B.Fz.csv")]) == 0
    assert "beyond the paper's Table 3" not in capsys.readouterr().out


def test_a_band_of_fewer_than_four_lines_warns_and_holds_what_lies_beside_it():
    """A 1 N RMS tone at 20 Hz and the 16 Hz third (14.1-17.8 Hz, 3.66 Hz wide) beside it: from
    0.44 s (df = 2.27 Hz, 1.6 lines in the band, the tone one line beyond its edge) the third reads
    0.30 N through Hann's window, about the 1/6 of the tone's power (0.41 N) a neighbouring line
    takes, and octave_rms warns naming the bands and the 1.09 s that give the 16 Hz third 4 lines;
    from 1.1 s (4 lines) it reads under 0.02 N, the tone beyond the main lobe's reach, and no band
    warns."""
    from cablecasing_core.errors import ModelWarning
    from cablecasing_core.nvh.bands import few_lines, octave_bands

    fs, bands = 1e4, octave_bands("third", 16, 25)
    for length, low, warns in ((0.44, (0.25, 0.41), True), (1.1, (0.0, 0.02), False)):
        t = np.arange(int(length * fs)) / fs
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            got = octave_rms(np.sqrt(2) * np.sin(2 * np.pi * 20 * t), fs, bands, name="tone").as_dict()
        assert low[0] <= got["16Hz"] <= low[1], (length, got)
        assert got["20Hz"] == pytest.approx(1.0, abs=0.08)  # (what the neighbours took)
        texts = [str(w.message) for w in said if issubclass(w.category, ModelWarning)]
        assert bool(texts) == warns == bool(few_lines(bands, length)), texts
        if warns:
            assert texts[0].startswith(
                "tone: its 0.44 s put fewer than 4 FFT lines (df = 2.27 Hz) in band(s) 16Hz, 20Hz"
            )
            assert "4 lines in 16Hz need a record of 4 / 3.66 Hz = 1.09 s" in texts[0], texts[0]


def test_an_ensemble_s_records_of_few_lines_warn_once_before_the_runs():
    """check_record_settings warns of the bands a record puts fewer than 4 lines in, once, where the
    ensembles and studies check their settings; the runs themselves do not warn again."""
    import cablecasing_core as cc
    from cablecasing_core.errors import ModelWarning
    from cablecasing_core.studies.evaluators import check_record_settings

    model = cc.load_model()
    with pytest.warns(
        ModelWarning, match=r"the records after skip = 0.06 s: its 0.24 s put fewer than 4 FFT lines .* oct1"
    ):
        check_record_settings(model, duration=0.3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_record_settings(model, duration=0.5)  # (0.44 s: 4.8 lines in oct1)
