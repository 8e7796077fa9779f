"""Defects of the time-domain API and the record files found by a review (review E): the CSV time
unit, CSV excitations that end before the run, the inputs of a loaded run, the passband through
load and save, repeated and quoted CSV headers, a save into a missing folder, ``simulate_sampled``'s
arguments, the API's argument names, and the seeds of two random excitations."""

import copy
import warnings
from pathlib import Path

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.errors import ModelError, ModelWarning
from cablecasing_core.files import WriteError
from cablecasing_core.model.schema import CHANNELS, INPUTS
from cablecasing_core.records import read_records
from cablecasing_core.timedomain.scenario import scenario_motion, short_tables
from cablecasing_core.timedomain.simulation import simulate_sampled

ROOT = Path(__file__).resolve().parents[2]


def _model(excitation, ramp=0.0, dt=1e-5, duration=0.2, base_dir=None):
    d = copy.deepcopy(cc.load_model().data)
    d["scenario"].update(excitation=excitation, ramp=ramp, dt=dt, duration=duration)
    return cc.model_from_dict(d, base_dir=base_dir)


@pytest.fixture(scope="module")
def run():
    """The built-in specimen's scenario over 5 ms (500 steps of 1e-5 s), without contact (fast)."""
    return cc.simulate(cc.load_model(), duration=0.005, contact=False)


# --- 1. the CSV time column's unit ----------------------------------------------------------------


@pytest.mark.parametrize(
    ("head", "fs"),
    [
        *[("time [s]", 10.0), ("time [ms]", 1e4), ("time_ms", 1e4), ("time [us]", 1e7), ("time [µs]", 1e7)],
        ("t", 10.0),
        # (the units a UFF 58 abscissa label takes, one table: time [sec] was read as s before the ms change)
        *[("time [sec]", 10.0), ("time_sec", 10.0), ("Time [Seconds]", 10.0), ("time (msec)", 1e4)],
        *[("time [usec]", 1e7), ("time [MS]", 1e4)],
    ],
)
def test_a_csv_records_time_is_read_in_its_unit(tmp_path, head, fs):
    path = tmp_path / "r.csv"
    path.write_text(f"{head},casing.B.Fz [N]\n0,0\n0.1,1\n0.2,0\n0.3,-1\n")
    rec = read_records(path)
    assert rec.fs == pytest.approx(fs, rel=1e-12)  # (0.1 in the unit, converted by one product)
    np.testing.assert_array_equal(rec.column("casing.B.Fz"), [0, 1, 0, -1])


@pytest.mark.parametrize("head", ["time [N]", "time [Hz]", "time_min", "t (h)"])
def test_a_csv_records_time_in_a_unit_not_of_time_is_refused(tmp_path, head):
    path = tmp_path / "r.csv"
    path.write_text(f"{head},casing.B.Fz [N]\n0,0\n0.1,1\n0.2,0\n")
    with pytest.raises(ModelError, match=r"^file = .*r\.csv'?: must give the time of its first column in s, ms or us"):
        read_records(path)


def test_a_csv_excitation_in_ms_runs_as_the_same_table_in_s(tmp_path):
    tt = np.linspace(0.0, 0.05, 51)
    x = 1e-4 * np.sin(2 * np.pi * 20.0 * tt)
    rows = [(float(t), float(v)) for t, v in zip(tt, x)]
    (tmp_path / "s.csv").write_text("time_s,u\n" + "".join(f"{t!r},{v!r}\n" for t, v in rows))
    (tmp_path / "ms.csv").write_text("time [ms],u\n" + "".join(f"{1e3 * t!r},{v!r}\n" for t, v in rows))
    col = CHANNELS.index("casing.A.z")
    tm = np.linspace(0.0, 0.05, 333)
    u = {}
    for name in ("s", "ms"):
        m = _model({"c": {"target": "casing.A.z", "kind": "csv", "file": f"{name}.csv"}}, base_dir=tmp_path)
        u[name] = scenario_motion(m)(tm)[0][:, col]
    # the same spline through times that differ by the rounding of 1e-3 * (1e3 t): 1e-16 relative
    np.testing.assert_allclose(u["ms"], u["s"], rtol=0, atol=1e-4 * 1e-12)
    # and it is the sine: a cubic spline through samples h = 1 ms apart errs by at most
    # 5/384 h^4 max|x''''| = 3.2e-10 m (measured 8.9e-11 m)
    np.testing.assert_allclose(u["s"], 1e-4 * np.sin(2 * np.pi * 20.0 * tm), rtol=0, atol=4e-10)


@pytest.mark.parametrize("head", ["displacement_m,time_s", "time [N],u", "x,u"])
def test_a_csv_excitation_must_have_the_time_first(tmp_path, head):
    (tmp_path / "c.csv").write_text(f"{head}\n0,0\n0.001,1e-5\n0.002,0\n")
    with pytest.raises(ModelError, match=r"^scenario\.excitation\.c\.file = .*c\.csv'?: must (have|give) the time"):
        scenario_motion(_model({"c": {"target": "casing.A.z", "kind": "csv", "file": "c.csv"}}, base_dir=tmp_path))


# --- 2. a CSV excitation that ends before the run -------------------------------------------------


def _sine_table(path, t_end):
    tt = np.arange(0.0, t_end + 1e-12, 1e-4)
    x = 1e-4 * np.sin(2 * np.pi * 100.0 * tt)
    path.write_text("time_s,u\n" + "".join(f"{float(t)!r},{float(v)!r}\n" for t, v in zip(tt, x)))


def test_a_csv_excitation_that_ends_before_the_run_warns(tmp_path):
    _sine_table(tmp_path / "cut.csv", 0.001)
    m = _model({"c": {"target": "casing.A.z", "kind": "csv", "file": "cut.csv"}}, duration=0.002, base_dir=tmp_path)
    (said,) = short_tables(m)
    assert "cut.csv ends at t = 0.001 s" in said and "scenario.duration = 0.002 s" in said
    assert "holds its last displacement at rest" in said
    with pytest.warns(ModelWarning, match=r"ends at t = 0\.001 s, before the end of the run, scenario\.duration"):
        res = cc.simulate(m, contact=False)
    # what it warns of: the support's velocity drops to 0 in one step (a sine of 100 Hz and 1e-4 m
    # ends at 0.0628 m/s; the spline's not-a-knot end slope of its 11 samples gives 0.051)
    v = res.inputs["casing.A.vz"]
    k = np.searchsorted(res.time, 0.001 + 1e-9)
    assert abs(v[k - 1]) > 0.04 and v[k] == 0.0
    # a run's own duration is named as such; a table that covers the run gives no warning
    with pytest.warns(ModelWarning, match=r"before the end of the run, duration = 0\.0015 s"):
        cc.simulate(m, duration=0.0015, contact=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)
        cc.simulate(m, duration=0.001, contact=False)
        _sine_table(tmp_path / "cut.csv", 0.002)
        assert short_tables(m) == []


# --- 3. and 4. a loaded run: its inputs and its passband ------------------------------------------


def test_a_loaded_run_has_only_the_driven_inputs_and_picks_the_contact_count(run, tmp_path):
    res = copy.deepcopy(run)
    res.contact_state[200:203, 3] = 1  # three steps of contact at one node
    res.save(tmp_path / "c.npz")
    back = cc.SimulationResult.load(tmp_path / "c.npz")
    assert list(back.inputs) == list(res.inputs) and set(back.inputs) <= set(INPUTS)
    assert set(back.initial_inputs) == set(res.inputs)
    got = back.records(1e-4).columns["contact.active"]
    np.testing.assert_array_equal(got, res.records(1e-4).columns["contact.active"])  # picked: whole counts
    np.testing.assert_array_equal(got, np.round(got))


def test_a_decimated_run_keeps_its_passband_through_load_and_save(run, tmp_path):
    run.save(tmp_path / "d.npz", output_interval=1e-4)
    assert read_records(tmp_path / "d.npz").passband_hz == pytest.approx(3500.0, rel=1e-12)  # 0.7 / (2 1e-4)
    back = cc.SimulationResult.load(tmp_path / "d.npz")
    back.save(tmp_path / "d2.npz")
    assert read_records(tmp_path / "d2.npz").passband_hz == pytest.approx(3500.0, rel=1e-12)
    assert back.records().passband_hz == pytest.approx(3500.0, rel=1e-12)
    # filtered again at 2e-4 s: the lower passband, 0.7 / (2 2e-4) = 1750 Hz
    assert back.records(2e-4).passband_hz == pytest.approx(1750.0, rel=1e-12)


# --- 5. and 6. repeated and quoted CSV headers ----------------------------------------------------


def test_a_column_repeated_in_its_earlier_form_is_refused(tmp_path):
    path = tmp_path / "r.csv"
    path.write_text("time [s],casing.B.Fz [N],casing.B.Fz_N\n0,1,2\n0.1,1,2\n0.2,1,2\n")
    with pytest.raises(ModelError, match=r"column 3 repeats the name of column 2"):
        read_records(path)


def test_quoted_csv_headers_and_numbers_are_read_without_the_quotes(tmp_path):
    path = tmp_path / "q.csv"
    path.write_text('"time [ms]","casing.B.Fz [N]"\n0,0.5\n0.1,1.5\n0.2,-2\n')
    rec = read_records(path)
    assert rec.names == ("casing.B.Fz",) and rec.unit("casing.B.Fz") == "N" and rec.fs == pytest.approx(1e4)
    path.write_text('"time [s]","casing.B.Fz [N]"\n"0","0.5"\n"0.1","1.5"\n"0.2","-2"\n')  # pandas quoting=ALL
    np.testing.assert_array_equal(read_records(path).column("casing.B.Fz"), [0.5, 1.5, -2.0])


# --- 7. a save into a folder that does not exist --------------------------------------------------


def test_a_save_into_a_missing_folder_names_the_target(run, tmp_path):
    target = tmp_path / "nonexist" / "x.csv"
    with pytest.raises(WriteError, match=r"its folder .*nonexist does not exist") as exc:
        run.save(target)
    assert exc.value.filename == str(target) and not exc.value.kept
    assert not (tmp_path / "nonexist").exists()


# --- 8. simulate_sampled's arguments --------------------------------------------------------------


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((1e-3, 1e-4, None), r"^duration = 0\.0001: must be at least one communication step \(step = 0\.001 s\)"),
        ((1e-4, 1e-3, np.zeros((5, 3))), r"^table = an array of shape \(5, 3\): must be an array of shape \(n, 36\)"),
        ((1e-4, 1.0, np.zeros((5, 36))), r"^table = an array of shape \(5, 36\): .* n = duration / step = 10000 steps"),
        ((1e-4, 3e-4, np.full((3, 36), np.nan)), r"^table = .*: must hold finite numbers"),
    ],
)
def test_simulate_sampled_refuses_bad_arguments_naming_them(args, message):
    step, duration, table = args
    with pytest.raises(ModelError, match=message):
        simulate_sampled(cc.load_model(), step, duration, table=table)


def test_simulate_sampled_runs_duration_over_step_rows_of_a_longer_table():
    model = cc.load_model()
    table = np.hstack(scenario_motion(model)(1e-4 * np.arange(8)))
    t, out = simulate_sampled(model, 1e-4, 5e-4, table=table, contact=False)
    t5, out5 = simulate_sampled(model, 1e-4, 5e-4, table=table[:5], contact=False)
    assert len(t) == 5 and np.array_equal(out, out5)


# --- 9. the API's errors name its arguments -------------------------------------------------------


def test_the_api_names_its_arguments_not_the_cli_options(run, tmp_path):
    with pytest.raises(ModelError, match=r"^output_interval = 0: must be"):
        run.records(0)
    with pytest.raises(ModelError, match=r"^output_interval = 1\.5e-05: must be a whole number of time steps"):
        run.save(tmp_path / "x.csv", output_interval=1.5e-5)
    with pytest.raises(ModelError, match=r"^path = '.*x\.txt': must end in \.csv, \.npz, \.uff"):
        run.save(tmp_path / "x.txt")


def test_the_cli_renames_the_save_arguments_to_its_options(tmp_path, monkeypatch, capsys):
    """``cablecasing simulate`` checks its options before the run; an error ``save`` raises after it
    is named by the option too (``renamed``)."""
    from cablecasing_core.cli import main
    from cablecasing_core.timedomain import simulation

    def refuse(self, path, output_interval=None, decimation="filter"):
        raise ModelError("output_interval", output_interval, "must be refused here")

    monkeypatch.setattr(simulation.SimulationResult, "save", refuse)
    args = ["simulate", "--duration", "0.0002", "--no-contact", "--no-progress", "--out", str(tmp_path / "r.npz")]
    assert main(args) == 2
    assert "--output-interval = None: must be refused here" in capsys.readouterr().err


# --- 10. two random excitations without their own seed --------------------------------------------


def _shakers(seed_b=None):
    b = {"target": "casing.B.y", "kind": "random", "rms": 5.0, "band": [10.0, 1000.0]}
    if seed_b is not None:
        b["seed"] = seed_b
    a = {"target": "casing.A.z", "kind": "random", "rms": 5.0, "band": [10.0, 1000.0]}
    return {"shaker_a": a, "shaker_b": b}


def test_two_random_excitations_without_a_seed_are_independent_and_the_first_keeps_its_record():
    from cablecasing_core.model.validate import derived_seed
    from cablecasing_core.timedomain.random_record import LINE_SPACING

    dt = 2.5e-4  # (4 kHz, above twice the band's top)
    two = _model(_shakers(), dt=dt)
    one = _model({"shaker_a": _shakers()["shaker_a"]}, dt=dt)
    ex, seed = two.scenario["excitation"], two.scenario["seed"]
    assert ex["shaker_a"]["seed"] == seed
    assert ex["shaker_b"]["seed"] == derived_seed(seed, "shaker_b") != seed
    t = dt * np.arange(int(round(1 / LINE_SPACING / dt)))  # one period, 64 s: the lines are orthogonal
    a = scenario_motion(two)(t)[2]
    za, yb = a[:, CHANNELS.index("casing.A.z")], a[:, CHANNELS.index("casing.B.y")]
    # the first, bit for bit the record of the model with it alone (so the specimens keep theirs)
    assert np.array_equal(za, scenario_motion(one)(t)[2][:, CHANNELS.index("casing.A.z")])
    # over a period the correlation is sum_k cos(phi_k - psi_k) / K of K = 63361 lines with
    # independent phases: standard deviation 1/sqrt(2 K) = 0.0028, so 0.02 is 7 of them
    assert abs(np.corrcoef(za, yb)[0, 1]) < 0.02
    # the same seed given to both: one record twice (what a derived seed avoids)
    same = scenario_motion(_model(_shakers(seed_b=seed), dt=dt))(t[:1000])[2]
    assert np.array_equal(same[:, CHANNELS.index("casing.A.z")], same[:, CHANNELS.index("casing.B.y")])
    # an override of scenario.seed derives both again; the derived seed is not written to TOML
    moved = two.with_overrides({"scenario.seed": 5}).scenario["excitation"]
    assert moved["shaker_a"]["seed"] == 5 and moved["shaker_b"]["seed"] == derived_seed(5, "shaker_b")
    assert "seed" not in two.to_toml().split("[scenario.excitation.shaker_b]")[1]


def test_simulate_sampled_drives_an_excited_clip_as_the_fmu_does():
    """A model with an excited clip has 15 channels (its x, y, z): the table's 45 columns were
    accepted and then cut as 12 channels (ValueError: inputs of shapes (12,), (12,), (21,)). Its run now returns every
    output of the engine, the clips' forces among them, and those follow the run on the exact
    scenario motion: the sampled run reconstructs each 1e-4 s step from the inputs at its start
    (measured within 2.7e-4 of each clip force's peak; 1e-3 leaves room for the random drive)."""
    from cablecasing_core.timedomain.engine import Engine

    m = cc.load_model(ROOT / "examples" / "clipped_specimen.toml")
    t, out = simulate_sampled(m, 1e-4, 0.02, contact=False)
    names = Engine(m, contact=False).output_names
    assert out.shape == (200, len(names))
    res = cc.simulate(m, duration=0.02, contact=False, progress=False)
    for name in [n for n in res.force_names if ".clip" in n and n[-2] == "F"]:
        ref = res.support_force(name)[9::10]  # (the run's steps of 1e-5 s at the sampled times)
        assert np.abs(out[:, names.index(name)] - ref).max() <= 1e-3 * np.abs(ref).max(), name
