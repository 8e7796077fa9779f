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
    band, rms, dt, T = [10.0, 1000.0], 5.0, 1e-5, 0.5
    exc = {"r": {"target": "casing.A.z", "kind": "random", "rms": rms, "band": band, "seed": 7}}
    mo = scenario_motion(_model(exc, dt=dt, duration=T))
    t = dt * np.arange(1, int(round(T / dt)) + 1)
    u, v, a = mo(t)
    col = CHANNELS.index("casing.A.z")
    assert np.count_nonzero(a[:, np.arange(12) != col]) == 0  # only the target channel
    x = a[:, col]
    assert np.sqrt(np.mean(x**2)) == pytest.approx(rms, rel=1e-12)  # scaled to the RMS exactly
    # spectrum: nothing outside the band (the record is periodic over T: no leakage)
    f = np.fft.rfftfreq(len(x), dt)
    X = np.abs(np.fft.rfft(x))
    out = (f < band[0]) | (f > band[1])
    assert X[out].max() < 1e-9 * X.max()
    # displacement and velocity are the exact periodic integrals: spectral derivatives give back a
    U, V = np.fft.rfft(u[:, col]), np.fft.rfft(v[:, col])
    w = 2 * np.pi * f
    np.testing.assert_allclose(np.fft.irfft(1j * w * U, len(x)), v[:, col], atol=1e-9 * np.abs(v[:, col]).max())
    np.testing.assert_allclose(np.fft.irfft(1j * w * V, len(x)), x, atol=1e-9 * rms)
    # between the samples (quintic Hermite) the three stay consistent: central differences of
    # step h agree to O((2 pi f h)^2 / 6) at 1 kHz, h = 1e-7 s: 7e-7 of the band's top frequency
    tm = t[100:200] + 0.37 * dt
    assert max(_derivative_mismatch(mo, tm, 1e-7)) < 1e-3
    # reproducible by seed, different for another seed
    assert np.array_equal(scenario_motion(_model(exc, dt=dt, duration=T))(t)[2], a)
    exc2 = copy.deepcopy(exc)
    exc2["r"]["seed"] = 8
    a2 = scenario_motion(_model(exc2, dt=dt, duration=T))(t)[2][:, col]
    assert abs(np.corrcoef(x, a2)[0, 1]) < 0.1  # 5e3 samples: |rho| ~ 0.014


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


@pytest.mark.parametrize(
    "rows,fragment",
    [
        ([(0.0, 0.0), (0.01, 1e-5), (0.01, 2e-5)], "time must increase strictly; row 3 has t = 0.01 after 0.01"),
        ([(0.0, 0.0), (0.02, 1e-5), (0.01, 2e-5)], "row 3 has t = 0.01 after 0.02"),
        ([(0.0, 0.0), (0.01, float("nan"))], "finite numbers only"),
        ([(0.0, 0.0)], "at least two rows"),
    ],
)
def test_bad_csv_is_refused_naming_the_file_and_what_is_wrong(tmp_path, rows, fragment):
    p = tmp_path / "bad.csv"
    _csv(p, rows)
    m = _model({"c": {"target": "casing.A.z", "kind": "csv", "file": str(p)}})
    with pytest.raises(cc.ModelError, match="scenario.excitation.file") as err:
        scenario_motion(m)
    assert fragment in str(err.value) and str(p) in str(err.value)


def test_missing_csv_file_is_refused(tmp_path):
    m = _model({"c": {"target": "casing.A.z", "kind": "csv", "file": "nowhere.csv"}}, base_dir=tmp_path)
    with pytest.raises(cc.ModelError, match="readable CSV"):
        scenario_motion(m)
