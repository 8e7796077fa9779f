"""A model's own warnings (what its values mean) are said once per process for the same words: a
command that builds the same model several times (an ensemble's --against model, each seed's
sample) does not repeat them; under "always" (pytest.warns) they are said every time."""

import warnings

import cablecasing_core as cc
from cablecasing_core import errors
from cablecasing_core.errors import ModelPropertyWarning

TEXT = 'contact.friction_law = "switch" (the paper\'s law) does not converge'


def _said(filter_action, monkeypatch, builds=3):
    monkeypatch.setattr(errors, "_SAID_ONCE", set())  # as in a process that said nothing yet
    installed = cc.load_model("installed")
    said = []
    for _ in range(builds):  # each in its own block, as the commands' steps are (a block resets Python's record)
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter(filter_action)
            installed.with_overrides({"contact.friction_law": "switch"})
        said += [x for x in w if TEXT in str(x.message)]
    return said


def test_the_switch_law_on_the_wall_is_said_once_for_three_builds_of_the_model(monkeypatch):
    said = _said("default", monkeypatch)
    assert len(said) == 1 and issubclass(said[0].category, ModelPropertyWarning)


def test_under_always_each_build_says_it(monkeypatch):
    assert len(_said("always", monkeypatch)) == 3


def test_another_value_is_other_words_and_said_again(monkeypatch):
    monkeypatch.setattr(errors, "_SAID_ONCE", set())
    installed = cc.load_model("installed")
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("default")
        for tension in (10.0, 12.0):
            installed.with_overrides({"contact.friction_law": "switch", "loads.cable_tension": tension})
    assert len([x for x in w if TEXT in str(x.message)]) == 2
