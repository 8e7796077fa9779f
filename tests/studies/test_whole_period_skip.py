"""The default skip of the band levels of an ensemble, a study, the report
(``timedomain.scenario.whole_period_skip``) and of ``bands``/``spectrum`` on a run's record (which
states its lines, ``records.Records.default_skip``): 0.05 s lengthened so that the rest of the
record holds whole periods of the scenario's harmonic excitations, whose lines then stay in their
bins of the rectangular window (docs/time_domain.md, "The record's length")."""

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelError
from cablecasing_core.nvh.bands import window_options
from cablecasing_core.records import after_skip, read_records
from cablecasing_core.studies import octave_rms, seed_ensemble
from cablecasing_core.timedomain.scenario import whole_period_skip
from cablecasing_core.timedomain.start_skip import LEAST_SKIP, skip_for_whole_periods

DRIVE = "scenario.excitation.cable_axial"


@pytest.fixture(scope="module")
def specimen():
    return cc.load_model()


def test_the_specimens_keep_whole_periods_of_their_50_hz_drive(specimen):
    """1 s keeps 0.94 s (47 periods of 20 ms), 0.5 s keeps 0.44 s (22), whatever the step; a record
    that holds whole periods after 0.05 s keeps them (0.15 s: 5 periods)."""
    assert whole_period_skip(specimen) == 0.06
    assert whole_period_skip(cc.load_model("installed")) == 0.06
    assert whole_period_skip(specimen, duration=0.5) == 0.06
    assert whole_period_skip(specimen, dt=2e-5) == 0.06
    assert whole_period_skip(specimen, duration=0.15) == 0.05


@pytest.mark.parametrize("dt", [7e-5, 3e-5, 1 / 30000])
def test_the_skip_lies_on_the_steps_grid_and_never_before_the_least(specimen, dt):
    """A step that does not divide the period (7e-5 s into 20 ms) puts the skip on the nearest step
    of the grid (a whole number of steps, within dt / 2 of 0.06 s); a grid step nearest to it
    but before 0.05 s gives way to the first step after 0.05 s (0.15 s with steps of 0.7 ms:
    0.0504 s, not 0.0497 s)."""
    skip = whole_period_skip(specimen, dt=dt)
    assert abs(skip / dt - round(skip / dt)) < 1e-9 and abs(skip - 0.06) <= dt / 2
    short = skip_for_whole_periods([50.0], 0.15, 7e-4)
    assert short >= LEAST_SKIP and short == pytest.approx(72 * 7e-4, abs=1e-15)


def test_a_study_sample_and_the_report_take_the_default_skip(specimen):
    """default_evaluate (a study's sample) without skip gives the levels after 0.06 s, not after
    0.05 s; the report's 0.5 s records leave out 0.32 s (at least the drive's start transient,
    report.start_transient, 0.30 s, then whole periods: 9 of 50 Hz in the 0.18 s left)."""
    from cablecasing_core.report import check_report_settings
    from cablecasing_core.studies.evaluators import default_evaluate

    got = default_evaluate({}, duration=0.3, model=specimen)
    assert got == default_evaluate({}, duration=0.3, skip=0.06, model=specimen)
    assert got != default_evaluate({}, duration=0.3, skip=0.05, model=specimen)
    assert check_report_settings(specimen, 0.5)[3] == 0.32


def test_the_common_period_of_several_lines_and_when_there_is_none(specimen):
    """50 and 75 Hz repeat together every 40 ms (their gcd 25 Hz): 23 periods of 1 s - 0.05 s, skip
    0.08 s. 50 and 50.5 Hz repeat every 2 s, longer than the record: 0.05 s. No line, or one of
    zero amplitude: 0.05 s. A fade-in longer than 0.05 s is left out too (0.2 s: 40 periods after it)."""
    import tomllib

    from cablecasing_core.model.load import model_from_dict

    def with_second(frequency):  # (an excitation comes with its kind and target from a model file)
        raw = tomllib.loads(specimen.to_toml())
        second = {"target": "casing.B.z", "kind": "harmonic", "amplitude": 1e-5, "frequency": frequency}
        raw["scenario"]["excitation"]["second"] = second
        return model_from_dict(raw)

    assert whole_period_skip(with_second(75.0)) == pytest.approx(0.08, abs=1e-12)
    assert whole_period_skip(with_second(50.5)) == LEAST_SKIP
    assert whole_period_skip(specimen.with_overrides({f"{DRIVE}.amplitude": 0.0})) == LEAST_SKIP
    assert whole_period_skip(specimen.without_excitations(["cable_axial"])) == LEAST_SKIP
    assert whole_period_skip(specimen.with_overrides({"scenario.ramp": 0.2})) == pytest.approx(0.2, abs=1e-12)


def test_a_line_of_whole_periods_stays_in_its_band_and_half_a_period_leaks(specimen):
    """The installed specimen's drive line (27 N RMS at 50 Hz in octave 3) over 1 s at 1e-5 s. After
    the default skip octaves 1-2 hold nothing of it through either window (DFT orthogonality; Hann's
    main lobe, bins 46-48, lies in octave 3: 1e-9 N bounds the round-off of 94 000 samples). After
    0.05 s (47.5 periods) it lies half a bin off every bin, d = 47.5 - k bins from bin k, and puts
    into bin k the share of its power of the window's kernel there: the rectangular window's
    1 / (pi d)^2, Hann's (power-normalised by 3/8) 2/3 / (pi d (d^2 - 1))^2; octave 2 (22-44 Hz, the
    bins k = 21 .. 42 of 1.0526 Hz, its edge bins by the share inside it) so holds 3.2 N of it
    through the rectangular window, 200 times the installed specimen's own level there, and 0.043 N
    through Hann's, still three times it. Hann's within 1 % (the kernel's large-n form); the
    rectangular window's within 15 % (the line's image at -50 Hz, 47.5 + k bins away, adds or takes
    with its phase)."""
    dt = 1e-5
    t = dt * np.arange(1, 100_001)
    F = 27.0 * np.sqrt(2.0) * np.sin(2 * np.pi * 50.0 * t + 0.4)
    df = 1 / 0.95
    k = np.arange(60)
    inside = np.clip(np.minimum(k + 0.5, 44 / df) - np.maximum(k - 0.5, 22 / df), 0, 1)
    d = 47.5 - k
    for window, share, rel in (
        ("hann", 2 / 3 / (np.pi * d * (d**2 - 1)) ** 2, 0.01),
        ("boxcar", 1 / (np.pi * d) ** 2, 0.15),
    ):
        whole = octave_rms(F[after_skip(t, whole_period_skip(specimen))], 1 / dt, **window_options(window)).rms
        assert np.all(whole[:2] < 1e-9) and whole[2] == pytest.approx(27.0, rel=1e-12)
        half = octave_rms(F[after_skip(t, 0.05)], 1 / dt, **window_options(window)).rms
        assert half[1] == pytest.approx(27.0 * np.sqrt(np.sum(inside * share)), rel=rel), window


def test_an_ensemble_takes_and_states_the_default_skip(specimen):
    """An ensemble of 0.3 s runs leaves out 0.05 s -> 0.06 s (12 whole periods) by default, says so in
    its settings, and a member's levels are the single run's after 0.06 s."""
    ens = seed_ensemble(specimen, [3, 4], duration=0.3)
    assert ens.settings["skip"] == 0.06
    run = cc.simulate(specimen.with_overrides({"scenario.excitation.casing_random.seed": 4}), duration=0.3)
    fs = 1.0 / (run.time[1] - run.time[0])  # (as the evaluator takes it)
    ref = octave_rms(run.support_force("casing.B.Fz")[after_skip(run.time, 0.06)], fs, "table3").rms
    np.testing.assert_array_equal(ens.levels[1], ref)


@pytest.mark.parametrize("suffix", [".csv", ".npz"])
def test_a_runs_record_states_its_lines_and_bands_keeps_whole_periods(specimen, tmp_path, capsys, suffix):
    """A run of 0.3 s writes its 50 Hz line (``# lines_hz = 50`` in a CSV, an array in an NPZ);
    read back, its default skip is 0.06 s (0.24 s = 12 periods after it), and `cablecasing bands`
    without --skip gives the levels after 0.06 s, as octave_rms of the run's samples after it
    (to the 6 digits of its table). A run of a motion of its own states no line (its default 0.05 s)."""
    run = cc.simulate(specimen, duration=0.3)
    path = tmp_path / f"run{suffix}"
    run.save(path)
    rec = read_records(path)
    assert rec.lines_hz == (50.0,) and rec.default_skip() == 0.06
    assert main(["bands", str(path), "--out", str(tmp_path / "b.csv")]) == 0
    assert "after 0.06 s" in capsys.readouterr().out
    got = np.loadtxt(tmp_path / "b.csv", delimiter=",", skiprows=1, usecols=4, comments="#")
    ref = octave_rms(run.support_force("casing.B.Fz")[after_skip(run.time, 0.06)], 1e5, "table3").rms
    np.testing.assert_allclose(got, ref, rtol=6e-6)  # (the table's 6 digits, the record's 9)
    still = cc.simulate(specimen, duration=0.3, motion=cc.timedomain.scenario.zero_motion)
    assert still.records().lines_hz == () and still.records().default_skip() == LEAST_SKIP


@pytest.mark.parametrize("suffix", [".csv", ".npz"])
def test_a_runs_record_states_its_fade_in_and_bands_starts_after_it_as_the_ensemble_does(
    specimen, tmp_path, capsys, suffix
):
    """A scenario fading in over 0.123 s (``scenario.ramp``) writes ``# ramp_s = 0.123``; read back,
    the record's default skip starts after it and keeps whole periods of the 50 Hz drive after that:
    0.14 s of 0.3 s (8 periods after it), the skip ``ensemble`` and ``study`` take for the same
    scenario (``whole_period_skip``), and `bands` without --skip says so. The specimen's own 0.01 s
    ramp is stated too and changes nothing (0.05 s is longer); a motion of its own has none."""
    model = specimen.with_overrides({"scenario.ramp": 0.123})
    run = cc.simulate(model, duration=0.3)
    path = tmp_path / f"run{suffix}"
    run.save(path)
    rec = read_records(path)
    assert rec.ramp_s == 0.123 and rec.default_skip() == pytest.approx(0.14, abs=1e-12)
    assert rec.default_skip() == pytest.approx(whole_period_skip(model, 0.3), abs=1e-12)
    if suffix == ".csv":
        assert "\n# ramp_s = 0.123 (s: " in path.read_text()[:2000]
    assert main(["bands", str(path)]) == 0
    assert "after 0.14 s" in capsys.readouterr().out
    if suffix == ".npz":  # (a loaded run passes it on to its records)
        assert cc.SimulationResult.load(path).records().ramp_s == 0.123
    plain = cc.simulate(specimen, duration=0.3).records()
    assert plain.ramp_s == 0.01 and plain.default_skip() == 0.06
    still = cc.simulate(specimen, duration=0.3, motion=cc.timedomain.scenario.zero_motion)
    assert still.records().ramp_s == 0.0


def test_a_record_that_states_its_fade_in_badly_is_refused(tmp_path):
    """``# ramp_s`` (CSV) or the array ``ramp_s`` (NPZ) must be one finite number of s, 0 or more
    (``scenario.ramp = 0`` is no fade-in); the NPZ's other statements are checked as a CSV's."""
    path = tmp_path / "r.csv"
    for bad in ("soon", "0.1 0.2", "-0.1", "inf", "nan"):
        path.write_text(f"time [s],casing.B.Fz [N]\n# ramp_s = {bad}\n0,1\n0.001,2\n")
        with pytest.raises(ModelError, match="line 2 states ramp_s, but not as a number of s, 0 or more"):
            read_records(path)
    path.write_text("time [s],casing.B.Fz [N]\n# ramp_s = 0\n0,1\n0.001,2\n")
    assert read_records(path).ramp_s == 0.0
    npz = tmp_path / "r.npz"
    good = {"time": np.array([0.0, 1e-3]), "table": np.ones((2, 1)), "names": np.array(["casing.B.Fz"])}
    for name, bad in [
        ("ramp_s", np.inf),
        ("ramp_s", [0.1, 0.2]),
        ("ramp_s", -1.0),
        ("ramp_s", np.nan),
        ("ramp_s", "soon"),
        ("lines_hz", [50.0, -1.0]),
        ("passband_hz", 0.0),
    ]:
        np.savez(npz, **good, **{name: np.array(bad)})
        with pytest.raises(ModelError, match=f"its array {name} must be"):
            read_records(npz)
    np.savez(npz, **good, ramp_s=np.array(0.2), lines_hz=np.array([50.0, 75.0]), passband_hz=np.array(300.0))
    rec = read_records(npz)
    assert (rec.ramp_s, rec.lines_hz, rec.passband_hz) == (0.2, (50.0, 75.0), 300.0)


def test_a_csv_that_states_its_lines_badly_is_refused(tmp_path):
    """``# lines_hz`` must be positive numbers of Hz separated by spaces."""
    path = tmp_path / "r.csv"
    for bad in ("fifty", "50, 75", "-50"):
        path.write_text(f"time [s],casing.B.Fz [N]\n# lines_hz = {bad}\n0,1\n0.001,2\n")
        with pytest.raises(ModelError, match="line 2 states lines_hz, but not as positive numbers of Hz"):
            read_records(path)
    path.write_text("time [s],casing.B.Fz [N]\n# lines_hz = 50 75 (Hz)\n0,1\n0.001,2\n")
    assert read_records(path).lines_hz == (50.0, 75.0)


def test_a_study_begun_with_the_earlier_skip_and_window_resumes_only_with_them(tmp_path):
    """A study's sidecar stores its record settings (skip None, Hann's window); one written before
    they were settings (no window, skip 0.05 s) took the rectangular window and 0.05 s, so resuming
    it with the present defaults is refused (its samples would mix two estimators), and with
    skip=0.05, window="boxcar" it resumes (two more samples of the design)."""
    import json

    from cablecasing_core.errors import ModelError
    from cablecasing_core.studies import run_study

    path = tmp_path / "s.csv"
    kw = dict(n_samples=2, seed=1, scheduler="serial", progress=False, max_samples=2)
    run_study(path, evaluate_kwargs={"duration": 0.15, "skip": 0.01}, **kw)
    sidecar = tmp_path / "s.csv.meta.json"
    meta = json.loads(sidecar.read_text())
    assert meta["evaluate_kwargs"]["window"] == "hann"  # (stored with the study)
    del meta["evaluate_kwargs"]["window"]  # (as a study of the earlier version stored it)
    meta["evaluate_kwargs"]["skip"] = 0.05
    sidecar.write_text(json.dumps(meta))
    with pytest.raises(ModelError, match="evaluate_kwargs"):
        run_study(path, evaluate_kwargs={"duration": 0.15, "skip": 0.05}, **kw)
    res = run_study(path, evaluate_kwargs={"duration": 0.15, "skip": 0.05, "window": "boxcar"}, **kw)
    assert len(res) == 4 and list(res.index) == [0, 1, 2, 3]


def test_an_ensemble_saved_before_the_window_was_a_setting_pools_with_a_rectangular_part(specimen, tmp_path):
    """An ensemble CSV whose settings hold a skip but no window took the rectangular window: it pools
    with a part of window="boxcar" (same skip) and not with one of Hann's."""
    from cablecasing_core.studies import load_ensemble, pool_ensembles

    old = seed_ensemble(specimen, [1, 2], duration=0.15, skip=0.05, window="boxcar")
    old.save(tmp_path / "old.csv")
    text = (tmp_path / "old.csv").read_text().replace(', "window": "boxcar"', "")
    (tmp_path / "old.csv").write_text(text)
    assert load_ensemble(tmp_path / "old.csv").settings["window"] == "boxcar"
    seed_ensemble(specimen, [3, 4], duration=0.15, skip=0.05, window="boxcar").save(tmp_path / "rect.csv")
    assert pool_ensembles([tmp_path / "old.csv", tmp_path / "rect.csv"]).n == 4
    seed_ensemble(specimen, [3, 4], duration=0.15, skip=0.05).save(tmp_path / "hann.csv")
    with pytest.raises(ModelError, match="settings"):
        pool_ensembles([tmp_path / "old.csv", tmp_path / "hann.csv"])


def test_paired_ensembles_take_the_same_samples_whatever_their_drive(tmp_path, capsys):
    """`ensemble --against` a drive of 60 Hz: both ensembles leave out the first's whole periods of
    50 Hz (0.06 s of 0.3 s), so they are paired on the same samples, and pool with their parts."""
    from cablecasing_core.studies import load_ensemble

    out = tmp_path / "e.csv"
    argv = ["ensemble", "--seeds", "2", "--duration", "0.3", "--scheduler", "serial", "--out", str(out)]
    assert main(argv + ["--against", f"{DRIVE}.frequency=60"]) == 0
    first, second = load_ensemble(out), load_ensemble(tmp_path / "e_against.csv")
    assert first.settings["skip"] == second.settings["skip"] == 0.06
