"""The frictionless contact of every cable node at a given state, for the static equilibrium
(timedomain/static_state.py): the time domain's own normal-plane search (Eqs. 36-39, in the frame
of Eqs. 32-35), penetration (Eqs. 14, 30-31) and law (Eq. 24 or 29), and the generalized forces on
both bodies that the step loop's contact solve applies for a normal force (its moment arms lie
along the normal, so a frictionless contact has no moment), with what the static Newton needs for
its tangent."""

from __future__ import annotations

import numpy as np
from numba import njit

from ._compile_options import FM
from ._contact_search_and_law import contact_law, search_cable_node
from ._hermite_interpolation import hermite_matrix


@njit(cache=True, fastmath=FM, error_model="numpy")
def static_contact(
    Xc, Tc, Uc, Xs, Rs, Ls, Us, elem, gap, law, k_lin, k_hertz, share, g, h, N, kn, nrm, xi, H, fcc, fcs
):
    """Contact of each cable node with the casing at the displacements Uc, Us (m, rad; all DOFs of
    cable and casing) for the frictionless static state.

    Xc, Tc: cable nodes and unit tangents at rest; Xs, Rs, Ls: casing nodes, element frames and
    lengths; elem: each node's casing element of the last search (updated); gap (m): the radial
    gap e; law, k_lin (N/m), k_hertz (N/m^1.5): the contact law (0 Hertz, 1 linear), times each
    node's share of it (``share``, dimensionless, one per node: ``engine.contact_shares``). Writes per
    node g (m, penetration, 0 where none), h (m, distance of the cable node from the casing axis
    where in contact), N (N, normal force) and kn (N/m, its slope dN/dg), nrm (unit normal from
    the casing axis towards the cable node), xi and H (the 6 x 12 interpolation matrix of the
    casing element at xi), and the generalized contact forces on the cable, fcc (-N n at the node),
    and the casing, fcs (H^T [N n; 0] on the element). Returns the number of nodes in contact."""
    for j in range(fcc.shape[0]):
        fcc[j] = 0.0
    for j in range(fcs.shape[0]):
        fcs[j] = 0.0
    nk = 0
    for i in range(Xc.shape[0]):
        g[i], h[i], N[i], kn[i] = 0.0, 0.0, 0.0, 0.0
        e, x, far, px, py, pz, x0, x1, x2 = search_cable_node(Xc, Tc, Uc, Xs, Rs, Ls, Us, elem, i, gap)
        if e < 0 or far:
            continue
        r0, r1, r2 = x0 - px, x1 - py, x2 - pz
        d = np.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
        if d - gap <= 0.0 or d == 0.0:
            continue
        n0, n1, n2 = r0 / d, r1 / d, r2 / d
        fe, ke = contact_law(d - gap, law, k_lin, k_hertz)
        fe, ke = fe * share[i], ke * share[i]
        g[i], h[i], N[i], kn[i], xi[i] = d - gap, d, fe, ke, x
        nrm[i, 0], nrm[i, 1], nrm[i, 2] = n0, n1, n2
        Hi = H[i]
        hermite_matrix(x, Ls[e], Rs[e], Hi)
        o = 6 * i
        fcc[o] -= fe * n0
        fcc[o + 1] -= fe * n1
        fcc[o + 2] -= fe * n2
        for c in range(12):
            fcs[6 * e + c] += fe * (Hi[0, c] * n0 + Hi[1, c] * n1 + Hi[2, c] * n2)
        nk += 1
    return nk
