"""A cable that gravity alone lays on the casing's wall, with the paper's switch friction law, is
warned of when a run starts (the loader warns of a cable tension on that law; gravity it cannot
judge, since only the static state tells whether the cable touches the wall), once per process and
model, and not where the law or the loads give no reason."""

import warnings

import numpy as np

import cablecasing_core as cc
from cablecasing_core import errors as errors_module

TEXT = "rests on the casing's wall"


def _said(model, runs=2):
    """The warnings of ``runs`` runs of ``model`` that say the cable rests on the wall, in a process
    that has said none (the record of what was said is emptied first: another test may have run
    the same model)."""
    errors_module._SAID_ONCE.clear()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("default")
        for _ in range(runs):
            cc.simulate(model, duration=0.001)
    return [x for x in w if TEXT in str(x.message)]


def test_gravity_on_the_switch_law_warns_once_naming_the_nodes_the_static_state_touches():
    m = cc.load_model("installed").with_overrides({"loads.cable_tension": 0.0, "contact.friction_law": "switch"})
    touching = int(np.count_nonzero(cc.static_state(m).normal_force > 0.0))
    assert touching > 0  # (the premise: gravity alone lays this cable on the wall)
    said = _said(m)
    assert len(said) == 1, [str(x.message) for x in said]  # (two runs, one model: once)
    assert issubclass(said[0].category, cc.ModelWarning)
    assert f"at {touching} nodes" in str(said[0].message) and "regularized" in str(said[0].message)
    assert said[0].filename == __file__  # (it points at the caller's simulate)


def test_no_warning_on_the_regularised_law_without_loads_or_with_a_tension():
    gravity_regularized = cc.load_model("installed").with_overrides({"loads.cable_tension": 0.0})
    assert _said(gravity_regularized, runs=1) == []
    assert _said(cc.default_model(), runs=1) == []  # (no loads: no static state; the paper's own specimen)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (the loader's own warning of the tension on the switch law)
        tension_switch = cc.load_model("installed").with_overrides({"contact.friction_law": "switch"})
    assert _said(tension_switch, runs=1) == []  # (said by the loader, not twice)
