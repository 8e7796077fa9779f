"""A tolerance on the step's local error (contact.event_tolerance; docs/time_domain.md, "A tolerance
instead of a bare step"): Zienkiewicz and Xie's estimate against the exact local error of an
average-acceleration step of a harmonic oscillator, and, on the installed specimen, the steps whose
estimate exceeds the tolerance recomputed in sub-steps: the record moves towards a converged one
as the tolerance tightens, at a fraction of a uniformly finer step's cost, the ledger closes, and
the run is the same to the bit however it is cut into calls."""

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.model.schema import SUPPORT_OUTPUTS
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.kernels._newmark_step_loop_with_ledger import local_error_estimate
from cablecasing_core.timedomain.scenario import scenario_motion

FZ = SUPPORT_OUTPUTS.index("casing.B.Fz")


@pytest.mark.parametrize("phase", [0.3, 1.0, 2.0])
def test_the_estimate_is_the_local_error_of_an_average_acceleration_step(phase):
    """u'' = -w^2 u from the exact state at phase w t = phase, one Newmark step (beta = 1/4) of h:
    the estimate h^2 / 12 |a_1 - a_0| is the leading term h^3 u''' / 12 of the step's local error,
    so the two agree to a relative O(w h), halving with h (measured ratios 1.002-1.25 over
    w h = 0.2 .. 0.0125). The rotations (DOFs 3-5 of a node) do not enter a displacement error."""
    w, amp = 2 * np.pi * 100.0, 1e-3  # rad/s, m
    dev = []
    for wh in (0.1, 0.05, 0.025, 0.0125):
        h = wh / w
        u0, v0, a0 = amp * np.sin(phase), amp * w * np.cos(phase), -w * w * amp * np.sin(phase)
        u1 = (u0 + h * v0 + h * h / 4 * a0) / (1 + w * w * h * h / 4)  # Newmark's step, closed form
        A, Ao = np.zeros(12), np.zeros(12)
        A[0], Ao[0] = -w * w * u1, a0
        A[3], A[9] = 1e9, -1e9  # rotations: ignored
        est = local_error_estimate(0, 12, A, Ao, h)
        dev.append(est / abs(u1 - amp * np.sin(wh + phase)) - 1)
    dev = np.abs(dev)
    assert dev[-1] < 0.02, dev  # at 500 steps per period within 2 %
    assert np.all((dev[:-1] / dev[1:] > 1.7) & (dev[:-1] / dev[1:] < 2.3)), dev  # first order in h


@pytest.mark.slow
def test_the_tolerance_brings_the_installed_record_to_a_fine_steps_at_a_fraction_of_its_cost():
    """The installed specimen (its regularised friction: no stick-slip events, so only the
    tolerance recomputes steps), 0.05 s from the static state (hardly chaotic, one trajectory
    converges), casing.B.Fz on the 1e-5 s grid against 3.125e-7 s, max over the record over the
    reference's RMS. Measured: the plain 1e-5 s 1.27e-3; a tolerance of 1e-9 m 2.5e-4 with 4.6 % of
    the steps recomputed (a uniform 2.5e-6 s: 3.2e-4 at four times the steps); 1e-10 m 1.1e-4
    (a uniform 1.25e-6 s: 1.7e-4 at eight times). Bounds: each tolerance cuts the error by at least
    1.5 x, and recomputes fewer than a tenth of the steps at 1e-9 m."""
    model = cc.load_model("installed")
    assert model.contact["friction_law"] == "regularized"

    def run(dt, tol, ledger=False):
        m = model.with_overrides({"contact.event_tolerance": tol})
        eng = Engine(m, dt=dt, ledger=ledger, record=True)
        eng.advance(0.05, scenario_motion(m, dt=dt))
        k = round(1e-5 / dt)
        return eng.history()["support_forces"][k - 1 :: k, FZ], eng

    ref, _ = run(3.125e-7, 0.0)
    rms = np.sqrt(np.mean(ref**2))
    plain, eng0 = run(1e-5, 0.0)
    loose, eng_loose = run(1e-5, 1.0)  # a tolerance no step reaches: the plain run to the bit
    tol9, eng9 = run(1e-5, 1e-9, ledger=True)
    tol10, eng10 = run(1e-5, 1e-10)
    err = np.array([np.abs(x - ref).max() / rms for x in (plain, tol9, tol10)])
    assert err[0] > 5e-4  # there is an error to take away
    assert np.all(err[:-1] > 1.5 * err[1:]), err
    assert eng0.refined_steps == eng_loose.refined_steps == 0 and eng0.max_local_error == 0.0
    np.testing.assert_array_equal(plain, loose)
    assert 0 < eng9.tolerance_steps == eng9.refined_steps < 0.1 * 5000
    assert eng10.tolerance_steps > eng9.tolerance_steps
    # what the run reports: the largest estimate of a step or sub-step kept (the sub-steps of the
    # worst steps may stay above the tolerance; a coarse step kept is within it)
    assert 0.0 < eng_loose.max_local_error <= 1.0 and eng9.max_local_error > 0.0
    e = eng9.energies()
    assert abs(e["residual"]) < 1e-3 * e["support_work"], e  # the ledger closes through the sub-steps


@pytest.mark.slow
def test_a_run_with_a_tolerance_is_the_same_in_one_call_or_in_communication_steps(cut_and_resumed):
    """The tolerance's decisions depend only on the step's own state, so a run cut into the FMU's
    1e-4 s calls, or resumed from get_state, is the same to the bit as one call (the motion
    evaluated on the exact grid: the calls' start times add up in floating point)."""
    model = cc.load_model("installed").with_overrides({"contact.event_tolerance": 1e-9})
    whole, steps, resumed = cut_and_resumed(model)
    assert whole.tolerance_steps > 0
    np.testing.assert_array_equal(whole.history()["support_forces"], steps.history()["support_forces"])
    np.testing.assert_array_equal(whole.output_values(), resumed.output_values())
    assert whole.tolerance_steps == steps.tolerance_steps


def test_a_tolerance_set_on_the_engine_takes_effect_from_the_next_call():
    """Engine.event_tolerance is read with the law's other attributes at each call: set on an
    engine of the regularised law (no sub-steps without it), the next call recomputes steps."""
    model = cc.load_model("installed")
    eng = Engine(model, ledger=False)
    motion = scenario_motion(model)
    eng.advance(0.005, motion)
    assert eng.event_substeps == 1 and eng.refined_steps == 0
    eng.event_tolerance = 1e-9
    eng.advance(0.005, motion)
    assert eng.event_substeps == 8 and eng.tolerance_steps > 0


def test_a_tolerance_without_substeps_is_refused_naming_both_keys():
    """A tolerance recomputes a step in contact.event_substeps sub-steps: with one there is nothing
    to recompute in, so the pair is refused, in a model file and on an engine, instead of the
    tolerance silently doing nothing; the engine keeps its tolerance."""
    model = cc.load_model("installed")
    with pytest.raises(cc.ModelError, match=r"contact\.event_tolerance.*contact\.event_substeps = 1"):
        model.with_overrides({"contact.event_tolerance": 1e-9, "contact.event_substeps": 1})
    eng = Engine(model.with_overrides({"contact.event_substeps": 1}), ledger=False)
    with pytest.raises(cc.ModelError, match=r"contact\.event_substeps = 1"):
        eng.event_tolerance = 1e-9
    with pytest.raises(cc.ModelError, match=r"event_tolerance = -1\.0"):
        eng.event_tolerance = -1.0
    assert eng.event_tolerance == 0.0


def test_a_tolerance_the_substeps_do_not_meet_is_said_and_one_they_meet_is_not():
    """A step over the tolerance is recomputed in sub-steps once; where the acceleration jumps their
    estimate can stay above it. Then the run says so: ``simulate`` warns with the tolerance and the
    largest estimate, and its solver report has tolerance_met False. On the installed specimen over
    0.05 s, 1e-9 m leaves 2.3e-9 m in the worst sub-steps (measured; a margin of 2.3 x); at 1e-8 m
    a step kept above the tolerance would need a coarse estimate 8-64 x the tolerance (the
    sub-steps' estimate falls as h^2 at a jump, h^3 where the motion is smooth), and none has one;
    and 1e-9 m with 16 sub-steps, as the warning advises, is met (the worst sub-steps at ~2.3e-9 / 4;
    the largest estimate kept, 9.9e-10 m, is a whole step's, within the tolerance by construction)."""
    import warnings

    model = cc.load_model("installed")
    with pytest.warns(cc.SolverWarning, match=r"contact\.event_tolerance = 1e-09 m was not met: .* (\d\.\d+e-09) m"):
        res = cc.simulate(model.with_overrides({"contact.event_tolerance": 1e-9}), duration=0.05)
    s = res.solver
    assert not s["tolerance_met"] and s["max_local_error"] > 1.5e-9 and s["tolerance_steps"] > 0, s
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no warning at all
        res = cc.simulate(model.with_overrides({"contact.event_tolerance": 1e-8}), duration=0.05)
    s = res.solver
    assert s["tolerance_met"] and 0.0 < s["max_local_error"] <= 1e-8 and s["tolerance_steps"] > 0, s
    # the warning's advice works: 16 sub-steps (a quarter of the estimate at a jump) meet 1e-9 m
    tighter = model.with_overrides({"contact.event_tolerance": 1e-9, "contact.event_substeps": 16})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert cc.simulate(tighter, duration=0.05).solver["tolerance_met"]
    assert cc.simulate(model, duration=0.002).solver["tolerance_met"]  # no tolerance: nothing to meet
