"""Band levels over excitation seeds (studies/ensemble.py): a member is the single run with its seed,
and the ensemble statistics have the sampling properties they claim (checked by drawing many
synthetic ensembles from a known distribution)."""

import copy
import dataclasses

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main as cli_main
from cablecasing_core.errors import ModelError
from cablecasing_core.model import model_from_dict
from cablecasing_core.records import after_skip
from cablecasing_core.studies import (
    Ensemble,
    load_ensemble,
    octave_rms,
    paired_difference,
    pool_ensembles,
    random_excitations,
    seed_ensemble,
    seed_overrides,
)

T = 0.15  # s per run: 0.1 s after the 0.05 s skip (octave 1, 11 Hz wide, needs > 91 ms)
SEED_KEY = "scenario.excitation.casing_random.seed"


def single_run(model, seed, duration=T):
    return cc.simulate(model.with_overrides({SEED_KEY: seed}), duration=duration)


def band_levels_of_single_run(model, seed, duration=T, skip=0.05):
    r = single_run(model, seed, duration)
    keep = after_skip(r.time, skip)
    return octave_rms(r.support_force("casing.B.Fz")[keep], 1.0 / (r.time[1] - r.time[0])).rms


def test_member_is_the_single_run_with_its_seed():
    model = cc.load_model()
    ens = seed_ensemble(model, [3, 5], duration=T)
    assert ens.levels.shape == (2, 9) and ens.labels[0] == "oct1" and list(ens.seeds) == [3, 5]
    for i, s in enumerate((3, 5)):
        np.testing.assert_array_equal(ens.levels[i], band_levels_of_single_run(model, s))
        np.testing.assert_array_equal(ens.contact_time[i], single_run(model, s).contact_time)  # Fig. 22, s
    assert ens.contact_time.shape == (2, 36) and ens.contact_time.sum() > 0
    assert np.argmax(ens.contact_share) == np.argmax(ens.contact_time.sum(axis=0))
    # the seeds drive different records: the members differ (chaos and the record itself)
    assert np.all(ens.levels[0] != ens.levels[1])


def test_overrides_apply_to_every_member():
    model = cc.load_model()
    ens = seed_ensemble(model, [2, 4], duration=T, overrides={"contact.friction": 0.05})
    changed = model.with_overrides({"contact.friction": 0.05})
    np.testing.assert_array_equal(ens.levels[1], band_levels_of_single_run(changed, 4))
    assert ens.overrides == {"contact.friction": 0.05}


def test_several_random_excitations_get_distinct_seeds():
    model = with_excitation(
        cc.load_model(),
        "cable_axial",
        {"target": "cable.A.axial", "kind": "random", "rms": 1.0, "band": [10.0, 1000.0]},
    )
    names = random_excitations(model)
    assert names == ("casing_random", "cable_axial")
    seen = [tuple(seed_overrides(model, s).values()) for s in range(0, 50)]
    flat = [x for pair in seen for x in pair]
    assert len(set(flat)) == len(flat)  # no two records share a seed
    # one varied excitation: member s is seed s (the single run of the model with that seed)
    assert seed_overrides(model, 7, ["cable_axial"]) == {"scenario.excitation.cable_axial.seed": 7}


def with_excitation(model, name, table):
    """The model with excitation ``name`` replaced by ``table`` (a change of kind changes the keys)."""
    data = copy.deepcopy(model.data)
    data["scenario"]["excitation"][name] = table
    return model_from_dict(data)


def synthetic(levels, seeds=None):
    n = len(levels)
    return Ensemble(
        np.arange(1, n + 1) if seeds is None else np.asarray(seeds),
        "casing.B.Fz",
        ("b1", "b2"),
        np.array([1.0, 2.0]),
        np.array([2.0, 4.0]),
        np.asarray(levels, float),
    )


def test_mean_confidence_interval_has_its_coverage():
    # For normal data the Student-t interval is exact: coverage 0.95; 4000 draws give a binomial SE
    # of 0.0034, so 3 SE is 0.010.
    rng = np.random.default_rng(1)
    true = np.array([1.0, 0.2])
    hits, ses, means = np.zeros(2), [], []
    for _ in range(4000):
        e = synthetic(true + rng.normal(0.0, [0.15, 0.05], size=(8, 2)))
        lo, hi = e.ci(0.95)
        hits += (lo < true) & (true < hi)
        ses.append(e.se)
        means.append(e.mean)
    assert np.all(np.abs(hits / 4000 - 0.95) < 0.010)
    # the standard error is the spread of the mean across ensembles (E[se^2] = var(mean) exactly for
    # normal data; 4000 draws estimate a variance to 2.2 %, so 10 % holds)
    np.testing.assert_allclose(np.mean(np.square(ses), axis=0), np.var(means, axis=0), rtol=0.10)


def test_paired_difference_standard_error_and_coverage():
    # Paired log-normal levels with seed-to-seed CV ~15 % and correlation ~0.5 (what chaos leaves of
    # the pairing); the true relative difference of the means is known.
    rng = np.random.default_rng(2)
    n, draws, ratio = 16, 3000, 1.1
    r_all, se_all, hits = [], [], 0
    for _ in range(draws):
        z = rng.normal(size=(n, 2))
        zb = z[:, 0]
        za = 0.5 * z[:, 0] + np.sqrt(1 - 0.25) * z[:, 1]
        b = np.exp(0.15 * zb[:, None])
        a = ratio * np.exp(0.15 * za[:, None])
        d = paired_difference(a, b)
        lo, hi = d.ci(0.95)
        r_all.append(d.r[0])
        se_all.append(d.se[0])
        hits += lo[0] < ratio - 1 < hi[0]
    r_all = np.array(r_all)
    # the estimator's bias is O(1/n): CV^2 (1 - rho) / n * ratio ~ 0.08 %, far below its spread (3.5 %)
    assert abs(r_all.mean() - (ratio - 1)) < 3 * r_all.std() / np.sqrt(draws) + 0.002
    # its standard error is the spread of r across ensembles: the linearisation is good to O(1/n)
    # (~6 % at n = 16); 3000 draws estimate a standard deviation to 1.3 %
    assert abs(np.sqrt(np.mean(np.square(se_all))) / r_all.std() - 1) < 0.10
    # t interval on the linearised estimator: coverage 0.95 up to O(1/n), binomial SE 0.4 %
    assert 0.92 < hits / draws < 0.97


def test_mean_of_ratios_is_biased_where_ratio_of_means_is_not():
    # Two independent draws of the same distribution (decorrelated records): r has no bias, the
    # mean of per-seed ratios is biased upwards by about CV^2 (Jensen), what the docstring says.
    rng = np.random.default_rng(3)
    a = np.exp(0.2 * rng.normal(size=(20000, 1)))
    b = np.exp(0.2 * rng.normal(size=(20000, 1)))
    d = paired_difference(a, b)
    assert abs(d.r[0]) < 3 * d.se[0]
    bias = np.mean(a / b) - 1  # E[a] E[1/b] - 1 = exp(0.04) - 1 = 4.1 %
    assert abs(bias - (np.exp(0.04) - 1)) < 0.005


def test_paired_difference_of_ensembles_checks_the_pairing():
    a = synthetic([[1.0, 2.0], [1.2, 2.1], [0.9, 1.8]])
    b = synthetic([[1.1, 2.0], [1.0, 2.3], [1.0, 1.9]])
    d = paired_difference(a, b)
    np.testing.assert_allclose(d.r, (a.levels.mean(0) - b.levels.mean(0)) / b.levels.mean(0))
    assert d.labels == ("b1", "b2") and d.n == 3
    with pytest.raises(ModelError, match="b.seeds"):
        paired_difference(a, synthetic(b.levels, seeds=[1, 2, 4]))
    one = paired_difference(a.levels[:1], b.levels[:1])  # one pair: r, and no standard error
    np.testing.assert_allclose(one.r, a.levels[0] / b.levels[0] - 1)
    assert np.all(np.isnan(one.se))
    with pytest.raises(ModelError, match="n >= 1"):
        paired_difference(a.levels[:0], b.levels[:0])
    # a band the compared output never reaches (a support left at rest): no relative change there,
    # the others as before
    zero = paired_difference(np.c_[a.levels, np.zeros(3)], np.c_[b.levels, np.zeros(3)])
    np.testing.assert_array_equal(zero.r[:2], d.r)
    assert np.isnan(zero.r[2]) and np.isnan(zero.se[2])
    with pytest.raises(ModelError, match="at least 0"):
        paired_difference(a.levels, -b.levels)


@pytest.mark.parametrize(
    "kwargs, key",
    [
        ({"seeds": 1}, "seeds"),
        ({"seeds": [1, 1]}, "seeds"),
        ({"seeds": [1, -2]}, "seeds"),
        ({"seeds": "ab"}, "seeds"),
        ({"output": "casing.B.Fq"}, "output"),
        ({"excitations": ["cable_axial"]}, "excitations"),
        ({"overrides": {SEED_KEY: 3}}, f"overrides[{SEED_KEY!r}]"),
        ({"overrides": {"contact.friction": -1.0}}, "contact.friction"),
        ({"bands": "decade"}, "bands"),
        ({"dt": 0.0}, "dt"),
        ({"duration": -1.0}, "duration"),
        ({"skip": -0.1}, "skip"),
        ({"dt": float("nan")}, "dt"),
    ],
)
def test_bad_input_is_refused_before_any_run(kwargs, key):
    with pytest.raises(ModelError) as exc:
        seed_ensemble(cc.load_model(), **{"seeds": 2, "duration": T, **kwargs})
    assert exc.value.key == key


def test_no_random_excitation_and_failed_members_are_named():
    model = with_excitation(
        cc.load_model(),
        "casing_random",
        {"target": "casing.A.z", "kind": "harmonic", "frequency": 100.0, "amplitude": 1e-5},
    )
    with pytest.raises(ModelError, match="random"):
        seed_ensemble(model, 2)
    with pytest.raises(ModelError, match="oct1"):  # too short for the bands: refused before any run
        seed_ensemble(cc.load_model(), [4, 6], duration=0.12, skip=0.05)
    with pytest.raises(ModelError, match="Nyquist"):  # bands beyond fs/2: refused before any run
        seed_ensemble(cc.load_model(), [4, 6], duration=0.15, dt=1e-4)
    # a member that fails is named with its error (here a soft contact under a 100 times stronger
    # shaking: the cable goes through the wall and the run stops with a SimulationError)
    soft = {
        "contact.law": "linear",
        "contact.stiffness": 10.0,
        "contact.damping": 0.0,
        "scenario.excitation.casing_random.rms": 500.0,
    }
    with pytest.raises(ModelError) as exc:
        seed_ensemble(cc.load_model(), [4, 6], duration=0.15, overrides=soft)
    assert exc.value.key == "seeds" and exc.value.value == 4 and "SimulationError" in str(exc.value)
    with pytest.raises(ModelError, match="confidence"):
        synthetic([[1.0, 2.0], [1.1, 2.0]]).ci(1.5)


def test_cli_prints_the_ensemble_and_the_paired_change(tmp_path, capsys):
    out = tmp_path / "levels.csv"
    assert (
        cli_main(
            [
                "ensemble",
                "--seeds",
                "2",
                "--first-seed",
                "3",
                "--duration",
                str(T),
                "--out",
                str(out),
                "--against",
                "contact.friction=0.05",
                "--plot",
                str(tmp_path / "ens.png"),
            ]
        )
        == 0
    )
    assert (tmp_path / "ens.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    text = capsys.readouterr().out
    model = cc.load_model()
    lv = [band_levels_of_single_run(model, s) for s in (3, 4)]
    mean = np.mean(lv, axis=0)
    rows = [line.split(",") for line in text.splitlines() if line.startswith("oct")]
    np.testing.assert_allclose([float(r[3]) for r in rows[:9]], mean, rtol=1e-5)  # printed to 6 digits
    saved = np.genfromtxt(out, delimiter=",", names=True)  # (it names the header's 'oct3 [N]' oct3_N)
    np.testing.assert_allclose(saved["oct3_N"], [x[2] for x in lv], rtol=1e-8)
    assert open(out).readline().startswith("seed,oct1 [N],oct2 [N],")  # the levels' unit in the header
    assert (tmp_path / "levels_against.csv").exists() and "relative change" in text
    assert cli_main(["ensemble", "--seeds", "1"]) == 2
    assert cli_main(["ensemble", "--plot", str(tmp_path / "no" / "such.png")]) == 2  # refused before any run
    assert cli_main(["ensemble", "--set", "friction"]) == 2
    assert "KEY=VALUE" in capsys.readouterr().err
    # --dt is both ensembles' step: with a scenario.dt to compare it would compare a step with itself
    assert cli_main(["ensemble", "--dt", "2e-5", "--against", "scenario.dt=1e-5"]) == 2
    err = capsys.readouterr().err
    assert "--against scenario.dt = 1e-5" in err and "--dt" in err  # (the value as typed)


def test_an_ensemble_run_in_parts_and_pooled_is_the_whole(tmp_path):
    # the parts go through CSV (17 digits: the numbers come back exactly) and are pooled in any
    # order; the result is the ensemble run in one go, member for member
    model = cc.load_model()
    whole = seed_ensemble(model, [1, 2, 3, 4], duration=T)
    seed_ensemble(model, [3, 4], duration=T).save(tmp_path / "b.csv")
    part_a = seed_ensemble(model, [1, 2], duration=T)
    part_a.save(tmp_path / "a.csv")
    back = load_ensemble(tmp_path / "a.csv")
    for name in ("seeds", "levels", "contact_time", "lower", "upper"):
        np.testing.assert_array_equal(getattr(back, name), getattr(part_a, name))
    assert (back.output, back.labels, back.settings) == (part_a.output, part_a.labels, part_a.settings)
    assert whole.settings == {
        "duration": T,
        "dt": 1e-5,
        "skip": 0.05,
        "window": "hann",
        "model": whole.settings["model"],
        "base_model": cc.load_model().fingerprint(),  # (no overrides: the same model)
    }
    pooled = pool_ensembles([tmp_path / "b.csv", str(tmp_path / "a.csv")])
    for name in ("seeds", "levels", "contact_time"):
        np.testing.assert_array_equal(getattr(pooled, name), getattr(whole, name))
    np.testing.assert_array_equal(pooled.se, whole.se)
    # the CSV stays a plain table for other readers: the settings line is a comment
    table = np.genfromtxt(tmp_path / "a.csv", delimiter=",", names=True)
    np.testing.assert_array_equal(table["oct3_N"], part_a.levels[:, 2])  # (the header's 'oct3 [N]')
    # a part saved before the header named the unit (bare labels) reads and pools the same
    lines = (tmp_path / "a.csv").read_text().splitlines(keepends=True)
    (tmp_path / "old.csv").write_text(lines[0].replace(" [N]", "") + "".join(lines[1:]))
    old = pool_ensembles([tmp_path / "b.csv", tmp_path / "old.csv"])
    np.testing.assert_array_equal(old.levels, whole.levels)
    # a header whose unit is not the output's is not this ensemble's file
    (tmp_path / "other.csv").write_text(lines[0].replace(" [N]", " [N.m]") + "".join(lines[1:]))
    with pytest.raises(ModelError, match="header must be 'seed' and the band labels .* with its output's unit"):
        load_ensemble(tmp_path / "other.csv")


def test_pooling_refuses_parts_of_different_runs(tmp_path):
    a = synthetic([[1.0, 2.0], [1.1, 2.1]])
    with pytest.raises(ModelError) as exc:  # a seed in two parts
        pool_ensembles([a, synthetic([[1.0, 2.0], [1.2, 2.2]], seeds=[2, 3])])
    assert exc.value.key == "ensembles[1].seeds" and exc.value.value == [2]  # (the part, by its place)
    other = [
        Ensemble(np.array([5, 6]), "casing.A.Fz", a.labels, a.lower, a.upper, a.levels),
        Ensemble(np.array([5, 6]), a.output, a.labels, a.lower, 2 * a.upper, a.levels),
        Ensemble(np.array([5, 6]), a.output, a.labels, a.lower, a.upper, a.levels, {"contact.friction": 0.2}),
        Ensemble(np.array([5, 6]), a.output, a.labels, a.lower, a.upper, a.levels, settings={"dt": 5e-6}),
    ]
    for e, key in zip(other, ("output", "bands", "overrides", "settings")):
        with pytest.raises(ModelError) as exc:
            pool_ensembles([a, e])
        assert exc.value.key == f"ensembles[1].{key}"  # (a part given as an Ensemble, by its place)
    a.save(tmp_path / "a1.csv")  # a part given as a file is named by it (`cablecasing pool` gives files)
    other[3].save(tmp_path / "a2.csv")
    with pytest.raises(ModelError) as exc:
        pool_ensembles([tmp_path / "a1.csv", tmp_path / "a2.csv"])
    assert exc.value.key == f"{tmp_path / 'a2.csv'}.settings" and f"that of {tmp_path / 'a1.csv'}" in str(exc.value)
    # the model is part of the settings: a changed parameter gives another fingerprint
    model = cc.load_model()
    assert model.fingerprint() == cc.load_model().fingerprint()
    assert model.fingerprint() != model.with_overrides({"contact.friction": 0.2}).fingerprint()
    (tmp_path / "plain.csv").write_text("seed,b1,b2\n1,1.0,2.0\n")
    with pytest.raises(ModelError, match="cablecasing-ensemble"):
        load_ensemble(tmp_path / "plain.csv")
    (tmp_path / "a.csv").write_text('seed,b1,b2\n# cablecasing-ensemble {"labels": ["b1"\n1,1.0,2.0\n')
    with pytest.raises(ModelError, match="unaltered"):  # a damaged settings line
        load_ensemble(tmp_path / "a.csv")
    a.save(tmp_path / "short.csv")
    with open(tmp_path / "short.csv", "a") as f:  # a row cut short
        f.write("3,1.0\n")
    with pytest.raises(ModelError, match="line 5 has 2 fields; the header has 3 columns"):  # (the line, no content)
        load_ensemble(tmp_path / "short.csv")
    with pytest.raises(ModelError, match="does not exist"):
        load_ensemble(tmp_path / "missing.csv")
    with pytest.raises(ModelError, match="non-empty"):
        pool_ensembles([])


def test_cli_pools_parts_and_prints_the_paired_change(tmp_path, capsys):
    rng = np.random.default_rng(4)
    b = 1.0 + 0.1 * rng.normal(size=(6, 2))
    a = 1.05 * b + 0.02 * rng.normal(size=(6, 2))
    for name, levels, overrides in (("p", b, {}), ("q", a, {"contact.friction": 0.2})):
        for k, rows in enumerate((slice(0, 3), slice(3, 6))):
            e = synthetic(levels[rows], seeds=np.arange(1, 7)[rows])
            part = Ensemble(e.seeds, e.output, e.labels, e.lower, e.upper, e.levels, overrides)
            part.save(tmp_path / f"{name}{k}.csv")
    files = [str(tmp_path / f) for f in ("p0.csv", "p1.csv")]
    assert (
        cli_main(
            [
                "pool",
                *files,
                "--against",
                str(tmp_path / "q1.csv"),
                str(tmp_path / "q0.csv"),
                "--out",
                str(tmp_path / "all.csv"),
            ]
        )
        == 0
    )
    text = capsys.readouterr().out
    rows = [line.split(",") for line in text.splitlines() if line[:3] in ("b1,", "b2,")]
    # (printed to 6 significant digits: 5e-6)
    np.testing.assert_allclose([float(r[3]) for r in rows[:2]], b.mean(axis=0), rtol=1e-5)
    d = paired_difference(a, b)
    np.testing.assert_allclose([float(r[2]) for r in rows[2:]], d.r, atol=6e-5)  # printed to 4 decimals
    assert "{'contact.friction': 0.2}" in text
    np.testing.assert_array_equal(load_ensemble(tmp_path / "all_against.csv").levels, a)
    # parts that do not pair: refused naming --against and both sets of seeds, before anything is written
    assert cli_main(["pool", *files, "--against", str(tmp_path / "q0.csv"), "--out", str(tmp_path / "x.csv")]) == 2
    err = capsys.readouterr().err
    assert "--against = " in err and "must pool to the seeds of the files it is compared with, 1..6" in err, err
    assert "they pool to 1..3" in err and not (tmp_path / "x.csv").exists()
    assert cli_main(["pool", files[0], files[0]]) == 2  # seeds twice
    assert cli_main(["pool", *files, "--against", str(tmp_path / "q0.csv")]) == 2  # seeds do not pair
    assert "seeds" in capsys.readouterr().err


def test_a_seed_gives_the_same_record_at_every_time_step():
    # what makes '--against scenario.dt=...' a paired comparison: the random record is one function
    # of time (same lines, phases and scale) whatever the step; only the blocks it is evaluated in
    # differ, so on the coarse grid the two agree to the rounding of two chirp-z transforms (measured
    # 1.1e-13 of the RMS for the acceleration; 1e-11 leaves room, a different record differs by order one)
    from cablecasing_core.timedomain.scenario import scenario_motion

    model = cc.load_model()
    t = np.arange(0, 2000) * 1e-5 + 0.02  # past the ramp
    coarse = scenario_motion(model, dt=1e-5)(t)
    fine = scenario_motion(model, dt=2.5e-6)(t)
    for c, f in zip(coarse, fine):
        assert np.abs(c - f).max() < 1e-11 * np.sqrt(np.mean(c**2))


def test_members_on_threads_equal_the_serial_ones():
    """scheduler="threads": the members at once on threads of this process (their step loops outside
    the interpreter's lock) give the serial members' levels and warnings, bit for bit, whatever order
    they finish in; and the caller's warning filters act as in serial, where each member records its
    warnings and the ensemble says them again under the caller's filters: "ignore" says none, "error"
    raises the first, naming its seed."""
    import warnings

    model = cc.load_model().with_overrides({"contact.damping": 1e5})  # (its members warn: the test below)
    serial = seed_ensemble(model, [1, 2, 3], duration=T)
    threads = seed_ensemble(model, [1, 2, 3], duration=T, scheduler="threads", n_workers=2)
    np.testing.assert_array_equal(threads.levels, serial.levels)
    assert threads.warnings == serial.warnings and sorted(serial.warnings) == [1, 2, 3]
    for scheduler in ("serial", "threads"):
        for module in ("", r"cablecasing_core\."):  # (a filter by the module the ensemble says them from)
            with warnings.catch_warnings(record=True) as got:
                warnings.simplefilter("always")
                warnings.filterwarnings("ignore", category=cc.SolverWarning, module=module)
                seed_ensemble(model, [1, 2], duration=T, scheduler=scheduler, n_workers=2)
            assert not [w for w in got if w.category is cc.SolverWarning], (scheduler, module)
        with warnings.catch_warnings(), pytest.raises(cc.SolverWarning, match=r"^seed \d: "):
            warnings.simplefilter("error", cc.SolverWarning)
            seed_ensemble(model, [1, 2], duration=T, scheduler=scheduler, n_workers=2)


def test_the_command_on_threads_prints_and_writes_what_it_does_serially(tmp_path, capsys):
    """`ensemble --scheduler threads --workers 2`: the same table and the same per-seed file as
    `--scheduler serial`, to the byte, with --against too; --workers with serial is refused."""
    base = ["ensemble", "--seeds", "3", "--duration", str(T), "--skip", "0.05", "--no-progress"]
    base += ["--against", "contact.friction=0.3"]
    said = {}
    for scheduler in ("serial", "threads"):
        extra = ["--workers", "2"] if scheduler == "threads" else []
        out = tmp_path / f"{scheduler}.csv"
        assert cli_main([*base, "--scheduler", scheduler, *extra, "--out", str(out)]) == 0
        said[scheduler] = capsys.readouterr().out.replace(str(tmp_path / scheduler), "OUT")
        said[scheduler + " file"] = out.read_bytes()
    assert said["serial"] == said["threads"] and said["serial file"] == said["threads file"]
    assert cli_main([*base, "--scheduler", "serial", "--workers", "2"]) == 2


@pytest.mark.slow  # a dask cluster
def test_members_on_dask_workers_equal_the_serial_ones():
    # workers run one BLAS thread; a record does not depend on that (the compliance comes from the
    # step loop's block solve), so the ensemble is the same in parallel as in this process
    import distributed  # noqa: F401  (required by the [test] extra: a missing one fails the test, not skips it)

    serial = seed_ensemble(cc.load_model(), [1, 2], duration=T)
    parallel = seed_ensemble(cc.load_model(), [1, 2], duration=T, scheduler="local", n_workers=2)
    np.testing.assert_array_equal(parallel.levels, serial.levels)


def test_a_members_warnings_are_said_with_its_seed_in_this_process_and_from_workers():
    """A member whose run warns (here the built-in specimen with contact.damping = 1e5 kg/s, where
    the contact Newton does not converge in a few steps: docs/time_domain.md, "Contact", item 5) is
    named by its seed, the same whether it ran here, on a thread here or on a dask worker, whose
    warnings would otherwise go to the worker's stderr without the seed."""
    import warnings

    import distributed  # noqa: F401  (required by the [test] extra: a missing one fails the test, not skips it)

    model = cc.load_model().with_overrides({"contact.damping": 1e5})
    said, kept = {}, {}
    for scheduler in ("serial", "threads", "local"):
        with warnings.catch_warnings(record=True) as got:
            warnings.simplefilter("always")
            kept[scheduler] = seed_ensemble(model, [1, 2], duration=T, scheduler=scheduler, n_workers=2).warnings
        said[scheduler] = sorted(str(w.message) for w in got if w.category is cc.SolverWarning)
    assert kept["serial"] == kept["threads"] == kept["local"] and sorted(kept["serial"]) == [1, 2]
    assert all("the contact Newton did not converge in" in m for m in kept["serial"].values()), kept
    # each distinct message is said once, prefixed with a seed that gave it (two members whose
    # messages are word for word the same are said once, by whichever finished first; the ensemble
    # keeps both)
    distinct = {m for line in kept["serial"].values() for m in line.split(" | ")}
    for scheduler, messages in said.items():
        seeds_said = [int(m.split(":")[0].removeprefix("seed ")) for m in messages]
        texts = [m.split(": ", 1)[1] for m in messages]
        assert sorted(texts) == sorted(distinct), (scheduler, messages)
        assert all(t in kept[scheduler][s] for s, t in zip(seeds_said, texts)), (scheduler, messages)


def test_a_members_warnings_are_kept_by_seed_and_round_trip_through_its_file(tmp_path):
    """The ensemble keeps each member's warnings by seed (the same messages the run said), its CSV
    keeps them, and pooling two parts keeps both parts'."""
    import warnings

    model = cc.load_model().with_overrides({"contact.damping": 1e5})
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        ens = seed_ensemble(model, [1, 2], duration=T)
    said = sorted(str(w.message) for w in got if w.category is cc.SolverWarning)  # (the runs' solver warnings)
    assert sorted(ens.warnings) == [1, 2]
    # every member's messages were said, for it or for a member that gave them word for word first
    for s in (1, 2):
        assert any(m == f"seed {j}: {ens.warnings[s]}" for j in (1, 2) for m in said), said
    assert set(said) <= {f"seed {s}: {ens.warnings[s]}" for s in (1, 2)}
    ens.save(tmp_path / "e.csv")
    back = load_ensemble(tmp_path / "e.csv")
    assert back.warnings == ens.warnings
    a, b = (
        dataclasses.replace(
            ens,
            seeds=ens.seeds[k : k + 1],
            levels=ens.levels[k : k + 1],
            contact_time=ens.contact_time[k : k + 1],
            warnings={int(ens.seeds[k]): ens.warnings[int(ens.seeds[k])]},
        )
        for k in (0, 1)
    )
    assert pool_ensembles([b, a]).warnings == ens.warnings
    quiet = seed_ensemble(cc.load_model(), [1, 2], duration=T)
    assert quiet.warnings == {}


def test_cli_says_which_members_warned_and_its_file_keeps_what(tmp_path, capsys):
    out = tmp_path / "levels.csv"
    args = ["ensemble", "--seeds", "2", "--duration", str(T), "--set", "contact.damping=1e5", "--out", str(out)]
    assert cli_main(args + ["--scheduler", "serial"]) == 0
    err = capsys.readouterr().err
    assert "cablecasing: warning: 2 of 2 members warned (seeds 1, 2;" in err, err
    kept = load_ensemble(out).warnings
    assert sorted(kept) == [1, 2] and all(any(f"seed {j}: {kept[s]}" in err for j in kept) for s in kept), err


def test_an_ensemble_stopped_in_its_against_run_leaves_the_pair_of_files_as_it_was(tmp_path, capsys, monkeypatch):
    """The two CSVs of `ensemble --against` are written once both ensembles are done: stopped in the
    second, neither file changes (the first was written already and sat beside a stale second), and
    the message says so."""
    import cablecasing_core.studies as studies

    calls = []

    def fake(model, overrides=None, **kw):
        calls.append(overrides)
        if len(calls) == 2:
            raise KeyboardInterrupt
        # (as seed_ensemble's: its settings hold the skip it took, on which --against pairs)
        return dataclasses.replace(synthetic([[1.0, 2.0], [1.1, 2.1]]), settings={"skip": 0.06})

    monkeypatch.setattr(studies, "seed_ensemble", fake)
    out = tmp_path / "levels.csv"
    out.write_text("earlier\n")
    code = cli_main(["ensemble", "--seeds", "2", "--against", "contact.friction=0.2", "--out", str(out)])
    assert code == 130 and len(calls) == 2
    assert out.read_text() == "earlier\n" and not (tmp_path / "levels_against.csv").exists()
    assert "levels.csv" in capsys.readouterr().err


def test_pool_against_parts_of_other_settings_is_refused_and_the_change_names_removed_overrides(tmp_path, capsys):
    base = dataclasses.replace(
        synthetic([[1.0, 2.0], [1.1, 2.1]]), overrides={"casing.E": 6e9}, settings={"duration": 0.2, "skip": 0.05}
    )
    other = dataclasses.replace(base, overrides={"contact.friction": 0.2}, levels=base.levels * 1.1)
    longer = dataclasses.replace(other, settings={"duration": 0.25, "skip": 0.05})
    for name, e in (("a", base), ("b", other), ("c", longer)):
        e.save(tmp_path / f"{name}.csv")
    assert cli_main(["pool", str(tmp_path / "a.csv"), "--against", str(tmp_path / "c.csv")]) == 2
    err = capsys.readouterr().err
    assert "--against = " in err and "its duration is 0.25, theirs 0.2" in err, err
    assert cli_main(["pool", str(tmp_path / "a.csv"), "--against", str(tmp_path / "b.csv")]) == 0
    said = capsys.readouterr().out
    assert "{'casing.E': \"(the model's value)\", 'contact.friction': 0.2}" in said, said


def test_seeds_beyond_what_the_csv_holds_exactly_are_refused():
    """An ensemble's CSV holds its seeds among doubles, exact up to 2**53: a seed above it was
    written as its neighbour (2**53 + 1 as 2**53), and the file then refused on reading."""
    with pytest.raises(ModelError, match=r"seeds = 9007199254740993: must be an integer from 0 to 9007199254740992"):
        seed_ensemble(cc.load_model(), [1, 2**53 + 1], duration=T)


def _one_band(levels):
    levels = np.asarray(levels, float)
    return Ensemble(np.arange(1, len(levels) + 1), "casing.B.Fz", ("b1",), np.array([1.0]), np.array([2.0]), levels)


def test_ensemble_statistics_of_three_members_by_hand():
    """Levels 1, 2, 3: mean 2, sample sd 1 (ddof 1), se 1/sqrt(3), cv = sd / mean = 0.5 (a single
    record's scatter), 95 % interval 2 -/+ t(0.975, 2 dof) se with t = 4.302653 (Student's table),
    cut at 0 below; exact up to the table's 7 digits."""
    e = _one_band([[1.0], [2.0], [3.0]])
    assert e.mean[0] == 2.0 and e.se[0] == pytest.approx(1 / np.sqrt(3), rel=1e-12)
    assert e.cv[0] == pytest.approx(0.5, rel=1e-12)
    lo, hi = e.ci(0.95)
    assert hi[0] - 2.0 == pytest.approx(4.302653 / np.sqrt(3), rel=1e-6)
    assert lo[0] == 0.0  # (2 - 2.484 < 0: cut to 0, a mean level is not negative)
    lo1, _ = _one_band([[5.0], [6.0], [7.0]]).ci(0.95)  # the same spread about 6: the whole interval
    assert 6.0 - lo1[0] == pytest.approx(4.302653 / np.sqrt(3), rel=1e-6)
    lo2, hi2 = _one_band([[1.0], [3.0]]).ci(0.95)  # n = 2: t(0.975, 1 dof) = 12.706205, se = 1
    # (2 - 12.7 < 0: a level's mean is not negative, so the interval ends at 0 below)
    assert lo2[0] == 0.0 and hi2[0] == pytest.approx(2.0 + 12.706205, rel=1e-6)


def test_paired_difference_of_three_pairs_by_hand():
    """a = 2, 4, 3 against b = 1, 2, 3: r = (3 - 2) / 2 = 0.5; e_i = (a_i - b_i) - r b_i = 0.5, 1, -1.5,
    sample sd sqrt(3.5 / 2) (ddof 1), SE(r) = sd / (sqrt(3) mean b) = 0.3818813; interval r -/+
    4.302653 SE (t, 2 dof), its lower end 0.5 - 1.643 = -1.143 cut at -1 (a mean level of 0: a level is
    not negative). Exact (floating point, and the table's 7 digits)."""
    d = paired_difference(np.array([[2.0], [4.0], [3.0]]), np.array([[1.0], [2.0], [3.0]]))
    se = np.sqrt(1.75) / np.sqrt(3) / 2.0
    assert d.r[0] == pytest.approx(0.5, rel=1e-12) and d.se[0] == pytest.approx(se, rel=1e-12)
    lo, hi = d.ci(0.95)
    assert 0.5 - 4.302653 * se < -1.0
    assert (lo[0], hi[0]) == pytest.approx((-1.0, 0.5 + 4.302653 * se), rel=1e-6)


def test_paired_difference_se_is_the_scatter_of_r_when_a_follows_b_closely():
    """a = 2 b (1 + 1 % noise), b with a 15 % seed-to-seed scatter: r = 1 with a scatter of ~1 %, which
    the ratio linearisation's SE gives (sd(a - b) would be 15 %). 2000 ensembles of 10 pairs estimate
    the spread to 1.6 %; the linearisation is good to O(1/n): 15 %."""
    rng = np.random.default_rng(5)
    r, se = [], []
    for _ in range(2000):
        b = np.exp(0.15 * rng.standard_normal((10, 1)))
        a = 2.0 * b * (1 + 0.01 * rng.standard_normal((10, 1)))
        d = paired_difference(a, b)
        r.append(d.r[0])
        se.append(d.se[0])
    assert np.sqrt(np.mean(np.square(se))) / np.std(r) == pytest.approx(1.0, abs=0.15)
