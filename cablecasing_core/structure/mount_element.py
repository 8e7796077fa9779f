"""The 6-DOF spring-damper of an elastic support: an end isolator (``supports.A = "isolator"``) or
a clip along the casing (``[[casing.clip]]``), between a node of the body and its support.

In the support's local axes (axial along the centerline's unit tangent at the node, Eq. 33; the
two lateral axes the element frame's y and z made normal to it) the mount is diagonal: translational
stiffness k = [k_a, k_1, k_2] (N/m) and damping c (N.s/m), rotational stiffness (N.m/rad) and damping
(N.m.s/rad) about the same axes. In global axes its 6 x 6 stiffness is K6 = blockdiag(R^T diag(k_t) R,
R^T diag(k_r) R), R the rows (axial, lateral_1, lateral_2), and so its damping C6. It acts on the
relative motion of node and support: the force the body exerts on the support is
F = K6 (u_node - u_support) + C6 (v_node - v_support) (N, N.m; the support's rotations are held).
In the frequency domain the mount's dynamic stiffness is K6 + i omega C6, or, when the mount has a
table (a rubber mount's measured dynamic stiffness and loss factor against frequency), K6
k_scale(f) (1 + i loss_factor(f)): the table then stands for stiffness and damping together, and
C6 is the time domain's viscous stand-in for it (choose c ~ loss k / omega at the frequencies that
matter; the time domain cannot follow a frequency-dependent stiffness).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.model import at_frequency
from ..model.schema import DIRECTIONS


@dataclass(frozen=True)
class Mount:
    """One elastic support of a body (SI units).

    label: "A"/"B" for an isolator, "clip<i>" for a clip; node: the body's node; K6, C6: 6 x 6
    stiffness (N/m, N.m/rad) and damping (N.s/m, N.m.s/rad) in global axes; axes: rows (axial,
    lateral_1, lateral_2) in global axes; table: (n, 3) array [f_Hz, k_scale, loss_factor] or None;
    channels: the three support channels of its translations (x, y, z) or None for a fixed clip;
    support: "A"/"B" for an isolator, None for a clip; at: the arc length (m) of the node the clip
    acts at (:func:`clip_node`: the nearest to the ``at`` its file asked for), None for an isolator."""

    label: str
    node: int
    K6: np.ndarray
    C6: np.ndarray
    axes: np.ndarray
    table: np.ndarray | None
    channels: tuple | None
    support: str | None = None
    at: float | None = None

    def local_stiffness(self):
        """(translational N/m, rotational N.m/rad): the stiffnesses in the local axes [axial,
        lateral_1, lateral_2], the diagonal of K6's blocks turned back into them; a value within
        the rounding of that turn (64 units of the block's largest) is exactly 0, so that a zero
        given stays zero."""
        out = []
        for block in (self.K6[:3, :3], self.K6[3:, 3:]):
            d = np.diag(self.axes @ block @ self.axes.T).copy()
            d[np.abs(d) <= 64 * np.finfo(float).eps * np.abs(block).max()] = 0.0
            out.append(d)
        return out[0], out[1]

    def dynamic_stiffness(self, freqs_hz, damped=True):
        """(nf, 6, 6) complex dynamic stiffness (N/m, N.m/rad) at ``freqs_hz`` (Hz): K6 + i omega C6,
        or with a table K6 k_scale(f) (1 + i loss(f)) (:func:`~cablecasing_core.model.model.at_frequency`:
        linear in f, held at the ends); without ``damped`` K6 (times k_scale(f) with a table)."""
        f = np.asarray(freqs_hz, dtype=float)
        if self.table is None:
            if not damped:
                return np.broadcast_to(self.K6.astype(complex), (len(f), 6, 6)).copy()
            return self.K6[None] + 1j * (2.0 * np.pi * f)[:, None, None] * self.C6[None]
        scale = at_frequency(self.table, f, 1)
        loss = at_frequency(self.table, f, 2) if damped else np.zeros_like(f)
        return (scale * (1.0 + 1j * loss))[:, None, None] * self.K6[None]


def local_axes(tangent, frame):
    """Rows (axial, lateral_1, lateral_2): the unit ``tangent`` and the element ``frame``'s y made
    normal to it, then their cross product."""
    t = tangent / np.linalg.norm(tangent)
    y = frame[1] - (frame[1] @ t) * t
    y /= np.linalg.norm(y)
    return np.array([t, y, np.cross(t, y)])


def _global(axes, translational, rotational):
    out = np.zeros((6, 6))
    out[:3, :3] = axes.T @ np.diag(translational) @ axes
    out[3:, 3:] = axes.T @ np.diag(rotational) @ axes
    return out


def _mount(label, node, keys, cl, channels, support=None, at=None):
    frame = cl.frames[min(node, cl.n_elements - 1)]
    axes = local_axes(cl.tangents[node], frame)
    table = np.asarray(keys["table"], dtype=float) if "table" in keys else None
    return Mount(
        label=label,
        node=int(node),
        K6=_global(axes, keys["stiffness"], keys["rotational_stiffness"]),
        C6=_global(axes, keys["damping"], keys["rotational_damping"]),
        axes=axes,
        table=table,
        channels=channels,
        support=support,
        at=at,
    )


def clip_node(s_nodes, at) -> int:
    """The node a clip at arc length ``at`` (m) acts at: the nearest of the nodes at arc lengths
    ``s_nodes`` (m). A clip joins one node to its support (its 6 x 6 block within the band); the
    model file's validation warns where that node lies far from ``at``."""
    return int(np.argmin(np.abs(np.asarray(s_nodes) - at)))


def clip_positions(model):
    """Arc lengths (m) of the nodes the casing's clips act at, in file order (each clip's
    :func:`clip_node` on the model's centerline)."""
    from .geometry import centerline_of

    clips = model.data.get("casing", {}).get("clip", [])
    if not clips:
        return []
    s = centerline_of(model).s
    return [float(s[clip_node(s, c["at"])]) for c in clips]


def mounts_of(model, body, centerline):
    """The :class:`Mount` s of ``body`` of ``model`` on its ``centerline``: its isolator supports
    (end nodes, driven by the support's channels ``<body>.<A|B>.<x|y|z>``), then, for the casing,
    its clips in file order (the node nearest to ``at``; driven by ``<excitation>.<x|y|z>`` when
    the clip has an excitation, else fixed)."""
    data = model.data[body]
    out = []
    for s, node in (("A", 0), ("B", centerline.n_elements)):
        if data["supports"][s] == "isolator":
            chans = tuple(f"{body}.{s}.{d}" for d in DIRECTIONS)
            out.append(_mount(s, node, data["isolator"][s], centerline, chans, support=s))
    for i, clip in enumerate(data.get("clip", [])):
        node = clip_node(centerline.s, clip["at"])
        chans = tuple(f"{clip['excitation']}.{d}" for d in DIRECTIONS) if "excitation" in clip else None
        out.append(_mount(f"clip{i}", node, clip, centerline, chans, at=float(centerline.s[node])))
    return tuple(out)
