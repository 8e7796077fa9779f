"""The FMU driven through fmpy, each scenario in a fresh process (FMUs share the host's interpreter)."""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
FMU = ROOT / "dist" / "CableCasing.fmu"
CONTACT_MODEL = {"scenario.excitation.cable_axial.amplitude": 1.5e-3}


@pytest.fixture(scope="session")
def fmu():
    sources = list((ROOT / "cablecasing_core").rglob("*.py")) + list((ROOT / "fmu_src").glob("*.py")) + [ROOT / "build_fmu.py"]
    if not FMU.exists() or FMU.stat().st_mtime < max(p.stat().st_mtime for p in sources):
        subprocess.run([sys.executable, str(ROOT / "build_fmu.py")], check=True, cwd=ROOT)
    return FMU


def drive(tmp_path, scenario, **args):
    out = tmp_path / f"{scenario}.npz"
    subprocess.run([sys.executable, str(ROOT / "tests" / "fmu_driver.py"), scenario, str(out), json.dumps(args)],
                   check=True, cwd=ROOT, timeout=900)
    return dict(np.load(out))


def test_fmpy_validate(fmu):
    from fmpy.validation import validate_fmu
    assert validate_fmu(str(fmu)) == []


def test_model_description_is_complete(fmu):
    from fmpy import read_model_description
    md = read_model_description(str(fmu))
    assert md.defaultExperiment.stopTime == "1.0" or float(md.defaultExperiment.stopTime) == 1.0
    assert float(md.defaultExperiment.stepSize) == 1e-4
    assert md.coSimulation.canGetAndSetFMUstate and md.coSimulation.canSerializeFMUstate
    for v in md.modelVariables:
        assert v.description
        if v.type == "Real":
            assert v.unit, v.name
    names = {v.name for v in md.modelVariables}
    assert {"casing.A.z", "casing.A.vz", "casing.A.az", "cable.B.Fz", "casing.B.Mx", "contact.active",
            "contact.max_penetration", "contact.dissipated_energy", "casing.E", "contact.friction",
            "model_file", "solver.dt"} <= names
    assert len(md.initialUnknowns) == len(md.outputs)
    import zipfile
    with zipfile.ZipFile(fmu) as z:
        files = set(z.namelist())
    assert {"documentation/index.html", "documentation/externalDependencies.txt", "model.png",
            "resources/cablecasing_core/engine.py"} <= files


def core_reference(duration, h=1e-4):
    """The core's own run of the same master signal: the engine with the same input reconstruction."""
    import cablecasing_core as cc
    from cablecasing_core.engine import Engine, OUTPUTS
    from cablecasing_core.kinematics import QuinticStep, taylor_target
    from cablecasing_core.scenario import scenario_motion
    m = cc.load_model().with_overrides(CONTACT_MODEL)
    t = h * np.arange(0, int(round(duration / h)))
    u, v, a = scenario_motion(m)(t)
    eng = Engine(cc.load_model(), ledger=False)
    support = tuple(np.zeros(12) for _ in range(3))
    outs = []
    for k in range(len(t)):
        step = QuinticStep(eng.time, h, support, taylor_target(u[k], v[k], a[k], h))
        eng.advance(h, step)
        support = step.end_state()
        o = eng.outputs()
        outs.append([o[n] for n in OUTPUTS if n != "contact.active"] + [o["contact.active"]])
    return np.array(outs)


def test_contact_run_equals_core(fmu, tmp_path):
    res = drive(tmp_path, "contact", model=CONTACT_MODEL, duration=0.03)
    ref = core_reference(0.03)
    assert ref[:, -1].max() > 0, "the scenario must bring the cable into contact"
    np.testing.assert_allclose(res["out"], ref, rtol=1e-12, atol=1e-15)   # same engine, same arithmetic


def test_state_get_set_and_serialize(fmu, tmp_path):
    res = drive(tmp_path, "state", model=CONTACT_MODEL, duration=0.02)
    assert np.array_equal(res["first"], res["second"])
    assert np.array_equal(res["first"], res["third"])


def test_two_instances_are_independent(fmu, tmp_path):
    p1, p2 = {"contact.friction": 0.05}, {"contact.friction": 0.3, "casing.E": 6e9}
    both = drive(tmp_path, "two", model=CONTACT_MODEL, duration=0.02, p1=p1, p2=p2)
    alone1 = drive(tmp_path, "contact", model=CONTACT_MODEL, duration=0.02, params=p1)
    alone2 = drive(tmp_path, "contact", model=CONTACT_MODEL, duration=0.02, params=p2)
    assert np.array_equal(both["o1"], alone1["out"]) and np.array_equal(both["o2"], alone2["out"])
    assert not np.array_equal(both["o1"], both["o2"])


def test_errors_are_reported_not_fatal(fmu, tmp_path):
    res = drive(tmp_path, "errors")
    assert res["nan_status"] in (2, 3)            # fmi2Discard or fmi2Error
    assert res["after_nan_status"] == 0           # the instance goes on
    assert res["badparam_status"] in (2, 3)
    log = " ".join(res["log"])
    assert "casing.A.z" in log and "nan" in log
    assert "casing.E" in log and "-1.0" in log


@pytest.mark.parametrize("d", ["x", "y", "z"])
def test_trfam_through_fmu(fmu, tmp_path, d):
    """Band-limited random motion of casing.A.<d> (10-1000 Hz, periodic over 1 s), contact off,
    communication step 1e-4 s: H = F/a over the second period (steady state, no leakage) against the
    core's frequency-domain TRFAM."""
    import cablecasing_core as cc
    from cablecasing_core.engine import OUTPUTS
    from scipy.signal import find_peaks
    over = {"scenario.excitation.casing_random.target": f"casing.A.{d}",
            "scenario.excitation.cable_axial.amplitude": 0.0, "scenario.duration": 1.0}
    h = 1e-4
    res = drive(tmp_path, "contact", model=over, duration=2.0, params={"contact.enabled": False}, h=h)
    F = res["out"][:, OUTPUTS.index(f"casing.B.F{d}")]
    m = cc.load_model().with_overrides(over)
    from cablecasing_core.scenario import scenario_motion
    t_out = h * np.arange(1, len(F) + 1)                           # outputs are at the step ends
    acc = scenario_motion(m)(t_out)[2][:, cc.config.CHANNELS.index(f"casing.A.{d}")]
    last = slice(len(F) // 2, len(F))                              # the second 1-s period
    f = np.fft.rfftfreq(len(F) // 2, h)
    H_fmu = -np.fft.rfft(F[last]) / np.fft.rfft(acc[last])         # reaction on the body = -output
    band = (f >= 20) & (f <= 800)
    H_core = cc.trfam(m, f"casing.A.{d}", f"casing.B.{d}", f[band], "viscous")
    H_fmu = H_fmu[band]
    mag = np.abs(H_core)
    keep = np.ones(band.sum(), bool)
    for i in find_peaks(-mag)[0]:                                  # away from anti-resonances (+-3 %)
        keep &= np.abs(f[band] - f[band][i]) > 0.03 * f[band][i]
    rel = np.abs(np.abs(H_fmu) - mag) / mag
    # Taylor extrapolation inside a 1e-4 s step errs by (w h)^3/6 < 2 % at 800 Hz; Newmark (w dt)^2/12
    assert np.max(rel[keep]) < 0.05
    pc = find_peaks(mag, prominence=0.2 * mag.max())[0]
    pf = find_peaks(np.abs(H_fmu), prominence=0.2 * np.abs(H_fmu).max())[0]
    assert len(pc) >= 2 and len(pc) == len(pf)
    assert np.max(np.abs(f[band][pc] - f[band][pf])) <= 1.0         # 1 Hz lines
