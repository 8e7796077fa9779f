"""simulate with a motion of its own records the inputs it moves in one evaluation of that motion:
once at t = 0 and once at each step's end beside the engine's own, its values those of the motion
bit for bit, a channel that starts moving in a later piece of the record as well as one from the
start; and a motion of the 12 fixed channels runs on a model with an excited clip."""

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.model.schema import CHANNELS
from cablecasing_core.timedomain import engine as engine_module
from cablecasing_core.timedomain import simulation

DT = 1e-5  # s, the default model's time step
STEPS = 24  # the run's steps: six pieces of four rows below
W, A = 2 * np.pi * 300.0, 1e-6  # rad/s, m: a small harmonic of casing.A.z


def own_motion(late_from):
    """A motion of the 12 fixed channels: casing.A.z harmonic from t = 0; cable.A.ax a constant
    0.5 m/s2 for t > ``late_from`` (s), -0.0 before it; cable.B.vx -0.0 throughout (it moves
    nothing). Returns the motion and the names of what it moves, kind-major."""
    z, late, still = CHANNELS.index("casing.A.z"), CHANNELS.index("cable.A.x"), CHANNELS.index("cable.B.x")

    def motion(t):
        t = np.asarray(t, dtype=float)
        u, v, a = (np.zeros((t.size, len(CHANNELS))) for _ in range(3))
        u[:, z], v[:, z], a[:, z] = A * np.sin(W * t), A * W * np.cos(W * t), -A * W * W * np.sin(W * t)
        a[:, late] = np.where(t > late_from, 0.5, -0.0)
        v[:, still] = -0.0
        return u, v, a

    moved = ["casing.A.z", "cable.A.x", "casing.A.vz", "cable.A.vx", "casing.A.az", "cable.A.ax"]
    return motion, moved


@pytest.fixture(scope="module")
def model():
    return cc.load_model()


def test_the_motion_is_evaluated_once_beside_the_engine(model, monkeypatch):
    motion, _ = own_motion(late_from=10 * DT)
    rows = {"outside": 0}
    inside = []
    advance = engine_module.Engine.advance

    def counted_advance(self, h, m):  # (what the engine evaluates is its own: not counted)
        inside.append(True)
        try:
            return advance(self, h, m)
        finally:
            inside.pop()

    def counted(t):
        if not inside:
            rows["outside"] += np.size(t)
        return motion(t)

    monkeypatch.setattr(engine_module.Engine, "advance", counted_advance)
    res = cc.simulate(model, duration=STEPS * DT, motion=counted)
    # once at t = 0 (the record's first row) and once at each of the run's step ends: the channels
    # moved are learned from the same evaluation that records them
    assert len(res.time) == STEPS
    assert rows["outside"] == STEPS + 1


def test_a_channel_that_starts_moving_in_a_later_piece_is_recorded_whole(model, monkeypatch):
    monkeypatch.setattr(simulation, "INPUT_PIECE", 4)  # (cable.A.ax starts moving in the fourth piece)
    late_from = 14.5 * DT
    motion, moved = own_motion(late_from)
    res = cc.simulate(model, duration=STEPS * DT, motion=motion)
    assert list(res.inputs) == moved  # (cable.B.vx at -0.0 throughout moves nothing)
    t = res.time
    expected = {
        "casing.A.z": A * np.sin(W * t),
        "casing.A.vz": A * W * np.cos(W * t),
        "casing.A.az": -A * W * W * np.sin(W * t),
        "cable.A.x": np.zeros(STEPS),
        "cable.A.vx": np.zeros(STEPS),
        "cable.A.ax": np.where(t > late_from, 0.5, -0.0),
    }
    for name, values in expected.items():
        # the motion's own values, bit for bit: the same expression at the same times, -0.0 kept
        np.testing.assert_array_equal(res.inputs[name], values, err_msg=name)
        np.testing.assert_array_equal(np.signbit(res.inputs[name]), np.signbit(values), err_msg=name)
    assert np.count_nonzero(res.inputs["cable.A.ax"]) == STEPS - 14  # (steps 15..24 end after late_from)
    at_rest = {"casing.A.z": 0.0, "casing.A.vz": A * W, "casing.A.az": -0.0, "cable.A.x": 0.0, "cable.A.vx": 0.0}
    assert res.initial_inputs == {**at_rest, "cable.A.ax": -0.0}  # (t = 0: sin 0, cos 0)
    rec = res.records()
    np.testing.assert_array_equal(rec.columns["cable.A.ax"], np.concatenate([[-0.0], expected["cable.A.ax"]]))


def test_a_motion_of_the_twelve_fixed_channels_runs_on_a_model_with_an_excited_clip(clipped_specimen):
    # the engine takes it with the clip's support at rest; the record did not (the inputs of 15
    # channels read from a motion of 12: a ValueError after the run)
    motion, moved = own_motion(late_from=0.0)
    res = cc.simulate(clipped_specimen, duration=8 * DT, motion=motion)
    assert list(res.inputs) == moved  # (dash.y, the clip's channel, at rest: not driven)
    np.testing.assert_array_equal(res.inputs["casing.A.az"], -A * W * W * np.sin(W * res.time))
