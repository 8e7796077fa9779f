"""Interpolation on a straight beam element of the casing (the shape functions of Eq. 9): the
deformed axis point and its slope, and the 6 x 12 interpolation matrix of displacements and
rotations, used by the contact search and the contact forces."""

from __future__ import annotations

from numba import njit

from ._compile_options import FM


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def hermite_cubics(xi):
    """The Hermite cubics of Eq. (9) at xi in [0, 1] (dimensionless) and their derivatives d/dxi,
    as (n1, n2, n3, n4, d1, d2, d3, d4): a lateral displacement on an element of length L (m) is
    n1 v_a + L n2 theta_a + n3 v_b + L n4 theta_b, its slope d/ds = (d1 v_a + L d2 theta_a + ...) / L."""
    x2 = xi * xi
    x3 = x2 * xi
    return (
        1 - 3 * x2 + 2 * x3,
        xi - 2 * x2 + x3,
        3 * x2 - 2 * x3,
        -x2 + x3,
        -6 * xi + 6 * x2,
        1 - 4 * xi + 3 * x2,
        6 * xi - 6 * x2,
        -2 * xi + 3 * x2,
    )


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _rot(R, U, o):
    """R @ U[o:o+3] as a tuple (global -> element axes)."""
    return (
        R[0, 0] * U[o] + R[0, 1] * U[o + 1] + R[0, 2] * U[o + 2],
        R[1, 0] * U[o] + R[1, 1] * U[o + 1] + R[1, 2] * U[o + 2],
        R[2, 0] * U[o] + R[2, 1] * U[o + 1] + R[2, 2] * U[o + 2],
    )


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def element_dofs(Rs, Us, e):
    """Element e's end displacements and rotations in its own axes (R @ each 3-vector), as a
    12-tuple (ua, ta, ub, tb); what axis_at needs besides xi."""
    R = Rs[e]
    o = 6 * e
    return _rot(R, Us, o) + _rot(R, Us, o + 3) + _rot(R, Us, o + 6) + _rot(R, Us, o + 9)


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def axis_at(Xs, Rs, Ls, e, xi, q):
    """axis_point from the element DOFs q = element_dofs(...) (hoisted out of the search's Newton
    iterations, which vary xi only)."""
    R = Rs[e]
    L = Ls[e]
    N1, n2, N3, n4, D1, d2, D3, d4 = hermite_cubics(xi)
    N2, N4, D2, D4 = L * n2, L * n4, L * d2, L * d4
    l0 = (1 - xi) * q[0] + xi * q[6]
    l1 = N1 * q[1] + N2 * q[5] + N3 * q[7] + N4 * q[11]
    l2 = N1 * q[2] - N2 * q[4] + N3 * q[8] - N4 * q[10]
    d0 = q[6] - q[0]
    d1 = D1 * q[1] + D2 * q[5] + D3 * q[7] + D4 * q[11]
    d2 = D1 * q[2] - D2 * q[4] + D3 * q[8] - D4 * q[10]
    px = Xs[e, 0] + xi * (Xs[e + 1, 0] - Xs[e, 0]) + R[0, 0] * l0 + R[1, 0] * l1 + R[2, 0] * l2
    py = Xs[e, 1] + xi * (Xs[e + 1, 1] - Xs[e, 1]) + R[0, 1] * l0 + R[1, 1] * l1 + R[2, 1] * l2
    pz = Xs[e, 2] + xi * (Xs[e + 1, 2] - Xs[e, 2]) + R[0, 2] * l0 + R[1, 2] * l1 + R[2, 2] * l2
    dx = Xs[e + 1, 0] - Xs[e, 0] + R[0, 0] * d0 + R[1, 0] * d1 + R[2, 0] * d2
    dy = Xs[e + 1, 1] - Xs[e, 1] + R[0, 1] * d0 + R[1, 1] * d1 + R[2, 1] * d2
    dz = Xs[e + 1, 2] - Xs[e, 2] + R[0, 2] * d0 + R[1, 2] * d1 + R[2, 2] * d2
    return px, py, pz, dx, dy, dz


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _frame_block(H, r0, c0, a, b, g, e0, e1, e2):
    """H[r0:r0+3, c0:c0+3] = a I + b e e^T + g [e]x (e a unit vector, [e]x v = e x v)."""
    H[r0, c0], H[r0, c0 + 1], H[r0, c0 + 2] = a + b * e0 * e0, b * e0 * e1 - g * e2, b * e0 * e2 + g * e1
    H[r0 + 1, c0], H[r0 + 1, c0 + 1], H[r0 + 1, c0 + 2] = b * e1 * e0 + g * e2, a + b * e1 * e1, b * e1 * e2 - g * e0
    H[r0 + 2, c0], H[r0 + 2, c0 + 1], H[r0 + 2, c0 + 2] = b * e2 * e0 - g * e1, b * e2 * e1 + g * e0, a + b * e2 * e2


@njit(cache=True, fastmath=FM, error_model="numpy")
def hermite_matrix(xi, L, R, H):
    """Global 6x12 interpolation matrix H of a straight beam element of length L (m) at xi in
    [0, 1] (dimensionless), written into H (dimensionless, except m on the rows of displacements
    from rotations and 1/m on the rows of rotations from displacements).

    Maps the element's 12 global DOFs to [ux uy uz rx ry rz] (global) at xi: Hermite cubics for
    the lateral displacements and the bending rotations (their slopes), linear for axial and twist;
    the shape functions of Eq. (9). R (3x3) is the element's direction-cosine matrix (rows: its
    local axes in global, right-handed): H = diag(R^T, R^T) H_local diag(R, R, R, R). Each local
    3x3 block is diag(axial, lateral, lateral) or lateral times the cross product with the local x
    axis, so each global block is a I + b e e^T + g [e]x with e = R[0] the element's direction,
    written directly (no products with R). The consistent nodal load of a point force F and moment
    Mo at xi is H^T [F; Mo]; it keeps the resultant and the moment of the load, because the shape
    functions reproduce rigid-body motion exactly.
    """
    n1, n2, n3, n4, d1, D2, d3, D4 = hermite_cubics(xi)
    N1, N2, N3, N4 = n1, L * n2, n3, L * n4
    D1, D3 = d1 / L, d3 / L  # (slopes along the element: d/ds = d/dxi / L)
    e0, e1, e2 = R[0, 0], R[0, 1], R[0, 2]
    # displacement rows: u = (1-xi) u_a e + N1 u_a,lat - N2 e x th_a + (same for b with N3, N4)
    _frame_block(H, 0, 0, N1, 1 - xi - N1, 0.0, e0, e1, e2)
    _frame_block(H, 0, 3, 0.0, 0.0, -N2, e0, e1, e2)
    _frame_block(H, 0, 6, N3, xi - N3, 0.0, e0, e1, e2)
    _frame_block(H, 0, 9, 0.0, 0.0, -N4, e0, e1, e2)
    # rotation rows: the slopes of the lateral displacement (e x u' terms) and linear twist
    _frame_block(H, 3, 0, 0.0, 0.0, D1, e0, e1, e2)
    _frame_block(H, 3, 3, D2, 1 - xi - D2, 0.0, e0, e1, e2)
    _frame_block(H, 3, 6, 0.0, 0.0, D3, e0, e1, e2)
    _frame_block(H, 3, 9, D4, xi - D4, 0.0, e0, e1, e2)


@njit(cache=True, fastmath=FM, error_model="numpy")
def hermite_matrix_slope(xi, L, R, A1):
    """dA/dxi, the derivative along the element of the displacement rows A = H[:3] of
    :func:`hermite_matrix` (same arguments: xi in [0, 1], L in m, R the direction cosines), written
    into A1 (3 x 12; m per unit xi on the rotation columns, dimensionless on the displacement
    columns): the exact slopes of the cubics of Eq. (9), so that dP/dxi = X_b - X_a + A1 q."""
    n1, n2, n3, n4, d1, d2, d3, d4 = hermite_cubics(xi)
    e0, e1, e2 = R[0, 0], R[0, 1], R[0, 2]
    # the derivatives of hermite_matrix's displacement blocks' coefficients (a, b, g)
    _frame_block(A1, 0, 0, d1, -1 - d1, 0.0, e0, e1, e2)
    _frame_block(A1, 0, 3, 0.0, 0.0, -L * d2, e0, e1, e2)
    _frame_block(A1, 0, 6, d3, 1 - d3, 0.0, e0, e1, e2)
    _frame_block(A1, 0, 9, 0.0, 0.0, -L * d4, e0, e1, e2)
