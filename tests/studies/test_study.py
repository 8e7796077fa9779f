"""Monte-Carlo study of Section 4.4: Saltelli's design, resume and enlargement, failures, dask ==
serial, Fig. 23; a study over other parameters of another model."""

import json
import os
import re
from pathlib import Path

import numpy as np
import pytest

from cablecasing_core.errors import ModelError
from cablecasing_core.studies import (
    PAPER_BOUNDS,
    _stand_ins,
    correlations,
    evaluators,
    load_results,
    plot_correlations,
    run_study,
    sobol_design,
    sobol_indices,
)

ANALYTIC = "cablecasing_core.studies._stand_ins:analytic_evaluate"


def _run(path, **kw):
    kw.setdefault("evaluate", ANALYTIC)
    kw.setdefault("n_samples", 24)  # 3 base points of 6 + 2 runs
    kw.setdefault("seed", 7)
    kw.setdefault("scheduler", "serial")
    kw.setdefault("progress", False)
    return run_study(str(path), **kw)


def _same(a, b):
    """Exact equality of two StudyResults apart from the wall time."""
    assert a.parameters == b.parameters and a.outputs == b.outputs
    np.testing.assert_array_equal(a.index, b.index)
    np.testing.assert_array_equal(a.X, b.X)
    np.testing.assert_array_equal(a.Y, b.Y)  # NaN == NaN for failed rows
    np.testing.assert_array_equal(a.status, b.status)
    np.testing.assert_array_equal(a.error, b.error)
    np.testing.assert_array_equal(a.warnings, b.warnings)


def _indices_in_file(path):
    with open(path) as fh:
        return [int(line.split(",", 1)[0]) for line in fh.read().splitlines()[1:]]


def test_saltelli_design_groups_balance_and_continuation():
    n, d = 64, len(PAPER_BOUNDS)
    X = sobol_design(PAPER_BOUNDS, n, seed=3)
    assert X.shape == (n * (d + 2), d)
    lo = np.array([b[0] for b in PAPER_BOUNDS.values()])
    hi = np.array([b[1] for b in PAPER_BOUNDS.values()])
    assert np.all((X >= lo) & (X <= hi))
    G = X.reshape(n, d + 2, d)  # per base point: A, AB_1..AB_d, B
    A, B = G[:, 0], G[:, -1]
    for i in range(d):  # AB_i is A with its i-th coordinate from B
        expect = A.copy()
        expect[:, i] = B[:, i]
        np.testing.assert_array_equal(G[:, 1 + i], expect)
    # a scrambled Sobol' sequence of 64 = 2^6 points: each coordinate has one point in each of the
    # 64 equal strata of its interval (the sequence's (0, m, s) net property in one dimension)
    for k in range(d):
        strata = np.floor((A[:, k] - lo[k]) / (hi[k] - lo[k]) * n).astype(int)
        assert sorted(strata) == list(range(n))
    np.testing.assert_array_equal(X, sobol_design(PAPER_BOUNDS, n, seed=3))
    assert not np.array_equal(X, sobol_design(PAPER_BOUNDS, n, seed=4))
    # a larger design continues the sequence: the smaller one is its beginning
    np.testing.assert_array_equal(sobol_design(PAPER_BOUNDS, 100, seed=3)[: len(X)], X)


@pytest.mark.parametrize(
    "kw, key",
    [
        (dict(bounds={"casing.G": (1.0, 2.0)}), "bounds.casing.G"),
        (dict(bounds={"casing.E": (2e9, 1e9)}), "bounds.casing.E"),
        (dict(bounds={"casing.E": (1e9, 1e9)}), "bounds.casing.E"),
        (dict(bounds={"casing.E": (1e9, float("nan"))}), "bounds.casing.E"),
        (dict(n_samples=1), "n_samples"),
        (dict(seed=-1), "seed"),
        (dict(outputs=["oct1", "casing.E"], bounds={"casing.E": (1e9, 2e9)}), "outputs"),
        (dict(evaluate="no_such_module:f"), "evaluate"),
        (dict(scheduler=42), "scheduler"),
        (dict(max_samples=-3), "max_samples"),
    ],
)
def test_bad_input_names_the_field(tmp_path, kw, key):
    with pytest.raises(ModelError) as e:
        _run(tmp_path / "s.csv", **kw)
    assert e.value.key == key


def test_serial_values_are_the_closed_form(tmp_path):
    res = _run(tmp_path / "s.csv", n_samples=20)  # rounded up to 3 groups of 8 runs
    assert len(res) == 24 and np.all(res.ok) and res.n_base == 3 and res.group_size == 8
    X = sobol_design(PAPER_BOUNDS, 3, seed=7)
    np.testing.assert_array_equal(res.X, X)
    for i in (0, 13):
        ref = _stand_ins.analytic_evaluate(dict(zip(PAPER_BOUNDS, X[i].tolist())))
        assert res.Y[i].tolist() == [ref[o] for o in res.outputs]  # exact: repr round-trips floats


@pytest.mark.slow  # a dask cluster
def test_dask_two_workers_equals_serial(tmp_path):
    kw = dict(n_samples=24, seed=11, evaluate_kwargs={"fail_above": 0.15})
    serial = _run(tmp_path / "serial.csv", **kw)
    dask = _run(tmp_path / "dask.csv", scheduler="local", n_workers=2, **kw)
    assert (serial.status == "failed").any()  # the failing rows are part of the comparison
    _same(serial, dask)
    assert sorted(_indices_in_file(tmp_path / "dask.csv")) == list(range(24))


@pytest.mark.slow  # a dask cluster
def test_existing_cluster_by_address(tmp_path):
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        res = _run(tmp_path / "addr.csv", scheduler=cluster.scheduler_address, n_samples=6)
    _same(res, _run(tmp_path / "serial.csv", n_samples=6))


def test_failed_sample_is_recorded_and_study_continues(tmp_path):
    res = _run(tmp_path / "s.csv", evaluate_kwargs={"fail_above": 0.12})
    fr = res.X[:, res.parameters.index("contact.friction")]
    np.testing.assert_array_equal(res.status == "failed", fr > 0.12)
    assert 0 < (res.status == "failed").sum() < 24
    assert all(e.startswith("ValueError: contact.friction") for e in res.error[res.status == "failed"])
    assert np.all(np.isnan(res.Y[res.status == "failed"])) and np.all(np.isfinite(res.Y[res.ok]))


def test_placeholder_evaluate_is_refused_before_starting(tmp_path):
    def placeholder(overrides):
        raise NotImplementedError("placeholder")

    placeholder.placeholder = True
    with pytest.raises(NotImplementedError, match="placeholder"):
        _run(tmp_path / "s.csv", evaluate=placeholder, n_samples=3)
    assert not (tmp_path / "s.csv").exists()


def test_default_evaluate_runs_the_model(tmp_path):
    """The real per-sample function: a short engine run per sample, serial, two samples."""
    res = run_study(
        tmp_path / "s.csv",
        n_samples=2,
        seed=1,
        scheduler="serial",
        progress=False,
        evaluate_kwargs={"duration": 0.12, "skip": 0.01},
        max_samples=2,
    )  # oct1 (11 Hz) needs 0.09 s
    assert list(res.status) == ["ok", "ok"]
    assert np.all(np.isfinite(res.Y)) and np.all(res.Y > 0)  # (RMS levels; the excitation drives every band)
    # each row is its own sample's run: the model with that row's parameters, run again here outside the study,
    # gives its levels (exactly: the same deterministic run), and the two samples' levels differ
    from cablecasing_core.studies.evaluators import default_evaluate

    for x, y in zip(res.X, res.Y):
        again = default_evaluate(dict(zip(res.parameters, x.tolist())), duration=0.12, skip=0.01)
        np.testing.assert_array_equal([again[o] for o in res.outputs], y)
    assert not np.array_equal(res.Y[0], res.Y[1])


def test_evaluate_errors_are_recorded_per_sample(tmp_path):
    def bad(overrides):
        if overrides["casing.E"] > 6e9:
            raise RuntimeError("line one\nline two")
        return {"x": 1.0}

    res = _run(tmp_path / "s.csv", evaluate=bad, n_samples=16, outputs=["x", "y"])
    assert set(res.status) == {"failed"}  # "y" missing from every result, RuntimeError for some
    big = res.X[:, 1] > 6e9
    assert all(e == "RuntimeError: line one | line two" for e in res.error[big])
    assert all(e.startswith("KeyError") and "'y'" in e for e in res.error[~big])


@pytest.mark.parametrize("scheduler", ["serial", "threads"])
def test_a_samples_warnings_are_said_with_its_index_and_a_shared_one_once(tmp_path, scheduler):
    """What a sample's evaluation warns is said in the caller's process, prefixed with the sample's
    index; a message every sample gives word for word (a model's warning) once, for the first. The
    study's file keeps every sample's own messages in its warnings column, the shared one too, so
    that the samples that warned can be told afterwards. The same on threads, where the samples warn
    at once and each warning must reach its own sample's row (and none the caller's display)."""
    import warnings

    from cablecasing_core.errors import ModelWarning

    def warning(overrides):
        warnings.warn("the same for every sample", ModelWarning, stacklevel=1)
        if overrides["casing.E"] > 6e9:
            warnings.warn(f"at {sorted(overrides.items())}", UserWarning, stacklevel=1)  # (its own text)
        return _stand_ins.analytic_evaluate(overrides)

    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        res = _run(tmp_path / "s.csv", evaluate=warning, n_samples=12, scheduler=scheduler)
    big = [int(i) for i, E in zip(res.index, res.X[:, list(res.parameters).index("casing.E")]) if E > 6e9]
    assert 0 < len(big) < 12
    shared = [w for w in said if "the same for every sample" in str(w.message)]
    assert len(shared) == 1 and shared[0].category is ModelWarning, shared
    # said for the first sample written: sample 0 in order, on threads whichever finished first
    label, text = str(shared[0].message).split(": ", 1)
    assert text == "the same for every sample" and (label == "sample 0" or scheduler == "threads"), shared
    assert int(label.removeprefix("sample ")) in range(12)
    own = [str(w.message) for w in said if w.category is UserWarning]
    assert all(m.split(": ", 1)[1].startswith("at [('cable.E'") for m in own), own
    assert sorted(int(m.split(":")[0].removeprefix("sample ")) for m in own) == sorted(big)
    assert "_warnings" not in (tmp_path / "s.csv").read_text()
    again = load_results(tmp_path / "s.csv")
    for i, text in zip(again.index, again.warnings):
        parts = text.split(" | ")
        assert parts[0] == "the same for every sample", text
        assert len(parts) == (2 if i in big else 1) and (i not in big or parts[1].startswith("at [('cable.E'")), text
    assert again.warned.all()


@pytest.mark.parametrize("scheduler", ["serial", "threads"])
def test_a_models_property_warning_is_said_once_per_process_on_either_scheduler(tmp_path, scheduler):
    """Review AP, W1: a model's property warning (a ModelPropertyWarning, warn_once_per_process) that its
    loading said already is not said again by the samples that build the model, and one not said yet is said
    once, for one sample: on threads as in serial, although the threads scheduler's own block is "always"
    (the caller's filters decide, here "default")."""
    import warnings

    from cablecasing_core.errors import warn_once_per_process

    before, new = "a property the model's loading said", "a property only the samples say"

    def evaluate(overrides):
        warn_once_per_process(before)  # (as each sample's build of the model says its properties)
        warn_once_per_process(new)
        return _stand_ins.analytic_evaluate(overrides)

    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("default")
        warn_once_per_process(before)
        _run(tmp_path / "s.csv", evaluate=evaluate, n_samples=4, scheduler=scheduler)
    texts = [str(w.message) for w in said]
    assert [t for t in texts if before in t] == [before], texts
    (once,) = [t for t in texts if new in t]
    assert re.fullmatch(rf"sample [0-3]: {new}", once), once


def test_a_study_begun_without_the_warnings_column_resumes_with_its_header(tmp_path):
    """A study whose CSV was begun before the warnings column (its sidecar does not say
    ``"warnings": true``) resumes with the header it has, the new rows the width of the old, and
    reads with no warnings."""
    path = tmp_path / "s.csv"
    _run(path, n_samples=12, max_samples=5)
    meta_path = tmp_path / "s.csv.meta.json"
    meta = json.loads(meta_path.read_text())
    assert meta.pop("warnings") is True
    meta_path.write_text(json.dumps(meta))
    lines = path.read_text().splitlines()
    cut = lambda line: ",".join(line.split(",")[:-3] + line.split(",")[-2:])  # noqa: E731 (no comma inside)
    path.write_text("\n".join(cut(line) for line in lines) + "\n")
    res = _run(path, n_samples=12)
    assert len(res) == res.n_base * res.group_size and res.ok.all() and not res.warned.any()
    head = path.read_text().splitlines()[0].split(",")
    assert "warnings" not in head and head[-2:] == ["elapsed_s", "error"]
    assert "warnings" not in json.loads(meta_path.read_text())


def test_resume_after_max_samples_repeats_nothing(tmp_path):
    calls = []

    def counting(overrides):
        calls.append(dict(overrides))
        return _stand_ins.analytic_evaluate(overrides)

    p = tmp_path / "s.csv"
    part = _run(p, evaluate=counting, max_samples=7)
    assert list(part.index) == list(range(7)) and len(calls) == 7
    full = _run(p, evaluate=counting)
    assert len(calls) == 24  # 17 more, none repeated
    assert _indices_in_file(p) == list(range(24))
    assert len({tuple(sorted(c.items())) for c in calls}) == 24
    again = _run(p, evaluate=counting)  # nothing left to do
    assert len(calls) == 24
    _same(full, again)
    _same(full, _run(tmp_path / "clean.csv", evaluate=counting))


def test_enlarging_a_study_runs_only_the_new_samples(tmp_path):
    calls = []

    def counting(overrides):
        calls.append(dict(overrides))
        return _stand_ins.analytic_evaluate(overrides)

    p = tmp_path / "s.csv"
    small = _run(p, evaluate=counting, n_samples=16)  # 2 base points
    assert len(calls) == 16 and small.n_base == 2
    big = _run(p, evaluate=counting, n_samples=40)  # 5 base points: the sequence goes on
    assert len(calls) == 40 and big.n_base == 5  # 24 new runs, none of the 16 again
    assert len({tuple(sorted(c.items())) for c in calls}) == 40
    np.testing.assert_array_equal(big.X[:16], small.X)
    np.testing.assert_array_equal(big.Y[:16], small.Y)
    assert json.loads(Path(str(p) + ".meta.json").read_text())["n_base"] == 5
    _same(big, _run(tmp_path / "clean.csv", evaluate=counting, n_samples=40))
    assert _run(p, evaluate=counting, n_samples=8).n_base == 5 and len(calls) == 80  # never shrunk


def test_resume_after_hard_interruption_and_torn_line(tmp_path):
    state = {"n": 0}

    def dies_after_five(overrides):
        state["n"] += 1
        if state["n"] > 5:
            raise KeyboardInterrupt  # not an Exception: stops the study
        return _stand_ins.analytic_evaluate(overrides)

    p = tmp_path / "s.csv"
    with pytest.raises(KeyboardInterrupt):
        _run(p, evaluate=dies_after_five)
    assert _indices_in_file(p) == list(range(5))
    with open(p, "a") as fh:  # a row torn by a kill mid-write
        fh.write("5,ok,3.1e10,4e9")
    state["n"] = -100
    res = _run(p, evaluate=dies_after_five)
    assert _indices_in_file(p) == list(range(24))  # torn row cut, sample 5 run once, no repeats
    _same(res, _run(tmp_path / "clean.csv", evaluate=dies_after_five))


def test_resume_with_other_settings_is_refused(tmp_path):
    p = tmp_path / "s.csv"
    _run(p, max_samples=3)
    with pytest.raises(ModelError) as e:
        _run(p, seed=8)
    assert e.value.key == "seed"
    with pytest.raises(ModelError) as e:
        _run(p, bounds={"casing.E": (2e9, 1e10), "contact.friction": (0.05, 0.2)})
    assert e.value.key == "bounds"
    meta = json.loads(Path(str(p) + ".meta.json").read_text())
    assert meta["seed"] == 7 and meta["evaluate"] == ANALYTIC


def test_infeasible_samples_are_recorded_not_evaluated(tmp_path):
    calls = []

    def ev(overrides):
        calls.append(overrides)
        return _stand_ins.analytic_evaluate(overrides)

    bounds = {"cable.d": (0.003, 0.0045), "casing.d_inner": (0.0034, 0.0046), "casing.E": (2e9, 1e10)}
    res = _run(tmp_path / "s.csv", evaluate=ev, bounds=bounds, n_samples=30)  # 6 groups of 5
    bad = res.X[:, 0] >= res.X[:, 1]
    assert bad.any() and len(calls) == 30 - bad.sum()
    np.testing.assert_array_equal(res.status == "infeasible", bad)
    assert all("cable.d" in e for e in res.error[bad])


def test_correlations_against_constructed_dependences(tmp_path):
    def ev(o):  # a: linear in cable.E; b: monotone, non-linear in casing.E; c: friction only
        return {"a": 2 * o["cable.E"] + 1, "b": np.exp(o["casing.E"] / 1e9), "c": o["contact.friction"] ** 3}

    res = _run(tmp_path / "s.csv", evaluate=ev, n_samples=64, outputs=["a", "b", "c"])  # 8 base points
    n = 2 * res.n_base  # the independent points of Saltelli's design (A and B; the rest share coordinates)
    pe, sp = correlations(res, "pearson"), correlations(res, "spearman")
    P, S = pe.as_dict(), sp.as_dict()
    assert P["cable.E"]["a"] == pytest.approx(1.0, abs=1e-12)
    assert S["casing.E"]["b"] == pytest.approx(1.0, abs=1e-12) and P["casing.E"]["b"] < 0.99
    assert S["contact.friction"]["c"] == pytest.approx(1.0, abs=1e-12)
    assert "gap" in pe.parameters
    # unrelated pairs: independent columns, r ~ N(0, 1/(n-1)) with n independent points -> |r| < 4/sqrt(n-1)
    assert abs(P["cable.E"]["b"]) < 4 / np.sqrt(n - 1) and abs(S["casing.E"]["c"]) < 4 / np.sqrt(n - 1)
    png = plot_correlations(res, str(tmp_path / "fig23.png"))
    assert os.path.getsize(png) > 10_000
    assert load_results(tmp_path / "s.csv").outputs == ("a", "b", "c")


def test_a_study_resumed_with_its_parameters_in_another_order_is_refused(tmp_path):
    """The design and the CSV's columns follow the order of the bounds: a resume that names them in
    another order is refused (a study stopped before its first row took it, and wrote the values
    of one parameter under the other's heading)."""
    bounds = {"casing.E": (2e9, 1e10), "contact.friction": (0.05, 0.2)}
    _run(tmp_path / "s.csv", bounds=bounds, n_samples=8, max_samples=0)
    swapped = dict(reversed(list(bounds.items())))
    with pytest.raises(ModelError, match=r"must name the parameters in the order of the study") as e:
        _run(tmp_path / "s.csv", bounds=swapped, n_samples=8)
    assert e.value.key == "bounds"


def test_a_hand_edited_value_that_is_no_number_is_named_by_line_and_column(tmp_path):
    res = _run(tmp_path / "s.csv", n_samples=8)
    lines = (tmp_path / "s.csv").read_text().splitlines()
    cells = lines[2].split(",")
    cells[2 + len(res.parameters)] = "abc"
    lines[2] = ",".join(cells)
    (tmp_path / "s.csv").write_text("\n".join(lines) + "\n")
    with pytest.raises(ModelError, match=rf"line 3, column {res.outputs[0]!r} must hold a number"):
        load_results(tmp_path / "s.csv")


def test_a_study_whose_model_file_changed_does_not_resume_and_the_fingerprint_follows_the_files(tmp_path):
    """A model file edited between two runs of a study would add samples of another model to it
    (they were taken): the study records the model's fingerprint and refuses the resume. The
    fingerprint follows the content of a tabulated excitation, not its folder: the same files in
    two folders give one fingerprint (pool refused such parts), an edited CSV another (it did not
    change)."""
    import cablecasing_core as cc

    def evaluate(overrides, model_file=None):
        return _stand_ins.analytic_evaluate(overrides)

    text = cc.load_model().to_toml()
    (tmp_path / "m.toml").write_text(text)
    _run(tmp_path / "s.csv", evaluate=evaluate, n_samples=8, evaluate_kwargs={"model_file": str(tmp_path / "m.toml")})
    (tmp_path / "m.toml").write_text(text.replace("rms = 5.0", "rms = 50.0"))
    with pytest.raises(ModelError, match="holds another model than when the study") as e:
        _run(
            tmp_path / "s.csv",
            evaluate=evaluate,
            n_samples=16,
            evaluate_kwargs={"model_file": str(tmp_path / "m.toml")},
        )
    assert e.value.key == "model_file"

    base = cc.load_model().data
    shaker = {"target": "casing.A.z", "kind": "csv", "file": "motion.csv", "quantity": "displacement"}
    data = {**base, "scenario": {**base["scenario"], "excitation": {"shaker": shaker}}}
    prints = []
    for folder, amplitude in (("a", 1e-4), ("b", 1e-4), ("c", 5e-4)):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "motion.csv").write_text(f"time_s,u_m\n0.0,0.0\n0.01,{amplitude}\n0.02,0.0\n")
        prints.append(cc.model_from_dict(data, base_dir=tmp_path / folder).fingerprint())
    assert prints[0] == prints[1] != prints[2]


def test_a_study_of_a_given_model_runs_that_model(tmp_path):
    """``model=`` names the model the study runs, not only the one its bounds are checked against:
    the rows of a study of the installed specimen equal default_evaluate on the installed specimen
    with the rows' parameters (exact: the same computation in this process), and the sidecar holds
    its name and fingerprint (a resume must run the same model)."""
    import cablecasing_core as cc

    bounds = {"contact.friction": (0.05, 0.2)}
    res = run_study(
        tmp_path / "s.csv",
        bounds=bounds,
        n_samples=2,
        model="installed",
        evaluate_kwargs={"duration": 0.15},
        scheduler="serial",
        progress=False,
        max_samples=2,
    )
    assert list(res.status) == ["ok", "ok"], res.error
    for x, y in zip(res.X, res.Y):
        ref = evaluators.default_evaluate(dict(zip(res.parameters, x.tolist())), duration=0.15, model_file="installed")
        assert y.tolist() == [ref[o] for o in res.outputs]
    meta = json.loads((tmp_path / "s.csv.meta.json").read_text())
    assert meta["evaluate_kwargs"]["model_file"] == "installed"
    assert meta["model_fingerprint"] == cc.load_model("installed").fingerprint()


def test_a_given_model_reaches_a_custom_evaluate_or_is_refused(tmp_path, monkeypatch):
    """A Model given to a custom evaluate is passed as ``model=`` (and its fingerprint recorded: a
    resume with another model is refused); a path as ``model_file=`` (absolute); an evaluate without
    that parameter is refused before anything is written (it would run another model than the one
    checked)."""
    import cablecasing_core as cc

    seen = []

    def with_model(overrides, model=None):
        seen.append(model)
        return {"E": float(model.data["casing"]["E"])}

    model = cc.load_model().with_overrides({"casing.E": 3e9})
    bounds = {"contact.friction": (0.05, 0.2)}
    res = _run(tmp_path / "s.csv", evaluate=with_model, bounds=bounds, model=model, outputs=["E"], n_samples=6)
    assert res.ok.all() and np.all(res.Y == 3e9) and all(m is model for m in seen)
    other = model.with_overrides({"casing.E": 4e9})
    with pytest.raises(ModelError, match="holds another model than when the study") as e:
        _run(tmp_path / "s.csv", evaluate=with_model, bounds=bounds, model=other, outputs=["E"], n_samples=9)
    assert e.value.key == "model"

    files = []

    def with_file(overrides, model_file=None):
        files.append(model_file)
        return _stand_ins.analytic_evaluate(overrides)

    (tmp_path / "m.toml").write_text(cc.load_model().to_toml())
    monkeypatch.chdir(tmp_path)  # (a relative path: evaluate gets it absolute, as dask workers need it)
    _run(tmp_path / "f.csv", evaluate=with_file, bounds=bounds, model="m.toml", n_samples=6)
    assert files and set(files) == {str(tmp_path / "m.toml")}

    with pytest.raises(ModelError, match="has no parameter 'model_file' to run it") as e:
        _run(tmp_path / "n.csv", bounds=bounds, model="installed")  # analytic_evaluate takes no model
    assert e.value.key == "model" and not (tmp_path / "n.csv").exists()


def test_non_finite_outputs_are_failed_runs_that_say_which(tmp_path):
    """An evaluate that returns NaN or inf (a diverged run) gives a failed row naming the output and
    the value: an ok row's outputs are all finite, so correlations and Sobol indices use them all."""

    def diverging(overrides):
        out = _stand_ins.analytic_evaluate(overrides)
        fr = overrides["contact.friction"]
        out["oct5"] = float("nan") if fr > 0.17 else float("-inf") if fr < 0.07 else out["oct5"]
        return out

    res = _run(tmp_path / "s.csv", evaluate=diverging, n_samples=32)
    fr = res.X[:, res.parameters.index("contact.friction")]
    np.testing.assert_array_equal(res.status == "failed", (fr > 0.17) | (fr < 0.07))
    assert 0 < (res.status == "failed").sum() < len(res)
    for f, err in zip(fr[~res.ok], res.error[~res.ok]):
        assert err == (
            "ValueError: evaluate returned nan for oct5" if f > 0.17 else "ValueError: evaluate returned -inf for oct5"
        )
    assert np.all(np.isfinite(res.Y[res.ok])) and np.all(np.isnan(res.Y[~res.ok]))
    n_failed = int((res.status == "failed").sum())
    with pytest.raises(ModelError, match=rf"of the 32 runs, {n_failed} failed \(their errors say why\)"):
        sobol_indices(res)  # (4 base points, some incomplete: the message says why)


def test_a_diameter_varied_alone_is_compared_with_the_models_other_one(tmp_path):
    """Varying cable.d past the model's fixed casing.d_inner (the built-in's, read here from the model)
    rejects those samples as infeasible without evaluating them, and says so when most of them are;
    with model=False there is no model value to compare with."""
    import warnings

    import cablecasing_core as cc
    from cablecasing_core.errors import ModelWarning

    d_inner = cc.load_model().data["casing"]["d_inner"]
    calls = []

    def ev(overrides):
        calls.append(overrides)
        return _stand_ins.analytic_evaluate(overrides)

    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        res = _run(tmp_path / "s.csv", evaluate=ev, bounds={"cable.d": (0.003, 0.01)}, n_samples=30)
    bad = res.X[:, 0] >= d_inner
    np.testing.assert_array_equal(res.status == "infeasible", bad)
    assert bad.sum() > len(res) / 2 and len(calls) == len(res) - bad.sum() and res.ok[~bad].all()
    assert all(
        e.startswith("infeasible: cable.d = ") and f"casing.d_inner = {d_inner!r} m" in e for e in res.error[bad]
    )
    most = [str(w.message) for w in said if w.category is ModelWarning]
    assert len(most) == 1 and most[0].startswith(f"{bad.sum()} of the {len(res)} samples to run are infeasible")
    res = _run(tmp_path / "f.csv", evaluate=ev, bounds={"cable.d": (0.003, 0.01)}, n_samples=30, model=False)
    assert res.ok.all()


@pytest.mark.parametrize(
    "bounds, fragment",
    [
        ([("casing.E", (2e9, 1e10)), ("casing.E", (3e9, 4e9))], "names 'casing.E' again (first (2000000000.0"),
        ({"casing.E": ("2e9", 1e10)}, "must be a pair (low, high) of numbers (not text or True/False)"),
        ({"contact.friction": (False, 0.2)}, "must be a pair (low, high) of numbers (not text or True/False)"),
        ({"contact.friction": (0.05,)}, "must be a pair (low, high) of numbers"),
    ],
)
def test_check_bounds_refuses_a_key_twice_and_bounds_that_are_not_numbers(bounds, fragment):
    from cablecasing_core.studies import check_bounds

    with pytest.raises(ModelError) as e:
        check_bounds(bounds)
    key = next(iter(dict(bounds)))
    assert e.value.key == f"bounds.{key}" and fragment in str(e.value), str(e.value)


def test_check_bounds_takes_a_sequence_of_pairs_and_numpy_numbers():
    from cablecasing_core.studies import check_bounds

    pairs = [("casing.E", (np.float64(2e9), np.int64(10**10))), ("contact.friction", [0.05, 0.2])]
    assert check_bounds(pairs) == {"casing.E": (2e9, 1e10), "contact.friction": (0.05, 0.2)}
