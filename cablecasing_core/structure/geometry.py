"""Centerline geometry: arc-length curve, equal-arc nodes (within the spans between clips), element frames, curvature.

The centerline at rest is shared by both bodies. Routed by segments (``[geometry] segments``,
:mod:`.routing`) it is the exact curve of straights and circular arcs: the nodes lie on the arcs
and carry the exact tangent and curvature (1/R in a bend). Through the model's points it is either
a cubic spline (``curve = "spline"``, parametrised by chord length and then re-parametrised by arc
length) or the polyline itself (``curve = "polyline"``). It is cut into ``n_elements`` straight
elements of equal arc length, or, with ``geometry.nodes_at_clips = true``, of equal arc length within
each span between the ends and the casing's clips (:func:`node_stations`: a node at each clip's
``at``, on the cable as on the casing, for both bodies share the centerline); each element
carries a right-handed local frame (x along the element chord). The frame's y axis is carried
from element to element by parallel transport (the minimal rotation that takes one chord
direction into the next), so the frame is well defined on straight and on curved
segments alike. Of the Frenet frame of Eqs. (33)-(35) the model needs the unit tangent (Eq. 33) at
the nodes (each cable node's normal plane in the contact search, Eqs. 36-39) and the curvature
|r' x r''| / |r'|^3 (the norm in Eq. 34), for the figures and the studies; its vector
r' x r'' / |r'|^3 = kappa b (Eq. 34's binormal) is the bending strain a cable that is stress-free
straight carries in the routing (structure/loads.py). On a polyline the curvature is concentrated
in its corners; there the curvature vector of a node is its turning angle over the mean length of
its two elements, about the axis t_before x t_after, and an end node takes its neighbour's (the
scalar curvature stays zero: a polyline has no smooth curvature to show); a node between two
elements that turn takes the bisector of their chords as its tangent (:func:`corner_tangents`). On a route by segments,
whose curvature jumps where a straight meets a bend, each element also carries its own end
curvature vectors (``element_curvature``, :meth:`.routing.SegmentRoute.element_curvature`): the
exact curvature of its own stretch of the route, which the nodal vectors, one per junction node,
cannot give to the elements on both of its sides.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .routing import SegmentRoute
from .spline import interpolating_spline


@dataclass(frozen=True)
class Centerline:
    """A discretised centerline (all lengths in m).

    Attributes
    ----------
    nodes : (n+1, 3) array, node positions at rest.
    s : (n+1,) array, arc length of each node from end A.
    tangents : (n+1, 3) array, unit tangent of the smooth curve at each node (Eq. 33).
    curvature : (n+1,) array, curvature of the smooth curve at each node in 1/m.
    frames : (n, 3, 3) array, rows are the local x, y, z axes of each element in global axes
        (the direction-cosine matrix of the element); None when built without them.
    lengths : (n,) array, element lengths (chords).
    curvature_vectors : (n+1, 3) array, kappa b at each node in 1/m (global): the tangent's rate
        of turning, t x dt/ds.
    element_curvature : (n, 2, 3) array or None, the curvature vectors (1/m, global) at each
        element's two ends, from the route on the element's own side of a junction (a route by
        segments); None where the nodal ``curvature_vectors`` serve (a spline, a polyline).
    """

    nodes: np.ndarray
    s: np.ndarray
    tangents: np.ndarray
    curvature: np.ndarray
    frames: np.ndarray | None
    lengths: np.ndarray
    curvature_vectors: np.ndarray
    element_curvature: np.ndarray | None = None

    @property
    def n_elements(self):
        return len(self.lengths)

    @property
    def length(self):
        """Arc length of the curve in m."""
        return float(self.s[-1])


def _perpendicular(t):
    """A unit vector perpendicular to unit vector ``t``."""
    ref = np.array([0.0, 0.0, 1.0]) if abs(t[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
    v = ref - (ref @ t) * t
    return v / np.linalg.norm(v)


def _transport(v, t0, t1):
    """Rotate ``v`` by the minimal rotation that takes unit ``t0`` to unit ``t1`` (Rodrigues)."""
    axis = np.cross(t0, t1)
    sin = np.linalg.norm(axis)
    cos = float(np.clip(t0 @ t1, -1.0, 1.0))
    if sin < 1e-14:
        return v
    k = axis / sin
    return v * cos + np.cross(k, v) * sin + k * (k @ v) * (1.0 - cos)


def element_chords(nodes):
    """(unit chord directions (n, 3), chord lengths (n,) in m) of the straight elements between
    consecutive ``nodes`` (m)."""
    d = np.diff(nodes, axis=0)
    lengths = np.linalg.norm(d, axis=1)
    return d / lengths[:, None], lengths


def element_frames(nodes, first_y=None):
    """Direction-cosine matrices of the straight elements between consecutive ``nodes``.

    Returns (frames, lengths): frames[e] has rows (x, y, z) of element e's local axes; x is the
    chord direction, y is parallel-transported from the previous element, z = x cross y.
    """
    xs, lengths = element_chords(nodes)
    frames = np.empty((len(xs), 3, 3))
    y = _perpendicular(xs[0]) if first_y is None else first_y - (first_y @ xs[0]) * xs[0]
    y = y / np.linalg.norm(y)
    for e, x in enumerate(xs):
        if e > 0:
            y = _transport(y, xs[e - 1], x)
            y = y - (y @ x) * x
            y /= np.linalg.norm(y)
        frames[e] = (x, y, np.cross(x, y))
    return frames, lengths


def share_elements(spans, n_elements):
    """How many of ``n_elements`` elements each of the ``spans`` (lengths, m, each > 0) gets: in
    proportion to its length, by the largest remainder (Hamilton's rule), and at least 1 each (a
    span whose share rounds to 0 takes 1 from the span that then has the shortest elements); the
    counts add up to ``n_elements``, which must be at least ``len(spans)``."""
    spans = np.asarray(spans, dtype=float)
    quota = n_elements * spans / spans.sum()
    counts = np.floor(quota).astype(int)
    rest = n_elements - int(counts.sum())
    order = np.argsort(-(quota - counts), kind="stable")  # (largest remainder first; ties: end A first)
    counts[order[:rest]] += 1
    for i in np.flatnonzero(counts == 0):
        donors = np.flatnonzero(counts >= 2)
        j = donors[np.argmin(spans[donors] / (counts[donors] - 1))]  # (the finest after giving one)
        counts[j] -= 1
        counts[i] = 1
    return counts


def node_stations(length, n_elements, breaks=None):
    """Arc lengths (m, ``n_elements`` + 1, from 0 to ``length``) of the nodes of a route of
    ``length`` m. Without ``breaks``, ``n_elements`` equal elements (``np.linspace``). With
    ``breaks`` (arc lengths in m strictly inside the route, distinct: the clips' ``at`` of
    ``geometry.nodes_at_clips``), the union of equal subdivisions of the spans [0, b_1, ..., b_k,
    length], which share the elements by :func:`share_elements`: each break is a node, exactly (its
    span's ends are those of ``np.linspace``), at any ``n_elements``."""
    if breaks is None:
        return np.linspace(0.0, length, n_elements + 1)
    edges = np.concatenate([[0.0], np.sort(np.asarray(breaks, dtype=float)), [length]])
    counts = share_elements(np.diff(edges), n_elements)
    parts = [np.linspace(a, b, c + 1)[:-1] for a, b, c in zip(edges[:-1], edges[1:], counts)]
    return np.concatenate([*parts, [length]])


def clip_breaks(geometry, casing):
    """The arc lengths (m) a node must sit at: the clips' ``at`` of the checked ``casing`` table
    when the checked ``geometry`` has ``nodes_at_clips = true``, else None (equal elements)."""
    if not geometry.get("nodes_at_clips", False):
        return None
    return sorted(float(c["at"]) for c in (casing or {}).get("clip", []))


def build_centerline(points, n_elements, curve="spline", frames=True, breaks=None):
    """Discretise the curve through ``points`` (m) into ``n_elements`` equal-arc elements (with
    ``breaks``, arc lengths in m, equal within the spans between them: :func:`node_stations`).

    Parameters
    ----------
    points : (k, 3) array-like, points on the centerline at rest, in m (end A first).
    n_elements : int, number of elements.
    curve : "spline" (cubic spline by arc length) or "polyline".
    frames : False leaves the elements' frames out (``frames`` is None): what only asks for arc
        lengths and curvature (a dense curvature profile) skips the parallel transport, a loop of
        ~0.2 ms per element in Python.
    """
    P = np.asarray(points, dtype=float)
    chord = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
    if curve == "polyline" or len(P) == 2:
        s_nodes = node_stations(chord[-1], n_elements, breaks)
        nodes = np.column_stack([np.interp(s_nodes, chord, P[:, k]) for k in range(3)])
        seg = np.clip(np.searchsorted(chord, s_nodes, side="right") - 1, 0, len(P) - 2)
        tangents = (P[seg + 1] - P[seg]) / (chord[seg + 1] - chord[seg])[:, None]
        curvature = np.zeros(len(s_nodes))
        s_out = s_nodes
        kvec = None  # from the corners of the discretised polyline, below
    else:
        # Cubic spline (not-a-knot) in the chord parameter; through 3 points the parabola.
        spl = interpolating_spline(chord, P)
        # Arc length by dense trapezoidal integration of |r'(u)| (error ~ h^2 on a smooth curve,
        # 200 samples per chord span keeps it below 1e-8 relative), then inverted by interpolation.
        u = np.linspace(0.0, chord[-1], 200 * (len(P) - 1) + 1)
        speed = np.linalg.norm(spl(u, 1), axis=1)
        # scipy.integrate.cumulative_trapezoid's own expression, written out: importing
        # scipy.integrate costs ~0.25 s of every command's start (it imports scipy.optimize)
        s_of_u = np.concatenate([[0.0], np.cumsum(np.diff(u) * (speed[1:] + speed[:-1]) / 2.0)])
        s_out = node_stations(s_of_u[-1], n_elements, breaks)
        u_nodes = np.interp(s_out, s_of_u, u)
        nodes = spl(u_nodes)
        r1 = spl(u_nodes, 1)
        r2 = spl(u_nodes, 2)
        tangents = r1 / np.linalg.norm(r1, axis=1)[:, None]  # Eq. (33)
        kvec = np.cross(r1, r2) / np.linalg.norm(r1, axis=1)[:, None] ** 3  # kappa b (Eq. 34)
        curvature = np.linalg.norm(kvec, axis=1)
    tangents = tangents / np.linalg.norm(tangents, axis=1)[:, None]
    if frames:
        frames, lengths = element_frames(nodes)
        chords = frames[:, 0]
    else:
        frames, (chords, lengths) = None, element_chords(nodes)
    if kvec is None:
        kvec = corner_curvature(chords, lengths)
        tangents = corner_tangents(tangents, chords)
    return Centerline(
        nodes=nodes,
        s=s_out,
        tangents=tangents,
        curvature=curvature,
        frames=frames,
        lengths=lengths,
        curvature_vectors=kvec,
    )


def corner_tangents(tangents, directions):
    """A polyline's node tangents (unit, one per node) with each interior node between two elements
    of different unit ``directions`` given their bisector, (d_before + d_after) / |...|: the
    tangent of the polygon of elements there, symmetric in its two sides, so that the cable's normal
    plane at the corner (Eqs. 36-39) leans to neither side and a tension pulls both legs equally
    (the direction of one span would make a tension of 10 N round a 90 degree corner pull its legs
    with 19.7 and 0.3 N). The nodes between parallel elements keep ``tangents`` as they are."""
    out = np.array(tangents, dtype=float)
    if len(directions) < 2:
        return out
    a, b = directions[:-1], directions[1:]
    turned = np.linalg.norm(np.cross(a, b), axis=1) > 1e-14
    mid = a + b
    out[1:-1][turned] = mid[turned] / np.linalg.norm(mid[turned], axis=1)[:, None]
    return out


def corner_curvature(directions, lengths):
    """Curvature vectors (1/m, global, one per node) of a polygon of elements with unit
    ``directions`` and ``lengths``: at an interior node the turning angle between its two elements
    over their mean length, about their cross product; an end node takes its neighbour's (so a
    circular arc sampled as a polyline has the same curvature vector at every node)."""
    k = np.zeros((len(lengths) + 1, 3))
    if len(lengths) < 2:
        return k
    a, b = directions[:-1], directions[1:]
    axis = np.cross(a, b)
    sin = np.linalg.norm(axis, axis=1)
    angle = np.arctan2(sin, np.einsum("ij,ij->i", a, b))
    turn = np.where(sin > 1e-14, angle / np.where(sin > 1e-14, sin, 1.0), 0.0)
    k[1:-1] = axis * (turn / (0.5 * (lengths[:-1] + lengths[1:])))[:, None]
    k[0], k[-1] = k[1], k[-2]
    return k


def route_of(model):
    """The :class:`~.routing.SegmentRoute` of a model routed by segments, else None (points)."""
    g = model.geometry
    if "segments" not in g:
        return None
    return SegmentRoute(g["start"], g["direction"], g["segments"])


def centerline_from_route(route, n_elements, breaks=None):
    """Discretise a :class:`~.routing.SegmentRoute` into ``n_elements`` elements of equal arc
    length (with ``breaks``, arc lengths in m, equal within the spans between them:
    :func:`node_stations`): nodes on the exact curve, with its exact unit tangent and curvature
    (1/m), and each element's end curvature vectors from its own stretch of the route
    (``element_curvature``)."""
    s = node_stations(route.length, n_elements, breaks)
    nodes, tangents, curvature, kvec = route._evaluate(s)
    frames, lengths = element_frames(nodes)
    return Centerline(
        nodes=nodes,
        s=s,
        tangents=tangents,
        curvature=curvature,
        frames=frames,
        lengths=lengths,
        curvature_vectors=kvec,
        element_curvature=route.element_curvature(s, lengths),
    )


def centerline_of(model, n_elements=None):
    """The centerline of a :class:`~cablecasing_core.model.Model` (shared by both bodies), with
    the model's ``geometry.n_elements`` or ``n_elements`` elements; with ``geometry.nodes_at_clips``
    a node at each casing clip's ``at`` (:func:`node_stations`)."""
    g = model.geometry
    n = g["n_elements"] if n_elements is None else int(n_elements)
    breaks = clip_breaks(g, model.data.get("casing"))
    route = route_of(model)
    if route is not None:
        return centerline_from_route(route, n, breaks)
    return build_centerline(g["points"], n, g["curve"], breaks=breaks)
