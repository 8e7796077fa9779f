"""Review R (an NVH engineer's ensembles and studies, serial and on dask): a change no seed can run
refused before the first member, naming the change; a study none of whose samples can run refused
before the first; a partly failed study's summary; the samples in flight when the scheduler is
lost in the lost log; the command and run_study refusing each other's study for the true reason;
the key hint without case; the study CSV's line ending and units; the kernels a study's rows were
computed with; Sobol tables too uncertain to print."""

import json

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.errors import InfrastructureError, ModelError, ModelWarning, closest
from cablecasing_core.studies import executor, load_results, run_study, sobol_design
from cablecasing_core.studies.results_store import LostLog

ANALYTIC = "cablecasing_core.studies._stand_ins:analytic_evaluate"
BOUNDS = {"casing.E": (2e9, 1e10), "contact.friction": (0.05, 0.2)}
# (records of 0.1 s from t = 0: the shortest that holds one bin of the 11-22 Hz band, 1/11 s)
SHORT = ["--duration", "0.1", "--skip", "0", "--scheduler", "serial"]


def _no_run(*args, **kwargs):
    raise AssertionError("a sample ran")


@pytest.fixture
def installed():
    """The installed specimen, the tension of the model file (N) and the casing's buckling load (N)."""
    model = cc.load_model("installed")
    return model, model.loads["cable_tension"], cc.body_buckling(model, "casing").load


# ---- R1: refused before the first run --------------------------------------------------------


@pytest.mark.parametrize("flag", ["--set", "--against"])
def test_a_tension_above_the_buckling_load_is_refused_before_any_member_naming_the_change(
    flag, installed, capsys, monkeypatch
):
    from cablecasing_core.studies import ensemble_runs

    _, _, p_cr = installed
    tension = round(1.1 * p_cr, 1)  # (10 % above the load the buckling module computes: no seed can run it)
    monkeypatch.setattr(ensemble_runs, "execute", _no_run)
    argv = ["ensemble", "installed", "--seeds", "3", *SHORT, flag, f"loads.cable_tension={tension}"]
    assert main(argv) == 2
    text = capsys.readouterr()
    assert f"{flag} loads.cable_tension = {tension}: must be below the casing's buckling load" in text.err
    assert "seeds =" not in text.err and "band,f_low_hz" not in text.out  # (no seed blamed; no base table)


def test_a_change_that_lowers_the_buckling_load_below_the_models_tension_is_named(installed, capsys, monkeypatch):
    from cablecasing_core.studies import ensemble_runs

    model, tension, p_cr = installed
    e = model.data["casing"]["E"] * 0.5 * tension / p_cr  # (K_E ~ E and K_G ~ the tension: P_cr ~ E)
    assert cc.body_buckling(model.with_overrides({"casing.E": e}), "casing").load < tension
    monkeypatch.setattr(ensemble_runs, "execute", _no_run)
    assert main(["ensemble", "installed", "--seeds", "2", *SHORT, "--against", f"casing.E={e!r}"]) == 2
    err = capsys.readouterr().err
    assert f"--against casing.E = {e!r}: conflicts with loads.cable_tension = {tension!r}" in err


def test_seed_ensemble_refuses_a_model_no_seed_can_run_before_its_first_member(installed, monkeypatch):
    from cablecasing_core.studies import ensemble_runs, seed_ensemble

    model, _, p_cr = installed
    monkeypatch.setattr(ensemble_runs, "execute", _no_run)
    with pytest.raises(ModelError) as e:
        seed_ensemble(model, 2, duration=0.1, skip=0.0, overrides={"loads.cable_tension": 1.1 * p_cr})
    assert e.value.key == "loads.cable_tension"


def test_a_study_none_of_whose_samples_can_run_is_refused_before_the_first(installed, tmp_path, monkeypatch):
    from cablecasing_core.studies import study

    model, _, p_cr = installed
    e0 = model.data["casing"]["E"]
    # the tension 10 % above the buckling load at the box's stiffest casing (P_cr ~ E): every sample buckles
    bad = model.with_overrides({"loads.cable_tension": 1.1 * p_cr})
    monkeypatch.setattr(study, "execute", _no_run)
    path = tmp_path / "s" / "study.csv"
    bounds = {"contact.friction": (0.05, 0.2), "casing.E": (0.9 * e0, e0)}
    with pytest.raises(ModelError) as err:
        run_study(path, bounds=bounds, n_samples=8, model=bad, evaluate_kwargs={"duration": 0.1, "skip": 0.0})
    assert err.value.key == "loads.cable_tension" and "every one of the 8 samples" in str(err.value)
    assert not path.parent.exists()  # (refused before anything was made)


def test_bounds_wholly_on_the_wrong_side_of_a_fixed_key_are_refused_by_the_command(tmp_path, capsys):
    out = tmp_path / "st"
    d_outer = cc.load_model(None).data["casing"]["d_outer"]
    assert d_outer < 0.0096  # (so every d_inner of the bounds lies above it: no sample is a casing)
    argv = ["study", "--vary", "casing.d_inner=0.0096:0.0100", "--samples", "3", *SHORT, "--out", str(out)]
    assert main(argv) == 2
    text = capsys.readouterr()
    assert "--vary casing.d_inner = [0.0096, 0.01]: must be smaller than casing.d_outer" in text.err
    assert "every one of the 6 samples" in text.err and not out.exists()
    assert "1 parameter," in text.out and "d = 1 parameter," in text.out  # (R6: not "1 parameters")


# ---- Misleading 4: a partly failed study says how many and the first --------------------------


def test_a_partly_failed_study_prints_the_failed_count_and_the_first_error_with_its_sample(tmp_path, capsys):
    out = tmp_path / "st"
    # d_inner from 9.0 to 9.8 mm in a casing of d_outer = 9.5 mm: the samples above 9.5 mm fail, the others run
    argv = ["study", "--vary", "casing.d_inner=0.0090:0.0098", "--samples", "6", *SHORT, "--out", str(out)]
    assert main(argv) == 0
    text = capsys.readouterr()
    res = load_results(out / "study.csv")
    d_outer = cc.load_model(None).data["casing"]["d_outer"]
    failed = res.status == "failed"
    np.testing.assert_array_equal(failed, res.X[:, 0] >= d_outer)  # (the rule the CSV's rows followed)
    assert 0 < failed.sum() < len(res)
    assert f"{int((~failed).sum())} of 6 runs ok, {int(failed.sum())} failed" in text.out
    j = int(np.flatnonzero(failed)[0])
    first = f"the first, sample {res.index[j]} (casing.d_inner = {res.X[j, 0]:.6g}): ModelError: casing.d_inner"
    assert f"{int(failed.sum())} of 6 runs failed; {first}" in text.err


# ---- R3: the samples in flight when the scheduler is lost --------------------------------------


class _Future:
    def __init__(self, i):
        self.i = i

    def result(self):
        raise AssertionError("never done")

    def release(self):
        pass


class _Client:
    """A dask client whose scheduler is lost: submits, and then distributed.wait raises."""

    status = "running"

    def nthreads(self):
        return {"tcp://w1": 1}

    def submit(self, fn, evaluate, kwargs, i, *args, **kw):
        return _Future(i)


@pytest.mark.parametrize(
    "raised, cause",
    [
        (None, "the dask scheduler was lost (FuturesCancelledError"),
        (TimeoutError(), "no sample finished within 5 s"),
    ],
)
def test_the_samples_in_flight_when_the_scheduler_is_lost_are_in_the_lost_log(raised, cause, tmp_path, monkeypatch):
    import distributed
    from distributed.client import FuturesCancelledError

    def wait(futures, timeout=None, return_when=None):
        raise raised if raised is not None else FuturesCancelledError([])  # (no group: "0 Future cancelled")

    monkeypatch.setattr(distributed, "wait", wait)
    workers = executor.Workers.__new__(executor.Workers)
    workers.scheduler, workers.client = "tcp://gone:8786", _Client()
    monkeypatch.setattr(executor, "_diagnose", lambda client: "the dask scheduler does not answer")
    path = tmp_path / "study.csv"
    todo = [(i, {"casing.E": 5e9}) for i in range(6)]
    with pytest.raises(InfrastructureError, match="run the same command again"):
        executor.execute(
            todo, ANALYTIC, {}, ("oct1",), None, None, workers, max_in_flight=4, progress_timeout=5, lost=LostLog(path)
        )
    lines = (tmp_path / "study.csv.lost.log").read_text().splitlines()
    # the window of 4 was in flight: each listed once with the cause, none of the two never submitted
    assert sorted(int(line.split(" sample ")[1].split(":")[0]) for line in lines) == [0, 1, 2, 3]
    assert all(cause in line for line in lines), lines


# ---- R4: the command and run_study do not resume each other's study ---------------------------


def test_the_command_and_run_study_refuse_each_others_study_saying_so(tmp_path, capsys, monkeypatch):
    from cablecasing_core.studies import study

    api = tmp_path / "api"
    kw = {"duration": 0.1, "skip": 0.0}
    run_study(api / "study.csv", bounds=BOUNDS, n_samples=8, evaluate_kwargs=kw, scheduler="serial", max_samples=0)
    varied = ["--vary", "casing.E=2e9:1e10", "--vary", "contact.friction=0.05:0.2", "--samples", "8"]
    assert main(["study", *varied, *SHORT, "--out", str(api)]) == 2
    err = capsys.readouterr().err
    assert "holds a study begun by run_study" in err and "resume it the way it began (run_study" in err
    assert "holds another model" not in err  # (the false reason of before)
    cli = tmp_path / "cli"  # (the command's sidecar and header, its samples not run: no rows)
    monkeypatch.setattr(study, "execute", lambda *args, **kwargs: None)
    assert main(["study", "--vary", "contact.friction=0.05:0.2", "--samples", "2", *SHORT, "--out", str(cli)]) == 1
    assert "no run" in capsys.readouterr().err
    with pytest.raises(ModelError, match="holds a study begun by `cablecasing study`.*the same `cablecasing study`"):
        run_study(
            cli / "study.csv",
            bounds={"contact.friction": (0.05, 0.2)},
            n_samples=2,
            evaluate_kwargs=kw,
            scheduler="serial",
        )


def test_a_study_of_run_study_is_refused_as_such_first_whatever_the_commands_settings(tmp_path, capsys):
    # (review V, D4: a sidecar without a window read as the command's earlier version first asked for
    # --skip 0.05, then --window boxcar, and printed the plan, before saying who began the study)
    api = tmp_path / "api"
    run_study(api / "study.csv", ANALYTIC, n_samples=6, bounds={"casing.E": (4e9, 6e9)}, scheduler="serial")
    for extra in ([], ["--skip", "0.05", "--window", "boxcar"], ["--vary", "contact.friction=0.05:0.2"]):
        argv = ["study", "--vary", "casing.E=4e9:6e9", "--samples", "6", "--scheduler", "serial", "--out", str(api)]
        assert main(argv + extra) == 2
        out, err = capsys.readouterr()
        assert out == ""  # (refused before the plan's header)
        assert err.count("cablecasing: error:") == 1 and "holds a study begun by run_study" in err, (extra, err)


@pytest.mark.parametrize("tensions, refused", [("40:70", False), ("100:200", True)])
def test_the_up_front_sample_check_says_none_of_its_warnings(tensions, refused, tmp_path, capsys, monkeypatch):
    # (review V, D5: the check of the samples before the runs printed each sample's model warning, a
    # tension that lays the cable on the wall, unprefixed and twice for a sample, then the runs said them
    # again with their samples; and it warned about tensions it then refused, above the buckling load)
    from cablecasing_core.studies import study

    monkeypatch.setattr(study, "execute", lambda *args, **kwargs: None)  # (no run: only the check speaks)
    argv = ["study", "--vary", f"loads.cable_tension={tensions}", "--samples", "3", *SHORT, "--out", str(tmp_path)]
    assert main(argv) == (2 if refused else 1)  # (1: no run is in the file, none having run)
    err = capsys.readouterr().err
    assert "lays the cable on the wall" not in err, err
    assert ("must be below the casing's buckling load" in err) == refused


# ---- R5: the key hint -----------------------------------------------------------------------------


def test_a_key_in_the_wrong_case_is_hinted_as_itself(tmp_path, capsys):
    keys = cc.load_model(None).parameters()
    assert closest("casing.e", keys) == ["casing.E"]  # (difflib alone, case-sensitive, says casing.I)
    assert closest("contact.frction", keys) == ["contact.friction"] and closest("zzz", keys) == []
    assert main(["study", "--vary", "casing.e=2e9:1e10", *SHORT, "--out", str(tmp_path / "st")]) == 2
    assert "(did you mean casing.E?)" in capsys.readouterr().err


@pytest.mark.parametrize("command", ["ensemble", "study"])
@pytest.mark.parametrize("typed, meant", [("casing.b.fz", "casing.B.Fz"), ("net.B.Fq", "net.B.Fz")])
def test_an_unknown_output_is_hinted_and_the_sums_the_option_takes_are_named(command, typed, meant, tmp_path, capsys):
    # (review V, D6: ensemble gave no hint, and neither named net.*, paths.F* or a+b, which --output takes)
    out = ["--out", str(tmp_path / ("e.csv" if command == "ensemble" else "st"))]
    assert main([command, "--output", typed, *SHORT, *out]) == 2
    err = capsys.readouterr().err
    assert f"--output = '{typed}'" in err and f"(did you mean {meant}?)" in err, err
    assert all(s in err for s in ("net.<A|B>.<Fx..Mz>", "paths.<Fx|Fy|Fz>", "a+b")), err
    assert not (tmp_path / "st").exists()  # (refused before anything is made)


# ---- R6: the CSV and the messages -------------------------------------------------------------


def _study(path, **kw):
    kw = {"bounds": BOUNDS, "n_samples": 8, "seed": 2, "scheduler": "serial", "progress": False} | kw
    return run_study(path, ANALYTIC, **kw)


def test_the_study_csv_has_lf_line_ends_and_its_parameters_units(tmp_path):
    path = tmp_path / "s.csv"
    _study(path)
    data = path.read_bytes()
    assert b"\r" not in data and data.count(b"\n") == 9  # (the header and 8 rows)
    head = data.split(b"\n")[0].decode().split(",")
    assert head[:4] == ["index", "status", "casing.E [Pa]", "contact.friction [-]"]  # (a modulus; a ratio)


def test_a_study_begun_with_crlf_and_bare_parameter_names_resumes_as_it_began(tmp_path):
    ref = _study(tmp_path / "ref.csv")
    path = tmp_path / "s.csv"
    _study(path, max_samples=3)
    # as earlier versions wrote it: CRLF line ends (the csv module's default), parameters without units
    lines = path.read_text().splitlines()
    lines[0] = lines[0].replace(" [Pa]", "").replace(" [-]", "")
    path.write_bytes(("\r\n".join(lines) + "\r\n").encode())
    meta = json.loads((tmp_path / "s.csv.meta.json").read_text())
    del meta["units"], meta["kernels"]
    (tmp_path / "s.csv.meta.json").write_text(json.dumps(meta))
    res = _study(path)
    for a, b in ((res.index, ref.index), (res.X, ref.X), (res.Y, ref.Y)):
        np.testing.assert_array_equal(a, b)
    data = path.read_bytes()
    assert data.count(b"\r\n") == data.count(b"\n") == 9  # (its own line end throughout)
    assert data.startswith(b"index,status,casing.E,contact.friction,")


def test_scheduler_and_output_folder_errors_come_before_the_plan(tmp_path, capsys, monkeypatch):
    base = ["study", "--vary", "casing.E=2e9:1e10", "--samples", "3", "--duration", "0.1", "--skip", "0"]
    assert main([*base, "--scheduler", "lcoal", "--out", str(tmp_path / "a")]) == 2
    text = capsys.readouterr()
    assert "--scheduler = 'lcoal': must be 'serial', 'threads', 'local' or a scheduler address" in text.err
    assert "(did you mean 'local'?)" in text.err and text.out == ""
    assert main([*base, "--scheduler", "thread", "--out", str(tmp_path / "a")]) == 2
    assert "(did you mean 'threads'?)" in capsys.readouterr().err
    assert main([*base, "--scheduler", "serial", "--workers", "2", "--out", str(tmp_path / "a")]) == 2
    assert "give --scheduler threads or local" in capsys.readouterr().err
    (tmp_path / "afile").write_text("x")
    assert main([*base, "--scheduler", "serial", "--out", str(tmp_path / "afile" / "x")]) == 2
    text = capsys.readouterr()
    assert "--out = " in text.err and "an existing file" in text.err and text.out == ""
    # run_study checks its folder before it starts a local cluster
    monkeypatch.setattr(executor.Workers, "__init__", _no_run)
    with pytest.raises(ModelError, match="an existing file") as e:
        _study(tmp_path / "afile" / "s.csv", scheduler="local")
    assert e.value.key == "path"


# ---- R2: the kernels the rows were computed with -------------------------------------------------


def test_the_sidecar_keeps_the_kernels_and_a_resume_with_others_warns(tmp_path, monkeypatch):
    import numpy

    monkeypatch.delenv("OPENBLAS_CORETYPE", raising=False)
    path = tmp_path / "s.csv"
    _study(path, max_samples=4)
    kernels = json.loads((tmp_path / "s.csv.meta.json").read_text())["kernels"]
    assert len(kernels) == 1 and kernels[0]["numpy"] == numpy.__version__ and "OPENBLAS_CORETYPE" not in kernels[0]
    monkeypatch.setenv("OPENBLAS_CORETYPE", "Nehalem")  # (what a worker of another CPU generation takes)
    with pytest.warns(ModelWarning, match="OPENBLAS_CORETYPE 'not set' then, 'Nehalem' now"):
        _study(path, max_samples=2)
    kernels = json.loads((tmp_path / "s.csv.meta.json").read_text())["kernels"]
    assert [k.get("OPENBLAS_CORETYPE") for k in kernels] == [None, "Nehalem"]
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)  # (the same kernels again: nothing to say)
        assert len(_study(path)) == 8
    # workers of two kinds of machine in one run (a mixed cluster) warn on a new study too
    from cablecasing_core.studies import study

    two = [{"cpu": "A", "numpy": numpy.__version__}, {"cpu": "B", "numpy": numpy.__version__}]
    monkeypatch.setattr(study, "kernel_environments", lambda workers: two)
    with pytest.warns(ModelWarning, match="have different floating-point kernels \\(cpu 'A' on one, 'B' on another\\)"):
        _study(tmp_path / "mixed.csv")


# ---- Misleading 6: Sobol indices too uncertain to print ------------------------------------------


def test_sobol_indices_whose_intervals_exceed_the_shown_limit_are_not_printed_as_a_table(capsys):
    from cablecasing_core.cli.study import print_study
    from cablecasing_core.studies import sobol_indices
    from cablecasing_core.studies.results_store import StudyResults

    X = sobol_design(BOUNDS, 4, seed=1)  # 4 base points of pure noise: intervals far wider than [0, 1]
    y = np.random.default_rng(5).lognormal(size=(len(X), 1))
    n = len(X)
    res = StudyResults(
        np.arange(n), tuple(BOUNDS), X, ("oct1",), y, np.full(n, "ok"), np.full(n, ""), np.zeros(n), None, 4, 4
    )
    sob = sobol_indices(res)
    widest = max(np.nanmax(sob.S1_conf), np.nanmax(sob.ST_conf))
    assert widest > 0.5
    print_study(res)
    text = capsys.readouterr()
    assert "Sobol indices (-)" not in text.out and " S1 " not in text.out
    assert f"Sobol indices from 4 complete base points are not shown: their intervals reach +-{widest:.3g}" in text.err


# ---- Misleading 1: the excitation of a sample ------------------------------------------------------


def test_excitation_seeds_make_each_sample_the_mean_over_the_ensembles_seeds(tmp_path, capsys):
    from cablecasing_core.records import after_skip
    from cablecasing_core.studies import octave_rms
    from cablecasing_core.studies.evaluators import default_evaluate

    model = cc.load_model(None)
    got = default_evaluate({"contact.friction": 0.1}, duration=0.1, skip=0.0, model=model, excitation_seeds=2)
    levels = []
    for s in (1, 2):  # (the built-in specimen's one random excitation: member s gives it seed s)
        changed = model.with_overrides({"contact.friction": 0.1, "scenario.excitation.casing_random.seed": s})
        run = cc.simulate(changed, duration=0.1)
        x = run.support_force("casing.B.Fz")[after_skip(run.time, 0.0)]
        levels.append(octave_rms(x, 1 / (run.time[1] - run.time[0])).rms)
    # (the same two runs and the same mean; 1e-12: only the order of a two-term sum may differ)
    np.testing.assert_allclose([got[f"oct{b}"] for b in range(1, 10)], np.mean(levels, axis=0), rtol=1e-12)
    argv = ["study", "--vary", "contact.friction=0.05:0.2", "--excitation-seeds", "1", *SHORT]
    assert main([*argv, "--out", str(tmp_path / "st")]) == 2
    assert "--excitation-seeds = 1: must be" in capsys.readouterr().err
