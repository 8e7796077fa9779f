"""Scenario excitations (Sections 4.1-4.2): each kind against its closed form or an independent
computation, the (u, v, a) of every kind consistent as derivatives, and bad CSV tables refused."""

import copy

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.model.schema import CHANNELS
from cablecasing_core.structure.geometry import centerline_of
from cablecasing_core.timedomain.scenario import scenario_motion


def _model(excitation, ramp=0.0, dt=1e-5, duration=0.2, base_dir=None):
    d = copy.deepcopy(cc.load_model().data)
    d["scenario"].update(excitation=excitation, ramp=ramp, dt=dt, duration=duration)
    return cc.model_from_dict(d, base_dir=base_dir)


def _derivative_mismatch(motion, t, h):
    """max |v - du/dt| / max|v| and |a - dv/dt| / max|a| by central differences of step h (s)."""
    u_p, v_p, _ = motion(t + h)
    u_m, v_m, _ = motion(t - h)
    _, v, a = motion(t)
    dv = (u_p - u_m) / (2 * h) - v
    da = (v_p - v_m) / (2 * h) - a
    return np.abs(dv).max() / np.abs(v).max(), np.abs(da).max() / np.abs(a).max()


def test_random_excitation_has_the_rms_band_and_seed_asked_for():
    # one period of the record (64 s) on a coarse grid (4 kHz, above twice the band's top): over a
    # period the line spectrum is exact, so RMS, band and integrals are checked without leakage
    from cablecasing_core.timedomain.random_record import LINE_SPACING

    band, rms, dt = [10.0, 1000.0], 5.0, 2.5e-4
    exc = {"r": {"target": "casing.A.z", "kind": "random", "rms": rms, "band": band, "seed": 7}}
    mo = scenario_motion(_model(exc, dt=dt, duration=0.2))
    n = int(round(1 / LINE_SPACING / dt))
    t = dt * np.arange(n)
    u, v, a = mo(t + 1.0)  # (past the ramp; the period is the same from any start)
    col = CHANNELS.index("casing.A.z")
    assert np.count_nonzero(a[:, np.arange(12) != col]) == 0  # only the target channel
    x = a[:, col]
    assert np.sqrt(np.mean(x**2)) == pytest.approx(rms, rel=1e-12)  # the RMS over a period, exactly
    f = np.fft.rfftfreq(n, dt)
    X = np.abs(np.fft.rfft(x))
    out = (f < band[0]) | (f > band[1])
    assert X[out].max() < 1e-9 * X.max()  # nothing outside the band (round-off: ~1e-11)
    lines = X > 1e-6 * X.max()
    assert np.allclose(X[lines], X[lines].mean(), rtol=1e-9)  # a flat spectrum: equal lines
    assert lines.sum() == round((band[1] - band[0]) / LINE_SPACING) + 1
    # displacement and velocity are the exact integrals: spectral derivatives give back v and a
    U, V = np.fft.rfft(u[:, col]), np.fft.rfft(v[:, col])
    w = 2 * np.pi * f
    np.testing.assert_allclose(np.fft.irfft(1j * w * U, n), v[:, col], atol=1e-9 * np.abs(v[:, col]).max())
    np.testing.assert_allclose(np.fft.irfft(1j * w * V, n), x, atol=1e-9 * rms)
    # between the samples (summed directly) the three stay consistent: central differences of step
    # h = 1e-7 s agree to O((2 pi f h)^2 / 6) = 7e-7 at the band's top
    tm = 0.1 + dt * np.arange(40) + 0.37 * dt
    assert max(_derivative_mismatch(mo, tm, 1e-7)) < 1e-3
    # reproducible by seed, different for another seed
    assert np.array_equal(scenario_motion(_model(exc, dt=dt, duration=0.2))(t + 1.0)[2], a)
    exc2 = copy.deepcopy(exc)
    exc2["r"]["seed"] = 8
    a2 = scenario_motion(_model(exc2, dt=dt, duration=0.2))(t + 1.0)[2][:, col]
    assert abs(np.corrcoef(x, a2)[0, 1]) < 0.02  # 2.6e5 samples of 6.3e4 lines: |rho| ~ 0.004


def test_random_record_is_the_sum_of_its_lines_at_any_time_and_grid():
    """The block evaluation on the run's grid (chirp-z) is the direct sum of the lines, at any grid,
    and the record does not depend on the run's duration or time step (there is no such argument)."""
    from cablecasing_core.timedomain.random_record import RandomRecord

    rec = RandomRecord(5.0, [10.0, 1000.0], 3, 1e-5)
    k = np.array([0, 1, 4095, rec.block - 1, rec.block, 3 * rec.block + 17, 10**6 + 5])  # across blocks
    direct = rec.direct(k * 1e-5)
    for got, ref in zip(rec(k * 1e-5), direct):  # phases reduced mod 1: agreement to ~1e-12 of the RMS
        assert np.abs(got - ref).max() < 1e-10 * np.sqrt(np.mean(ref**2) + np.abs(ref).max() ** 2)
    other = RandomRecord(5.0, [10.0, 1000.0], 3, 4e-5)  # another grid: the same function of time
    for got, ref in zip(other(k[k % 4 == 0] * 1e-5), rec(k[k % 4 == 0] * 1e-5)):
        assert np.abs(got - ref).max() < 1e-10 * np.abs(ref).max()
    # a band's common lines keep their phases (the seed's stream is indexed from 0 Hz)
    narrow = RandomRecord(1.0, [100.0, 200.0], 3, 1e-5)
    j = np.searchsorted(np.arange(rec.k_lo, rec.k_lo + rec.n_lines), narrow.k_lo)
    np.testing.assert_allclose(np.angle(narrow.coef[2]), np.angle(rec.coef[2, j : j + narrow.n_lines]), atol=1e-12)


def test_random_psd_is_the_periodogram_of_one_period_of_the_record():
    """random_psd (the report's input spectrum) against the record itself: over one period, 64 s,
    every line falls on an FFT bin of spacing 1/64 Hz, so the periodogram's density on a bin, 2 |X_k|^2
    / (N^2 df), is the line's mean square over df. Tolerance 1e-9: the evaluation's ~1e-12 of the
    RMS and round-off; outside the band the PSD is 0 and the periodogram ~1e-20 of it."""
    from cablecasing_core.timedomain.random_record import LINE_SPACING, RandomRecord, random_psd

    rms, band, dt = 2.0, [10.0, 12.5], 1e-2
    n = int(round(1 / LINE_SPACING / dt))
    _, _, a = RandomRecord(rms, band, 5, dt)(np.arange(n) * dt)
    f = np.fft.rfftfreq(n, dt)
    density = 2 * np.abs(np.fft.rfft(a)) ** 2 / (n * n * LINE_SPACING)
    G = random_psd(rms, band, f)
    np.testing.assert_allclose(density, G, rtol=0, atol=1e-9 * G.max())
    assert np.count_nonzero(G) == 161  # lines 640..800, the band's ends included
    fine = np.arange(0.0, 20.0, LINE_SPACING / 64)  # its integral is the mean square
    assert np.sum(random_psd(rms, band, fine)) * LINE_SPACING / 64 == pytest.approx(rms**2, rel=1e-12)


@pytest.mark.parametrize("dt", [1e-5, 2e-5, 1 / 30000])
def test_random_record_between_grid_points_is_the_sum_of_its_lines(dt):
    """A time off the run's grid (a shorter last step: an FMU's communication step of 2.5e-5 s at
    dt = 1e-5 s) takes the quintic Hermite polynomial through its two grid neighbours' u, v, a,
    not the direct sum of 63 000 lines (which made such a call 20 times dearer): against that sum,
    within 1e-10 of the RMS in u, 1e-8 in v and 1e-5 in a (measured 3e-12, 2e-9 and 9e-7 at
    worst: the polynomial's error grows as (w dt)^(6 - d) for the d-th derivative)."""
    from cablecasing_core.timedomain.random_record import RandomRecord

    rec = RandomRecord(5.0, [10.0, 1000.0], 7, dt)
    t = np.sort(np.random.default_rng(0).uniform(0.01, 0.3, 60))
    assert not np.any(np.abs(t / dt - np.rint(t / dt)) < 1e-9)  # (all off the grid)
    ref = rec.direct(t)
    rms = [np.sqrt(np.mean(x**2)) for x in rec(dt * np.arange(int(0.3 / dt)))]
    for got, want, scale, bound in zip(rec(t), ref, rms, (1e-10, 1e-8, 1e-5)):
        assert np.abs(got - want).max() < bound * scale


def test_harmonic_and_impulse_are_their_closed_forms():
    f, A, ph = 50.0, 5e-4, 0.3
    mo = scenario_motion(
        _model({"h": {"target": "cable.B.y", "kind": "harmonic", "frequency": f, "amplitude": A, "phase": ph}})
    )
    t = np.linspace(0.0, 0.1, 777)
    u, v, a = mo(t)
    col = CHANNELS.index("cable.B.y")
    w = 2 * np.pi * f
    np.testing.assert_allclose(u[:, col], A * np.sin(w * t + ph), atol=1e-15)
    np.testing.assert_allclose(v[:, col], A * w * np.cos(w * t + ph), atol=1e-12)
    np.testing.assert_allclose(a[:, col], -A * w * w * np.sin(w * t + ph), atol=1e-9)

    amp, width, start = 1e-4, 2e-3, 0.01
    mo = scenario_motion(
        _model({"i": {"target": "casing.B.x", "kind": "impulse", "amplitude": amp, "width": width, "start": start}})
    )
    col = CHANNELS.index("casing.B.x")
    t = np.linspace(0.0, 0.03, 30001) + 0.5e-6  # the bump's ends fall between samples
    u, v, a = (x[:, col] for x in mo(t))
    # (the top falls 0.5 us from a sample: (pi 0.5e-6 / 2e-3)^2 = 6e-7 low; the argmax within the 1 us grid)
    assert u.max() == pytest.approx(amp, rel=1e-6) and abs(t[np.argmax(u)] - (start + width / 2)) < 1e-6
    assert not u[(t < start) | (t > start + width)].any()  # at rest outside, and back
    # the velocity integrates to the displacement and the acceleration to the velocity
    # (trapezoidal rule on 1 us steps: error (w h)^2 / 12 ~ 8e-7 of the peak; the acceleration
    # jumps by amplitude/2 (2 pi/width)^2 at either end of a displacement bump, and a jump halfway
    # between two samples costs the trapezoidal rule nothing)
    iu = np.concatenate([[0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])
    iv = np.concatenate([[0], np.cumsum(0.5 * (a[1:] + a[:-1]) * np.diff(t))])
    assert np.abs(iu - u).max() < 1e-5 * amp
    assert np.abs(iv - v).max() < 1e-5 * np.abs(v).max()


def test_axial_target_moves_along_the_tangent_at_that_end():
    m = _model({"ax": {"target": "cable.B.axial", "kind": "harmonic", "frequency": 50.0, "amplitude": 1e-3}})
    t = np.array([0.005])  # quarter period: u = amplitude
    u = scenario_motion(m)(t)[0][0]
    col = CHANNELS.index("cable.B.x")
    tangent = centerline_of(m).tangents[-1]
    np.testing.assert_allclose(u[col : col + 3], 1e-3 * tangent, atol=1e-15)
    assert np.linalg.norm(tangent) == pytest.approx(1.0)
    assert np.count_nonzero(np.delete(u, np.s_[col : col + 3])) == 0


def test_ramp_fades_in_from_rest_with_consistent_derivatives():
    T = 0.01
    mo = scenario_motion(
        _model(
            {"h": {"target": "casing.A.y", "kind": "harmonic", "frequency": 200.0, "amplitude": 1e-4, "phase": 1.0}},
            ramp=T,
        )
    )
    u, v, a = mo(np.array([0.0]))
    assert not (u.any() or v.any())  # starts at rest (the acceleration, window'' u(0), need not)
    t = np.linspace(1e-4, 2 * T, 400)
    # product rule of the half-cosine window, against central differences (h = 1e-7 s: O(1e-6))
    assert max(_derivative_mismatch(mo, t, 1e-7)) < 1e-4
    late = np.array([1.5 * T, 1.9 * T])
    col = CHANNELS.index("casing.A.y")
    np.testing.assert_allclose(mo(late)[0][:, col], 1e-4 * np.sin(2 * np.pi * 200.0 * late + 1.0), atol=1e-16)


def _csv(path, rows):
    path.write_text("time_s,displacement_m\n" + "".join(f"{float(t)!r},{float(x)!r}\n" for t, x in rows))


def test_csv_excitation_interpolates_the_table_from_the_model_folder(tmp_path):
    tt = np.linspace(0.0, 0.05, 51)
    x = 1e-4 * np.sin(2 * np.pi * 20.0 * tt)
    _csv(tmp_path / "shaker.csv", zip(tt, x))
    # a relative path is read from the model file's folder
    m = _model({"c": {"target": "casing.A.z", "kind": "csv", "file": "shaker.csv"}}, base_dir=tmp_path)
    mo = scenario_motion(m)
    col = CHANNELS.index("casing.A.z")
    u, v, a = (y[:, col] for y in mo(tt))
    np.testing.assert_allclose(u, x, atol=1e-18)  # through every sample
    # between the samples a cubic spline of a 20 Hz sine sampled at 1 kHz: within 1e-4 of the
    # amplitude (interpolation error ~ (w h)^4 / 384 ~ 4e-8 plus the not-a-knot ends)
    tm = np.linspace(0.0, 0.05, 1001)
    assert np.abs(mo(tm)[0][:, col] - 1e-4 * np.sin(2 * np.pi * 20.0 * tm)).max() < 1e-4 * 1e-4
    assert max(_derivative_mismatch(mo, tm[10:-10], 1e-7)) < 1e-4
    # past the table: the last value, at rest
    u, v, a = (y[:, col] for y in mo(np.array([0.06, 0.1])))
    np.testing.assert_allclose(u, x[-1], atol=1e-18)
    assert not (v.any() or a.any())


@pytest.mark.parametrize("quantity", ["velocity", "acceleration"])
def test_csv_velocity_or_acceleration_is_integrated_against_the_closed_form(tmp_path, quantity):
    """A recorded u = A sin(w t) + its drift: an accelerometer's offset c (a = -A w^2 sin(w t) + c) or
    a velocity record v = A w cos(w t) + c. Integrated with the drift removal of the docs (means of
    a, v and u removed over the table), whole periods: back to u, v, a of the closed form."""
    A, f, c = 1e-4, 20.0, 0.3  # m, Hz, offset (m/s2 or m/s)
    w = 2 * np.pi * f
    tt = np.linspace(0.0, 0.25, 1001)  # 5 periods at 4 kHz
    value = -A * w * w * np.sin(w * tt) + c if quantity == "acceleration" else A * w * np.cos(w * tt) + c
    _csv(tmp_path / "rec.csv", zip(tt, value))
    exc = {"c": {"target": "casing.A.z", "kind": "csv", "file": "rec.csv", "quantity": quantity}}
    mo = scenario_motion(_model(exc, base_dir=tmp_path))
    col = CHANNELS.index("casing.A.z")
    tm = np.linspace(0.001, 0.249, 997)
    u, v, a = (y[:, col] for y in mo(tm))
    # cubic-spline interpolation of a 20 Hz sine at 4 kHz: relative error ~ (w h)^4 / 384 ~ 2e-9 for
    # the values and ~(w h)^3 / 24 ~ 1e-7 for each derivative; the integrals add the same order
    # (the means of a sampled sine over whole periods vanish to the same accuracy): 1e-5 bounds all
    assert np.abs(u - A * np.sin(w * tm)).max() < 1e-5 * A
    assert np.abs(v - A * w * np.cos(w * tm)).max() < 1e-5 * A * w
    assert np.abs(a + A * w * w * np.sin(w * tm)).max() < 1e-4 * A * w * w
    assert max(_derivative_mismatch(mo, tm[10:-10], 1e-7)) < 1e-4  # u, v, a consistent


def test_csv_quantity_is_checked_by_the_schema(tmp_path):
    _csv(tmp_path / "rec.csv", [(0.0, 0.0), (0.01, 1.0)])
    exc = {"c": {"target": "casing.A.z", "kind": "csv", "file": "rec.csv", "quantity": "jerk"}}
    with pytest.raises(cc.ModelError, match="scenario.excitation.c.quantity"):
        _model(exc, base_dir=tmp_path)


def test_a_model_without_excitation_warns(recwarn):
    m = _model({})
    res = cc.simulate(m, duration=0.001)
    assert not res.support_forces.any()
    w = [x for x in recwarn if "no excitation" in str(x.message)]
    assert len(w) == 1 and "every output stays zero" in str(w[0].message)


def test_an_installed_model_without_excitation_warns_that_its_outputs_stay_static(recwarn):
    """The installed specimen without its excitation: the outputs are its static reactions, not
    zero (the warning said zero), and stay near them: within 1e-4 of the largest over 1 ms (measured
    ~1e-5, a transient in the first 0.1 ms with either friction law: the static state's contact
    solve and the step's agree to their tolerances, not to the bit)."""
    data = cc.load_model("installed").data
    m = cc.model_from_dict({**data, "scenario": {**data["scenario"], "excitation": {}}})
    res = cc.simulate(m, duration=0.001)
    w = [str(x.message) for x in recwarn if "no excitation" in str(x.message)]
    assert len(w) == 1 and "every output stays at its static value" in w[0], w
    f0, f = res.initial_forces[: res.support_forces.shape[1]], res.support_forces
    assert np.abs(f0).max() > 1.0 and np.abs(f - f0).max() <= 1e-4 * np.abs(f0).max()


@pytest.mark.slow  # a 1 s run
def test_a_runs_beginning_does_not_depend_on_its_length():
    """The first 0.1 s of a 0.2 s and of a 1 s run of the default scenario (contact, chaos) are
    bitwise equal, with and without the progress bar (which splits the run into pieces)."""
    m = cc.load_model()
    short = cc.simulate(m, duration=0.2)
    long = cc.simulate(m, duration=1.0, progress=True)
    n = 10_000  # 0.1 s
    for name in ("support_forces", "contact_state", "normal_force", "penetration"):
        assert np.array_equal(getattr(short, name)[:n], getattr(long, name)[:n]), name
    assert np.array_equal(short.inputs["casing.A.az"], long.inputs["casing.A.az"][: len(short.time)])


@pytest.mark.parametrize(
    "rows,fragment",
    [
        # (the messages name the data row or line and quote nothing of the file, issue 26)
        (
            [(0.0, 0.0), (0.01, 1e-5), (0.01, 2e-5)],
            "time (its first column) must increase strictly; data row 3 does not",
        ),
        ([(0.0, 0.0), (0.02, 1e-5), (0.01, 2e-5)], "data row 3 does not"),
        ([(0.0, 0.0), (0.01, float("nan"))], "line 3, column 2 is not a finite number"),
        ([(0.0, 0.0)], "has 1 rows of numbers"),
    ],
)
def test_bad_csv_is_refused_naming_the_file_and_what_is_wrong(tmp_path, rows, fragment):
    p = tmp_path / "bad.csv"
    _csv(p, rows)
    m = _model({"c": {"target": "casing.A.z", "kind": "csv", "file": str(p)}})
    with pytest.raises(cc.ModelError, match=r"scenario\.excitation\.c\.file") as err:
        scenario_motion(m)
    assert fragment in str(err.value) and str(p) in str(err.value)


def test_missing_csv_file_is_refused(tmp_path):
    m = _model({"c": {"target": "casing.A.z", "kind": "csv", "file": "nowhere.csv"}}, base_dir=tmp_path)
    with pytest.raises(cc.ModelError, match="does not exist"):
        scenario_motion(m)


def test_a_run_s_own_step_must_resolve_the_random_band_and_contact_is_a_bool():
    """The built-in random band reaches 1000 Hz: a run at dt = 1e-3 s (Nyquist 500 Hz) is refused
    naming dt, as the model file's scenario.dt is (it ran, half the band aliased); 4e-4 s runs.
    ``contact`` takes None, True or False only (a string was taken as True)."""
    m = cc.load_model()
    with pytest.raises(cc.ModelError, match=r"dt = 0.001: must resolve the random excitation .* dt < 0.0005 s"):
        cc.simulate(m, duration=0.01, dt=1e-3)
    with pytest.raises(cc.ModelError, match=r"Nyquist frequency 1 / \(2 scenario.dt\) = 500 Hz \(scenario.dt = 0.001"):
        m.with_overrides({"scenario.dt": 1e-3})
    cc.simulate(m, duration=0.002, dt=4e-4)
    with pytest.raises(cc.ModelError, match=r"contact = 'no': must be None .*, True or False"):
        cc.simulate(m, duration=1e-4, contact="no")
