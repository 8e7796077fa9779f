"""Input reconstruction of the FMU (cablecasing_core.timedomain.support_motion) against exact polynomials and sines."""

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.timedomain.support_motion import QuinticStep, SupportReconstruction, taylor_target


def roundoff(u, v, a, h, d):
    """Round-off bound of the power-form evaluation for the d-th derivative: a thousand ulps of
    the step's displacement scale |u| + h|v| + h^2|a|, divided by h^d (m, m/s, m/s2)."""
    scale = np.max(np.abs(u)) + h * np.max(np.abs(v)) + h * h * np.max(np.abs(a))
    return 1e3 * np.finfo(float).eps * scale / h**d


def hermite_basis_maxima(d):
    """max over s in [0, 1] of |d-th s-derivative| of the six quintic Hermite basis functions
    (value, slope, curvature at s = 0, then at s = 1), built independently of the module by solving
    the 6x6 end-condition system."""
    rows = []
    for s0 in (0.0, 1.0):
        for k in range(3):
            rows.append([float(np.prod(range(j - k + 1, j + 1))) * s0 ** (j - k) if j >= k else 0.0 for j in range(6)])
    coef = np.linalg.solve(np.array(rows), np.eye(6))  # column i: power coefficients of basis i
    s = np.linspace(0, 1, 2001)
    return np.array(
        [
            np.max(np.abs(np.polynomial.Polynomial(coef[:, i]).deriv(d)(s)))
            if d
            else np.max(np.abs(np.polynomial.Polynomial(coef[:, i])(s)))
            for i in range(6)
        ]
    )


def test_quintic_matches_end_conditions_and_reproduces_quintics():
    rng = np.random.default_rng(3)
    t0, h = 0.37, 2.5e-4
    # a quintic in (t - t0) whose six terms are of similar size (1e-4 m) over the step
    p = np.polynomial.Polynomial(1e-4 * rng.normal(size=6) / h ** np.arange(6))
    u, v, a = (lambda t, q=q: q(t - t0) for q in (p, p.deriv(1), p.deriv(2)))
    ones = np.ones(2)
    step = QuinticStep(
        t0, h, (u(t0) * ones, v(t0) * ones, a(t0) * ones), (u(t0 + h) * ones, v(t0 + h) * ones, a(t0 + h) * ones)
    )
    t = t0 + h * np.linspace(0, 1, 11)
    got = step(t)
    assert all(g.shape == (11, 2) for g in got)
    # a quintic is its own quintic Hermite interpolant: equal up to round-off
    for d, ref in enumerate((u, v, a)):
        np.testing.assert_allclose(got[d][:, 1], ref(t), rtol=0, atol=roundoff(u(t), v(t), a(t), h, d))


def _remembered(rec, a_prev, t_prev):
    """Set the reconstruction's memory of the previous communication point (its acceleration
    inputs a_prev, m/s2, at t_prev, s), as if it had taken a step from there."""
    rec.state[3] = a_prev
    rec.state[4] = t_prev


@pytest.mark.parametrize("degree", [2, 3])
def test_reconstruction_is_exact_for_cubic_inputs(degree):
    # Taylor to third order with the jerk from the last two acceleration inputs is exact for a
    # cubic (its acceleration is linear), and the quintic then reproduces it
    p = np.polynomial.Polynomial([2e-4, -3e-2, 40.0, 9e4][: degree + 1])
    u, v, a = p, p.deriv(1), p.deriv(2)
    h = 1e-4
    rec = SupportReconstruction(1)
    rec.state[:3] = [[u(0.0)], [v(0.0)], [a(0.0)]]
    _remembered(rec, [a(-h)], -h)
    for k in range(20):
        t0 = k * h
        m = rec.motion(t0, h, [u(t0)], [v(t0)], [a(t0)])
        t = t0 + h * np.linspace(0.1, 1, 10)
        for d, (got, ref) in enumerate(zip(m(t), (u, v, a))):
            np.testing.assert_allclose(got[:, 0], ref(t), rtol=0, atol=roundoff(u(t), v(t), a(t), h, d))
        rec.accept(m)


def test_from_rest_a_quadratic_is_exact_at_once_and_a_cubic_from_the_third_step():
    """Without a previous input the first target has no jerk (Taylor to second order): a
    quadratic is still exact; a cubic's first target misses j h^3/6, which the second step starts
    from, and from the third step on the steps start and end on the cubic."""
    h = 1e-4
    for degree, first_exact in ((2, 0), (3, 2)):
        p = np.polynomial.Polynomial([2e-4, -3e-2, 40.0, 9e4][: degree + 1])
        u, v, a = p, p.deriv(1), p.deriv(2)
        rec = SupportReconstruction(1)
        rec.state[:3] = [[u(0.0)], [v(0.0)], [a(0.0)]]
        for k in range(6):
            t0 = k * h
            m = rec.motion(t0, h, [u(t0)], [v(t0)], [a(t0)])
            t = t0 + h * np.linspace(0.1, 1, 10)
            err = np.max(np.abs(m(t)[0][:, 0] - u(t)))
            tol = roundoff(u(t), v(t), a(t), h, 0)
            assert (err <= tol) == (k >= first_exact), (degree, k, err)
            rec.accept(m)


def test_reconstruction_is_continuous_and_starts_from_the_support_state():
    rng = np.random.default_rng(0)
    rec = SupportReconstruction(12)
    h = 1e-4
    a_prev = None
    for k in range(5):
        u, v, a = rng.normal(size=(3, 12)) * [[1e-3], [1e-1], [10.0]]  # arbitrary, even inconsistent inputs
        m = rec.motion(k * h, h, u, v, a)
        # the end target written out here (taylor_target calls the kernel under test): the jerk is
        # the backward difference of the acceleration inputs, none at the first step
        j = np.zeros(12) if a_prev is None else (a - a_prev) / h
        target = (u + v * h + 0.5 * h * h * a + h**3 / 6 * j, v + a * h + 0.5 * h * h * j, a + j * h)
        for when, ref in ((k * h, tuple(rec.state[:3])), ((k + 1) * h, target)):
            got = m(np.array([when]))
            for d in range(3):
                np.testing.assert_allclose(got[d][0], ref[d], rtol=0, atol=roundoff(*ref, h, d))
        rec.accept(m)
        np.testing.assert_array_equal(rec.state[3], a)  # the memory of this step's inputs
        assert np.all(rec.state[4] == k * h)
        a_prev = a


def test_a_short_step_does_not_magnify_the_next_steps_extrapolation():
    """A master that shortens one step (1e-7 s) to meet an event, the acceleration input jumping
    from 0 to 1 m/s2 there: the next step of 1e-4 s takes the jerk over its own length, so its
    target acceleration is a + (a - a_prev) = 2 m/s2, as with equal steps, not a + 1000 (a - a_prev)
    (the backward difference over 1e-7 s carried over 1e-4 s). Over equal or shorter steps the
    difference is the plain backward one (the cubic tests above)."""
    rec = SupportReconstruction(1)
    t = 0.0
    for h, a in ((1e-4, 0.0), (1e-4, 0.0), (1e-7, 0.0), (1e-4, 1.0)):
        m = rec.motion(t, h, [0.0], [0.0], [a])
        rec.accept(m)
        t += h
    assert rec.state[2, 0] == pytest.approx(2.0, rel=1e-12)
    # and a step shorter than the last keeps the backward difference over the last interval
    m = rec.motion(t, 1e-5, [0.0], [0.0], [1.5])
    assert m.end_state()[2][0] == pytest.approx(1.5 + (1.5 - 1.0) / 1e-4 * 1e-5, rel=1e-12)


def test_reset_forgets_the_inputs():
    rec = SupportReconstruction(2)
    rec.accept(rec.motion(0.0, 1e-4, [1e-3, 0.0], [0.1, 0.0], [5.0, 1.0]))
    rec.reset()
    assert np.all(rec.state[:4] == 0.0) and np.all(np.isnan(rec.state[4]))
    # so the next target has no jerk: its acceleration is the input's
    m = rec.motion(1e-4, 1e-4, [0.0, 0.0], [0.0, 0.0], [2.0, 0.0])
    np.testing.assert_array_equal(m.end_state()[2], [2.0, 0.0])


def test_a_state_of_another_shape_is_refused_before_the_kernel_reads_it():
    rec = SupportReconstruction(1)
    rec.state = np.zeros((3, 1))  # (the layout without the memory of the inputs)
    with pytest.raises(ValueError, match=r"state of shape \(3, 1\).*\(5, 1\)"):
        rec.motion(0.0, 1e-4, [0.0], [0.0], [0.0])


@pytest.mark.parametrize("f_hz", [50.0, 400.0, 800.0])
def test_sine_error_is_bounded_by_the_taylor_remainders(f_hz):
    """u = A sin(w t), x = w h. The jerk's backward difference over h misses the third derivative
    by at most |u''''| h / 2 = A w^4 h / 2, so the nodal data carry, against the exact values, at
    most d0 = A x^4 (1/24 + 1/12) = A x^4 / 8 (m), d1 = A w x^3 (1/6 + 1/4) = 5/12 A w x^3 (m/s)
    and d2 = A w^2 x^2 (1/2 + 1/2) (m/s2) (the Taylor remainder plus the jerk's error times h^3/6,
    h^2/2, h) at both ends of a step; inside, the error is at most these times the maxima of the
    Hermite basis functions, plus the interpolation error of exact data, O(x^6), which the 1 %
    margin covers. Nothing accumulates over steps."""
    A, h, w = 1e-4, 1e-4, 2 * np.pi * f_hz
    exact = (lambda t: A * np.sin(w * t), lambda t: A * w * np.cos(w * t), lambda t: -A * w * w * np.sin(w * t))
    rec = SupportReconstruction(1)
    rec.state[:3] = [[e(0.0)] for e in exact]
    _remembered(rec, [exact[2](-h)], -h)
    err = np.zeros(3)
    for k in range(int(round(3 / (f_hz * h)))):  # three periods
        t0 = k * h
        m = rec.motion(t0, h, *([e(t0)] for e in exact))
        t = t0 + h * np.linspace(0, 1, 41)
        for i, (got, e) in enumerate(zip(m(t), exact)):
            err[i] = max(err[i], np.max(np.abs(got[:, 0] - e(t))))
        rec.accept(m)
    x = w * h
    delta = np.array([A * x**4 / 8, 5 / 12 * A * w * x**3, A * w * w * x**2])
    for d in range(3):
        L = hermite_basis_maxima(d)  # order: u0, h v0, h^2 a0, u1, h v1, h^2 a1
        weight = np.array([1.0, h, h * h]) / h**d  # data error j enters the s-basis scaled by h^j
        bound = sum(L[3 * end + j] * weight[j] * delta[j] for end in range(2) for j in range(3))
        assert err[d] <= 1.01 * bound
    assert err[0] <= 0.015 * A  # displacement within 1.5 % even at w h = 0.5 (800 Hz, h = 1e-4 s): 1.3 %


def test_harmonic_gain_of_the_reconstruction():
    """The component at w of the reconstructed motion. With x = w h, the step-end targets from
    the inputs at t - h (and the jerk from those at t - 2 h) are e^{iwt} times the nodal gains
    (1 + ix - x^2/2 - x^2 (1 - e^{-ix})/6) e^{-ix} (displacement), (1 + ix + ix (1 - e^{-ix})/2) e^{-ix}
    (velocity) and 2 e^{-ix} - e^{-2ix} (acceleration), derived by hand here; the Hermite blend
    between the nodes multiplies the displacement's by 1 + O(x^4) (about 0.02 x^4 up to x = 0.63)."""
    h = 1e-4
    for f_hz in (100.0, 500.0, 800.0):
        w = 2 * np.pi * f_hz
        x = w * h
        e1 = np.exp(-1j * x)
        nodal = (
            (1 + 1j * x - x * x / 2 - x * x * (1 - e1) / 6) * e1,
            (1 + 1j * x + 1j * x * (1 - e1) / 2) * e1,
            2 * e1 - e1 * e1,
        )
        t = np.linspace(0.0, h, 4001)
        z = np.zeros(len(t), complex)
        ends = np.zeros(3, complex)
        for part, unit in ((np.real, 1.0), (np.imag, 1j)):

            def data(tk, part=part, w=w):  # periodic steady state: a step starts at the previous target
                e = np.exp(1j * w * tk)
                return np.array([part(e)]), np.array([part(1j * w * e)]), np.array([part(-w * w * e)])

            start = taylor_target(*data(-2 * h), h, a_prev=data(-3 * h)[2], h_prev=h)
            end = taylor_target(*data(-h), h, a_prev=data(-2 * h)[2], h_prev=h)
            m = QuinticStep(-h, h, start, end)
            z += unit * m(t - h)[0][:, 0]
            ends += unit * np.array([q[0] for q in end])
        for d in range(3):  # the targets at t = 0 against the true values (i w)^d e^{i 0}
            assert abs(ends[d] / (1j * w) ** d - nodal[d]) < 1e-12
        gain = np.trapezoid(z * np.exp(-1j * w * (t - h)), t) / h
        assert abs(gain / nodal[0] - 1) < x**4 / 30  # the blend's 0.02 x^4, with a margin of 1.5
        assert abs(abs(gain) - 1) < 0.01  # -0.7 % at 800 Hz with h = 1e-4 s (module docstring)


def test_the_driven_support_force_converges_at_second_order_in_the_communication_step():
    """The force at a driven support contains the inertia of its own node, mass times the
    support's acceleration at the output instant, so its error follows the error of the target
    acceleration, 2 e^{-ix} - e^{-2ix} - 1 = O(x^2) (a held acceleration would be O(x): first
    order). The engine driven by the exact motion (Engine.advance with the motion itself) is the
    reference; the reconstruction from inputs sampled every H is compared with it on the 1e-4 s
    grid, contact off, for 300 and 600 Hz on casing.A.y: the observed order between H = 1e-4,
    5e-5 and 2e-5 s is at least 1.8 (theory: 2; 1.3 with the acceleration held)."""
    from cablecasing_core.model.schema import CHANNELS
    from cablecasing_core.timedomain.engine import Engine

    model = cc.load_model().with_overrides({"contact.enabled": False})
    iy = CHANNELS.index("casing.A.y")
    w, A, T = 2 * np.pi * 300.0, 1e-5, 0.03

    def motion(t):  # A (1 - cos wt)^2 (300 and 600 Hz): starts at rest, with zero velocity and acceleration
        t = np.atleast_1d(t)
        c, sn = np.cos(w * t), np.sin(w * t)
        u, v, a = (np.zeros((len(t), 12)) for _ in range(3))
        u[:, iy] = A * (1 - c) ** 2
        v[:, iy] = 2 * A * (1 - c) * w * sn
        a[:, iy] = 2 * A * w * w * (sn * sn + (1 - c) * c)
        return u, v, a

    def run(H, exact):
        eng = Engine(model, dt=1e-5, ledger=False)
        out, rows = np.zeros(len(eng.output_names)), []
        rec = SupportReconstruction(12)
        for k in range(int(round(T / H))):
            if exact:
                eng.advance(H, motion)
            else:
                u, v, a = (np.ascontiguousarray(q[0]) for q in motion(k * H))
                eng.advance_reconstructed(H, rec, u, v, a, out)
            eng.output_values(out)
            rows.append(out.copy())
        every = int(round(1e-4 / H))
        return np.array(rows)[every - 1 :: every, eng.output_names.index("casing.A.Fy")]

    ref = run(1e-4, exact=True)
    steps = (1e-4, 5e-5, 2e-5)
    err = [np.sqrt(np.mean((run(H, exact=False) - ref) ** 2) / np.mean(ref**2)) for H in steps]
    orders = [np.log(err[i] / err[i + 1]) / np.log(steps[i] / steps[i + 1]) for i in range(2)]
    assert min(orders) >= 1.8, (err, orders)


def test_bad_step_is_refused():
    with pytest.raises(ValueError, match="positive"):
        QuinticStep(0.0, 0.0, np.zeros((3, 12)), np.zeros((3, 12)))


def test_inputs_of_the_wrong_length_are_refused_before_anything_is_written():
    # the compiled reconstruction does not check bounds, so the shapes are checked before it runs
    rec = SupportReconstruction(12)
    rec.state[:] = 1.0
    with pytest.raises(ValueError, match=r"shape \(12,\)"):
        rec.motion(0.0, 1e-4, np.zeros(11), np.zeros(12), np.zeros(12))
    assert np.all(rec.state == 1.0)


@pytest.mark.parametrize("which", ["specimen", "clipped"])
def test_the_fused_communication_step_equals_advance_accept_and_outputs(which, clipped_specimen):
    """Engine.advance_reconstructed (one compiled call per communication step: motion, Newmark
    steps with contact, outputs) against the calls it replaces, on 0.05 s of the default scenario
    with contact (chaotic: any difference in rounding would grow to the visible), steps of 1e-4 s
    and, in between, steps that are not multiples of dt (which take the general path): equal to
    the bit, outputs, engine state and the supports' state. The fused engine reads its inputs from
    the same buffers every step, as the FMU does (its remembered context is reused), and one step
    with a NaN input fails in between: it must leave the engine and the supports' state as they
    were (the roll-back), so the run goes on equal to the bit. The first steps are a grid's
    differences t_(k+1) - t_k, as fmusim and libcosim compute them (1e-4 s but for the last
    bits): the fused step follows them h by h, with each h's exact quintic matrix. The same for
    the specimen with two clips, one excited (15 channels, the clips' forces among the outputs):
    the fused step takes every channel, and its outputs are the plain path's to the bit."""
    from cablecasing_core.model.schema import OUTPUTS
    from cablecasing_core.timedomain.engine import Engine
    from cablecasing_core.timedomain.scenario import scenario_motion

    model = cc.load_model() if which == "specimen" else clipped_specimen
    nch, nout = len(Engine(model).channels), len(Engine(model).output_names)
    assert (nch, nout) == ((12, len(OUTPUTS)) if which == "specimen" else (15, len(OUTPUTS) + 12))
    # fmusim's and libcosim's steps t_(k+1) - t_k of t_k = k h: 1e-4 s give or take the last bits
    grid = np.diff(np.arange(301) * 1e-4)
    assert len(set(grid.tolist())) > 1  # (the case the fused context must follow, h by h)
    steps = np.concatenate([grid, [3.7e-5, 1.13e-4] * 20, [1e-4] * 160])
    t = np.concatenate([[0.0], np.cumsum(steps)[:-1]])
    table = np.hstack(scenario_motion(model)(t))
    fused, plain = Engine(model, ledger=False), Engine(model, ledger=False)
    rf, rp = SupportReconstruction(nch), SupportReconstruction(nch)
    of, op = np.zeros((len(steps), nout)), np.zeros((len(steps), nout))
    buffers, out = (np.zeros(nch), np.zeros(nch), np.zeros(nch)), np.zeros(nout)
    fused_calls = 0
    for k, (h, row) in enumerate(zip(steps, table)):
        u, v, a = (np.ascontiguousarray(row[nch * q : nch * q + nch]) for q in range(3))
        if k == 150:  # a failing fused step: rolled back
            before, support = fused.get_state(), rf.state.copy()
            for b, x in zip(buffers, (u, v, a)):
                b[:] = x
            buffers[2][5] = np.nan
            with pytest.raises(cc.CableCasingError):
                fused.advance_reconstructed(float(h), rf, *buffers, out)
            after = fused.get_state()
            assert all(np.array_equal(before[n], after[n]) for n in before) and np.array_equal(rf.state, support)
        for b, x in zip(buffers, (u, v, a)):
            b[:] = x
        fused.advance_reconstructed(float(h), rf, *buffers, out)
        fused_calls += fused._cstep_memo is not None  # (this step was the one compiled call)
        of[k] = out
        m = rp.motion(plain.time, float(h), u, v, a)
        plain.advance(float(h), m)
        rp.accept(m)
        plain.output_values(op[k])
    assert of[:, OUTPUTS.index("contact.active")].max() >= 1  # the contact path ran
    assert fused_calls >= 400  # every step of 1e-4 s but the first (the 40 others take the general path)
    if which == "clipped":  # the clips' forces are outputs, and the excited clip moved the casing
        assert np.max(np.abs(of[:, len(OUTPUTS) + 6 :])) > 1e-3
    assert np.array_equal(of, op)
    assert fused.time == plain.time and np.array_equal(rf.state, rp.state)
    sf, sp = fused.get_state(), plain.get_state()
    assert all(np.array_equal(sf[k], sp[k]) for k in sp)


def test_the_random_excitation_computed_ahead_is_the_one_computed_within_the_steps(monkeypatch):
    """GridMotion.prepare (what an FMU driven by its scenario does in initialisation) computes the
    random record's blocks (~30 ms each) that cover the run, so that over communication steps of
    ten grid steps no block is computed within the steps, as far as the blocks kept allow
    (KEEP_BLOCKS, here 3 of 64 samples: past them the steps compute blocks again); and the values
    are those of a motion that computes its blocks as it goes, to the bit."""
    from cablecasing_core.model.load import load_model
    from cablecasing_core.timedomain import random_record
    from cablecasing_core.timedomain.random_record import RandomRecord
    from cablecasing_core.timedomain.scenario import scenario_motion
    from cablecasing_core.timedomain.support_motion import GridMotion

    dt = 1e-5
    monkeypatch.setattr(GridMotion, "CHUNK", 32)
    monkeypatch.setattr(random_record, "KEEP_BLOCKS", 3)
    model = load_model()
    within = GridMotion(scenario_motion(model, dt=dt), dt)
    ahead = GridMotion(scenario_motion(model, dt=dt), dt)
    for g in (within, ahead):  # (blocks of 64 samples, so that a few steps cross several)
        for _, _, sig in g.motion.terms:
            if isinstance(sig, RandomRecord):
                sig.block = 64
    assert ahead.prepare(2.5 * 64 * dt) == pytest.approx(3 * 64 * dt)  # three blocks cover 2.5
    assert ahead.prepare(1.0) == pytest.approx(3 * 64 * dt)  # no more than the blocks kept
    computed = []
    even = RandomRecord.even
    monkeypatch.setattr(RandomRecord, "even", lambda self, *a: computed.append(a[0]) or even(self, *a))
    a, b = np.empty((3, 10, 12)), np.empty((3, 10, 12))
    for k0 in range(0, 160, 10):  # chunks of grid steps 1-160, inside the prepared blocks: nothing computed
        ahead.fill(k0, b)
    assert computed == []
    for k0 in range(0, 6 * 64, 10):  # the same values as computed as they come, past the blocks too
        within.fill(k0, a)
        ahead.fill(k0, b)
        assert np.array_equal(a, b), k0
    assert np.abs(a).max() > 0  # (the scenario moves the supports)
