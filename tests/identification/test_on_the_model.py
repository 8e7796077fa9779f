"""Identification on the model itself (issue 5): damping ratios from an impulse response run through
the FMU, the loss factor from the core's structurally damped TRFAM, and eta against 2 zeta (Table 1).

The specimen is a straight clamped-clamped casing (Table 2's section, 0.85 m) so that its first three
bending modes in y are well separated (1 : 2.76 : 5.40); Rayleigh alpha = 2 1/s, beta = 4.23e-5 s.
"""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.identification import loss_factor_circle, wavelet_damping

ROOT = Path(__file__).resolve().parents[2]
ALPHA, BETA, ETA = 2.0, 4.23e-5, 0.05


def straight_casing_toml(path):
    m = cc.load_model()
    d = m.data
    casing = dict(d["casing"], alpha=ALPHA, beta=BETA, loss_factor=ETA)
    data = {
        "geometry": {"points": [[0.0, 0, 0], [0.85, 0, 0]], "n_elements": 35, "curve": "polyline"},
        "casing": casing,
        "contact": d["contact"],
        "scenario": {"duration": 1.0, "dt": 1e-5},
    }
    model = cc.model_from_dict(data)
    path.write_text(model.to_toml())
    return cc.load_model(path)


def bending_y(model, n=3):
    f, shapes = cc.modes(model, "casing")
    u = shapes.reshape(-1, 6, shapes.shape[1])
    y_share = np.sum(u[:, 1] ** 2, axis=0) / np.sum(u[:, :3] ** 2, axis=(0, 1))
    return f[y_share > 0.5][:n]


IMPULSE_DRIVER = r"""
import json, sys
import numpy as np
from fmpy import simulate_fmu
path, model_file, out = sys.argv[1], sys.argv[2], sys.argv[3]
h, T, w = 1e-4, 1.5, 2e-3                        # s: communication step, record, pulse width
t = np.arange(0.0, T + h / 2, h)
tau = np.clip((t - 0.01) / w, 0, 1)
on = (t >= 0.01) & (t <= 0.01 + w)
A, om = 1e-5 / 2, 2 * np.pi / w                  # Hann displacement bump of 10 um in y at end A
sig = np.zeros(len(t), dtype=[("time", float), ("casing.A.y", float), ("casing.A.vy", float), ("casing.A.ay", float)])
sig["time"] = t
sig["casing.A.y"] = np.where(on, A * (1 - np.cos(2 * np.pi * tau)), 0)
sig["casing.A.vy"] = np.where(on, A * om * np.sin(2 * np.pi * tau), 0)
sig["casing.A.ay"] = np.where(on, A * om * om * np.cos(2 * np.pi * tau), 0)
r = simulate_fmu(path, stop_time=T, step_size=h, output_interval=h, input=sig,
                 start_values={"model_file": model_file}, output=["casing.B.Fy"])
np.savez(out, t=r["time"], F=r["casing.B.Fy"])
"""


@pytest.fixture(scope="module")
def straight_casing(tmp_path_factory):
    return straight_casing_toml(tmp_path_factory.mktemp("m") / "straight.toml")


@pytest.mark.slow  # runs the FMU in a fresh process
def test_wavelet_damping_of_fmu_impulse_response(straight_casing, tmp_path, fmu):
    out = tmp_path / "imp.npz"
    subprocess.run(
        [sys.executable, "-c", IMPULSE_DRIVER, str(fmu), straight_casing.source, str(out)],
        check=True,
        cwd=ROOT,
        timeout=900,
    )
    r = np.load(out)
    keep = r["t"] > 0.015  # the free decay after the pulse
    f = bending_y(straight_casing)
    res = wavelet_damping(r["F"][keep], 1e4, f)
    w = 2 * np.pi * f
    expected = ALPHA / (2 * w) + BETA * w / 2  # Eq. (41)
    zeta = np.array([x.zeta for x in res])
    # the 3 % bound: ridge method on a 1.5 s record at 10 kHz
    np.testing.assert_allclose(zeta, expected, rtol=0.03)


def test_loss_factor_from_structural_trfam(straight_casing):
    f = bending_y(straight_casing)
    freqs = np.arange(5.0, 1.3 * f[-1], 0.02)
    H = cc.trfam(straight_casing, "casing.A.y", "casing.B.y", freqs, "structural")
    res = loss_factor_circle(freqs, H, f_res_hz=f, kind="apparent_mass")
    eta = np.array([x.eta for x in res])
    np.testing.assert_allclose(eta, ETA, rtol=0.02)  # the 2 % bound


def test_eta_against_two_zeta_as_in_table_1(straight_casing):
    """Viscous (Rayleigh) TRFAM: the circle fit's loss factor at each mode is close to 2 zeta
    (Henwood, eta ~ 2 zeta for eta < 0.4), the comparison of Table 1."""
    f = bending_y(straight_casing)
    freqs = np.arange(5.0, 1.3 * f[-1], 0.02)
    H = cc.trfam(straight_casing, "casing.A.y", "casing.B.y", freqs, "viscous")
    eta = np.array([x.eta for x in loss_factor_circle(freqs, H, f_res_hz=f, kind="apparent_mass")])
    w = 2 * np.pi * f
    zeta = ALPHA / (2 * w) + BETA * w / 2
    # a viscous mode's circle gives eta = 2 zeta exactly at resonance; off resonance the viscous
    # damping force grows with frequency (c omega / k varies by +-zeta across the fitted window), but
    # that first-order change cancels between the angle pairs below and above resonance: on a single
    # viscous mode the estimate is 2 zeta (1 + 1.5 zeta^2) (measured for zeta = 0.005..0.04), <= 4e-4
    # here (zeta <= 0.016); the other modes' residue adds the rest: measured 5.4e-4, 3e-5 and
    # 1.1e-3 for the three modes, the same at half the frequency step. 3e-3 bounds it with margin.
    np.testing.assert_allclose(eta, 2 * zeta, rtol=3e-3)
