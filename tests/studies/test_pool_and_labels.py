"""What a review of the ensembles and studies found: `pool --against` compares ensembles of the same
model only (it credited a stiffer casing to a friction override); an ensemble of a clip's output
loads back (its own file was refused as altered); the records' few-lines warning before an
ensemble names no `--fmin` (the commands have none) and is said once; the figures' confidence
levels and Sobol panels show what the numbers are."""

import warnings

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelWarning
from cablecasing_core.studies.ensemble import Ensemble, load_ensemble, pool_ensembles
from cablecasing_core.studies.evaluators import check_record_settings
from cablecasing_core.studies.plots import _percent, _sobol_limits
from cablecasing_core.studies.sensitivity import SobolIndices

LABELS = ("oct1", "oct2")
LOW, HIGH = np.array([11.0, 22.0]), np.array([22.0, 44.0])


def ensemble(seeds, overrides, base_model, output="casing.B.Fz", scale=1.0):
    """A two-band ensemble with the settings a run writes (``model``: the fingerprint with the
    overrides, ``base_model``: before them)."""
    levels = scale * (1.0 + 0.1 * np.arange(2 * len(seeds)).reshape(len(seeds), 2))
    settings = {"duration": 1.0, "dt": 1e-5, "skip": 0.06, "window": "hann"}
    settings |= {"model": f"{base_model}+{sorted(overrides.items())}", "base_model": base_model}
    seeds = np.array(seeds)
    contact_time = np.zeros((len(seeds), 0))  # (no contact time columns, as without a cable)
    return Ensemble(seeds, output, LABELS, LOW, HIGH, levels, dict(overrides), contact_time, settings)


def test_pool_against_an_ensemble_of_another_model_is_refused(tmp_path, capsys):
    """Base parts of friction 0.05 on model a, --against parts of friction 0.2 on model b (another
    casing.E in the file): the change would not be the override's alone, so it is refused naming
    --against; the same --against parts of model a are compared."""
    ensemble([1, 2, 3], {"contact.friction": 0.05}, "a").save(tmp_path / "base.csv")
    ensemble([1, 2, 3], {"contact.friction": 0.2}, "b", scale=2.0).save(tmp_path / "other.csv")
    ensemble([1, 2, 3], {"contact.friction": 0.2}, "a", scale=1.1).save(tmp_path / "same.csv")
    assert main(["pool", str(tmp_path / "base.csv"), "--against", str(tmp_path / "other.csv")]) == 2
    err = capsys.readouterr().err
    assert "--against = " in err and "is of another model (its fingerprint before the overrides b, theirs a)" in err
    assert main(["pool", str(tmp_path / "base.csv"), "--against", str(tmp_path / "same.csv")]) == 0
    assert "relative change" in capsys.readouterr().out


def test_parts_saved_before_the_base_model_was_kept_still_pool():
    """A part without ``base_model`` (saved before it was kept) pools with one that has it: its
    ``model`` fingerprint, with the same overrides, implies the rest."""
    new = ensemble([1, 2], {}, "a")
    old = ensemble([3, 4], {}, "a")
    settings = {k: v for k, v in old.settings.items() if k != "base_model"}
    old = Ensemble(old.seeds, old.output, LABELS, LOW, HIGH, old.levels, {}, old.contact_time, settings)
    pooled = pool_ensembles([new, old])
    assert list(pooled.seeds) == [1, 2, 3, 4] and "base_model" not in pooled.settings


def test_an_ensemble_of_a_clip_s_force_loads_back(tmp_path):
    """A clip's output (casing.clip0.Fz) is an ensemble's output like a support's: its own CSV loads
    back equal (it was refused: 'names an output that is not one of the model's outputs')."""
    ens = ensemble([1, 2], {}, "a", output="casing.clip0.Fz")
    ens.save(tmp_path / "clip.csv")
    back = load_ensemble(tmp_path / "clip.csv")
    assert back.output == "casing.clip0.Fz" and np.array_equal(back.levels, ens.levels)


def test_the_few_lines_warning_before_the_runs_names_no_fmin_and_is_said_once():
    """0.3 s records of the built-in specimen (0.24 s after the skip: 2.6 lines in oct1): one warning
    for two checks (a study checks in its command and again in run_study), naming the record that
    gives the band 4 lines and no --fmin, which ensemble and study do not have."""
    model = cc.load_model()
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("default")
        check_record_settings(model, duration=0.3)
        check_record_settings(model, duration=0.3)
    texts = [str(w.message) for w in said if issubclass(w.category, ModelWarning) and "FFT lines" in str(w.message)]
    assert len(texts) == 1, texts
    assert "4 lines in oct1 need a record of 4 / 11 Hz = 0.364 s" in texts[0] and "--fmin" not in texts[0]


def test_a_confidence_level_is_shown_as_given():
    assert [_percent(c) for c in (0.95, 0.975, 0.995, 0.9)] == ["95%", "97.5%", "99.5%", "90%"]


def test_a_sobol_panel_holds_every_bar_and_interval():
    """An S1 of 1.15 with an interval of 0.3 and an ST of -0.4 with 0.1 (few base points): the panel
    reaches beyond both (it was cut at -0.2 and 1.1); indices within [0, 1] keep -0.2 .. 1.1."""
    wild = SobolIndices(
        parameters=("a",),
        outputs=LABELS,
        S1=np.array([[1.15, 0.2]]),
        S1_conf=np.array([[0.3, 0.05]]),
        ST=np.array([[0.5, -0.4]]),
        ST_conf=np.array([[0.1, 0.1]]),
        n_base=8,
        conf_level=0.95,
    )
    lo, hi = _sobol_limits(wild, 0)
    assert lo < -0.5 and hi > 1.45
    tame = SobolIndices(
        parameters=("a",),
        outputs=LABELS,
        S1=np.array([[0.3, 0.2]]),
        S1_conf=np.array([[0.1, 0.05]]),
        ST=np.array([[0.5, 0.4]]),
        ST_conf=np.array([[0.1, 0.1]]),
        n_base=8,
        conf_level=0.95,
    )
    assert _sobol_limits(tame, 0) == pytest.approx((-0.2, 1.1))
