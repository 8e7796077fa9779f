"""An undamped response evaluated exactly at a natural frequency: unbounded where the mode couples
the two supports, and untouched by a mode that does not couple them (no nan, no library warnings)."""

import warnings

import numpy as np

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
