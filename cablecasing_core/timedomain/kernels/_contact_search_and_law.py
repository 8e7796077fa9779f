"""Contact search and contact law (Eqs. 14, 24, 29-39): where the normal plane of a cable node cuts
the deformed casing axis, the cheap far-from-wall test that most nodes pass, the penetration's
normal force (linear, Eq. 24, or Hertz, Eq. 29) and the elastic energy stored in the contacts.
Hertz's constant 4/3 E* r^1/2 (Eqs. 27-28) comes in as ``k_hertz``, from
``timedomain.engine.hertz_constant``."""

from __future__ import annotations

import numpy as np
from numba import njit

from ._compile_options import FM
from ._hermite_interpolation import axis_at, element_dofs


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def contact_law(g, law, k_lin, k_hertz):
    """Normal elastic force (N) and its slope (N/m) at penetration g (m): linear (Eq. 24, law 1) or
    Hertz (Eq. 29, law 0, and the elastic part of Hunt-Crossley, law 2) with k_hertz = 4/3 E* r^1/2;
    zero for g <= 0 (no adhesion)."""
    if g <= 0.0:
        return 0.0, 0.0
    if law != 1:
        sg = np.sqrt(g)
        return k_hertz * g * sg, 1.5 * k_hertz * sg
    return k_lin * g, k_lin


@njit(cache=True, fastmath=FM, error_model="numpy")
def contact_potential(g, law, k_lin, k_hertz, share):
    """Elastic energy (J) stored in contacts of penetrations g (m, one per cable node): the integral
    of :func:`contact_law`, 2/5 k_hertz g^5/2 (Hertz, Hunt-Crossley) or k_lin g^2 / 2 (linear), zero for g <= 0,
    times each node's share of the law (``share``, dimensionless, one per node: ``engine.contact_shares``)."""
    e = 0.0
    for i in range(g.shape[0]):
        if g[i] > 0.0:
            e += share[i] * (0.4 * k_hertz * g[i] * g[i] * np.sqrt(g[i]) if law != 1 else 0.5 * k_lin * g[i] * g[i])
    return e


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def cable_node(Xc, Tc, Uc, i):
    """Deformed position (m) and tangent (not normalised; small rotations) of cable node i."""
    o = 6 * i
    T0, T1, T2 = Tc[i, 0], Tc[i, 1], Tc[i, 2]
    th0, th1, th2 = Uc[o + 3], Uc[o + 4], Uc[o + 5]
    return (
        Xc[i, 0] + Uc[o],
        Xc[i, 1] + Uc[o + 1],
        Xc[i, 2] + Uc[o + 2],
        T0 + th1 * T2 - th2 * T1,
        T1 + th2 * T0 - th0 * T2,
        T2 + th0 * T1 - th1 * T0,
    )


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _chord(x0, x1, x2, t0, t1, t2, Xs, Ls, Us, e):
    """The normal plane of a cable node (point x, tangent t of any length) against the chord of
    casing element e between its deformed nodes (Eqs. 37, 39): (den, xi, reach). xi = num/den is
    where the plane cuts the chord (no cut when den = 0); reach (m) bounds the node's distance from
    the element's Hermite axis at that cut from above (to first order in the rotations, as the
    axis itself): the distance from the chord plus the most the axis can depart from it. In the
    element's axes the departure is N2 (theta_a - psi) + N4 (theta_b - psi), bending components
    only, psi = e0 x (u_b - u_a) / L the chord's rotation (e0 the element's direction, N2, N4 the
    Hermite slope functions of Eq. 9, |N2| + |N4| <= L/4): a rigidly moving element does not
    depart from its chord however far it turns."""
    o = 6 * e
    L = Ls[e]
    a0, a1, a2 = Xs[e, 0] + Us[o], Xs[e, 1] + Us[o + 1], Xs[e, 2] + Us[o + 2]
    b0, b1, b2 = Xs[e + 1, 0] + Us[o + 6], Xs[e + 1, 1] + Us[o + 7], Xs[e + 1, 2] + Us[o + 8]
    den = (b0 - a0) * t0 + (b1 - a1) * t1 + (b2 - a2) * t2
    num = (x0 - a0) * t0 + (x1 - a1) * t1 + (x2 - a2) * t2
    xi = num / den
    dl = (a0 + xi * (b0 - a0) - x0) ** 2 + (a1 + xi * (b1 - a1) - x1) ** 2 + (a2 + xi * (b2 - a2) - x2) ** 2
    e0, e1, e2 = (Xs[e + 1, 0] - Xs[e, 0]) / L, (Xs[e + 1, 1] - Xs[e, 1]) / L, (Xs[e + 1, 2] - Xs[e, 2]) / L
    u0, u1, u2 = Us[o + 6] - Us[o], Us[o + 7] - Us[o + 1], Us[o + 8] - Us[o + 2]
    p0, p1, p2 = (e1 * u2 - e2 * u1) / L, (e2 * u0 - e0 * u2) / L, (e0 * u1 - e1 * u0) / L  # psi
    # |theta - psi| without the twist (psi has none: it is normal to e0), at either end
    w0, w1, w2 = Us[o + 3] - p0, Us[o + 4] - p1, Us[o + 5] - p2
    v0, v1, v2 = Us[o + 9] - p0, Us[o + 10] - p1, Us[o + 11] - p2
    tw, tv = w0 * e0 + w1 * e1 + w2 * e2, v0 * e0 + v1 * e1 + v2 * e2
    ba = np.sqrt(max(w0 * w0 + w1 * w1 + w2 * w2 - tw * tw, 0.0))
    bb = np.sqrt(max(v0 * v0 + v1 * v1 + v2 * v2 - tv * tv, 0.0))
    return den, xi, np.sqrt(dl) + 0.25 * L * (ba + bb)


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _cut_on_axis(x0, x1, x2, t0, t1, t2, Xs, Rs, Ls, Us, e, xi):
    """Where the normal plane of a cable node (point x, unit tangent t) cuts the Hermite axis of
    casing element e (Eq. 39): Newton on phi(xi) = (p(xi) - x) . t from xi in [0, 1], kept in [0, 1].
    Returns (xi, px, py, pz, converged): the axis point p (m) at xi."""
    q = element_dofs(Rs, Us, e)
    px, py, pz, dx, dy, dz = axis_at(Xs, Rs, Ls, e, xi, q)
    for _ in range(4):
        phi = (px - x0) * t0 + (py - x1) * t1 + (pz - x2) * t2
        dphi = dx * t0 + dy * t1 + dz * t2
        if abs(dphi) < 1e-300:
            break
        xn = min(max(xi - phi / dphi, 0.0), 1.0)
        if abs(xn - xi) <= 1e-10:
            # converged: xi within ~1e-10 of the root, a few pm along the element; the distance
            # to the axis, measured in the normal plane, changes only to second order
            return xi, px, py, pz, True
        xi = xn
        px, py, pz, dx, dy, dz = axis_at(Xs, Rs, Ls, e, xi, q)
    return xi, px, py, pz, False


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def follow_cut(x0, x1, x2, t0, t1, t2, Xs, Rs, Ls, Us, e, xi):
    """The cut of a node's normal plane on the casing axis followed from where it was (element e,
    coordinate xi inside it; the sub-steps of a recomputed step, where it moves by ~1e-6 of the
    element): (found, xi, px, py, pz), found when the Newton of :func:`_cut_on_axis` converges
    strictly inside e, where :func:`search_node` would find the same cut (a plane that cuts e's axis
    away from its ends cuts no neighbour; see there). Otherwise the caller searches."""
    xi, px, py, pz, ok = _cut_on_axis(x0, x1, x2, t0, t1, t2, Xs, Rs, Ls, Us, e, xi)
    return ok and 0.0 < xi < 1.0, xi, px, py, pz


#: the elements on either side of a node's last one that its contact search looks at (search_node)
SEARCH_WINDOW = 2


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def search_node(x0, x1, x2, t0, t1, t2, Xs, Rs, Ls, Us, e_guess, far_below):
    """Contact search of one cable node (point x, unit tangent t, as scalars); see search_casing.
    Returns (element, xi, far, p): p = (px, py, pz) the axis point at xi when refined (else NaN);
    element -1 when the normal plane cuts no chord within SEARCH_WINDOW elements of e_guess.

    Only the elements e_guess, +1, -1, +2, -2 are looked at, in that order: between two searches of
    a node (a step of the time domain; an accepted iterate of the static Newton, whose rejected
    trials do not move the guess) it moves along the casing by far less than an element, and the
    normal planes leave no gap at an interior casing node (a plane near the vertex cuts one chord
    or the other), so a plane that cuts none of them lies beyond an end of the casing: no contact.
    A cut farther along the casing is on another part of it, not the node's own section (on a route
    that comes back past its start, ~0.3 m away: it was read as a penetration of 0.28 m)."""
    ne = Ls.shape[0]
    best_e, best_xi, best_d = -1, np.nan, 1e300
    bx, by, bz = np.nan, np.nan, np.nan
    for de in range(0, 2 * SEARCH_WINDOW + 1):
        off = (de + 1) // 2 * (1 if de % 2 == 1 else -1)
        e = e_guess + off
        if e < 0 or e >= ne:
            continue
        den, xi, reach = _chord(x0, x1, x2, t0, t1, t2, Xs, Ls, Us, e)  # Eq. (39) on the chord
        if abs(den) < 1e-300:
            continue
        if xi < -1e-9 or xi > 1 + 1e-9:
            continue
        if reach < far_below:  # cheap exit: a node this far inside cannot touch (returned as far)
            return e, xi, True, np.nan, np.nan, np.nan
        xi, px, py, pz, _ = _cut_on_axis(x0, x1, x2, t0, t1, t2, Xs, Rs, Ls, Us, e, min(max(xi, 0.0), 1.0))
        d = (px - x0) ** 2 + (py - x1) ** 2 + (pz - x2) ** 2
        if best_e < 0 and 0.01 < xi < 0.99:
            # well inside the element: the plane cannot cut a neighbour within the +-2 elements
            # looked at (the axis turns by far less than a right angle over them)
            return e, xi, False, px, py, pz
        if d < best_d:
            best_d, best_e, best_xi = d, e, xi
            bx, by, bz = px, py, pz
        if abs(off) >= 2 and best_e >= 0:
            break
    return best_e, best_xi, False, bx, by, bz


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def search_cable_node(Xc, Tc, Uc, Xs, Rs, Ls, Us, elem, i, gap):
    """Cable node i's deformed position and unit tangent and its contact search (:func:`search_node`
    from its last element elem[i], which it updates when an element is found). Returns
    (e, xi, far, px, py, pz, x0, x1, x2): the element (-1: none), its coordinate, the far-from-wall
    flag, the axis point and the node. The contact solve of a step and the static state share it."""
    x0, x1, x2, t0, t1, t2 = cable_node(Xc, Tc, Uc, i)
    tn = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
    t0, t1, t2 = t0 / tn, t1 / tn, t2 / tn
    e, xi, far, px, py, pz = search_node(x0, x1, x2, t0, t1, t2, Xs, Rs, Ls, Us, elem[i], gap)
    if e >= 0:
        elem[i] = e
    return e, xi, far, px, py, pz, x0, x1, x2


@njit(cache=True, fastmath=FM, error_model="numpy")
def far_from_wall(Xc, Tc, Uc, Xs, Ls, Us, elem, gap, far):
    """far[i]: cable node i certainly lies farther than ``gap`` (m) inside the wall, by the cheap
    test of :func:`search_node` on its previous element elem[i] alone (the normal plane cuts that
    element's chord, and the node is within the gap of it by more than the Hermite axis can depart
    from the chord). Most nodes pass it in most steps; one branch-free pass over all nodes (it
    vectorises) is much cheaper than the per-node search they then skip. Nodes that fail it get the
    full search."""
    ne = Ls.shape[0]
    for i in range(Xc.shape[0]):
        x0, x1, x2, t0, t1, t2 = cable_node(Xc, Tc, Uc, i)
        e = min(max(elem[i], 0), ne - 1)
        den, xi, reach = _chord(x0, x1, x2, t0, t1, t2, Xs, Ls, Us, e)
        far[i] = (elem[i] == e) & (abs(den) >= 1e-300) & (xi >= -1e-9) & (xi <= 1 + 1e-9) & (reach < gap)


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def tangent_basis(n0, n1, n2, ta, tb):
    """Write two unit vectors completing n to a right-handed orthonormal basis into ta, tb."""
    r0, r1, r2 = (1.0, 0.0, 0.0) if abs(n0) < 0.9 else (0.0, 1.0, 0.0)
    dn = r0 * n0 + r1 * n1 + r2 * n2
    a0, a1, a2 = r0 - dn * n0, r1 - dn * n1, r2 - dn * n2
    s = np.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    ta[0], ta[1], ta[2] = a0 / s, a1 / s, a2 / s
    tb[0] = n1 * ta[2] - n2 * ta[1]
    tb[1] = n2 * ta[0] - n0 * ta[2]
    tb[2] = n0 * ta[1] - n1 * ta[0]
