"""A centerline routed as a cable engineer draws it: straights joined by circular bends.

``[geometry] start, direction, segments`` (docs/model_file.md, Routing by segments) give a
tangent-continuous curve of exact straights and circular arcs. A straight of length L moves along
the current tangent t; a bend ``{radius = R, angle_deg = phi, toward = w}`` turns t by phi about
the axis t x n, where n is the unit part of w normal to t (the bend's inward normal: its centre is
at p + R n). On a bend the position is p + R sin(theta) t + R (1 - cos theta) n, the tangent
cos(theta) t + sin(theta) n and the curvature exactly 1/R (Eqs. 33-34 of a circle), at arc length
R theta from the bend's start; its curvature vector t x dt/ds = kappa b is (t x n) / R.
:class:`SegmentRoute` evaluates them at any arc length, so the nodes of the discretisation lie on
the exact arcs and carry the exact tangent and curvature.
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
