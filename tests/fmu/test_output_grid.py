"""The FMU's output grid and the core's agree (issue 34): fmpy's rows of a run with the model's own
scenario are t = 0, h, ..., T, the first the state before any step, and each row equals the core's
record on the grid t = 0, h, ..., T with its samples picked (``records(h, "pick")``)."""

import subprocess
import sys

import numpy as np
import pytest

import cablecasing_core as cc

SCRIPT = """
import sys, numpy as np
from fmpy import simulate_fmu
r = simulate_fmu(sys.argv[1], stop_time=0.002, step_size=1e-4, output_interval=1e-4,
                 start_values={"scenario.drive": True}, output=["casing.B.Fz", "cable.A.Fx"])
np.savez(sys.argv[2], time=r["time"], fz=r["casing.B.Fz"], fx=r["cable.A.Fx"])
"""


@pytest.mark.slow
def test_fmpy_rows_are_the_cores_grid_t0_to_T(fmu, tmp_path):
    out = tmp_path / "fmu.npz"
    subprocess.run([sys.executable, "-c", SCRIPT, str(fmu), str(out)], check=True, timeout=600, cwd=tmp_path)
    z = np.load(out)
    rec = cc.simulate(cc.load_model(), duration=0.002).records(1e-4, "pick")
    assert z["time"][0] == 0 and len(z["time"]) == len(rec.time) == 21
    np.testing.assert_allclose(z["time"], rec.time, rtol=0, atol=1e-15)  # (k h against k m dt in double)
    # the same engine on the same grid before any contact (the first contact is at 0.024 s): the
    # same numbers, 1e-12 relative for any difference of summation order
    for name, col in (("fz", "casing.B.Fz"), ("fx", "cable.A.Fx")):
        ref = rec.columns[col]
        assert np.max(np.abs(ref)) > 0
        assert np.max(np.abs(z[name] - ref)) <= 1e-12 * np.max(np.abs(ref)), col
