"""Review N: two designs compared on the same seeds. ``paired_difference`` refuses ensembles run with
another duration, dt, skip or window (it paired them silently); ``pool --against --other-model``
compares ensembles of two model files (a clip moved), which ``pool --against`` refuses without it;
``pool``'s refusal of parts with other settings names each setting and both values (it quoted the
settings table cut off where the differing one began)."""

import dataclasses

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelError
from cablecasing_core.studies.ensemble import Ensemble, load_ensemble, paired_difference, pool_ensembles

LABELS = ("oct1", "oct2")
LOW, HIGH = np.array([11.0, 22.0]), np.array([22.0, 44.0])


def ensemble(base_model="a", overrides=None, scale=1.0, **settings):
    """A two-band ensemble of seeds 1..3 with the settings a run writes, changed by ``settings``."""
    overrides = dict(overrides or {})
    levels = scale * (1.0 + 0.1 * np.arange(6).reshape(3, 2))
    given = {"duration": 0.5, "dt": 1e-5, "skip": 0.05, "window": "hann"}
    given |= {"model": f"{base_model}+{sorted(overrides.items())}", "base_model": base_model} | settings
    return Ensemble(np.array([1, 2, 3]), "casing.A.Fx", LABELS, LOW, HIGH, levels, overrides, np.zeros((3, 0)), given)


@pytest.mark.parametrize(
    "key, value, said",
    [("duration", 1.0, "0.5"), ("dt", 2e-5, "1e-05"), ("skip", 0.2, "0.05"), ("window", "boxcar", "'hann'")],
)
def test_paired_difference_refuses_ensembles_of_other_run_settings(key, value, said):
    a = ensemble("clip3", scale=0.96)
    b = ensemble("clip2", **{key: value})
    with pytest.raises(ModelError) as e:
        paired_difference(a, b)
    assert e.value.key == f"b.settings['{key}']" and e.value.value == value
    assert f"must equal that of a, {said}, to pair them" in str(e.value)


def test_paired_difference_pairs_two_models_and_a_declared_setting():
    """Other models (a clip moved) pair; so does a dt that an override changed between the two."""
    d = paired_difference(ensemble("clip3", scale=0.96), ensemble("clip2"))
    assert np.allclose(d.r, -0.04) and np.allclose(d.se, 0.0)
    a = ensemble(overrides={"scenario.dt": 2e-5}, dt=2e-5)
    assert np.allclose(paired_difference(a, ensemble()).r, 0.0)


def test_pool_names_each_setting_that_differs_with_both_values():
    with pytest.raises(ModelError) as e:
        pool_ensembles([ensemble(), dataclasses.replace(ensemble("b"), seeds=np.array([4, 5, 6]))])
    msg = str(e.value)
    assert e.value.value == "model"  # (base_model: implied by model with the same overrides)
    assert (
        "its model (the fingerprint of the model data with its overrides) is 'b+[]', that of ensembles[0] 'a+[]'" in msg
    )
    assert "--other-model" in msg and "..." not in msg


def test_pool_against_another_model_file_with_other_model(tmp_path, capsys, monkeypatch):
    """Two model files (another casing modulus standing for a moved clip), 2 seeds of 0.1 s each:
    pool --against refuses them naming --other-model; with it the paired change is printed as the
    models' whole difference, and equals paired_difference of the two files."""
    monkeypatch.chdir(tmp_path)
    text = cc.load_model().to_toml()
    (tmp_path / "a.toml").write_text(text)
    (tmp_path / "b.toml").write_text(text.replace("E = 5000000000.0", "E = 6000000000.0", 1))
    run = ["--seeds", "2", "--duration", "0.1", "--skip", "0"]
    for name in ("a", "b"):
        assert main(["ensemble", f"{name}.toml", *run, "--out", f"{name}.csv"]) == 0
    capsys.readouterr()
    assert main(["pool", "a.csv", "--against", "b.csv"]) == 2
    assert "add --other-model" in capsys.readouterr().err
    assert main(["pool", "a.csv", "--against", "b.csv", "--other-model"]) == 0
    out = capsys.readouterr().out
    assert "instead of the files' (" in out and "the models' whole difference (paired on the same seeds)" in out
    d = paired_difference(load_ensemble("b.csv"), load_ensemble("a.csv"))
    row = [line for line in out.splitlines() if line.startswith("oct4,")][-1]  # (the change table)
    assert float(row.split(",")[2]) == pytest.approx(d.r[3], abs=1e-4)  # (printed as {r:+.4f}: 5e-5, and rounding)
    # the settings must still match: another duration is refused naming it
    assert main(["ensemble", "b.toml", "--seeds", "2", "--duration", "0.12", "--skip", "0", "--out", "b2.csv"]) == 0
    capsys.readouterr()
    assert main(["pool", "a.csv", "--against", "b2.csv", "--other-model"]) == 2
    assert "its duration is 0.12, theirs 0.1" in capsys.readouterr().err
    assert main(["pool", "a.csv", "--other-model"]) == 2
    assert "give --against too" in capsys.readouterr().err
