"""The 12-DOF spatial Euler-Bernoulli beam element (Eqs. 4-9).

This is where the bending, torsion and axial equations of the beams (Eqs. 1-3) are discretised:
their finite-element form is the mass and stiffness of :func:`local_matrices`. The element damping
C_e of Eq. 5 is not built per element: the bodies' damping is Rayleigh's C = alpha M + beta K of the
assembled matrices (Eq. 40, Eq. 5 assembled), applied where it acts (``frequency.trfam``,
``timedomain.body_storage``, the Newmark kernels).

Local DOF order (Eq. 8): ``[u1 v1 w1 gamma1 xi1 zeta1 u2 v2 w2 gamma2 xi2 zeta2]``: axial
displacement, the two lateral displacements, twist, and the rotations about local y and z.
Bending uses cubic Hermite polynomials in both planes, axial and torsion linear polynomials.
The mass matrix is consistent (Eq. 4) with the torsional rotary inertia rho*Ip; the bending
rotary inertia is left out, as Euler-Bernoulli theory does. Matrices go to global axes with the
direction-cosine matrix R (rows: local axes in global coordinates): K_g = T^T K T, T = diag(R,R,R,R).

The same element with an axial force P (tension positive) is a beam-column: its geometric
stiffness (:func:`geometric_stiffness`) is the consistent one of these shape functions, and a
curvature strain that the body carries at rest (a cable that is stress-free straight, bent into
the routing) loads it by the consistent initial-strain load of :func:`initial_curvature_load`.
Gravity's consistent load (Eq. 7) is the mass matrix times the rigid translation g (see
``structure/loads.py``).
"""

from __future__ import annotations

import numpy as np


def _plane_blocks(L):
    """Hermite bending stiffness (times L^3/EI) and mass (times 420/(m)) in (v, rot) order."""
    k = np.array(
        [
            [12.0, 6 * L, -12.0, 6 * L],
            [6 * L, 4 * L * L, -6 * L, 2 * L * L],
            [-12.0, -6 * L, 12.0, -6 * L],
            [6 * L, 2 * L * L, -6 * L, 4 * L * L],
        ]
    )
    m = np.array(
        [
            [156.0, 22 * L, 54.0, -13 * L],
            [22 * L, 4 * L * L, 13 * L, -3 * L * L],
            [54.0, 13 * L, 156.0, -22 * L],
            [-13 * L, -3 * L * L, -22 * L, 4 * L * L],
        ]
    )
    return k, m


def local_matrices(L, E, G, A, I, J, rho, Ip):
    """Local stiffness (N/m, N, N.m) and consistent mass (kg, kg.m, kg.m2) of one element.

    Parameters: L length (m), E Young's modulus (Pa), G shear modulus (Pa), A area (m2),
    I second moment per bending plane (m4), J torsion constant (m4), rho density (kg/m3),
    Ip polar moment for rotary inertia (m4). Returns (K, M), each 12x12, Eqs. (4) and (6).
    """
    K = np.zeros((12, 12))
    M = np.zeros((12, 12))
    m = rho * A * L
    for (i, j), kv, mv in (((0, 6), E * A / L, m), ((3, 9), G * J / L, rho * Ip * L)):
        K[np.ix_([i, j], [i, j])] = kv * np.array([[1.0, -1.0], [-1.0, 1.0]])
        M[np.ix_([i, j], [i, j])] = mv / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
    kb, mb = _plane_blocks(L)
    # plane x-y: (v, rotation about z); plane x-z: (w, rotation about y) with the sign of the
    # rotation reversed (a positive rotation about y lowers w ahead of the node).
    for idx, sign in (([1, 5, 7, 11], 1.0), ([2, 4, 8, 10], -1.0)):
        S = np.diag([1.0, sign, 1.0, sign])
        K[np.ix_(idx, idx)] = E * I / L**3 * (S @ kb @ S)
        M[np.ix_(idx, idx)] = m / 420.0 * (S @ mb @ S)
    return K, M


def geometric_stiffness(L, P, A, Ip):
    """Local geometric stiffness (N/m, N, N.m) of an element under the axial force P (N, tension
    positive), consistent with the element's shape functions (Eq. 9): the second-order work
    P/2 int (u'^2 + v'^2 + w'^2) dx of the axial force on the slopes, and the Wagner term P Ip/A of the
    twist (Przemieniecki, Theory of Matrix Structural Analysis, 1968, Sec. 15; McGuire, Gallagher
    and Ziemian, Matrix Structural Analysis, 2nd ed., Eq. 9.18, without the end-moment terms). In
    each bending plane, in (v, rotation) order: P/(30 L) [[36, 3L, -36, 3L], [3L, 4L^2, -3L, -L^2],
    [-36, -3L, 36, -3L], [3L, -L^2, -3L, 4L^2]]. L (m), A (m2), Ip (m4, polar moment). 12x12."""
    G = np.zeros((12, 12))
    bar = np.array([[1.0, -1.0], [-1.0, 1.0]])
    G[np.ix_([0, 6], [0, 6])] = P / L * bar
    G[np.ix_([3, 9], [3, 9])] = P * Ip / (A * L) * bar
    g = (
        P
        / (30.0 * L)
        * np.array(
            [
                [36.0, 3 * L, -36.0, 3 * L],
                [3 * L, 4 * L * L, -3 * L, -L * L],
                [-36.0, -3 * L, 36.0, -3 * L],
                [3 * L, -L * L, -3 * L, 4 * L * L],
            ]
        )
    )
    for idx, sign in (([1, 5, 7, 11], 1.0), ([2, 4, 8, 10], -1.0)):
        S = np.diag([1.0, sign, 1.0, sign])
        G[np.ix_(idx, idx)] = S @ g @ S
    return G


def initial_curvature_load(L, EI, k1, k2):
    """Local consistent load (N, N.m), 12 values, of a curvature strain the element carries with no
    displacement: f = -int B^T D eps0 dx (Eq. 6's B and D), eps0 the curvature vector of the
    reference shape relative to the stress-free one, linear along the element between its local
    (y, z) components k1 at end 1 and k2 at end 2 (1/m). The bending strains are the curvatures
    kappa_z = v'' and kappa_y = -w'' of the cubic Hermite displacement, so per plane (exact for a
    linear eps0): moments EI k1 at end 1 and -EI k2 at end 2, and the shear pair -+EI (k2 - k1)/L
    of its gradient. A uniform curvature (an arc) therefore loads only the element's ends, and its
    interior nodes not at all; the load lives where the curvature changes. EI in N.m2."""
    f = np.zeros(12)
    (ky1, kz1), (ky2, kz2) = k1, k2
    # plane x-y (v, rotation about z), curvature kappa_z = v''
    f[[1, 5, 7, 11]] = -EI * np.array([(kz2 - kz1) / L, -kz1, -(kz2 - kz1) / L, kz2])
    # plane x-z (w, rotation about y), curvature kappa_y = -w''
    f[[2, 4, 8, 10]] = -EI * np.array([-(ky2 - ky1) / L, -ky1, (ky2 - ky1) / L, ky2])
    return f


def transformation(R):
    """12x12 transformation T = diag(R, R, R, R) from global to local element DOFs."""
    T = np.zeros((12, 12))
    for b in range(4):
        T[3 * b : 3 * b + 3, 3 * b : 3 * b + 3] = R
    return T


def global_matrices(L, R, E, G, A, I, J, rho, Ip):
    """Element stiffness and mass in global axes: T^T K T, T^T M T (units as local_matrices)."""
    K, M = local_matrices(L, E, G, A, I, J, rho, Ip)
    T = transformation(R)
    return T.T @ K @ T, T.T @ M @ T
