"""Whether the structure as built can carry its loads: each body held against every rigid motion
its loads would move, checked before any work (when a model is validated).

A body with a clamped support has no rigid motion left. A body held by springs alone (isolators
at its ends, clips along it: structure/mount_element.py) is held against the rigid motions that
its mounts' static stiffness resists. These are exact and mesh-independent: a rigid motion of the
body is a translation t and a small rotation w about a reference point x0 (its centre of mass: the
centroid of its elements' midpoints weighted by their lengths, where its weight has no moment),
u(x) = t + w x (x - x0), rotations w, which the beam elements carry without strain; on the
six coordinates a = [t, L w] (m, L the body's length) the mounts' stiffness is the 6 x 6 matrix

    S = sum over mounts  Q_m^T K6_m Q_m,    Q_m = [[I, -[x_m - x0]x / L], [0, I / L]]

(N/m; x_m the mount's node, K6_m its 6 x 6 stiffness in global axes), the elastic stiffness K_E of
the structure on its rigid motions. Its null space is the null space of K_E: the rigid motions
that nothing holds (a mechanism). The body's loads have the generalised force F = [W, M / L] on
them: its weight W = m g (N) and the weight's moment M about x0 (N.m), from the element masses at
their chords' midpoints (what the consistent mass matrix gives for a rigid motion). The prestress
of a tension and the rest shape of a straight cable are self-equilibrated (no resultant).

A model is refused (:class:`~cablecasing_core.errors.ModelError`, one line naming the load, the
supports and the direction) when:

* a tension (``loads.cable_tension``) is applied to a body with a free end, or an end on an
  isolator with no stiffness along the body's axis: neither carries an axial force, so the tension
  (the casing's compression) has nowhere to go;
* the isolators at a body's ends are so soft along its axis that the tension would stretch them by
  T (1/k_A + 1/k_B) > :data:`STRETCH` of the body's length L (k_A, k_B their axial stiffness,
  N/m; a clamped end counts 1/k = 0): the linear static state holds the body's mean axial force
  at T, but its ends move in by the stretch, a mean strain eps = -stretch / L on which the
  geometric stiffness's axial term (T / L_e per element) carries a share, so the isolators carry
  T / (1 + stretch / L) instead of T (k = 1e3 N/m, T = 10 N, L = 1 m: 9.80 N; k = 1e-3: 0.0005 N);
* a loaded body (gravity, a tension, a straight cable's rest shape) has a rigid motion that its
  mounts do not hold (eigenvalue of S below :data:`NULL` times its largest: rounding): the static state would
  be singular, however fine the mesh. The message says whether the mounts give that motion no
  stiffness, or one that counts as none, below the threshold (0.02 N.m/rad of torsion beside
  isolators of 1e12 N/m, whose threshold is 0.0284 N.m/rad on a metre's casing): then with that
  stiffness, the mounts giving it, the largest stiffness and the threshold on the motion (SI units),
  which a stiffness there must exceed;
* its mounts hold it, but so softly that its weight would move it rigidly by more than its length
  (S^-1 F): the linear static state means nothing there.

The contact with the other body is not counted as a support: frictionless and one-sided at rest,
it holds no axial load and no rotation about the centerline.
"""

from __future__ import annotations

import numpy as np

from ..errors import ModelError

#: Eigenvalues of the mounts' rigid stiffness S below this fraction of its largest count as zero:
#: 64 rounding units, above the error of a symmetric eigensolver (~ eps |S|), so that a zero
#: stiffness gives a zero and any spring (however soft beside a rigid one: 1 N.m/rad beside 1e12 N/m
#: is 5e-13) does not; a soft spring's effect is bounded by the rigid displacement S^-1 F.
NULL = 64 * np.finfo(float).eps

#: The largest axial stretch of a body's end isolators under the tension, T (1/k_A + 1/k_B), as a
#: fraction of the body's length: the force the isolators carry in the linear static state is
#: T / (1 + stretch / L), so at 1 % it is within 1 % of T (a tension given to a few percent), and
#: beyond it the static state's tension drifts from the one given (to nothing as k goes to 0).
STRETCH = 0.01


def _rows(r, L):
    """Q (6 x 6): a node's [u, theta] from the rigid coordinates [t, L w], r = x_node - x0 (m)."""
    Q = np.zeros((6, 6))
    Q[:3, :3] = np.eye(3)
    Q[:3, 3:] = -np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]]) / L
    Q[3:, 3:] = np.eye(3) / L
    return Q


def centre_of_mass(centerline):
    """The centroid (m) of a uniform body on ``centerline``: its elements' chord midpoints weighted
    by their lengths (what the consistent mass matrix gives for a rigid motion)."""
    mid = 0.5 * (centerline.nodes[1:] + centerline.nodes[:-1])
    return (centerline.lengths @ mid) / centerline.lengths.sum()


def rigid_stiffness(nodes, mounts, L, x0):
    """S: the mounts' stiffness on the body's rigid motions (6 x 6, N/m, coordinates [t, L w] about
    the reference point x0, m)."""
    S = np.zeros((6, 6))
    for m in mounts:
        Q = _rows(nodes[m.node] - x0, L)
        S += Q.T @ m.K6 @ Q
    return 0.5 * (S + S.T)


def rigid_load(centerline, mass_per_length, gravity, x0, L):
    """F (6): the weight (N) and its moment about x0 over L (N) of a body of ``mass_per_length``
    (kg/m) on ``centerline`` under ``gravity`` (m/s2)."""
    g = np.asarray(gravity, dtype=float)
    mid = 0.5 * (centerline.nodes[1:] + centerline.nodes[:-1])
    m = mass_per_length * centerline.lengths
    W = m.sum() * g
    M = np.cross(mid - x0, g).T @ m
    return np.concatenate([W, M / L])


def describe(a, x0, L):
    """A rigid motion [t, L w] in words: a translation along a unit vector, or a rotation about an
    axis through a point (m, three significant digits)."""
    t, w = a[:3], a[3:] / L
    if np.linalg.norm(w) * L <= 1e-6 * np.linalg.norm(a):
        d = t / np.linalg.norm(t)
        return f"a translation along {_vec(d)}"
    axis = w / np.linalg.norm(w)
    p = x0 + np.cross(w, t) / (w @ w)  # (the point of the screw axis nearest to x0)
    return f"a rotation about {_vec(axis)} through {_vec(p, L)} m"


def _vec(v, scale=0.0):
    """``v`` to three digits, its components below 5e-4 of ``scale`` or of its largest written 0
    (a point at the origin is [0, 0, 0], not rounding's [-1.11e-16, ...])."""
    v = np.where(np.abs(v) < 5e-4 * max(np.abs(v).max(), scale), 0.0, v)  # (no -0.0 and 1e-17)
    return "[" + ", ".join(f"{x:.3g}" for x in v + 0.0) + "]"


def _analysis(centerline, mounts, clamped, mass_per_length, gravity):
    """(null basis (6 x k), description of the free motion most loaded or None, rigid displacement
    of the weight at its worst node (m), F, x0, L, that free motion as unit coordinates [t, L w] or
    None, the largest eigenvalue of S (N/m))."""
    L = centerline.length
    x0 = centre_of_mass(centerline)
    S = rigid_stiffness(centerline.nodes, mounts, L, x0)
    F = rigid_load(centerline, mass_per_length, gravity, x0, L)
    if clamped:
        return np.zeros((6, 0)), None, 0.0, F, x0, L, None, np.inf
    w, V = np.linalg.eigh(S)
    top = max(float(w.max()), 0.0)
    null = w <= NULL * top if top > 0.0 else np.ones(6, bool)
    Z = V[:, null]
    if Z.shape[1]:
        v = Z @ (Z.T @ F)  # (the free motion the loads drive; else the first one)
        a = v if np.linalg.norm(v) > 1e-9 * max(np.linalg.norm(F), 1e-300) else Z[:, 0]
        a = a / np.linalg.norm(a)
        return Z, describe(a, x0, L), np.inf, F, x0, L, a, top
    a = V @ ((V.T @ F) / w)
    u = max(np.linalg.norm((_rows(x - x0, L) @ a)[:3]) for x in centerline.nodes[[0, -1]])
    return Z, None, float(u), F, x0, L, None, top


def _unresolved(a, nodes, mounts, given, x0, L, top):
    """What the mounts give the free rigid motion ``a`` (unit coordinates [t, L w]) that the rule
    takes for no stiffness, S's eigenvalue there being at most :data:`NULL` of its largest ``top``
    (N/m): (stiffness, threshold, unit, the mounts that give it), per metre of the motion (N/m) for
    a translation, per radian (N.m/rad) for a rotation; stiffness 0.0 when the mounts give it none.
    ``given``: each mount's stiffness as the model gives it, (translational N/m, rotational N.m/rad)
    in its local axes (not K6's diagonal turned back, which rounds 1e-3 beside 1e12 to 0). Summed
    over the mounts' stiffness components (k_j along local axis j, translation or rotation),
    each k_j (v_j . a)^2 with v_j its row of S's coordinates (S = sum k_j v_j v_j^T), only where the
    motion moves the component by more than 1e-6 of its unit: a stiff component that the null motion
    does not move gets a share that is the rounding of the eigenvector (~ eps), which k_j (v_j . a)^2
    would count as 1e12 * 1e-32 N/m and so report a stiffness where none is given. A stiff component
    the motion does move counts with its share, which is small (review BF1: on a bent casing the
    twist of each end's isolator, 1.5 N.m/rad about the end tangent, at 85 degrees from the free
    rotation about the chord, holds it by 1.5 cos^2 85 = 0.0114 N.m/rad)."""
    floor, total, who = NULL * top, 0.0, []
    for m, stiffness in zip(mounts, given):
        Q = _rows(nodes[m.node] - x0, L)
        part = 0.0
        for k, rows in zip(stiffness, (slice(0, 3), slice(3, 6))):
            for j in range(3):
                e = np.zeros(6)
                e[rows] = m.axes[j]
                v = Q.T @ e
                va = float(v @ a)
                if k[j] > 0.0 and va * va > 1e-12 * (v @ v):
                    part += k[j] * va * va
        if part > 0.0:
            total += part
            who.append(m)
    scale, unit, _ = _per_unit(a, L)
    return total / scale, floor / scale, unit, who


def _per_unit(a, L):
    """(|a|^2 per unit of the motion, its unit, its kind) of a rigid motion ``a`` = [t, L w]: per
    metre (N/m) of a translation (as :func:`describe` tells it), per radian (N.m/rad) of a rotation,
    so that a^T S a / scale is its stiffness in SI units."""
    w = a[3:] / L
    if np.linalg.norm(w) * L <= 1e-6 * np.linalg.norm(a):
        return float(a[:3] @ a[:3]), "N/m", "a translation"
    return float(w @ w), "N.m/rad", "a rotation"


def _mount_name(body, m):
    """The model file's key of mount ``m`` of ``body``: ``<body>.isolator.A``, ``casing.clip[0]``."""
    return f"{body}.isolator.{m.support}" if m.support else f"{body}.clip[{m.label[4:]}]"


def _no_stiffness(name, data, mounts, nodes, a, x0, L, top):
    """Why the mounts leave the free motion ``a`` free, in words, and what would hold it: (reason,
    remedy; ``data``: the body's table of the model file, for its mounts' stiffness as given). They
    give it none (reason "the mounts have no stiffness there", remedy None), or a stiffness that
    the rule takes for none (:func:`_unresolved`): then the reason gives it, the mounts that give
    it, the threshold and the largest stiffness it is relative to (SI units), and the remedy a
    stiffness above the threshold."""
    keys = [data["isolator"][m.support] if m.support else data["clip"][int(m.label[4:])] for m in mounts]
    k = [(np.asarray(c["stiffness"], float), np.asarray(c["rotational_stiffness"], float)) for c in keys]
    given, threshold, unit, who = _unresolved(a, nodes, mounts, k, x0, L, top)
    if given <= 0.0:
        return "the mounts have no stiffness there", None
    w, V = np.linalg.eigh(rigid_stiffness(nodes, mounts, L, x0))
    scale, per, kind = _per_unit(V[:, -1], L)
    reason = (
        f"the mounts' stiffness there, {given:.3g} {unit} from {' and '.join(_mount_name(name, m) for m in who)}, "
        f"counts as none: it is below {NULL:.3g} (64 rounding units) of their largest stiffness on a rigid motion, "
        f"{top / scale:.3g} {per} ({kind}), {threshold:.3g} {unit} on this motion, under which double precision "
        "cannot tell it from none"
    )
    return reason, f"a stiffness above {threshold:.3g} {unit} in all in that direction"


def free_rigid(system):
    """What the supports and mounts of ``system`` (an assembled BodySystem) leave free, from one
    analysis of its rigid motions: (every one of them, in words: the basis :func:`free_motions`
    names, joined, "a translation along [1, 0, 0], a translation along [0, 1, 0] and a translation
    along [0, 0, 1]", or None when a clamped support or the mounts hold every one; those motions as
    displacements of its free DOFs, augmented: the mounts' support nodes stay at rest, n_free x k
    with orthonormal columns Phi, k = 0 when held; ``words(c)``: the rigid motion Phi c in words)."""
    n = len(system.free)
    if "clamped" in system.spec.supports.values():
        return None, np.zeros((n, 0)), None
    cl = system.centerline
    Z, _, _, _, x0, L, _, _ = _analysis(cl, system.mounts, False, 0.0, np.zeros(3))
    if not Z.shape[1]:
        return None, np.zeros((n, 0)), None
    free = _joined(_named(Z, x0, L))
    U = np.zeros((system.n_augmented, Z.shape[1]))
    for i, x in enumerate(cl.nodes):
        U[6 * i : 6 * i + 6] = _rows(x - x0, L) @ Z
    Phi, R = np.linalg.qr(U[system.free])

    def words(c):
        a = Z @ np.linalg.solve(R, c)  # (Phi c = U R^-1 c: the rigid coordinates [t, L w] of Z R^-1 c)
        return describe(a / np.linalg.norm(a), x0, L)

    return free, Phi, words


def free_motions(model, name) -> list[str]:
    """The rigid motions that the supports and mounts of body ``name`` of ``model`` leave free, in
    words: a basis of them (translations along and rotations about the axes of the mounts' rigid
    stiffness S, each signed so that its largest coordinate is positive), empty when a clamped
    support or the mounts hold every one. Without a load these are the body's 0 Hz modes; under one
    :func:`check_supported` refuses the model (the same analysis, from the same route and mounts:
    no assembly)."""
    from .geometry import centerline_of
    from .mount_element import mounts_of

    if "clamped" in model.bodies[name].supports.values():
        return []
    cl = centerline_of(model)
    Z, _, _, _, x0, L, _, _ = _analysis(cl, mounts_of(model, name, cl), False, 0.0, np.zeros(3))
    return _named(Z, x0, L)


def _named(Z, x0, L):
    """The free rigid motions Z (6 x k, orthonormal columns [t, L w] about x0, m) in words, one a
    column, each signed so that its largest coordinate is positive."""
    return [describe(a * np.sign(a[np.argmax(np.abs(a))]), x0, L) for a in Z.T]


def _joined(words):
    """["a", "b", "c"] as "a, b and c"."""
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " and " + words[-1]


def axial_stiffness(mounts, end):
    """The stiffness (N/m) of the isolator at ``end`` ("A" or "B") along the body's axis there
    (its local axial direction, the centerline's tangent); inf where ``end`` has no isolator."""
    return next((float(m.local_stiffness()[0][0]) for m in mounts if m.support == end), float("inf"))


def _supports(name, supports, mounts):
    ends = ", ".join(f"{s} {supports[s]}" for s in ("A", "B"))
    clips = [m for m in mounts if m.support is None]
    return ends + (f", clips at s = {', '.join(f'{m.at:.4g}' for m in clips)} m" if clips else ", no clip")


def _check_axial_stretch(name, spec, mounts, T, cl):
    """Refuse a tension T (N) that would stretch the axial springs of the isolators at the ends of
    body ``name`` by more than :data:`STRETCH` of its length (module docstring)."""
    ends = [s for s in ("A", "B") if spec.supports[s] == "isolator"]
    if not ends:
        return
    k = {s: axial_stiffness(mounts, s) for s in ends}
    stretch = T * sum(1.0 / k[s] for s in ends)  # (a clamped end: 1/k = 0)
    L = cl.length
    if stretch <= STRETCH * L:
        return
    named = " and ".join(f"{name}.isolator.{s} (axial stiffness {k[s]:.4g} N/m)" for s in ends)
    if name == "cable":
        load, verb, then = (
            "tension",
            "stretch",
            f"the isolators would carry {T / (1.0 + stretch / L):.4g} N instead of {T:g} N",
        )
    else:
        load, verb, then = "compression", "compress", f"the casing's compression of {T:g} N would relax into them"
    k_min = T * len(ends) / (STRETCH * L)
    raise ModelError(
        "loads.cable_tension",
        T,
        f"is too much for the {name}'s end isolators along its axis: {named} {verb} by T (1/k_A + 1/k_B) = "
        f"{stretch:.4g} m under the {load}, {100 * stretch / L:.3g} % of the {name}'s length {L:.4g} m (at most "
        f"{100 * STRETCH:g} %), and in the linear static state {then}; stiffen the isolators along the axis (to "
        f"at least {k_min:.3g} N/m each), clamp the end or lower the tension",
    )


def check_supported(model) -> None:
    """Refuse (ModelError) a :class:`~cablecasing_core.model.Model` whose bodies cannot carry
    their loads (module docstring): a free end under a tension, end isolators that the tension
    would stretch by more than :data:`STRETCH` of the body's length, a loaded body that its
    supports and mounts leave free to move rigidly, or one whose mounts are so soft that its weight
    would move it by more than its length."""
    from .geometry import centerline_of
    from .mount_element import mounts_of
    from .sections import section_of

    loads = model.loads
    g, T = loads["gravity"], loads["cable_tension"]
    for name, spec in model.bodies.items():
        causes = []
        if any(g):
            causes.append(("loads.gravity", g, "its weight"))
        if T > 0.0:
            causes.append(("loads.cable_tension", T, "the tension" if name == "cable" else "the compression"))
        if name == "cable" and spec.rest_shape != "routing":
            causes.append(("cable.rest_shape", spec.rest_shape, "the bending of its rest shape"))
        if not causes:
            continue
        clamped = "clamped" in spec.supports.values()
        # (the mounts only where they are looked at: an isolator under a tension, or no clamped end)
        mounted = not clamped or (T > 0.0 and "isolator" in spec.supports.values())
        cl = centerline_of(model) if mounted else None
        mounts = mounts_of(model, name, cl) if mounted else []
        if T > 0.0:
            what = "the tension" if name == "cable" else "the compression"
            for s in ("A", "B"):
                if spec.supports[s] == "free":
                    raise ModelError(
                        "loads.cable_tension",
                        T,
                        f"needs both ends of the {name} held (clamped or isolator): {name}.supports.{s} is free, "
                        f"and a free end carries no axial force, so nothing holds the {name} along its axis at {s} "
                        f"and {what} has nowhere to go",
                    )
                if spec.supports[s] == "isolator" and axial_stiffness(mounts, s) == 0.0:
                    raise ModelError(
                        "loads.cable_tension",
                        T,
                        f"needs both ends of the {name} held along its axis: {name}.isolator.{s} has no stiffness "
                        f"along the {name}'s axis at {s}, and a spring of no stiffness carries no axial force, so "
                        f"{what} has nowhere to go; give the isolator an axial stiffness or clamp the end",
                    )
            _check_axial_stretch(name, spec, mounts, T, cl)
        if clamped:
            continue
        mass = spec.rho * section_of(spec).A
        Z, free, u, F, x0, L, a, top = _analysis(cl, mounts, clamped, mass, g)
        held = _supports(name, spec.supports, mounts)
        key, value, what = causes[0]
        # (a cable lying in its casing looks carried to its author: say why the contact does not count)
        besides = (
            "; the contact with the casing is not counted (one-sided and frictionless at rest, it holds no axial "
            "load and no rotation about the centerline)"
            if name == "cable" and len(model.bodies) == 2 and model.contact["enabled"]
            else ""
        )
        pushed = free is not None and np.linalg.norm(Z @ (Z.T @ F)) > 1e-9 * max(np.linalg.norm(F), 1e-300)
        if free is not None:
            # (none given there, or one too small beside the others to count: say which, with the numbers)
            reason, remedy = _no_stiffness(name, model.data[name], mounts, cl.nodes, a, x0, L, top)
        if free is not None and not pushed:
            # (the motion is free, not loaded: the static solve and the time domain need it held all
            # the same, their stiffness singular on it; the loads are not what is wrong)
            hint = (
                " (for a rotation, a rotational stiffness about its axis: a twist about the body's own axis needs "
                "a torsional stiffness, which may be far below the others)"
                if free.startswith("a rotation") and remedy is None
                else ""
            )
            pushes = "its weight does not push it there" if any(g) else "its loads have no resultant on it"
            raise ModelError(
                key,
                value,
                f"needs the {name} held against every rigid motion, but its supports ({held}) leave it free in {free} "
                f"({reason}): {pushes}, yet the static state and the time domain of a "
                f"loaded body are singular on a free motion{besides}; give the isolators or clips "
                f"{remedy or 'a stiffness in that direction, however small'}{hint}, or clamp a support",
            )
        if free is not None:
            raise ModelError(
                key,
                value,
                f"cannot be carried by the {name}: its supports ({held}) leave it free in {free} (a mechanism: "
                f"{reason}), and a loaded body must be held against every rigid motion{besides}; clamp a support or "
                f"give the isolators or clips {remedy or 'stiffness in that direction'}",
            )
        if u > L:
            raise ModelError(
                key,
                value,
                f"cannot be carried by the {name}: its mounts ({held}) are so soft that {what} would move it rigidly "
                f"by {u:.3g} m, more than its length {L:.4g} m{besides}; stiffen the isolators or clips",
            )
