"""Review AZ, the core's part: a NaN or an infinity is refused with the allowed range, as any other
value outside it (AZ5: the validator both shells use, so --set and the FMU say the same); whose
fault a refused change is lives in the core (AZ3: model.changes.with_changes, the rule of the
command line's --set and of the FMU's parameters)."""

import math

import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelError
from cablecasing_core.model.changes import with_changes
from cablecasing_core.model.schema import lookup
from cablecasing_core.model.validators import Number


def _refusal(key, value):
    """The message that refuses ``value`` of ``key``, or None if it is allowed."""
    try:
        lookup(key).check(value, key)
    except ModelError as exc:
        return str(exc)
    return None


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_a_non_finite_value_is_refused_with_the_range_every_other_refusal_gives(bad):
    """Every numeric key of the built-in specimens (the FMU's Real parameters; a vector by its
    components): the message for a non-finite value is the one for any value outside the range, with
    the number said finite (the range read from the text of that other refusal, not from the code)."""
    keys = set(cc.load_model().parameters()) | set(cc.load_model("installed").parameters())
    checked = 0
    for key in sorted(keys):
        number = getattr(lookup(key).validator, "number", lookup(key).validator)  # (NumberOrTable: its Number)
        if not isinstance(number, Number) or number.integer:
            continue
        outside = _refusal(key, -1e308) or _refusal(key, 1e308)
        if outside is None:  # (no bound: a harmonic's phase, any finite number of rad)
            continue
        allowed = outside.partition(": must be ")[2]
        said = _refusal(key, bad)
        assert said == f"{key} = {bad!r}: must be {allowed.replace(' number', ' finite number', 1)}", (said, outside)
        checked += 1
    assert checked >= 33  # (moduli, densities, diameters, damping, contact, loads, scenario: most keys)


def test_the_command_line_says_the_range_of_a_nan(capsys):
    code = main(["simulate", "--duration", "0.001", "--set", "contact.friction=nan"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and err == ["cablecasing: error: --set contact.friction = nan: must be a finite number in [0, 10]"]


def test_a_conflict_is_named_by_the_change_with_or_without_a_flag():
    """The core's rule: the change that makes the model fail alone, and the model's key and value it
    conflicts with; the command line gives its flag, the FMU none (its parameter's name alone)."""
    base = cc.load_model()
    for flag, name in (("--set", "--set casing.d_outer"), ("", "casing.d_outer")):
        with pytest.raises(ModelError) as err:
            with_changes(base, {"casing.d_outer": (flag, 0.0035)})
        assert err.value.key == name and err.value.value == 0.0035
        assert str(err.value.allowed).startswith("conflicts with casing.d_inner = 0.004 of the model <built-in>: ")
    with pytest.raises(ModelError) as err:  # (a key set that is itself refused: named as it is)
        with_changes(base, {"casing.d_inner": ("", 0.0036), "cable.d": ("", 0.0038)})
    assert (
        str(err.value) == "casing.d_inner = 0.0036: must be larger than cable.d = 0.0038 m (there must be a radial gap)"
    )


def test_a_change_that_fails_alone_for_another_key_is_not_blamed_for_this_one():
    """Review BA3: cable.d = 0.0045 (beyond the bore, d_inner = 0.004 m) with scenario.dt = 1e-3 (the random
    band's 1000 Hz above its Nyquist frequency, 500 Hz) each fail alone, on different keys; the bore's error is
    cable.d's alone. Two changes that each make d_inner fail (d_outer 0.0035 below it, cable.d 0.0045 above it)
    are named together."""
    base = cc.load_model()
    with pytest.raises(ModelError) as err:
        with_changes(base, {"cable.d": ("", 0.0045), "scenario.dt": ("", 1e-3)})
    assert err.value.key == "cable.d" and err.value.value == 0.0045, str(err.value)
    assert str(err.value.allowed).startswith("conflicts with casing.d_inner = 0.004 of the model <built-in>: ")
    with pytest.raises(ModelError) as err:
        with_changes(base, {"casing.d_outer": ("", 0.0035), "cable.d": ("", 0.0045), "scenario.dt": ("", 1e-3)})
    assert str(err.value).startswith("casing.d_outer=0.0035, cable.d=0.0045: conflicts with casing.d_inner"), str(
        err.value
    )
