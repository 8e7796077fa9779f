"""Steps recomputed in sub-steps around stick-slip events (contact.event_substeps;
docs/time_domain.md, "Events inside the step"): on the installed specimen with the paper's switch
law of friction (contact.friction_law = "switch"; the specimen's own law is regularised and has no
events), where the cable slides
through 13 closed contacts and sticks at every reversal of the drive, they give the trajectory of a
uniformly fine step; the run stays reproducible to the bit however it is cut into calls, through
its state, and its energy ledger closes."""

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.model.schema import SUPPORT_OUTPUTS
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion

pytestmark = pytest.mark.slow

FZ = SUPPORT_OUTPUTS.index("casing.B.Fz")


@pytest.fixture(scope="module")
def installed():
    return cc.load_model("installed").with_overrides({"contact.friction_law": "switch"})


def force(model, dt, nsub, duration):
    """casing.B.Fz (N) on the 1e-5 s grid, and the engine."""
    eng = Engine(model.with_overrides({"contact.event_substeps": nsub}), dt=dt, ledger=True, record=True)
    eng.advance(duration, scenario_motion(model, dt=dt))
    k = round(1e-5 / dt)
    return eng.history()["support_forces"][k - 1 :: k, FZ], eng


def test_substeps_give_the_fine_steps_trajectory_through_stick_and_slip(installed):
    """0.06 s from the static state (three reversals of the 50 Hz drive at every contact; the
    installed response is hardly chaotic, so one trajectory converges). Against a uniform 1.25e-6 s,
    the default 1e-5 s step is off by ~4 % of the force's RMS (the stick-slip switches decided once
    per step, first order); its 8 sub-steps around the events, at the same 1.25e-6 s, must take most
    of that away: what stays is the unrefined steps' Newmark error (second order, ~0.2 % here)."""
    ref, _ = force(installed, 1.25e-6, 1, 0.06)
    plain, eng1 = force(installed, 1e-5, 1, 0.06)
    sub, eng8 = force(installed, 1e-5, 8, 0.06)
    rms = np.sqrt(np.mean((ref - ref.mean()) ** 2))
    err_plain = np.sqrt(np.mean((plain - ref) ** 2)) / rms
    err_sub = np.sqrt(np.mean((sub - ref) ** 2)) / rms
    assert eng1.refined_steps == 0 and eng8.refined_steps > 0.1 * 6000  # the events are many here
    assert err_plain > 0.01  # the effect is there to be removed
    assert err_sub < 0.2 * err_plain and err_sub < 0.005, (err_plain, err_sub)
    e = eng8.energies()
    assert abs(e["residual"]) < 0.01 * e["support_work"]  # the ledger closes with sub-steps


def test_substeps_are_the_same_in_one_call_or_in_communication_steps(installed, cut_and_resumed):
    """The sub-steps' motion starts from the supports' state and a step that ends in its sub-steps
    with an event on makes the next start in them: both are engine state, so a run cut into 1e-4 s
    calls (the FMU's) or restored from get_state is the same to the bit as one call. (The motion is
    evaluated on the exact grid: the calls' start times add up in floating point.)"""
    whole, steps, resumed = cut_and_resumed(installed)
    assert whole.refined_steps > 0
    np.testing.assert_array_equal(whole.history()["support_forces"], steps.history()["support_forces"])
    np.testing.assert_array_equal(whole.output_values(), resumed.output_values())
    assert whole.refined_steps == steps.refined_steps


def test_kept_delassus_matrix_changes_the_response_by_less_than_a_part_in_ten_thousand(installed):
    """The sub-steps after the first keep the Delassus matrix while the same contacts are closed
    (it moves by ~1e-4 of itself over a step with the contact points): against recomputing it in
    every sub-step, casing.B.Fz moves by ~1e-7 of its RMS until, ~0.01 s in, the rounding flips a
    step's refinement decision (the turn test of DIAG_SLOW_SLIP, a threshold); that shifts the
    record by ~1e-4 of its RMS, which does not grow (measured over 0.1 s: 1.1e-4; bar 5e-4)."""
    forces = []
    for reuse in (True, False):
        eng = Engine(installed, ledger=False, record=True)
        eng.reuse_delassus = reuse
        eng.advance(0.1, scenario_motion(installed, dt=1e-5))
        forces.append(eng.history()["support_forces"][:, FZ])
    a, b = forces
    rms = np.sqrt(np.mean((b - b.mean()) ** 2))
    assert np.max(np.abs(a - b)[:500]) < 1e-5 * rms  # before any decision flips: the reuse's own error
    assert np.sqrt(np.mean((a - b) ** 2)) < 5e-4 * rms
