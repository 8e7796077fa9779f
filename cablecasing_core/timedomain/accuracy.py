"""Newmark's accuracy in the time domain (Eq. 18, the average acceleration rule, gamma = 1/2,
beta = 1/4): its relative period error at a frequency and step (:func:`newmark_period_error`), and
the step that keeps it within a given error (:func:`step_for_period_error`). ``cablecasing geometry``'s
band advice (``structure.route_summary.band_advice``) and the commands' notes on bands beyond Table 3
use them. numpy only: importing this module loads no engine.
"""

from __future__ import annotations

import numpy as np


def newmark_period_error(f_hz, dt):
    """Newmark's relative period error at ``f_hz`` (Hz) with the step ``dt`` (s), (2 pi f dt)^2 / 12
    (dimensionless; 0.01 is 1 %): the average acceleration rule (gamma = 1/2, beta = 1/4, the time
    domain's) steps an undamped oscillator of angular frequency w at the frequency W of
    tan(W dt / 2) = w dt / 2, so its period is T (w dt / 2) / arctan(w dt / 2), too long by
    (w dt)^2 / 12 - (w dt)^4 / 180 + ...: the leading term (docs/time_domain.md), which overstates the
    error by (w dt)^2 / 15 of itself (0.8 % of a 1 % error). Verified against the average acceleration
    rule stepped by hand in tests/model/test_mesh_advice.py."""
    return (2.0 * np.pi * np.asarray(f_hz, dtype=float) * dt) ** 2 / 12.0


def step_for_period_error(f_hz, error):
    """The longest step dt (s) of two significant digits (a value to type) at which
    :func:`newmark_period_error` at ``f_hz`` (Hz) is at most ``error`` (0.005: 0.5 %)."""
    dt = float(np.sqrt(12.0 * error) / (2.0 * np.pi * f_hz))
    e = int(np.floor(np.log10(dt))) - 1
    return float(f"{int(np.floor(dt / 10.0**e * (1 + 1e-12)))}e{e}")  # (1.9e-05, not 1.8999999999999998e-05)
