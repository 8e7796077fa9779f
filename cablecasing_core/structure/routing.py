"""A centerline routed as a cable engineer draws it: straights joined by circular bends.

``[geometry] start, direction, segments`` (docs/model_file.md, Routing by segments) give a
tangent-continuous curve of exact straights and circular arcs. A straight of length L moves along
the current tangent t; a bend ``{radius = R, angle_deg = phi, toward = w}`` turns t by phi about
the axis t x n, where n is the unit part of w normal to t (the bend's inward normal: its centre is
at p + R n). On a bend the position is p + R sin(theta) t + R (1 - cos theta) n, the tangent
cos(theta) t + sin(theta) n and the curvature exactly 1/R (Eqs. 33-34 of a circle), at arc length
R theta from the bend's start; its curvature vector t x dt/ds = kappa b is (t x n) / R.
:class:`SegmentRoute` evaluates them at any arc length, so the nodes of the discretisation lie on
the exact arcs and carry the exact tangent and curvature. The curvature vector is constant on each
piece and jumps where a straight meets a bend; :meth:`SegmentRoute.element_curvature` gives each
element the exact moments of the curvature over its own stretch of the route, so that the
rest-shape load (structure/loads.py) sees a junction where it is, not a blend of its two sides.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Piece:
    """One segment of a route (lengths in m): start arc length ``s0`` and length ``length``,
    start point ``p0`` and unit tangent ``t0``; for a bend the radius ``radius`` (m, 0 for a
    straight), the unit inward normal ``n0`` and the angle ``angle_deg``."""

    s0: float
    length: float
    p0: np.ndarray
    t0: np.ndarray
    radius: float = 0.0
    n0: np.ndarray | None = None
    angle_deg: float = 0.0

    @property
    def is_bend(self):
        return self.radius > 0.0


class SegmentRoute:
    """The exact curve of a list of segments from ``start`` (m) along unit ``direction``.

    ``segments``: validated dicts ``{"straight": L}`` or ``{"bend": {"radius": R, "angle_deg":
    phi, "toward": [x, y, z]}}`` (m, degrees, a direction). Evaluate with :meth:`position`,
    :meth:`tangent`, :meth:`curvature` at arc lengths s (m from end A)."""

    def __init__(self, start, direction, segments):
        p = np.asarray(start, dtype=float)
        t = np.asarray(direction, dtype=float)
        t = t / np.linalg.norm(t)
        s = 0.0
        pieces = []
        for seg in segments:
            if "straight" in seg:
                L = float(seg["straight"])
                pieces.append(Piece(s, L, p.copy(), t.copy()))
                p = p + L * t
            else:
                b = seg["bend"]
                R, phi = float(b["radius"]), np.radians(float(b["angle_deg"]))
                w = np.asarray(b["toward"], dtype=float)
                n = w - (w @ t) * t
                n = n / np.linalg.norm(n)  # (validated: toward is not along the tangent)
                pieces.append(Piece(s, R * phi, p.copy(), t.copy(), R, n, float(b["angle_deg"])))
                p = p + R * np.sin(phi) * t + R * (1.0 - np.cos(phi)) * n
                t = np.cos(phi) * t + np.sin(phi) * n
                t = t / np.linalg.norm(t)
            s += pieces[-1].length
        self.pieces = tuple(pieces)
        self.length = s
        self.end = p
        self._s0 = np.array([q.s0 for q in pieces])

    @property
    def bends(self):
        """The bends as (start arc length m, radius m, angle deg), from end A."""
        return [(q.s0, q.radius, q.angle_deg) for q in self.pieces if q.is_bend]

    def _piece_index(self, s):
        return np.clip(np.searchsorted(self._s0, s, side="right") - 1, 0, len(self.pieces) - 1)

    def _evaluate(self, s):
        s = np.atleast_1d(np.asarray(s, dtype=float))
        idx = self._piece_index(s)
        pos = np.empty((len(s), 3))
        tan = np.empty((len(s), 3))
        kap = np.zeros(len(s))
        kvec = np.zeros((len(s), 3))
        for i, q in enumerate(self.pieces):
            m = idx == i
            if not m.any():
                continue
            d = (s[m] - q.s0)[:, None]
            if q.is_bend:
                th = d / q.radius
                pos[m] = q.p0 + q.radius * np.sin(th) * q.t0 + q.radius * (1.0 - np.cos(th)) * q.n0
                tan[m] = np.cos(th) * q.t0 + np.sin(th) * q.n0
                kap[m] = 1.0 / q.radius
                inward = -np.sin(th) * q.t0 + np.cos(th) * q.n0
                kvec[m] = np.cross(tan[m], inward) / q.radius  # t x dt/ds = kappa b
            else:
                pos[m] = q.p0 + d * q.t0
                tan[m] = q.t0
        return pos, tan, kap, kvec

    def element_curvature(self, s_nodes, lengths):
        """Per element between the arc lengths ``s_nodes`` (m, n+1, increasing) with chords
        ``lengths`` (m, n): the curvature vectors (1/m, global, (n, 2, 3)) at its two ends of the
        linear field k(x) on the chord (x in m from its first node) that has the same integral and
        first moment as the route's own kappa b over the element's stretch [a, b] of arc length h,
        taken onto the chord by x = (s - a) L / h and k = kappa b h / L. The consistent
        initial-strain load of a cubic element (Eq. 6's B linear in x) depends on these two moments
        alone, so it is exact for the piecewise constant curvature of straights and arcs wherever a
        junction falls; the integral of k over the chord is the route's turning over the element,
        int kappa b ds, so the elements' loads add up to the route's whole turning. Inside an arc
        k = (h / R) / L: the element's turning over its chord, as a polyline's corner curvature."""
        s_nodes = np.asarray(s_nodes, dtype=float)
        lengths = np.asarray(lengths, dtype=float)
        a, b = s_nodes[:-1], s_nodes[1:]
        m0 = np.zeros((len(a), 3))  # int kappa b ds over [a, b] (rad, a vector)
        m1 = np.zeros((len(a), 3))  # int kappa b (s - a) ds over [a, b] (m)
        for q in self.pieces:
            if not q.is_bend:
                continue
            kb = np.cross(q.t0, q.n0) / q.radius  # (constant on the arc: t x inward = t0 x n0)
            lo = np.clip(q.s0, a, b) - a
            hi = np.clip(q.s0 + q.length, a, b) - a
            m0 += np.outer(hi - lo, kb)
            m1 += np.outer(0.5 * (hi * hi - lo * lo), kb)
        h, L = (b - a)[:, None], lengths[:, None]
        M0, M1 = m0, m1 * L / h  # the moments of k(x) on the chord
        k1 = 4.0 * M0 / L - 6.0 * M1 / L**2
        k2 = 6.0 * M1 / L**2 - 2.0 * M0 / L
        return np.stack([k1, k2], axis=1)

    def position(self, s):
        """Points (n, 3) in m at arc lengths ``s`` (m)."""
        return self._evaluate(s)[0]

    def tangent(self, s):
        """Unit tangents (n, 3) at arc lengths ``s`` (m), Eq. (33)."""
        return self._evaluate(s)[1]

    def curvature(self, s):
        """Curvature (n,) in 1/m at arc lengths ``s`` (m): 1/R on a bend, 0 on a straight (a
        junction takes the value of the segment that starts there)."""
        return self._evaluate(s)[2]
