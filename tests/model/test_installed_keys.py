"""The installed cable's keys (issue 23): loads.gravity, loads.cable_tension, cable.rest_shape in the
one schema; their scalar forms as parameters; the built-in specimens by name; bad input named."""

import math

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.model import specimen_names
from cablecasing_core.model.schema import lookup, markdown_table


def test_the_keys_are_in_the_schema_with_units_and_defaults():
    g, T, shape = lookup("loads.gravity"), lookup("loads.cable_tension"), lookup("cable.rest_shape")
    assert (g.unit, g.default, g.components) == ("m/s2", [0.0, 0.0, 0.0], ("x", "y", "z"))
    assert (T.unit, T.default) == ("N", 0.0)
    assert shape.default == "routing" and "straight" in shape.allowed
    assert lookup("loads.gravity.z").unit == "m/s2" and lookup("loads.gravity.z").default == 0.0
    table = markdown_table()
    assert all(f"`{k}`" in table for k in ("loads.gravity", "loads.cable_tension", "cable.rest_shape"))


def test_a_model_without_loads_is_the_paper_s_and_not_installed():
    model = cc.load_model()
    assert model.loads == {"gravity": [0.0, 0.0, 0.0], "cable_tension": 0.0}
    assert model.bodies["cable"].rest_shape == "routing" and not model.installed


def test_vector_keys_are_parameters_by_component():
    model = cc.load_model()
    p = model.parameters()
    assert {"loads.gravity.x", "loads.gravity.y", "loads.gravity.z", "loads.cable_tension"} <= set(p)
    m2 = model.with_overrides({"loads.gravity.z": -9.81, "loads.cable_tension": 5.0, "cable.rest_shape": "straight"})
    assert m2.loads["gravity"] == [0.0, 0.0, -9.81] and m2.loads["cable_tension"] == 5.0 and m2.installed
    assert m2.parameters()["loads.gravity.z"] == -9.81
    assert m2.text_parameters()["cable.rest_shape"] == "straight"
    assert model.loads["gravity"] == [0.0, 0.0, 0.0]  # the copy is a copy
    assert cc.load_model(None).fingerprint() == cc.load_model("default").fingerprint()


def test_the_installed_specimen_by_name():
    assert {"default", "installed"} <= set(specimen_names())
    m = cc.load_model("installed")
    assert m.bodies["cable"].rest_shape == "straight"
    assert m.loads["gravity"] == [0.0, 0.0, -9.81] and m.loads["cable_tension"] == 10.0
    # otherwise the paper's specimen
    d = cc.load_model()
    for key, value in d.parameters().items():
        if not key.startswith("loads."):
            assert m.parameters()[key] == value, key


@pytest.mark.parametrize(
    "overrides, key, words",
    [
        ({"loads.cable_tension": -1.0}, "loads.cable_tension", "a number in [0, 1e+07] in N"),
        ({"loads.cable_tension": math.nan}, "loads.cable_tension", "finite"),
        ({"loads.gravity": [0.0, -9.81]}, "loads.gravity", "three finite numbers"),
        ({"loads.gravity": [0.0, math.nan, -9.81]}, "loads.gravity", "three finite numbers"),
        ({"loads.gravity": [0.0, math.inf, -9.81]}, "loads.gravity", "three finite numbers"),
        ({"loads.gravity": "down"}, "loads.gravity", "three finite numbers"),
        ({"loads.gravity": [0.0, "x", -9.81]}, "loads.gravity", "three finite numbers"),
        ({"cable.rest_shape": "curly"}, "cable.rest_shape", "'routing', 'straight'"),
    ],
)
def test_bad_input_names_the_key(overrides, key, words):
    with pytest.raises(cc.ModelError) as err:
        cc.load_model().with_overrides(overrides)
    assert err.value.key == key and words in str(err.value)


def test_a_tension_above_the_casing_s_buckling_load_is_refused_by_name():
    """The routed casing (clamped, E = 5e9 Pa) buckles at ~55 N under the compression it carries;
    every use of the model refuses a tension above it, naming the key and giving the load."""
    model = cc.load_model().with_overrides({"loads.cable_tension": 60.0})
    from cablecasing_core.timedomain.engine import Engine
    from cablecasing_core.timedomain.static_state import static_state

    for use in (
        lambda: cc.natural_frequencies(model, "casing", 1),
        lambda: Engine(model),
        lambda: static_state(model),
    ):
        with pytest.raises(cc.ModelError) as err:
            use()
        assert err.value.key == "loads.cable_tension" and err.value.value == 60.0
        assert "buckling load 54.72 N" in str(err.value) and "supports: A clamped; B clamped" in str(err.value)
        assert "its mode largest at s = " in str(err.value)
    cc.natural_frequencies(cc.load_model().with_overrides({"loads.cable_tension": 54.0}), "casing", 1)  # below: fine


def test_loads_need_the_bodies_and_supports_that_carry_them(beam_model):
    pts = [[0.0, 0, 0], [1.0, 0, 0]]
    cable_only = beam_model(pts, 10, supports=("clamped", "clamped"))
    with pytest.raises(cc.ModelError) as err:
        beam_model(pts, 10, supports=("free", "free")).with_overrides({"loads.gravity": [0.0, 0.0, -9.81]})
    assert err.value.key == "loads.gravity" and "no clamped or isolator support" in str(err.value)
    with pytest.raises(cc.ModelError) as err:
        beam_model(pts, 10, supports=("free", "free")).with_overrides({"cable.rest_shape": "straight"})
    assert err.value.key == "cable.rest_shape"
    data = cable_only.data
    casing_only = cc.model_from_dict(
        {
            "geometry": data["geometry"],
            "casing": {"E": 5e9, "rho": 4850.0, "d_outer": 0.0095, "d_inner": 0.004},
        }
    )
    with pytest.raises(cc.ModelError) as err:
        casing_only.with_overrides({"loads.cable_tension": 5.0})
    assert err.value.key == "loads.cable_tension" and "needs a [cable]" in str(err.value)
    assert np.isclose(cable_only.with_overrides({"loads.cable_tension": 5.0}).loads["cable_tension"], 5.0)


def test_an_unknown_specimen_name_says_what_exists():
    with pytest.raises(cc.ModelError) as err:
        cc.load_model("instaled")
    assert err.value.key == "model_file" and "installed" in str(err.value)


def test_a_tension_on_the_switch_friction_law_warns_naming_the_regularized_law():
    """A cable under a tension lies on the wall, where the switch law's stick-slip switches multiply
    as the step shrinks (docs/time_domain.md): loading such a model warns and names the law to set;
    the built-in installed specimen (regularised), a model without friction and one without a
    tension do not warn."""
    import warnings

    installed = cc.load_model("installed")
    with pytest.warns(cc.ModelWarning, match=r'loads.cable_tension = 10 N .* set contact.friction_law = "regularized"'):
        installed.with_overrides({"contact.friction_law": "switch"})
    with warnings.catch_warnings():
        warnings.simplefilter("error", cc.ModelWarning)
        cc.load_model("installed")
        installed.with_overrides({"contact.friction_law": "switch", "contact.friction": 0.0})
        cc.load_model("default")
