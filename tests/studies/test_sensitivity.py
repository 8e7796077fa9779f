"""Sobol indices (studies.sensitivity, SALib) against the Ishigami function's closed forms, through
the study's own design and results file; and the sample-size warnings."""

import numpy as np
import pytest

from cablecasing_core.studies import critical_correlation, run_study, size_warnings, sobol_design, sobol_indices
from cablecasing_core.studies._stand_ins import ishigami_evaluate
from cablecasing_core.studies.results_store import StudyResults

BOUNDS = {"x1": (-np.pi, np.pi), "x2": (-np.pi, np.pi), "x3": (-np.pi, np.pi)}
# benchmarks.md, "Sensitivity analysis: the Ishigami function" (a = 7, b = 0.1)
S1 = np.array([0.3139, 0.4424, 0.0])
ST = np.array([0.5576, 0.4424, 0.2437])


def _results(X, y):
    """StudyResults of a complete design (all runs ok) with one output 'f'."""
    n = len(X)
    return StudyResults(
        index=np.arange(n),
        parameters=tuple(BOUNDS),
        X=X,
        outputs=("f",),
        Y=np.asarray(y, float)[:, None],
        status=np.full(n, "ok"),
        error=np.full(n, ""),
        elapsed_s=np.zeros(n),
        group_size=len(BOUNDS) + 2,
        n_base=n // (len(BOUNDS) + 2),
    )


def test_sobol_indices_of_the_ishigami_function_are_its_closed_forms():
    X = sobol_design(BOUNDS, 4096, seed=1)  # 20480 evaluations
    y = [ishigami_evaluate(dict(zip(BOUNDS, x)))["f"] for x in X]
    sob = sobol_indices(_results(X, y), conf_level=0.99, num_resamples=300)
    # the closed form (given to 4 digits: +-5e-5) lies inside the 99 % bootstrap interval of each
    # estimate (seeded, so deterministic), and the intervals are narrow enough for this to bite
    assert np.all(np.abs(sob.S1[:, 0] - S1) <= sob.S1_conf[:, 0] + 5e-5), (sob.S1[:, 0], sob.S1_conf[:, 0])
    assert np.all(np.abs(sob.ST[:, 0] - ST) <= sob.ST_conf[:, 0] + 5e-5), (sob.ST[:, 0], sob.ST_conf[:, 0])
    assert sob.S1_conf.max() < 0.06 and sob.ST_conf.max() < 0.06
    assert sob.n_base == 4096 and size_warnings(_results(X, y), sob) == []


def test_a_study_gives_the_indices_of_its_design_and_drops_incomplete_groups(tmp_path):
    res = run_study(
        tmp_path / "s.csv",
        "cablecasing_core.studies._stand_ins:ishigami_evaluate",
        bounds=BOUNDS,
        n_samples=5 * 64,
        seed=1,
        outputs=["f"],
        scheduler="serial",
        model=False,
        progress=False,
    )
    assert res.group_size == 5 and res.n_base == 64 and np.all(res.ok)
    direct = sobol_indices(_results(res.X, res.Y[:, 0]))
    np.testing.assert_array_equal(sobol_indices(res).ST, direct.ST)  # the file's rows are the design's
    # a failed run leaves its whole group out: the indices of the 63 other groups
    res.status[7] = "failed"  # (group 1)
    keep = np.r_[0:5, 10:320]
    part = sobol_indices(res)
    assert part.n_base == 63
    np.testing.assert_array_equal(part.S1, sobol_indices(_results(res.X[keep], res.Y[keep, 0])).S1)
    warn = size_warnings(res, part)
    assert any("Sobol indices from 63 base points" in w for w in warn)  # +-0.1 or worse at 63 points


def test_the_critical_correlation_is_fishers_and_small_studies_warn():
    assert critical_correlation(44) < 0.3 < critical_correlation(43)  # the "too small" limit of the docs
    assert critical_correlation(103) == pytest.approx(np.tanh(1.96 / 10))
    X = sobol_design(BOUNDS, 8, seed=0)
    res = _results(X, [ishigami_evaluate(dict(zip(BOUNDS, x)))["f"] for x in X])
    (w,) = size_warnings(res)
    assert "16 independent points" in w and "indicative only" in w


def test_the_bootstrap_intervals_do_not_depend_on_numpy_s_global_random_state():
    """The intervals are seeded (SALib takes a seed of 0 for none and then draws from np.random's
    global state, which other code moves: a study's intervals then changed with what ran before)."""
    X = sobol_design(BOUNDS, 256, seed=1)
    y = [ishigami_evaluate(dict(zip(BOUNDS, x)))["f"] for x in X]
    conf = []
    for state in (1, 99):
        np.random.seed(state)
        conf.append(sobol_indices(_results(X, y)).S1_conf)
    np.testing.assert_array_equal(conf[0], conf[1])


@pytest.mark.parametrize(
    "kwargs, key",
    [({"seed": -1}, "seed"), ({"conf_level": 1.5}, "conf_level"), ({"num_resamples": 1}, "num_resamples")],
)
def test_sobol_settings_are_checked(kwargs, key):
    """seed -1 had reached SALib as 0, its "no seed" (an unseeded bootstrap); 1.5 and 1 had given
    SALib's RuntimeError and NaN intervals."""
    from cablecasing_core.errors import ModelError
    from cablecasing_core.studies.results_store import StudyResults

    n = 5 * 8  # (never read: the settings are checked first)
    res = StudyResults(
        np.arange(n),
        ("a", "b", "c"),
        np.zeros((n, 3)),
        ("y",),
        np.zeros((n, 1)),
        np.full(n, "ok"),
        np.full(n, ""),
        np.zeros(n),
        None,
        5,
        8,
    )
    with pytest.raises(ModelError) as e:
        sobol_indices(res, **kwargs)
    assert e.value.key == key


def test_the_study_command_prints_and_plots_the_indices_it_computed_once(tmp_path, capsys, monkeypatch):
    from cablecasing_core import studies
    from cablecasing_core.cli.study import print_study
    from cablecasing_core.studies import plots, sensitivity

    X = sobol_design(BOUNDS, 64, seed=1)
    res = _results(X, [ishigami_evaluate(dict(zip(BOUNDS, x)))["f"] for x in X])
    calls = []
    real = sensitivity.sobol_indices
    counted = lambda *a, **k: calls.append(1) or real(*a, **k)  # noqa: E731
    monkeypatch.setattr(sensitivity, "sobol_indices", counted)
    monkeypatch.setattr(studies, "sobol_indices", counted)
    cors, sob = print_study(res)
    plots.plot_sobol(res, tmp_path / "sobol.png", sob=sob)
    assert len(calls) == 1 and (tmp_path / "sobol.png").stat().st_size > 10_000
    np.testing.assert_array_equal(sob.ST, real(res).ST)  # the indices printed are the study's
    out = capsys.readouterr().out
    assert f"x2 S1{'':35s}{sob.S1[1, 0]:+10.2f}" in out and [c.method for c in cors] == ["pearson", "spearman"]
