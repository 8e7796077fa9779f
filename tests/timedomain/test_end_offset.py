"""Engine.end_offset_excess: how far the support displacements set the casing's and the cable's
supports at each end apart across the route (the part of their difference normal to the route's
tangent there), against the radial gap; the FMU logs what it returns (tests/fmu/
test_fmu_integrator_leftovers.py). Checked by hand on a route of exact arcs whose tangents are known:
(1, 1, 0)/sqrt(2) at end A, then a bend of 90 deg towards +z, so +z at end B."""

import numpy as np
import pytest

from cablecasing_core import model_from_dict
from cablecasing_core.model.schema import CHANNELS
from cablecasing_core.timedomain.engine import Engine

ROUTE = {
    "direction": [1.0, 1.0, 0.0],
    "segments": [{"straight": 0.2}, {"bend": {"radius": 0.15, "angle_deg": 90.0, "toward": [0, 0, 1]}},
                 {"straight": 0.2}],
    "n_elements": 10,
}  # fmt: skip


def _engine(paper_bodies, contact=True, **supports):
    bodies = paper_bodies
    for key, kind in supports.items():  # e.g. cable_A="free"
        body, end = key.split("_")
        bodies[body]["supports"] = {"A": "clamped", "B": "clamped", end: kind}
    model = model_from_dict({"geometry": ROUTE, **bodies, "contact": {"enabled": contact}})
    return Engine(model, ledger=False)


def _u(**values):
    """The 12 support displacements (m) of CHANNELS with ``values`` ({"casing_A_x": 1e-3}) set."""
    u = np.zeros(len(CHANNELS))
    for key, value in values.items():
        u[CHANNELS.index(key.replace("_", "."))] = value
    return u


def test_the_offset_across_the_route_at_each_end_by_hand(paper_bodies):
    eng = _engine(paper_bodies)
    ends = eng.end_offset_excess(_u(casing_A_x=1e-3, casing_A_y=0.2e-3, cable_B_x=0.3e-3, cable_B_z=5e-3))
    assert ends.gap == pytest.approx((0.004 - 0.003) / 2, rel=1e-12)  # (d_inner - d) / 2
    # exact arcs: the tangents are the route's direction and the bend's end direction (rounding only)
    np.testing.assert_allclose(ends.tangent, [[2**-0.5, 2**-0.5, 0.0], [0.0, 0.0, 1.0]], atol=1e-12)
    # A: d = (1, 0.2, 0) mm, t = (1, 1, 0)/sqrt(2): d - (d.t) t = (0.4, -0.4, 0) mm, 0.4 sqrt(2) mm across
    # B: d = casing - cable = (-0.3, 0, -5) mm, t = z: the 5 mm along the route slide, 0.3 mm across
    np.testing.assert_allclose(ends.across, [0.4e-3 * 2**0.5, 0.3e-3], rtol=1e-12)
    # linear in u, and the same with the channels of more than the 12 supports (an excited clip's)
    more = eng.end_offset_excess(np.concatenate([2 * _u(casing_A_y=0.25e-3), [9.0, 9.0, 9.0]]))
    np.testing.assert_allclose(more.across, [0.5e-3 * 2**-0.5, 0.0], atol=1e-18)


def test_an_end_with_a_free_support_and_a_run_without_contact_do_not_count(paper_bodies):
    u = _u(casing_A_y=1e-3, cable_B_y=1e-3)
    free = _engine(paper_bodies, cable_A="free").end_offset_excess(u)
    np.testing.assert_allclose(free.across, [0.0, 1e-3], rtol=1e-12)  # (B: along y, normal to t = z)
    assert _engine(paper_bodies, contact=False).end_offset_excess(u) is None
