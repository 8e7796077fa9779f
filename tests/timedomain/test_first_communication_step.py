"""An FMU's first communication step (review W W2): after the FMU's warm-up (two steps, then
``reset``) it is one compiled call like the others, not the general path, with the general path's
results to the bit; and the contact's dissipated energy reads +0, not -0, before anything is
dissipated."""

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.model.schema import OUTPUTS
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion
from cablecasing_core.timedomain.support_motion import GridMotion, SupportReconstruction

H = 1e-4  # s, the communication step (10 steps of the engine's 1e-5 s)


def _steps(eng, n, inputs, drive):
    """n communication steps of ``eng`` through ``advance_reconstructed`` with the inputs row k at
    step k (u, v, a of the 12 channels, m, m/s, m/s2) and the scenario's motion added (``drive``):
    the outputs after each step and the energies at the end."""
    nch = len(eng.channels)
    recon, out = SupportReconstruction(nch), np.zeros(len(eng.output_names))
    u, v, a = np.zeros(nch), np.zeros(nch), np.zeros(nch)
    rows = []
    for k in range(n):
        u[:], v[:], a[:] = inputs[k, :nch], inputs[k, nch : 2 * nch], inputs[k, 2 * nch :]
        eng.advance_reconstructed(H, recon, u, v, a, out, drive)
        rows.append(out.copy())
    return np.array(rows), eng.energies()


def test_the_first_step_after_a_warm_up_is_one_compiled_call_with_the_general_path_s_bits(monkeypatch):
    """The scenario's own motion sampled as inputs and the drive added, 8 steps with contact: an
    engine warmed up as the FMU warms up (two steps of zero inputs, then reset) takes its first step
    without Engine.advance (the general path), and its outputs and energies equal, bit for bit, those
    of an engine that records (which always takes the general path: the compiled call records
    nothing)."""
    model = cc.load_model()
    t = H * np.arange(8)
    inputs = np.hstack(scenario_motion(model)(t))
    fused, general = Engine(model, ledger=True), Engine(model, ledger=True, record=True)
    drive_f, drive_g = (GridMotion(scenario_motion(model, dt=e.dt), e.dt) for e in (fused, general))
    _steps(fused, 2, np.zeros_like(inputs), drive_f)  # the FMU's warm-up
    fused.reset()

    def general_path(*args, **kwargs):
        raise AssertionError("the general path was taken")

    monkeypatch.setattr(fused, "advance", general_path)
    out_f, e_f = _steps(fused, 8, inputs, drive_f)
    monkeypatch.undo()
    out_g, e_g = _steps(general, 8, inputs, drive_g)
    np.testing.assert_array_equal(out_f, out_g)
    assert e_f == e_g
    assert np.any(out_f[:, OUTPUTS.index("casing.B.Fz")] != 0.0)


def test_the_dissipated_energy_reads_plus_zero_before_anything_is_dissipated():
    """-ledger - (pot - pot0) gave -0.0 at t = 0 (fmusim printed '-0'); through both the Python
    outputs and the compiled step's, a run without contact reads +0."""
    model = cc.load_model()
    i = OUTPUTS.index("contact.dissipated_energy")
    eng = Engine(model)
    assert eng.output_values()[i] == 0.0 and not np.signbit(eng.output_values()[i])
    assert not np.signbit(eng.energies()["contact_dissipation"])
    quiet = Engine(model.with_overrides({"contact.enabled": False}))
    out, _ = _steps(quiet, 3, np.zeros((3, 36)), None)
    assert np.all(out[:, i] == 0.0) and not np.any(np.signbit(out[:, i]))


def test_a_refused_first_step_leaves_the_engine_as_it_was():
    """Review AB AB1: beginning the run (its start energy, the supports' state at t = 0) came before
    the step's own snapshot, so a refused first step (an input that overflows the reconstruction,
    1e300 m) left a NaN in the state: get_state could not be set back, and a retry of the
    installed specimen failed. Now the state is as before the call to the bit, and a sane step
    after it equals a fresh engine's."""
    model = cc.load_model()
    eng, fresh = Engine(model, ledger=True), Engine(model, ledger=True)
    before = eng.get_state()
    nch = len(eng.channels)
    inputs = np.zeros((1, 3 * nch))
    inputs[0, 6] = 1e300  # (cable.A.x: finite, as the FMU lets through, but its quintic overflows)
    with pytest.raises(cc.ModelError, match=r"must be finite"):
        _steps(eng, 1, inputs, None)
    after = eng.get_state()
    assert all(np.array_equal(before[k], after[k]) for k in before if k != "model"), [
        k for k in before if k != "model" and not np.array_equal(before[k], after[k])
    ]
    Engine(model).set_state(after)  # (refused before: state.chan held a non-finite value)
    sane = np.hstack(scenario_motion(model)(H * np.arange(3)))
    out_a, e_a = _steps(eng, 3, sane, None)
    out_b, e_b = _steps(fresh, 3, sane, None)
    np.testing.assert_array_equal(out_a, out_b)
    assert e_a == e_b
