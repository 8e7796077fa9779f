"""A model change that a run setting takes the place of is refused before any run (a review of the
command line, findings 4, 8, 9 and 12): ``--duration`` wins over ``scenario.duration``, ``--dt`` over
``scenario.dt``, ``--no-contact`` over ``contact.enabled`` and an ensemble's seeds over the seeds it
varies and ``scenario.seed``. Accepted, such a change was recorded and did nothing: an ensemble's
"relative change" of +0.0000 +- 0.0000, a study's nan correlations, a warning about a duration the
run did not use. Also: the keys a study lists for an unknown --vary key are those it can vary, and
the errors of --vary-file and pool name the file."""

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelError
from cablecasing_core.studies import Ensemble, check_bounds, pool_ensembles, run_study, seed_ensemble


@pytest.fixture
def no_run(monkeypatch):
    """Any run (a member, a sample, a simulation step) fails the test: what is refused is refused first."""
    from cablecasing_core.studies import ensemble_runs, study
    from cablecasing_core.timedomain import simulation

    fail = lambda *a, **k: pytest.fail("a run started")  # noqa: E731
    monkeypatch.setattr(ensemble_runs, "execute", fail)
    monkeypatch.setattr(study, "execute", fail)
    monkeypatch.setattr(simulation.Engine, "advance", fail)


def error_line(capsys, argv):
    """The one line of error of ``main(argv)``, which must exit with status 2 and print nothing."""
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    err = err.strip().splitlines()
    assert code == 2 and len(err) == 1 and out == "", (code, out, err)
    return err[0].split("error: ", 1)[1]


DURATION = "(--duration is the simulated time of every run{} and takes the place of scenario.duration"
ENSEMBLE_CASES = [
    (
        ["--duration", "0.2", "--set", "scenario.duration=0.15"],
        "--set scenario.duration = 0.15: cannot be given with --duration 0.2 " + DURATION.format(""),
    ),
    (
        ["--duration", "0.2", "--against", "scenario.duration=0.15"],
        "--against scenario.duration = 0.15: cannot be given with --duration 0.2 "
        + DURATION.format(" of both ensembles"),
    ),
    (
        ["--duration", "0.2", "--set", "contact.friction=0.1", "--against", "scenario.duration=0.15"],
        "--against scenario.duration = 0.15: cannot be given with --duration 0.2",
    ),
    (["--dt", "2e-5", "--set", "scenario.dt=1e-5"], "--set scenario.dt = 1e-5: cannot be given with --dt 2e-05 (--dt"),
    (["--dt", "2e-5", "--against", "scenario.dt=1e-5"], "--against scenario.dt = 1e-5: cannot be given with --dt"),
    # the members set every random excitation's seed: scenario.seed, which gives only seeds left out, does nothing
    (["--set", "scenario.seed=4"], "--set scenario.seed = 4: must not set the seeds that the ensemble varies"),
    (["--against", "scenario.seed=4"], "--against scenario.seed = 4: must not set the seeds that the ensemble"),
]


@pytest.mark.parametrize("given, said", ENSEMBLE_CASES, ids=[" ".join(c[0]) for c in ENSEMBLE_CASES])
def test_an_ensemble_refuses_a_change_its_settings_would_ignore(no_run, capsys, given, said):
    line = error_line(capsys, ["ensemble", "--seeds", "2", *given])
    assert line.startswith(said), line


def test_the_ensemble_says_how_to_compare_two_values_of_such_a_key(no_run, capsys):
    line = error_line(capsys, ["ensemble", "--seeds", "2", "--duration", "0.2", "--against", "scenario.duration=0.15"])
    assert line.endswith(
        "give one of them (compare two values with --set scenario.duration=... --against scenario.duration=... and "
        "no --duration)"
    ), line


def test_seed_ensemble_refuses_overrides_its_arguments_would_ignore(no_run):
    model = cc.load_model()
    with pytest.raises(ModelError, match=r"overrides\['scenario.duration'\] = 0.15: cannot be given with duration 0.2"):
        seed_ensemble(model, 2, duration=0.2, overrides={"scenario.duration": 0.15})
    with pytest.raises(ModelError, match=r"overrides\['scenario.dt'\] = 1e-05: cannot be given with dt 2e-05"):
        seed_ensemble(model, 2, duration=0.2, dt=2e-5, overrides={"scenario.dt": 1e-5})
    with pytest.raises(ModelError, match=r"overrides\['scenario.seed'\] = 4: must not set the seeds"):
        seed_ensemble(model, 2, duration=0.2, overrides={"scenario.seed": 4})


TWO_SHAKERS = """
[geometry]
n_elements = 12
points = [[0.0, 0.0, 0.0], [0.3, 0.0, 0.0], [0.6, 0.1, 0.0]]

[casing]
E = 5.0e9
rho = 4850.0
d_outer = 0.0095
d_inner = 0.004

[scenario]
duration = 0.15
seed = 3

[scenario.excitation.a]
target = "casing.A.z"
kind = "random"
rms = 5.0

[scenario.excitation.b]
target = "casing.B.z"
kind = "random"
rms = 5.0
"""


def test_scenario_seed_is_the_ensembles_only_when_it_varies_every_random_excitation(tmp_path):
    from cablecasing_core.studies.ensemble_runs import seed_keys

    path = tmp_path / "two.toml"
    path.write_text(TWO_SHAKERS)
    model = cc.load_model(path)
    assert seed_keys(model) == {"scenario.excitation.a.seed", "scenario.excitation.b.seed", "scenario.seed"}
    # varying a alone, scenario.seed still gives b's seed (derived from it): a change of it does something
    assert seed_keys(model, ["a"]) == {"scenario.excitation.a.seed"}
    b = lambda m: m.scenario["excitation"]["b"]["seed"]  # noqa: E731
    assert b(model.with_overrides({"scenario.seed": 4})) != b(model)


SIMULATE_CASES = [
    (
        ["--duration", "0.01", "--set", "scenario.duration=0.02"],
        "--set scenario.duration = 0.02: cannot be given with --duration 0.01 (--duration is the simulated time of "
        "the run and takes the place of scenario.duration, which would be ignored); give one of them",
    ),
    (
        ["--dt", "1e-5", "--set", "scenario.dt=2e-5"],
        "--set scenario.dt = 2e-5: cannot be given with --dt 1e-05 (--dt is the time step of the run and takes the "
        "place of scenario.dt, which would be ignored); give one of them",
    ),
    (
        ["--no-contact", "--set", "contact.enabled=true"],
        "--set contact.enabled = true: cannot be given with --no-contact (--no-contact is the contact switch of the "
        "run and takes the place of contact.enabled, which would be ignored); give one of them",
    ),
]


@pytest.mark.parametrize("given, said", SIMULATE_CASES, ids=[" ".join(c[0]) for c in SIMULATE_CASES])
def test_simulate_refuses_a_change_its_options_would_ignore(no_run, capsys, recwarn, given, said):
    # (before: the run took --duration and warned about the fade-in against the --set duration it did not use)
    assert error_line(capsys, ["simulate", *given, "--no-progress"]) == said
    assert not recwarn.list  # (nothing warned about a run that does not happen)


def test_a_study_refuses_to_vary_what_its_duration_takes_the_place_of(no_run, tmp_path, capsys):
    out = tmp_path / "st"
    argv = ["study", "--samples", "4", "--duration", "0.2", "--scheduler", "serial", "--out", out]
    line = error_line(capsys, [*argv, "--vary", "scenario.duration=0.15:0.2"])
    assert line == (
        "--vary scenario.duration = (0.15, 0.2): cannot be given with --duration 0.2 (--duration is the simulated "
        "time of every sample and takes the place of scenario.duration, which would be ignored); vary "
        "scenario.duration without --duration (each sample runs its own)"
    )
    vary = tmp_path / "vf.toml"
    vary.write_text("scenario.duration = [0.15, 0.2]\n")
    line = error_line(capsys, [*argv, "--vary-file", vary])
    assert line.startswith(f"--vary-file {vary}: scenario.duration = [0.15, 0.2]: cannot be given with --duration 0.2")
    assert not out.exists()


def test_run_study_refuses_bounds_on_a_key_its_evaluate_settings_take_the_place_of(no_run, tmp_path):
    with pytest.raises(ModelError, match=r"bounds.scenario.dt = \(1e-05, 2e-05\): cannot be given with dt 1e-05"):
        run_study(
            tmp_path / "s.csv", bounds={"scenario.dt": (1e-5, 2e-5)}, evaluate_kwargs={"duration": 0.2, "dt": 1e-5}
        )
    assert not (tmp_path / "s.csv").exists()
    # without the setting the samples run the key's values: accepted
    assert check_bounds({"scenario.duration": (0.15, 0.2)}, settings={"duration": ("duration", None)}) == {
        "scenario.duration": (0.15, 0.2)
    }


@pytest.mark.parametrize("duration", [None, 0.3])
def test_the_keys_listed_for_an_unknown_key_are_those_a_study_can_vary(no_run, tmp_path, capsys, duration):
    """The list once offered integer keys (geometry.n_elements, scenario.seed, contact.event_substeps, the
    excitation's seed), refused when varied, and scenario.duration beside --duration, ignored."""
    given = [] if duration is None else ["--duration", str(duration)]
    argv = ["study", "--vary", "casing.foo=1:2", *given, "--scheduler", "serial", "--out", tmp_path / "st"]
    line = error_line(capsys, argv)
    assert line.startswith("--vary casing.foo: is not a numeric parameter of the model <built-in>")
    listed = line.split("those a study can vary: ", 1)[1].split(", ")
    model = cc.load_model()
    refused = {
        "geometry.n_elements",
        "scenario.seed",
        "contact.event_substeps",
        "scenario.excitation.casing_random.seed",
    }
    assert listed and not refused & set(listed)
    assert ("scenario.duration" in listed) == (duration is None)
    settings = {"duration": ("--duration", duration)}
    for key in listed:  # each can be varied: bounds about its value pass every check
        v = model.parameters()[key]
        d = max(abs(v), 1e-6) * 1e-3
        passed = []
        for bounds in ((v, v + d), (v - d, v)):  # (one of them inside the key's allowed range)
            try:
                passed.append(check_bounds({key: bounds}, model=model, settings=settings))
            except ModelError:
                pass
        assert passed, key
    for key in refused:  # and those not listed are refused
        with pytest.raises(ModelError, match="a study samples continuous"):
            check_bounds({key: (1.0, 2.0)}, model=model)


def test_a_vary_file_error_names_the_option_and_the_file(no_run, tmp_path, capsys):
    vary = tmp_path / "vf.toml"
    vary.write_text("casing.E = [2e9]\n")
    out = tmp_path / "st"
    line = error_line(capsys, ["study", "--vary-file", vary, "--scheduler", "serial", "--out", out])
    assert line == (
        f"--vary-file {vary}: casing.E = [2000000000.0]: must be a pair (low, high) of numbers (not text or True/False)"
    )
    vary.write_text("geometry.n_elements = [10, 20]\n")
    line = error_line(capsys, ["study", "--vary-file", vary, "--scheduler", "serial", "--out", out])
    assert line.startswith(f"--vary-file {vary}: geometry.n_elements = [10.0, 20.0]: is a key of type int")
    # a --vary beside the file is named as the --vary
    line = error_line(
        capsys, ["study", "--vary-file", vary, "--vary", "casing.E=1:0", "--scheduler", "serial", "--out", out]
    )
    assert line.startswith("--vary casing.E = (1.0, 0.0): lower bound must be below")
    assert not out.exists()


def _part(seeds):
    labels = ("b1", "b2")
    levels = np.ones((len(seeds), 2))
    return Ensemble(np.array(seeds), "casing.B.Fz", labels, np.array([10.0, 20.0]), np.array([20.0, 40.0]), levels)


def test_pool_names_the_files_that_share_a_seed(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    for name, seeds in (
        ("e1.csv", [1, 2]),
        ("e2.csv", [2, 3]),
        ("e3.csv", [3, 3]),
        ("a1.csv", [1, 2]),
        ("a2.csv", [1, 2]),
    ):
        _part(seeds).save(name)
    cases = {
        ("e1.csv", "e1.csv"): "file = 'e1.csv': is given twice (parts 1 and 2): give each part once",
        ("e1.csv", "e2.csv"): "file = 'e2.csv': holds seed 2 that e1.csv holds too: each seed must be in one part only",
        ("e3.csv",): "file = 'e3.csv': holds seed 3 more than once: each member must have a seed of its own",
        ("e1.csv", "--against", "a1.csv", "a2.csv"): (
            "--against = 'a2.csv': holds seeds 1, 2 that a1.csv holds too: each seed must be in one part only"
        ),
    }
    for argv, said in cases.items():
        assert error_line(capsys, ["pool", *argv]) == said
    # in Python, an Ensemble by its index
    with pytest.raises(ModelError, match=r"ensembles\[1\].seeds = \[2\]: each seed must be in one part only"):
        pool_ensembles([_part([1, 2]), _part([2, 3])])
