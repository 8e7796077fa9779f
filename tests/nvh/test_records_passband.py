"""A run's decimated record states its passband, and an output interval longer than the run is
refused."""

import numpy as np
import pytest

from cablecasing_core import ModelError
from cablecasing_core.model.schema import SUPPORT_OUTPUTS
from cablecasing_core.records import read_records


def _result(n=1000, dt=1e-5):
    from cablecasing_core.timedomain.simulation import SimulationResult

    t, z = dt * np.arange(1, n + 1), np.zeros((n, 3))
    forces = np.sin(2e3 * t)[:, None] * np.ones((1, len(SUPPORT_OUTPUTS)))
    return SimulationResult(
        time=t,
        support_forces=forces,
        contact_state=z,
        normal_force=z,
        penetration=z,
        contact_time=np.zeros(3),
        curvature=np.zeros(3),
        arc_length=np.zeros(3),
        energies={},
        solver={"dt": dt},
        initial_forces=np.zeros(len(SUPPORT_OUTPUTS)),
    )


def test_a_filtered_record_states_its_passband_through_its_npz_file(tmp_path):
    """0.7 of the new Nyquist frequency 1/(2 S): S = 1e-4 s, 3500 Hz (to round-off); picked or every
    step, the Nyquist frequency."""
    res = _result()
    assert res.records(1e-4).passband_hz == pytest.approx(3500.0, rel=1e-12)
    assert res.records(1e-4, "pick").passband_hz == pytest.approx(5000.0, rel=1e-12)
    assert res.records().passband_hz == pytest.approx(50000.0, rel=1e-12)
    res.save(tmp_path / "r.npz", output_interval=1e-4)
    assert read_records(tmp_path / "r.npz").passband_hz == pytest.approx(3500.0, rel=1e-12)


def test_an_output_interval_longer_than_the_run_is_refused_naming_the_duration():
    res = _result()
    assert res.records(0.01).time.size == 2  # t = 0 and T
    with pytest.raises(ModelError, match=r"^output_interval = 0.5: must be at most the run's duration \(0.01 s\)"):
        res.records(0.5)
