"""Review I, D15: an ensemble's ``levels`` are band RMS values (N), not dB; ``rms`` is the same array."""

import numpy as np

from cablecasing_core.studies.ensemble import Ensemble


def test_ensemble_rms_is_its_levels_in_the_outputs_unit():
    levels = np.array([[1.0, 2.0], [3.0, 4.0]])
    e = Ensemble(
        np.array([1, 2]), "casing.B.Fz", ("oct1", "oct2"), np.array([11.0, 22.0]), np.array([22.0, 44.0]), levels
    )
    assert e.rms is e.levels
    np.testing.assert_allclose(e.mean, [2.0, 3.0])  # (N: the mean of the RMS values, not of dB)
    assert "not dB" in Ensemble.__doc__ and "not dB" in Ensemble.rms.__doc__
