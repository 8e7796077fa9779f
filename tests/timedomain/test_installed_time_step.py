"""Where the installed specimen's time-step error lives (docs/time_domain.md, "The time step on the
installed specimen"): without friction its 13 closed contacts converge under refinement and the
default step is already close to a fine one; with the paper's switch law of friction the same
record is a hundred times further off and converges at first order or less, because the
stick-slip switches multiply as the step shrinks ("How many events there are"); with Coulomb's law
regularised over the switch law's band (contact.friction_law = "regularized", "A friction law
whose limit exists", the specimen's own law) it converges like the frictionless one, and its energy
ledger closes."""

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.errors import ModelError
from cablecasing_core.model.schema import SUPPORT_OUTPUTS
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion

pytestmark = pytest.mark.slow

FZ = SUPPORT_OUTPUTS.index("casing.B.Fz")
DURATION = 0.06  # s: three reversals of the 50 Hz drive at every contact, hardly chaotic
GRID = 2e-5  # s: the coarsest step's grid, on which the records are compared


def force(model, dt, ledger=None):
    """casing.B.Fz (N) on the GRID, from a run of DURATION at the time step dt (s); the engine's
    energies (J) appended to ``ledger`` when given."""
    eng = Engine(model, dt=dt, ledger=ledger is not None, record=True)
    eng.advance(DURATION, scenario_motion(model, dt=dt))
    if ledger is not None:
        ledger.append(eng.energies())
    return eng.history()["support_forces"][round(GRID / dt) - 1 :: round(GRID / dt), FZ]


def errors(model, ledger=None):
    """RMS distance of the records at 2e-5, 1e-5 and 5e-6 s from 1.25e-6 s, over the RMS of the
    latter's fluctuation (-)."""
    ref = force(model, 1.25e-6)
    rms = np.sqrt(np.mean((ref - ref.mean()) ** 2))
    return np.array([np.sqrt(np.mean((force(model, dt, ledger) - ref) ** 2)) / rms for dt in (2e-5, 1e-5, 5e-6)])


def test_without_friction_the_installed_contacts_converge_and_with_it_they_carry_the_error():
    installed = cc.load_model("installed")
    frictionless = errors(installed.with_overrides({"contact.friction": 0.0}))
    default = errors(installed.with_overrides({"contact.friction_law": "switch"}))  # the sub-steps around its events
    # without friction: each refinement brings the record closer (measured 6.2e-4, 2.1e-4, 1.2e-4),
    # and the default step is within 1e-3 of its RMS, 5x what it is, for the machine's rounding
    assert np.all(np.diff(frictionless) < 0), frictionless
    assert frictionless[1] < 1e-3, frictionless
    # with friction the same step is more than ten times further off (measured 2.5e-2, a hundred
    # times), and halving the step gains less than second order would (measured orders 0.45, 0.7)
    assert default[1] > 10 * frictionless[1], (default, frictionless)
    assert np.all(default[:-1] / default[1:] < 2.0**1.5), default


def test_the_regularized_friction_law_converges_like_no_friction_and_its_ledger_closes():
    installed = cc.load_model("installed")
    ledgers = []
    assert installed.contact["friction_law"] == "regularized"  # the specimen's own law
    regularized = errors(installed, ledgers)
    # measured 4.0e-4, 1.7e-4, 7.0e-5: each refinement closer, the default step within 1e-3 of the
    # RMS (the frictionless bound above), where the switch law is at 2.5e-2
    assert np.all(np.diff(regularized) < 0), regularized
    assert regularized[1] < 1e-3, regularized
    for e in ledgers:  # the friction power is the law's force on the end-of-step velocity
        assert abs(e["residual"]) < 1e-3 * e["support_work"], e  # measured 1e-7 .. 9e-8


def test_the_regularized_law_needs_a_speed_to_regularize_over():
    """stick_velocity = 0 would make the regularised law the switch at zero again: refused, naming the
    field, before anything runs (when the model is validated: the engine's own check is not reached)."""
    with pytest.raises(ModelError) as err:
        Engine(cc.load_model().with_overrides({"contact.friction_law": "regularized", "contact.stick_velocity": 0.0}))
    assert err.value.key == "contact.stick_velocity" and "regularized" in str(err.value)
