"""The interpolating spline of a centerline routed through points, the parametric curve r(s) of
Eq. (32): a cubic spline with not-a-knot ends in the chord parameter, or the parabola through three
points (structure/geometry.py re-parametrises it by arc length).

Written here rather than taken from ``scipy.interpolate`` (``CubicSpline``, ``make_interp_spline``,
which give the same curve: the interpolant is unique, and tests/model/test_spline.py checks
both against it): importing scipy.interpolate costs 0.13 s on a quiet machine and 0.32-0.75 s on a
slow one (scipy 1.17 imports scipy.optimize with it and parses the docstrings of some 300 functions
at import), 15-30 % of ``cablecasing static``, and every command that builds a point-routed
model paid it. The solve is scipy.linalg's banded LAPACK, imported by those commands anyway.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_banded


@dataclass(frozen=True)
class PointSpline:
    """A piecewise cubic r(u) = c0 + c1 t + c2 t^2 + c3 t^3 (t = u - knots[i] on span i) through
    the points, vector-valued (m, by the chord parameter u in m). c: (4, n_spans, dim)."""

    knots: np.ndarray
    c: np.ndarray

    def __call__(self, u, nu=0):
        """The curve (nu = 0, m), its first (nu = 1, m/m) or second (nu = 2, 1/m) derivative at the
        parameters u (m, an array); outside the knots' range the end spans' cubics continue."""
        u = np.asarray(u, dtype=float)
        i = np.clip(np.searchsorted(self.knots, u, side="right") - 1, 0, len(self.knots) - 2)
        t = (u - self.knots[i])[:, None]
        c0, c1, c2, c3 = (self.c[k][i] for k in range(4))
        if nu == 0:
            return c0 + t * (c1 + t * (c2 + t * c3))
        if nu == 1:
            return c1 + t * (2.0 * c2 + t * (3.0 * c3))
        if nu == 2:
            return 2.0 * c2 + 6.0 * t * c3
        raise ValueError(f"nu = {nu}: the derivative order must be 0, 1 or 2")


def interpolating_spline(x, y):
    """The spline through the points y (n, dim; m) at the strictly increasing parameters x (n; m):
    cubic with not-a-knot ends for n >= 4 (the first two and the last two spans each one cubic),
    the parabola through them for n = 3, the line for n = 2.

    The slopes s_i solve the usual tridiagonal system (continuity of the second derivative at the
    interior knots) with the not-a-knot end rows (continuity of the third derivative at the second
    and the last but one knot, eliminated into two-term rows); each span's cubic is then its
    Hermite form in (y_i, y_i+1, s_i, s_i+1)."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    n = len(x)
    h = np.diff(x)
    m = np.diff(y, axis=0) / h[:, None]  # the chords' slopes
    if n == 2:
        s = np.vstack([m, m])
    elif n == 3:  # the parabola: its slope at each knot from the divided differences
        a = (m[1] - m[0]) / (h[0] + h[1])
        s = np.vstack([m[0] - a * h[0], m[0] + a * h[0], m[1] + a * h[1]])
    else:
        ab = np.zeros((3, n))  # ab[1 + i - j, j] = A[i, j]
        b = np.zeros((n, y.shape[1]))
        ab[1, 1:-1] = 2.0 * (h[:-1] + h[1:])
        ab[0, 2:] = h[:-1]  # A[i, i + 1]
        ab[2, :-2] = h[1:]  # A[i, i - 1]
        b[1:-1] = 3.0 * (h[1:, None] * m[:-1] + h[:-1, None] * m[1:])
        d = h[0] + h[1]
        ab[1, 0], ab[0, 1] = h[1], d
        b[0] = ((h[0] + 2.0 * d) * h[1] * m[0] + h[0] ** 2 * m[1]) / d
        d = h[-1] + h[-2]
        ab[1, -1], ab[2, -2] = h[-2], d
        b[-1] = (h[-1] ** 2 * m[-2] + (2.0 * d + h[-1]) * h[-2] * m[-1]) / d
        s = solve_banded((1, 1), ab, b, check_finite=False)
    t = (s[:-1] + s[1:] - 2.0 * m) / h[:, None]
    c = np.stack([y[:-1], s[:-1], (m - s[:-1]) / h[:, None] - t, t / h[:, None]])
    return PointSpline(knots=x, c=c)
