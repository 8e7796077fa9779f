"""Model files: the built-in specimen and every bad-input case of the issue."""

import copy

import numpy as np
import pytest

from cablecasing_core import ModelError, load_model, model_from_dict
from cablecasing_core.structure.geometry import centerline_of
from cablecasing_core.timedomain.scenario import scenario_motion


def raw():
    m = load_model()
    return copy.deepcopy(m.data)


def test_default_model_is_the_paper_specimen():
    m = load_model()
    cl = centerline_of(m)
    assert abs(cl.length - 0.85) < 2e-3  # 850 mm casing
    assert cl.n_elements == 35
    P = cl.nodes - cl.nodes[0]
    # non-planar: the points span three dimensions
    assert np.linalg.svd(P, compute_uv=False)[2] > 1e-3
    assert 0.12 < 1 / cl.curvature.max() < 0.16  # tightest bend about 0.15 m
    assert m.bodies["casing"].I_override == 2.7261e-10
    assert m.radial_gap == pytest.approx(0.5e-3)
    assert m.data["contact"]["damping"] == 100.0 and m.data["contact"]["friction"] == 0.15


def test_model_round_trips_through_toml(tmp_path):
    m = load_model()
    p = tmp_path / "m.toml"
    p.write_text(m.to_toml())
    assert load_model(p).data == m.data


def _bad(mutate, key_fragment):
    d = raw()
    mutate(d)
    with pytest.raises(ModelError) as exc:
        model_from_dict(d)
    assert key_fragment in str(exc.value)
    return exc.value


@pytest.mark.parametrize(
    "mutate,key",
    [
        (lambda d: d["geometry"].update(points=[[0, 0, 0]]), "geometry.points"),
        (lambda d: d["geometry"].update(points=[[0, 0, 0], [1, 0, 0], [1, 0, 0]]), "geometry.points[2]"),
        (lambda d: d["casing"].update(E=-1.0), "casing.E"),
        (lambda d: d["cable"].update(rho=0.0), "cable.rho"),
        (lambda d: d["cable"].update(d=-0.003), "cable.d"),
        (lambda d: d["geometry"].update(n_elements=0), "geometry.n_elements"),
        (lambda d: d["casing"].update(d_inner=0.003), "casing.d_inner"),
        (lambda d: d["casing"].update(supports={"A": "pinned", "B": "clamped"}), "casing.supports.A"),
        (lambda d: d["casing"].update(Ee=5e9), "casing.Ee"),
        (lambda d: d["casing"].update(E=[[100.0, 5e9], [50.0, 6e9]]), "casing.E"),
        (lambda d: d["contact"].update(friction=-0.1), "contact.friction"),
        (lambda d: d["scenario"].update(dt=0.0), "scenario.dt"),
        (lambda d: d["scenario"].update(duration=1e-6), "scenario.duration"),
    ],
)
def test_bad_input_names_the_key(mutate, key):
    err = _bad(mutate, key)
    assert err.key.startswith(key.split("[")[0])


def test_no_gap_message_says_what_is_allowed():
    err = _bad(lambda d: d["casing"].update(d_inner=0.003), "casing.d_inner")
    assert "larger than cable.d" in str(err)


def test_one_body_is_enough_but_not_zero():
    d = raw()
    del d["cable"]
    d["scenario"]["excitation"].pop("cable_axial")
    assert list(model_from_dict(d).bodies) == ["casing"]
    del d["casing"]
    with pytest.raises(ModelError, match="body"):
        model_from_dict(d)


def test_overrides_validate_and_reject_unknown_keys():
    m = load_model()
    assert m.with_overrides({"casing.E": 6e9}).bodies["casing"].E == 6e9
    with pytest.raises(ModelError, match="casing.Ex"):
        m.with_overrides({"casing.Ex": 1.0}).bodies["casing"]
    with pytest.raises(ModelError, match="casing.E"):
        m.with_overrides({"casing.E": 0.0})


def test_unreadable_file(tmp_path):
    with pytest.raises(ModelError, match="model_file"):
        load_model(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[geometry\n")
    with pytest.raises(ModelError, match="valid TOML"):
        load_model(bad)


def test_an_excitation_seed_left_out_follows_an_override_of_the_scenario_seed():
    """A random excitation without a seed of its own takes scenario.seed (the schema's default_from);
    an override of scenario.seed must move it too (before, the filled-in seed stayed and the 'seed 2'
    run was seed 1's record), while a seed the file or an override gives stays."""
    m = load_model("installed")
    assert m.scenario["excitation"]["casing_random"]["seed"] == m.scenario["seed"] == 1
    m2 = m.with_overrides({"scenario.seed": 2})
    assert m2.scenario["excitation"]["casing_random"]["seed"] == 2
    own = m.with_overrides({"scenario.excitation.casing_random.seed": 7}).with_overrides({"scenario.seed": 3})
    assert own.scenario["excitation"]["casing_random"]["seed"] == 7
    u2 = scenario_motion(m2, dt=1e-5)(np.array([0.05]))[2]
    u1 = scenario_motion(m, dt=1e-5)(np.array([0.05]))[2]
    assert not np.array_equal(u1, u2)  # another record
