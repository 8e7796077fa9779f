"""Time domain: Newmark against the frequency domain and theory, energy ledger, state, errors and recording
(the contact geometry and law: test_contact.py)."""

import re

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.model.schema import CHANNELS, OUTPUTS
from cablecasing_core.timedomain import kernels as K
from cablecasing_core.timedomain.engine import Engine, state_from_bytes, state_to_bytes
from cablecasing_core.timedomain.scenario import scenario_motion, zero_motion


def harmonic(channel, amp, f_hz):
    col = CHANNELS.index(channel)
    w = 2 * np.pi * f_hz

    def motion(t):
        u, v, a = zero_motion(t)
        u[:, col], v[:, col], a[:, col] = amp * np.sin(w * t), amp * w * np.cos(w * t), -amp * w * w * np.sin(w * t)
        return u, v, a

    return motion


@pytest.mark.parametrize("d", ["y", "z"])
def test_harmonic_response_matches_trfam(d):
    m = cc.load_model().with_overrides({"casing.alpha": 60.0, "contact.enabled": False})
    f0, amp, dt = 63.0, 1e-5, 1e-5
    eng = Engine(m, dt=dt, contact=False, record=True, ledger=False)
    eng.advance(0.5, harmonic(f"casing.A.{d}", amp, f0))
    F = eng.history()["support_forces"][:, 6 + "xyz".index(d)]  # casing.B.F<d>
    t = dt * np.arange(1, len(F) + 1)
    last = t > 0.4  # transients decayed: alpha = 60 1/s damps every mode as e^(-alpha t / 2), e^-12 = 6e-6
    w = 2 * np.pi * f0
    X = np.column_stack([np.sin(w * t[last]), np.cos(w * t[last])])
    c = np.linalg.lstsq(X, F[last], rcond=None)[0]
    measured = c[0] + 1j * c[1]  # F = Im(measured e^{iwt})
    H = cc.trfam(m, f"casing.A.{d}", f"casing.B.{d}", [f0], "viscous")[0]
    expected = -H * (-(w**2) * amp)  # body-on-support = -reaction
    # what is left is Newmark's frequency warping: it responds as the continuous system at
    # w' = (2/dt) tan(w dt/2), 1.3e-6 above w, which the slope of H turns into 4.5e-6 (y), 1.3e-5 (z)
    # (H(w')/H(w) - 1; measured 4.1e-6, 1.2e-5); 5e-5 bounds it, and reactions without the alpha M v
    # term miss by 2.5e-4 (y), 4.8e-4 (z)
    assert abs(measured / expected - 1) < 5e-5


def test_newmark_period_elongation(straight):
    m = straight(1.0, 10, supports=("clamped", "free"))
    f1, shapes = cc.modes(m, "cable", 1)
    w1 = 2 * np.pi * f1[0]
    Om = 0.6
    dt = Om / w1
    eng = Engine(m, dt=dt, contact=False, record=True)
    s = eng.get_state()
    s["cable.U"] = 1e-3 * shapes[:, 0]
    eng.set_state(s)
    eng.advance(dt * 4000, zero_motion)
    F = eng.history()["support_forces"][:, 12 + 1]  # cable.A.Fy, proportional to the modal coordinate
    F = np.concatenate([[s["cable.U"] @ np.zeros_like(s["cable.U"])], F])
    z = np.nonzero(np.diff(np.sign(F[1:])))[0]
    # interpolated zero crossings -> period
    tz = (z + F[1:][z] / (F[1:][z] - F[1:][z + 1])) * dt
    T_num = 2 * np.mean(np.diff(tz))
    ratio = T_num / (2 * np.pi / w1)
    expected = (Om / 2) / np.arctan(Om / 2)
    assert abs(ratio / expected - 1) < 1e-4  # zero-crossing interpolation error over ~100 periods


def test_energy_conserved_without_dissipation(pair_model, kick, energy_samples):
    """Kinetic + strain + contact energy stays what the kick gave, sampled every 10 steps over 0.5 s
    (65 impacts), the samples in contact included: there the contact holds up to 10 % of the energy,
    so a contact energy that is not the integral of the contact force would show."""
    m = pair_model()
    dt = 2.5e-6
    eng = Engine(m, dt=dt, contact=True, ledger=True)
    kick(eng, 0.3)
    E, pot = energy_samples(eng, 20_000, dt * 10)
    on = pot > 0
    assert on.sum() > 100, "the kick must bring the cable into contact"  # (217 samples)
    # Newmark conserves a linear system's energy exactly; the penalty contact adds an O(dt^2) error per
    # impact, a drift over the impacts (measured: 0.39 %, 0.14 % at dt = 5, 2.5 us): 0.3 % at 2.5 us
    assert np.max(np.abs(E - 1)) < 3e-3
    # within a contact episode the energy stays what it was before it, while the contact holds a share:
    # against the last sample out of contact before it, in the samples where the contact holds > 2 %
    # (measured: 4.5e-4 at most, 1.3e-3 at 5 us); a contact energy off by a quarter (0.5 for Hertz's
    # 2/5) would move these by 0.25 x 2 % = 5e-3 or more
    before = np.maximum.accumulate(np.where(~on, np.arange(len(on)), -1))
    deep = on & (pot > 0.02) & (before >= 0)
    assert deep.sum() >= 20  # (40)
    assert np.max(np.abs(E[deep] - E[before[deep]])) < 1.5e-3


def test_ledger_closes_with_damping_and_friction(pair_model, kick):
    """A kicked arc with Rayleigh damping, the contact damper and friction on: the ledger closes
    within 1 %. Its impacts are nearly normal, so friction takes ~5e-10 J of the ~3.2e-5 J the
    contact dissipates: this weighs the damper and Rayleigh's terms, and only the sign of the
    friction's; friction's power itself is checked against closed forms in test_friction.py (the
    belt's limit cycle, mu N |v_rel|, the capstan)."""
    m = pair_model(friction=0.2, damping=50.0, alpha=20.0, beta=2e-5)
    eng = Engine(m, dt=2e-5, contact=True, ledger=True, record=True)
    kick(eng, 0.3)
    e0 = eng.energies()
    E0 = e0["kinetic"] + e0["strain"]
    eng.advance(0.5, zero_motion)
    e = eng.energies()
    # (the contact force's sign, no pull while the gap opens: test_contact_law_impact.py, the linear
    # law with its damper; the recorded normal force holds only contacts that push, so N >= 0 here
    # could not fail)
    assert e["contact_dissipation"] > 0 and e["rayleigh_dissipation"] > 0
    # the contact dissipation is defined as what balances the contact forces' work against the stored
    # contact energy, so this residual cannot see an error of the contact law or of its dissipated
    # parts: those are checked against independent solutions in test_friction.py (friction power =
    # mu N |v_rel|) and test_contact_law_impact.py (the damper's loss against solve_ivp)
    assert abs(e["residual"]) < 0.01 * E0  # the ledger closes within 1%
    # the two parts, integrated from their powers, add up to the work-based contact dissipation: on an
    # arc kicked out of its plane the normal forces do next to no work of their own (docs/time_domain.md,
    # "The normal force's work on a mesh"); what is left is the impacts' quadrature, a few per cent
    parts = e["contact_damping_dissipation"] + e["friction_dissipation"]
    assert e["friction_dissipation"] > 0 and e["contact_damping_dissipation"] > 0
    assert abs(parts / e["contact_dissipation"] - 1) < 0.05
    assert e["kinetic"] + e["strain"] < 0.5 * E0  # and most energy has been dissipated


def test_state_round_trip_is_bit_identical(pair_model, kick):
    m = pair_model(friction=0.2, damping=50.0)
    e1 = Engine(m, dt=2e-5)
    kick(e1, 0.3)
    e1.advance(0.01, zero_motion)
    s = state_from_bytes(state_to_bytes(e1.get_state()))
    e1.advance(0.01, zero_motion)
    e2 = Engine(m, dt=2e-5)
    e2.set_state(s)
    e2.advance(0.01, zero_motion)
    assert e1.outputs() == e2.outputs()


def test_state_round_trip_with_the_regularised_law_keeps_the_last_two_forces():
    """The installed specimen (regularised friction, its contacts persistent): continued from its
    saved state it equals the uninterrupted run to the bit. Its contact Newton starts from the
    extrapolation of each contact's last two forces (Pn, Pn_prev), so Pn_prev is state: a state
    without it continues differently."""
    m = cc.load_model("installed")
    motion = scenario_motion(m)
    e1 = Engine(m)
    e1.advance(0.002, motion)
    s = state_from_bytes(state_to_bytes(e1.get_state()))
    assert np.count_nonzero(s["Pn_prev"].any(axis=1)) >= 5  # contacts that persist over the saved step
    e1.advance(0.002, motion)
    runs = []
    for state in (s, dict(s, Pn_prev=np.zeros_like(s["Pn_prev"]))):
        e = Engine(m)
        e.set_state(state)
        e.advance(0.002, motion)
        runs.append(e.outputs())
    assert runs[0] == e1.outputs()
    assert runs[1] != e1.outputs()


def test_snapshot_restore_is_bit_identical_and_bad_states_change_nothing(pair_model, kick):
    """The FMU's roll-back (snapshot/restore) continues exactly like the uninterrupted run; a
    state with a wrong shape is refused before anything is written; output_values is outputs()."""
    m = pair_model(friction=0.2, damping=50.0)
    e1 = Engine(m, dt=2e-5)
    kick(e1, 0.3)
    e1.advance(0.01, zero_motion)
    snap = e1.snapshot()
    e1.advance(0.01, zero_motion)
    first = e1.outputs()
    assert first["contact.active"] > 0 or e1.ledger[4] != 0.0  # contact took part
    e1.restore(snap)
    e1.advance(0.01, zero_motion)
    assert e1.outputs() == first
    np.testing.assert_array_equal(e1.output_values(), [first[k] for k in OUTPUTS])
    before = e1.get_state()
    bad = dict(before, **{"cable.U": np.zeros(3)})
    with pytest.raises(cc.ModelError, match="cable.U"):
        e1.set_state(bad)
    after = e1.get_state()
    assert all(np.array_equal(before[k], after[k]) for k in before)


def test_contact_time_counts_every_step(pair_model, kick):
    """The highest-contact-area histogram (Fig. 22) counts dt for every step a node ends in
    contact, whether the histories are recorded or not and however the run is cut into advances
    (the FMU advances one communication step at a time). A step recomputed in sub-steps around a
    contact event (contact.event_substeps) counts the sub-steps' share instead: that is tested on
    the default model below, and the count per step here without them."""
    m = pair_model(friction=0.2, damping=50.0).with_overrides({"contact.event_substeps": 1})
    dt = 2e-5
    whole = Engine(m, dt=dt, record=True)
    kick(whole, 0.3)
    whole.advance(0.01, zero_motion)
    steps = Engine(m, dt=dt)
    kick(steps, 0.3)
    for _ in range(100):
        steps.advance(1e-4, zero_motion)
    counted = dt * np.count_nonzero(whole.history()["contact_state"] != K.OPEN, axis=0)
    assert counted.sum() > 10 * dt  # contact took part (37 node-steps)
    np.testing.assert_allclose(whole.contact_time, counted, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(steps.contact_time, counted, rtol=1e-12, atol=1e-15)
    sp = whole.history(sparse=True)  # the stored form: only the nodes in contact, each pushing
    assert (sp["normal_force"] > 0).all() and (sp["contact_state"] != K.OPEN).all()
    np.testing.assert_allclose(dt * np.bincount(sp["contact_node"], minlength=len(counted)), counted, rtol=1e-12)
    sub = Engine(m.with_overrides({"contact.event_substeps": 8}), dt=dt, record=True)
    kick(sub, 0.3)
    sub.advance(0.01, zero_motion)
    counted = dt * np.count_nonzero(sub.history()["contact_state"] != K.OPEN, axis=0)
    # a recomputed step counts its sub-steps in contact: it differs from dt per node and step at most
    assert np.all(np.abs(sub.contact_time - counted) <= dt * sub.refined_steps + 1e-15)


def test_bad_time_inputs():
    m = cc.load_model()
    with pytest.raises(cc.ModelError, match="dt"):
        Engine(m, dt=0.0)
    eng = Engine(m, dt=1e-5)
    with pytest.raises(cc.ModelError, match="h"):
        eng.advance(-1.0, zero_motion)

    def nan_motion(t):
        u, v, a = zero_motion(t)
        u[:, 2] = np.nan
        return u, v, a

    eng.advance(2e-5, scenario_motion(m))
    before = eng.get_state()
    with pytest.raises(cc.ModelError, match="casing.A.z displacement"):
        eng.advance(1e-4, nan_motion)
    after = eng.get_state()  # refused before any step: nothing half-written
    assert all(np.array_equal(before[k], after[k]) for k in before)


def test_blow_up_says_when_where_what_and_changes_nothing(pair_model):
    """A casing carried sideways (both supports, 0.5 m/s in z) past a cable clamped at rest, with a
    contact too soft to resist (linear law, 1 N/m): at the clamped ends both axes are prescribed,
    so the penetration there is exactly 0.5 t - gap, and it passes the cable radius at
    t = (gap + r) / 0.5 m/s = 4 ms, within the step that follows. A support acceleration of
    1e306 m/s2 (finite, so accepted) overflows the support forces. Either stops with an error
    that names the time, the place and the value, and leaves the engine as before the call."""
    m = pair_model().with_overrides({"contact.law": "linear", "contact.stiffness": 1.0})
    dt = 2e-5

    def carried(t):
        u, v, a = zero_motion(t)
        for ch in ("casing.A.z", "casing.B.z"):
            u[:, CHANNELS.index(ch)], v[:, CHANNELS.index(ch)] = 0.5 * t, 0.5
        return u, v, a

    def huge(t):
        u, v, a = zero_motion(t)
        a[:, CHANNELS.index("casing.A.y")] = 1e306
        return u, v, a

    for motion, where in ((carried, r"cable node (\d+)"), (huge, "the support forces")):
        eng = Engine(m, dt=dt, record=True)
        eng.advance(10 * dt, zero_motion)
        eng.CHUNK = 64  # the blow-up falls in a later chunk of the call
        before, h0 = eng.get_state(), eng.history()
        with pytest.raises(cc.SimulationError, match=where) as err:
            eng.advance(0.01, motion)
        after, h1 = eng.get_state(), eng.history()
        assert all(np.array_equal(before[k], after[k]) for k in before)  # rolled back
        assert all(np.array_equal(h0[k], h1[k]) for k in h0)
        msg = str(err.value)
        t_fail = float(msg.split("t = ")[1].split(" s")[0])
        if motion is carried:
            t_exact = (eng.gap + eng.r_cable) / 0.5  # the casing is at 0.5 t (m)
            assert t_exact <= t_fail <= t_exact + dt * (1 + 1e-9)
            assert int(re.search(where, msg).group(1)) in (0, len(eng.Xc) - 1)  # a clamped end
            assert "exceeds the cable radius" in msg
            pen = float(msg.split("penetration ")[1].split(" m")[0])
            assert eng.r_cable < pen <= eng.r_cable + 0.5 * dt * 1.01
        else:
            assert "no longer finite" in msg and 10 * dt < t_fail <= 12 * dt  # first or second step
        eng.advance(dt, zero_motion)  # and it can go on from where it was
        assert eng.time == pytest.approx(11 * dt)


def test_advance_in_chunks_is_invariant_and_bad_late_input_changes_nothing(pair_model, kick):
    """advance evaluates the motion in chunks of Engine.CHUNK steps: the result does not depend on
    the chunk size (the motion is a function of t), and a non-finite motion in a later chunk leaves
    state and recorded history as they were before the call (nothing half-written)."""
    m = pair_model(friction=0.2, damping=50.0)
    runs = []
    for chunk in (10**9, 64):
        eng = Engine(m, dt=2e-5, record=True)
        eng.CHUNK = chunk
        kick(eng, 0.3)
        eng.advance(0.01, zero_motion)  # 500 steps: one chunk, or 8
        runs.append(eng)
    one, cut = runs
    assert one.outputs() == cut.outputs() and one.time == cut.time
    h1, h2 = one.history(), cut.history()
    assert all(np.array_equal(h1[k], h2[k]) for k in h1)
    assert np.count_nonzero(h1["contact_state"]) > 0  # contact took part

    t_bad = cut.time + 0.005

    def late_nan(t):
        u, v, a = zero_motion(t)
        a[t > t_bad, 1] = np.inf  # from step 250 on: the 4th chunk of 64
        return u, v, a

    before = cut.get_state()
    with pytest.raises(cc.ModelError, match="casing.A.y acceleration"):
        cut.advance(0.01, late_nan)
    after = cut.get_state()
    assert all(np.array_equal(before[k], after[k]) for k in before)
    assert cut.time == one.time and all(np.array_equal(h2[k], cut.history()[k]) for k in h2)
    t_end = cut.time + 64 * 2e-5 + 1e-5  # one full chunk, then the shorter last substep

    def bad_last_substep(t):
        u, v, a = zero_motion(t)
        a[t > t_end - 5e-6, 1] = np.inf
        return u, v, a

    with pytest.raises(cc.ModelError, match="casing.A.y acceleration"):
        cut.advance(64 * 2e-5 + 1e-5, bad_last_substep)
    after = cut.get_state()
    assert all(np.array_equal(before[k], after[k]) for k in before)


def test_ledger_closes_under_support_excitation():
    """Default scenario (random casing motion + 50 Hz cable axial), contact off: the supports' work
    equals the stored energy plus the Rayleigh dissipation (Newmark's discrete energy identity)."""
    m = cc.load_model()
    res = cc.simulate(m, duration=0.05, contact=False)
    e = res.energies
    # prescribed support kinematics are exact, not Newmark-integrated: O(dt^2) mismatch, ~1e-5 here
    assert abs(e["residual"]) < 1e-3 * e["support_work"]
    assert e["support_work"] > 0 and e["rayleigh_dissipation"] > 0


def test_every_contact_step_converges_in_the_default_scenario():
    """The contact equations are solved in every step of the paper's experiment (0.1 s, about 70 %
    of the steps in contact). Before the 'touch' reading of the damper's switch at g = 0, 3-5 % of
    the steps had no solution and ended with an arbitrary force."""
    from cablecasing_core.timedomain.scenario import scenario_motion

    m = cc.load_model()
    eng = Engine(m, dt=1e-5, ledger=False)
    eng.advance(0.1, scenario_motion(m, dt=1e-5))
    its, passes, failed = eng.solver_counts
    assert passes > 1000  # contact was solved in many steps
    assert failed == 0
    assert its / passes < 5  # Newton converges in a few iterations per pass


def test_contact_episodes_are_the_runs_of_contact_per_node():
    state = np.array([[0, 1, 0], [2, 1, 0], [0, 0, 1], [1, 0, 1]])  # steps x nodes
    node, start, length = cc.contact_episodes(state)
    # node 0: steps 1 and 3; node 1: steps 0-1; node 2: steps 2-3 (still on at the end)
    assert node.tolist() == [0, 0, 1, 2] and start.tolist() == [1, 3, 0, 2] and length.tolist() == [1, 1, 2, 2]
    assert all(len(x) == 0 for x in cc.contact_episodes(np.zeros((5, 4))))
    with pytest.raises(cc.ModelError, match="contact_state"):
        cc.contact_episodes(np.zeros(5))


@pytest.mark.slow  # steps down to 1e-8 s
def test_rattle_after_lift_off_is_the_models_motion_and_converges():
    """With the contact damper on, cable node 8 of the reference record (seed 1) lets go of the wall
    at t = 0.06049 s + 47 µs and then leaves and touches again in ever shorter bounces
    (docs/time_domain.md, Known limits; benchmarks/rattle.py). At dt = 1e-5 these show as contact
    episodes of one or two steps, like chatter of the time step; they are not: continued from one
    state at dt = 2.0e-8 and 9.8e-9 s, the bounces last hundreds of steps and land at the same times."""
    m = cc.load_model()
    motion = scenario_motion(m, dt=1e-5)
    eng = Engine(m, dt=1e-5, ledger=False)
    eng.advance(0.06049, motion)
    state = eng.get_state()
    assert state["cstate"][8] > 0  # the scene: node 8 pressed onto the wall at the start

    def bounces(dt):
        e = Engine(m, dt=dt, ledger=False, record=True)
        e.set_state(state)
        e.advance(1.2e-4, motion)
        node, start, length = cc.contact_episodes(e.history()["contact_state"])
        mine = node == 8
        return start[mine] * dt, (start[mine] + length[mine]) * dt, length[mine]

    (s1, e1, n1), (s2, e2, n2) = bounces(1e-5 / 2**9), bounces(1e-5 / 2**10)
    assert len(s1) >= 5 and len(s2) >= 5  # the lift-off and at least four bounces
    assert n1[1] > 100 and n2[1] > 100  # the first bounce: hundreds of steps, not one or two
    # an event is located to one step (0.02 µs) and each bounce inherits the timing error of the
    # ones before; 0.25 µs (3 % of the first bounce, 6 % of the second) bounds the lift-off and the
    # first two bounces (0.05 µs measured), and a sequence set by the time step would move by whole
    # bounces (µs) when dt halves
    np.testing.assert_allclose(s1[:3], s2[:3], atol=0.25e-6)
    np.testing.assert_allclose(e1[:3], e2[:3], atol=0.25e-6)
    # the time in contact over the window: within 1 %
    assert abs((e1 - s1).sum() / (e2 - s2).sum() - 1) < 0.01


_RECORD = """
import sys, numpy as np, cablecasing_core as cc
np.save(sys.argv[1], cc.simulate(cc.load_model(), duration=0.15).support_forces)
"""


@pytest.mark.slow  # runs in fresh processes
def test_record_does_not_depend_on_the_blas_thread_count(tmp_path):
    # The contact response is chaotic: a rounding difference in the set-up grows to newtons within
    # 0.15 s (1.7 N when the compliance came from threaded LAPACK). A record must be the same in a
    # dask worker or an FMU host that limits BLAS to one thread as in a process that does not.
    import os
    import subprocess
    import sys

    out = []
    for n in ("1", "2"):
        env = {**os.environ, "OMP_NUM_THREADS": n, "OPENBLAS_NUM_THREADS": n, "MKL_NUM_THREADS": n}
        path = tmp_path / f"threads{n}.npy"
        subprocess.run([sys.executable, "-c", _RECORD, str(path)], env=env, check=True, timeout=300)
        out.append(np.load(path))
    assert np.array_equal(out[0], out[1])


def test_whole_steps_take_a_clocks_rounding_as_no_time():
    from cablecasing_core.timedomain.engine import whole_steps

    dt = 1e-5
    t = 1000.0 + 1e-4 * np.arange(50)  # a master's clock late in a run: its steps differ from 1e-4 by ulp(1000)
    assert {whole_steps(h, dt) for h in np.diff(t)} == {(10, 0.0)}
    assert whole_steps(1e-15, dt) == (0, 0.0) and whole_steps(3.5e-5, dt)[0] == 3
    assert whole_steps(3.5e-5, dt)[1] == pytest.approx(5e-6, rel=1e-9)


@pytest.mark.parametrize("rest", [2e-6, 1e-5])
def test_a_rest_too_short_for_newmark_goes_into_the_last_step(rest):
    """A call of 10 dt + rest dt, repeated: its rest as a step of its own would put the digits
    Newmark's update a = 4 (u - u_old) / h**2 - ... cancels, (dt / h)**2 = 1e10 times a rounding
    error, into the accelerations (measured as such: 0.53 and 0.012 of the support force's RMS off,
    against 0.0031 for whole steps); taken by the last step (dt + rest) it errs as a whole step does.
    Both against an engine of dt / 4 over the same calls: the error within twice that of the run
    of whole calls (10 dt) at 60 Hz."""
    m = cc.load_model().with_overrides({"contact.enabled": False})
    motion = harmonic("casing.A.y", 1e-5, 60.0)
    dt = 1e-5

    def run(h, step):
        eng = Engine(m, dt=step, contact=False, ledger=False)
        out = []
        for _ in range(100):
            eng.advance(h, motion)
            out.append(eng.outputs()["casing.B.Fy"])
        return np.array(out), eng.time

    errs = []
    for h in (10 * dt, 10 * dt + rest * dt):
        coarse, t_end = run(h, dt)
        fine, _ = run(h, dt / 4)
        assert t_end == pytest.approx(100 * h, rel=1e-12)  # the rests were integrated, not dropped
        errs.append(np.max(np.abs(coarse - fine)) / np.sqrt(np.mean(fine**2)))
    assert errs[1] < 2 * errs[0] + 1e-9, errs


def test_a_step_shorter_than_newmark_takes_alone_is_refused_and_a_clocks_rounding_is_no_time():
    m = cc.load_model().with_overrides({"contact.enabled": False})
    eng = Engine(m, contact=False, ledger=False)
    motion = harmonic("casing.A.y", 1e-5, 60.0)
    eng.advance(1e-4, motion)
    before = state_to_bytes(eng.get_state())
    with pytest.raises(cc.ModelError, match=r"h = 1e-09.*at least 0.001 of the time step dt = 1e-05 s"):
        eng.advance(1e-9, motion)
    eng.advance(1e-12, motion)  # within 1e-6 dt: the rounding of a clock
    assert state_to_bytes(eng.get_state()) == before


@pytest.mark.parametrize("share", [5e-3, 1e-3])
def test_a_lone_step_down_to_1e_3_dt_is_one_newmark_step_of_it(share):
    """A call of h < 1e-2 dt (a master's last step clamped to its stop time) is one step of h down to
    1e-3 dt: on the installed specimen (its static state in the displacements whose differences the
    update cancels) under a 300 Hz drive, the support forces at t + h and over the next 100 steps of
    dt are those of the unbroken run interpolated linearly to t + h (plus k dt) within 1e-3 of their
    RMS: the interpolation's own error is 1e-4, the lost digits add up to 3.6e-4 at 1e-3 dt and make
    9.4e-3 at 1e-4 dt (measured), which the bound separates."""
    dt = 1e-5
    eng = Engine(cc.load_model("installed"), dt=dt, ledger=False)
    motion = harmonic("casing.B.y", 2e-5, 300.0)
    forces = [j for j, n in enumerate(eng.output_names) if n[:-1].endswith((".F", ".A.F", ".B.F"))]
    eng.advance(200 * dt, motion)
    saved = eng.get_state()
    whole = []
    for _ in range(101):
        whole.append(eng.output_values()[forces])
        eng.advance(dt, motion)
    whole = np.array(whole)
    rms = np.sqrt(np.mean((whole - whole.mean(axis=0)) ** 2, axis=0))  # (a third of the drive's period)
    eng.set_state(saved)
    eng.advance(share * dt, motion)
    assert eng.time == pytest.approx((200 + share) * dt, rel=1e-12)
    short = []
    for _ in range(100):
        short.append(eng.output_values()[forces])
        eng.advance(dt, motion)
    expected = whole[:-1] + share * (whole[1:] - whole[:-1])
    assert np.max(np.abs(np.array(short) - expected) / rms) < 1e-3


def test_a_run_with_a_short_rest_is_the_same_in_pieces():
    """A duration of whole pieces of the progress bar and 1e-3 dt: the bar's pieces leave the rest to
    the last piece (alone it would be a step too short for Newmark, refused), so the run equals the
    one call's to the bit."""
    from cablecasing_core.timedomain.simulation import PROGRESS_STEPS

    m = cc.load_model().with_overrides({"contact.enabled": False})
    d = PROGRESS_STEPS * 1e-5 + 1e-3 * 1e-5
    whole, pieces = (cc.simulate(m, duration=d, progress=p) for p in (False, True))
    np.testing.assert_array_equal(whole.support_forces, pieces.support_forces)
    assert whole.time[-1] == pytest.approx(d, rel=1e-12)  # the last step, dt + rest, ends at d


def test_a_run_split_into_calls_stays_on_the_grid_of_one_call():
    """The default scenario (contact, chaos) over 0.6 s in calls of 37 steps equals one call to the
    bit: each call's end time is put back on the grid k dt its steps' sum lies within 1e-6 dt of
    (the sums had drifted, and the record's motion left its grid, from step 49752 on)."""
    from cablecasing_core.timedomain.scenario import scenario_motion

    m = cc.load_model()
    one, split = Engine(m, ledger=False), Engine(m, ledger=False)
    motion = scenario_motion(m)
    one.advance(0.6, motion)
    for _ in range(int(0.6 / (37 * 1e-5))):
        split.advance(37 * 1e-5, motion)
    split.advance(0.6 - split.time, motion)
    assert split.time == one.time == 60000 * 1e-5
    np.testing.assert_array_equal(split.output_values(), one.output_values())


def test_what_the_engine_takes_from_a_caller_is_checked():
    """An output buffer the compiled writer would overrun (it crashed the process), a motion that
    is not three real arrays, a negative friction coefficient (it created energy) and a residual
    without the ledger's Rayleigh dissipation: each a ModelError naming it, or NaN."""
    m = cc.load_model().with_overrides({"contact.enabled": False})
    eng = Engine(m, ledger=False)
    motion = harmonic("casing.A.y", 1e-5, 60.0)
    for bad in (np.zeros(5), np.zeros(len(OUTPUTS), dtype=np.int64), np.zeros((len(OUTPUTS), 2))[:, 0]):
        with pytest.raises(cc.ModelError, match=r"^out = .*at least \d+ values"):
            eng.output_values(bad)
    for wrong in (lambda t: motion(t)[:2], lambda t: None, lambda t: tuple(x + 0j for x in motion(t))):
        with pytest.raises(cc.ModelError, match=r"^motion = 'function': must be a callable"):
            eng.advance(1e-4, wrong)
    assert eng.time == 0.0
    eng.mu = -0.5
    with pytest.raises(cc.ModelError, match=r"^mu = -0.5: must be a finite number >= 0"):
        eng.advance(1e-4, motion)
    eng.mu = 0.15
    eng.advance(1e-4, motion)
    assert np.isnan(eng.energies()["residual"]) and np.isnan(eng.energies()["rayleigh_dissipation"])


def test_a_state_that_is_not_one_is_refused_and_changes_nothing(pair_model, kick):
    """set_state and restore check before they write: non-finite displacements, a NaN or negative
    time, a contact state outside open/stick/slip (1.7 was cast to 1), a casing element past the
    last, something that is not a state or a snapshot: a ModelError naming it, the engine as it was."""
    eng = Engine(pair_model(friction=0.2, damping=50.0), dt=2e-5)
    kick(eng, 0.3)
    eng.advance(0.005, zero_motion)
    good, before = eng.get_state(), state_to_bytes(eng.get_state())
    bad_cases = [
        ("casing.U", lambda s: s["casing.U"].__setitem__(3, np.nan)),
        ("time", lambda s: s.__setitem__("time", np.array([np.nan]))),
        ("time", lambda s: s.__setitem__("time", np.array([-1.0]))),
        ("cstate", lambda s: s.__setitem__("cstate", s["cstate"] + 1.7)),
        ("cstate", lambda s: s.__setitem__("cstate", s["cstate"] + 7)),
        ("celem", lambda s: s.__setitem__("celem", s["celem"] + 10_000)),
    ]
    for key, spoil in bad_cases:
        state = {k: np.array(v, copy=True) for k, v in good.items()}
        spoil(state)
        with pytest.raises(cc.ModelError, match=rf"^state\.{key} = "):
            eng.set_state(state)
    with pytest.raises(cc.ModelError, match=r"^state = 'dict': must be a state of Engine.get_state"):
        eng.set_state({"time": "soon", **{k: v for k, v in good.items() if k != "time"}})
    with pytest.raises(cc.ModelError, match=r"^snap = "):
        eng.restore([0.0, np.zeros(3), np.zeros(3)])
    assert state_to_bytes(eng.get_state()) == before


def test_a_run_step_outside_the_plausible_range_warns_as_in_a_model_file():
    data = cc.load_model().data
    m = cc.model_from_dict({**data, "scenario": {**data["scenario"], "excitation": {}}})
    from cablecasing_core.errors import ModelWarning

    with pytest.warns(ModelWarning, match=r"dt = 0.002 s is outside the plausible 1e-08 to 0.001 s"):
        cc.simulate(m, duration=0.01, dt=2e-3)


def test_a_state_continues_only_the_structure_it_was_taken_from(pair_model, kick):
    """A state of the same shapes from another model (another casing modulus, same mesh) was taken
    silently, and the run went on with displacements in equilibrium with other stiffnesses. It is
    refused, naming the structures' fingerprints; another scenario of the same structure is
    accepted (a state may be continued under a new drive), and so is an older state without one."""
    m = pair_model(friction=0.2, damping=50.0)
    e1 = Engine(m, dt=2e-5)
    kick(e1, 0.3)
    e1.advance(0.002, zero_motion)
    s = state_from_bytes(state_to_bytes(e1.get_state()))
    other = Engine(m.with_overrides({"casing.E": 1.1 * m.bodies["casing"].E_ref}), dt=2e-5)
    before = other.get_state()
    with pytest.raises(cc.ModelError) as err:
        other.set_state(s)
    assert err.value.key == "state.model" and "another model's structure" in str(err.value)
    assert all(np.array_equal(before[k], v) for k, v in other.get_state().items())  # (nothing written)
    redriven = Engine(m.with_overrides({"scenario.seed": 7}), dt=2e-5)
    redriven.set_state(s)
    redriven.set_state({k: v for k, v in s.items() if k != "model"})
    assert redriven.time == e1.time


def test_the_normal_forces_own_work_falls_as_the_mesh_is_refined():
    """A cable kicked laterally (0.3 m/s, a half sine) inside the default route, without friction,
    contact damping or Rayleigh damping: the only loss or gain is the normal force's own work
    (``contact_normal_dissipation``), since the force -N n at the normal plane's cut is not the
    gradient of V(g) on a curved casing (docs/time_domain.md, "The normal force's work on a mesh").
    The kinetic + strain + contact energy changes by exactly that work (the ledger), and it falls as
    the elements shorten (measured -3.7e-3 of the kick's energy at 35 elements, -4.2e-4 at 140)."""
    off = {"contact.friction": 0.0, "contact.damping": 0.0}
    off.update({f"{b}.{k}": 0.0 for b in ("casing", "cable") for k in ("alpha", "beta")})
    made = {}
    for n in (35, 140):
        eng = Engine(cc.load_model("default").with_overrides({**off, "geometry.n_elements": n}), dt=6.25e-7)
        s = eng.get_state()
        nodes = len(s["cable.V"]) // 6
        s["cable.V"][2::6] = 0.3 * np.sin(np.pi * np.arange(nodes) / (nodes - 1))
        eng.set_state(s)
        e0 = eng.energies()
        E0 = e0["kinetic"] + e0["strain"] + e0["contact_potential"]
        eng.advance(0.01, zero_motion)
        e = eng.energies()
        assert abs(e["contact_damping_dissipation"]) + abs(e["friction_dissipation"]) < 1e-12 * E0  # (round-off)
        stored = e["kinetic"] + e["strain"] + e["contact_potential"]
        # (the ledger's residual, below 1e-8 of E0 here: the trapezoidal work of the contact forces)
        assert stored - E0 == pytest.approx(-e["contact_normal_dissipation"], abs=1e-8 * E0)
        made[n] = -e["contact_normal_dissipation"] / E0
    assert made[35] > 1e-3  # (a test that could not fail otherwise: the work the mesh makes is there)
    # at least first order in the element length: a mesh 4 times finer, a quarter (measured 0.11)
    assert abs(made[140]) < 0.25 * made[35]
