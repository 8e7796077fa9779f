"""Cross-section properties of the two bodies (SI units).

Casing: an annulus of ``d_outer`` and ``d_inner``; the second moment ``I`` may be overridden by an
effective value (Table 2 gives I_op for the helically wound casing). Cable: a solid circle of
diameter ``d``. Both sections are circular, so the two bending planes have the same I and the
torsion constant is J = 2 I (for the casing with an effective I, J = 2 I_eff as well). Mass terms
always use the geometric area and polar moment: the effective I describes stiffness only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Section:
    """A (m2), I (m4, each bending plane), J (m4, torsion constant), Ip (m4, geometric polar
    moment for rotary inertia), r_outer (m, outer radius of the body's contact surface)."""

    A: float
    I: float
    J: float
    Ip: float
    r_outer: float
    r_inner: float


def section_of(body):
    """:class:`Section` of a :class:`~cablecasing_core.model.BodySpec`."""
    do, di = body.d_outer, body.d_inner
    A = np.pi / 4.0 * (do**2 - di**2)
    Ip = np.pi / 32.0 * (do**4 - di**4)
    I = body.I_override if body.I_override is not None else Ip / 2.0
    return Section(A=A, I=I, J=2.0 * I, Ip=Ip, r_outer=do / 2.0, r_inner=di / 2.0)
