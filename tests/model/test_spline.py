"""The spline of a point route (structure/spline.py) against scipy's interpolants, an independent
implementation of the same unique curve: the not-a-knot cubic (``CubicSpline``) through 4 or more
points, the interpolating parabola (``make_interp_spline``, k = 2) through 3."""

import numpy as np
import pytest
from scipy.interpolate import CubicSpline, make_interp_spline

from cablecasing_core.structure.spline import interpolating_spline


@pytest.mark.parametrize("n", [3, 4, 5, 9, 40])
def test_spline_is_scipys_interpolant(n):
    rng = np.random.default_rng(n)
    x = np.cumsum(rng.uniform(0.02, 0.3, n))  # uneven spans (m), as chord lengths are
    y = rng.normal(0.0, 0.2, (n, 3))
    ref = CubicSpline(x, y, bc_type="not-a-knot") if n >= 4 else make_interp_spline(x, y, k=2)
    spl = interpolating_spline(x, y)
    u = np.linspace(x[0], x[-1], 997)
    for nu in (0, 1, 2):
        want = ref(u, nu)
        # rounding of a well-conditioned tridiagonal solve and of the span polynomials: 1e-11 of
        # the derivative's scale, which grows by 1 / span per order
        tol = 1e-11 * np.abs(want).max()
        np.testing.assert_allclose(spl(u, nu), want, rtol=0, atol=tol, err_msg=f"derivative {nu}")


def test_spline_interpolates_and_reproduces_cubics():
    x = np.array([0.0, 0.1, 0.35, 0.4, 0.9, 1.0])
    y = np.column_stack([x, 2 * x**3 - x**2 + 0.5, -(x**3)])  # cubics: not-a-knot reproduces them exactly
    spl = interpolating_spline(x, y)
    np.testing.assert_allclose(spl(x), y, atol=1e-15)
    u = np.linspace(0.0, 1.0, 101)
    np.testing.assert_allclose(spl(u, 2)[:, 1], 12 * u - 2, atol=1e-12)
