"""The constant loads of a body at rest, over all its DOFs in global axes (N, N.m): gravity, the
prestress's own load in the routing, and the load of a cable that is stress-free straight.

* gravity (Eq. 7): f = int N^T rho A g dx per element, the consistent nodal load of the cubic and
  linear shape functions; since those reproduce a rigid translation exactly, it is the consistent
  mass matrix (Eq. 4) times the rigid translation g at every node: f = M G.
* axial prestress N0 (the cable's tension T, the casing's compression -T): the element forces at
  rest, N0 along each chord, are the internal force vector f_int0 = sum_e N0 [-t_e; t_e]; what
  holds them is the load -f_int0: at an interior node N0 (t_e - t_(e-1)), towards the inside of
  the bend for a tension (T / R per length on an arc of radius R, the capstan's), outwards for the
  casing's compression, and N0 t along the tangent at the supports (the tension pulls on them).
* rest shape "straight": the cable bent into the routing carries the curvature strain
  eps0 = kappa b of the routing; its load is the consistent initial-strain load
  -int B^T D eps0 dx of each element (``element_beam.initial_curvature_load``), with the
  centerline's curvature vectors in each element's bending axes: on a route by segments each
  element's own end vectors (``Centerline.element_curvature``: the exact moments of the route's
  piecewise constant curvature over the element, a junction on its own side), so that a cantilever
  released from the route turns by exactly its total turning; on a spline or a polyline the nodal
  vectors, linear in each element. It assumes, like the whole
  linear model, small displacements: the wire's deflection within the gap (0.5 mm) is small
  against the bend radii (0.15 m), so the moment it carries is EI kappa of the routing.

The total load goes into the static state (timedomain/static_state.py) and stays on throughout
the time domain (docs/installed.md).
"""

from __future__ import annotations

import numpy as np

from .element_beam import initial_curvature_load, transformation


def gravity_load(M, g):
    """Consistent gravity load (N, N.m) of Eq. (7): the mass matrix M (kg, kg.m; all DOFs, six per
    node) times the rigid translation g (m/s2, global [x, y, z]) at every node."""
    n = M.shape[0] // 6
    G = np.zeros(M.shape[0])
    for c in range(3):
        G[c::6] = g[c]
    return np.asarray(M @ G).ravel() if n else G


def prestress_load(centerline, N0):
    """-f_int0 (N, all DOFs) of the axial force N0 (N, tension positive) in every element along its
    chord: +N0 t_e at the element's first node and -N0 t_e at its second."""
    ne = centerline.n_elements
    f = np.zeros(6 * (ne + 1))
    for e in range(ne):
        t = centerline.frames[e, 0]
        f[6 * e : 6 * e + 3] += N0 * t
        f[6 * e + 6 : 6 * e + 9] -= N0 * t
    return f


def rest_shape_load(centerline, EI):
    """The load (N, N.m, all DOFs) of a body that is stress-free straight, bent into the centerline:
    per element the initial-strain load of the routing's curvature vectors at its two ends (the
    element's own, ``element_curvature``, where the route gives them, else those of its two nodes;
    their components about the element's local y and z axes), in global axes. EI in N.m2."""
    ne = centerline.n_elements
    f = np.zeros(6 * (ne + 1))
    kv = centerline.curvature_vectors
    ke = centerline.element_curvature
    for e in range(ne):
        R = centerline.frames[e]
        k1, k2 = (R @ kv[e], R @ kv[e + 1]) if ke is None else (R @ ke[e, 0], R @ ke[e, 1])
        fl = initial_curvature_load(centerline.lengths[e], EI, k1[1:], k2[1:])
        f[6 * e : 6 * e + 12] += transformation(R).T @ fl
    return f
