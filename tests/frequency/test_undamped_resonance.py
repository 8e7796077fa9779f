"""An undamped response evaluated exactly at a natural frequency: unbounded where the mode couples
the two supports, and untouched by a mode that does not couple them (no nan, no library warnings)."""

import warnings

import numpy as np
import pytest

from cablecasing_core.frequency.trfam import FrequencyResponse
from cablecasing_core.structure.assembly import assemble_body


def test_undamped_support_force_at_a_natural_frequency_is_infinite_not_nan(straight):
    system = assemble_body(straight(1.0, 20, supports=("clamped", "clamped")), "cable")
    fr = FrequencyResponse(system)
    f = np.sqrt(fr.lam[0]) / (2.0 * np.pi)
    ports = [system.prescribed_index(s, c) for s in ("A", "B") for c in (0, 1, 2)]  # x, y, z at A then B
    near = fr.support_forces([f * (1 + 1e-9)], "none", rows=ports, cols=ports)[0]
    # the first bending pair (y and z) at exactly the grid's frequency: a grid point on the resonance
    fr.lam[:2] = (2.0 * np.pi * f) ** 2
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        on = fr.support_forces([f], "none", rows=ports, cols=ports)[0]
    assert not np.isnan(on).any()
    # y at A to y at B, and z to z, go through the bending pair: unbounded
    assert np.isinf(on[1, 4]) and np.isinf(on[2, 5])
    # y to z does not: the pair's shapes are any rotation of each other, and their residues there
    # cancel (1e-9 Hz beside, ~4e-4 N/m against ~4.5e12 for y to y)
    assert np.isfinite(on[1, 5]) and np.isfinite(on[2, 4])
    # nor does the axial force: its row and column stay finite (they were inf with a threshold that
    # took the supports' reactions for inertia, the more so the finer the mesh)
    assert np.isfinite(on[[0, 3], :]).all() and np.isfinite(on[:, [0, 3]]).all()
    # the axial force does not see the bending modes: finite, and continuous with a frequency 1e-9
    # beside (its own nearest mode is far, so 1e-9 in frequency moves it by ~1e-9 relatively)
    assert np.isfinite(on[0, 3]) and abs(on[0, 3] - near[0, 3]) <= 1e-6 * abs(near[0, 3])


@pytest.mark.parametrize("tilt", [1e-6, 1e-4])
def test_a_weak_but_true_coupling_at_a_natural_frequency_is_infinite(beam_model, tilt):
    """Review AP, TR2: the threshold that tells a mode's true coupling of two supports from round-off (1e-8 of
    its largest) had only couplings of about 1 and 1e-16 to tell apart. A beam tilted by ``tilt`` rad in the x-y
    plane: its bending pair's residues, summed, are the projector on the plane across the beam, whose x-y entry
    is -sin(tilt) cos(tilt); so x at A and y at B couple through the pair by tan(tilt) of y to y, weakly but truly.
    At the pair's frequency that entry is unbounded; z to y (across the tilt's plane) stays finite."""
    pts = [[0.0, 0.0, 0.0], [np.cos(tilt), np.sin(tilt), 0.0]]
    system = assemble_body(beam_model(pts, 20, supports=("clamped", "clamped")), "cable")
    fr = FrequencyResponse(system)
    f = np.sqrt(fr.lam[0]) / (2.0 * np.pi)
    ports = [system.prescribed_index(s, c) for s in ("A", "B") for c in (0, 1, 2)]  # x, y, z at A then B
    # the reference, 1e-9 Hz beside the resonance, where the pair's term outweighs the rest by ~1e9: x-to-y is
    # tan(tilt) of y-to-y (to 1e-4 of it: the rest's share, and the tilt's second order)
    near = fr.support_forces([f * (1 + 1e-9)], "none", rows=ports, cols=ports)[0]
    assert abs(abs(near[0, 4] / near[1, 4]) / np.tan(tilt) - 1) < 1e-4
    fr.lam[:2] = (2.0 * np.pi * f) ** 2  # (the pair exactly at the grid's frequency, as in the test above)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        on = fr.support_forces([f], "none", rows=ports, cols=ports)[0]
    assert np.isinf(on[0, 4]) and np.isinf(on[1, 3]) and np.isinf(on[1, 4])
    assert np.isfinite(on[2, 4]) and np.isfinite(on[1, 5])  # (z does not couple to the tilt's plane)
