"""Reconstruction of the support motion inside one communication step (for the FMU).

An FMI 2.0 co-simulation master gives the inputs at the start t of a step [t, t + h] only. From
the displacement u, velocity v and acceleration a of each channel at t, the motion at the end is
extrapolated by Taylor, u + v h + a h^2/2, v + a h, a. Inside the step the engine follows the
quintic Hermite polynomial from the support state it has actually reached at t (continuous
displacement, velocity and acceleration, so the supports never jump) to that target. When the
inputs are samples of a smooth signal the reconstruction error is O(h^3) in displacement.

The closed-form quintic Hermite basis is written here (rather than scipy's BPoly, which interpolates
one scalar at a time) so that all 12 channels are evaluated in one vectorised expression.
"""
from __future__ import annotations

import numpy as np


def taylor_target(u, v, a, h):
    """(u, v, a) at t + h (m, m/s, m/s2) extrapolated from values at t; h in s."""
    return u + v * h + 0.5 * a * h * h, v + a * h, a.copy()


class QuinticStep:
    """Motion over [t0, t0 + h]: quintic Hermite from ``start`` to ``end`` (each a tuple of arrays
    (u, v, a) of shape (12,), m, m/s, m/s2). Callable t (s, array) -> (u, v, a), each (len(t), 12)."""

    def __init__(self, t0, h, start, end):
        self.t0, self.h = float(t0), float(h)
        self.start = [np.asarray(x, float) for x in start]
        self.end = [np.asarray(x, float) for x in end]

    def __call__(self, t):
        h = self.h
        s = np.clip((np.atleast_1d(t) - self.t0) / h, 0.0, 1.0)[:, None]
        s2, s3, s4, s5 = s * s, s**3, s**4, s**5
        # basis (value, first and second derivative in s) of the six quintic Hermite functions
        H = [(1 - 10 * s3 + 15 * s4 - 6 * s5, -30 * s2 + 60 * s3 - 30 * s4, -60 * s + 180 * s2 - 120 * s3),
             (s - 6 * s3 + 8 * s4 - 3 * s5, 1 - 18 * s2 + 32 * s3 - 15 * s4, -36 * s + 96 * s2 - 60 * s3),
             (0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5, s - 4.5 * s2 + 6 * s3 - 2.5 * s4, 1 - 9 * s + 18 * s2 - 10 * s3),
             (10 * s3 - 15 * s4 + 6 * s5, 30 * s2 - 60 * s3 + 30 * s4, 60 * s - 180 * s2 + 120 * s3),
             (-4 * s3 + 7 * s4 - 3 * s5, -12 * s2 + 28 * s3 - 15 * s4, -24 * s + 84 * s2 - 60 * s3),
             (0.5 * s3 - s4 + 0.5 * s5, 1.5 * s2 - 4 * s3 + 2.5 * s4, 3 * s - 12 * s2 + 10 * s3)]
        (u0, v0, a0), (u1, v1, a1) = self.start, self.end
        coef = [u0, v0 * h, a0 * h * h, u1, v1 * h, a1 * h * h]
        out = []
        for d in range(3):
            val = sum(Hk[d] * c[None, :] for Hk, c in zip(H, coef))
            out.append(val / h**d)
        return tuple(out)

    def end_state(self):
        return tuple(x.copy() for x in self.end)
