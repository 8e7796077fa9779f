"""dist/CableCasing.fmu driven through fmpy (and libcosimpy), each scenario in a fresh process.

The FMU is rebuilt first when it is missing or older than its sources. The references are
independent of the FMU: the core's frequency-domain TRFAM, and the core's engine driven by the
same input reconstruction (cablecasing_core.timedomain.support_motion) in this process.

This module is over 400 lines because every FMU scenario is checked against the core here, with
one build of the FMU and one driver (fmu_driver.py).
"""

import re
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
from scipy.signal import csd, find_peaks, welch

import cablecasing_core as cc
from cablecasing_core.model.schema import CHANNELS, INTEGER_OUTPUTS, OUTPUTS, lookup
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion

pytestmark = pytest.mark.slow  # every test runs the FMU in fresh processes


ROOT = Path(__file__).resolve().parents[2]
FMU = ROOT / "dist" / "CableCasing.fmu"
H = 1e-4  # communication step (s)
NCH = len(CHANNELS)


# ------------------------------------------------------------------------------ signals and references
def scenario_table(model, duration, h=H):
    """The model's own scenario motion sampled at the communication points t = k h: (n, 36)."""
    t = h * np.arange(int(round(duration / h)))
    u, v, a = scenario_motion(model)(t)
    return np.hstack([u, v, a])


def multisine(channel, period, h, cycles, band=(10.0, 1000.0), rms=5.0, ramp=0.02, seed=7):
    """Periodic random support acceleration of one channel: flat spectrum over ``band`` (Hz),
    random phases, RMS ``rms`` (m/s2), with its exact periodic velocity and displacement, faded in
    over ``ramp`` s by a half-cosine (product rule, so u, v, a stay consistent), then ``cycles``
    periods. Returns the input table (n, 36) at t = k h and a function k -> acceleration at t_k."""
    n = int(round(period / h))
    f = np.fft.rfftfreq(n, h)
    on = (f >= band[0]) & (f <= band[1])
    A = np.zeros(len(f), complex)
    A[on] = np.exp(2j * np.pi * np.random.default_rng(seed).random(on.sum()))
    A *= rms / np.sqrt(np.mean(np.fft.irfft(A, n) ** 2))
    iw = np.zeros(len(f), complex)
    iw[1:] = 1 / (2j * np.pi * f[1:])
    u, v, a = np.fft.irfft(A * iw * iw, n), np.fft.irfft(A * iw, n), np.fft.irfft(A, n)
    r0 = int(round(ramp / h))
    k = np.arange(r0 + cycles * n)
    x = np.minimum(k * h / ramp, 1.0)
    inside = x < 1
    r = 0.5 * (1 - np.cos(np.pi * x))
    dr = np.where(inside, 0.5 * np.pi / ramp * np.sin(np.pi * x), 0.0)
    ddr = np.where(inside, 0.5 * (np.pi / ramp) ** 2 * np.cos(np.pi * x), 0.0)
    uk, vk, ak = u[k % n], v[k % n], a[k % n]
    table = np.zeros((len(k), 3 * NCH))
    c = CHANNELS.index(channel)
    table[:, c], table[:, NCH + c], table[:, 2 * NCH + c] = uk * r, vk * r + uk * dr, ak * r + 2 * vk * dr + uk * ddr
    return table, (lambda j: a[np.asarray(j) % n])


@pytest.fixture
def run(fmu_driver):
    """``run(tmp_path, scenario, fmu, **job)``: a scenario of fmu_driver.py in a fresh process, at the
    communication step H with every output unless the job says otherwise."""

    def scenario_run(tmp_path, scenario, fmu, **kw):
        kw.setdefault("h", H)
        kw.setdefault("outputs", list(OUTPUTS))
        return fmu_driver.run(tmp_path, scenario, fmu, **kw)

    return scenario_run


# ------------------------------------------------------------------------------ the archive
def test_fmpy_validate_finds_no_problem(fmu):
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(fmu)) == []


def test_parameters_declare_the_values_the_fmu_takes(fmu, tmp_path, fmu_driver):
    """Every number parameter carries min and max (FMI 2.0: inclusive): the schema's allowed values,
    an exclusive bound as the next double inside it (casing.E > 0: min 5e-324), an Integer also
    within FMI's 32 bits; its start lies inside. A value just outside (the next double past max)
    is refused at initialisation naming the parameter, the bound itself is taken."""
    import math

    from fmpy import read_model_description

    md = read_model_description(str(fmu))
    var = {v.name: v for v in md.modelVariables}
    numbers = [v for v in md.modelVariables if v.causality == "parameter" and v.type in ("Real", "Integer")]
    assert len(numbers) > 30
    for v in numbers:
        lo, hi = (-math.inf if v.min is None else float(v.min)), (math.inf if v.max is None else float(v.max))
        assert lo <= float(v.start) <= hi, v.name
    assert sum(v.min is None or v.max is None for v in numbers) == 1  # the phase, below
    assert var["scenario.excitation.cable_axial.phase"].min is None  # (any angle)
    assert (float(var["casing.E"].min), float(var["casing.E"].max)) == (5e-324, 1e16)
    assert (float(var["casing.nu"].min), float(var["casing.nu"].max)) == (-0.999, 0.4999)
    assert (var["scenario.seed"].min, var["scenario.seed"].max) == ("0", str(2**31 - 1))
    assert (float(var["solver.dt"].min), float(var["solver.dt"].max)) == (1e-10, 1.0)
    past = math.nextafter(0.4999, 1.0)
    refused = fmu_driver.run(tmp_path, "initial_outputs", fmu, params=[{"casing.nu": past}], outputs=["casing.B.Fz"])
    assert refused["status"][-1] == 3 and any("casing.nu" in line for line in refused["log"]), refused["log"]
    taken = fmu_driver.run(tmp_path, "initial_outputs", fmu, params=[{"casing.nu": 0.4999}], outputs=["casing.B.Fz"])
    assert np.all(taken["status"] == 0), taken["log"]


def test_model_description_is_complete(fmu, fmu_driver):
    from fmpy import read_model_description

    md = read_model_description(str(fmu))
    de = md.defaultExperiment
    # 0 s to the built-in specimen's own scenario.duration (1 s), in communication steps of 1e-4 s
    duration = float(cc.load_model().scenario["duration"])
    assert (float(de.startTime), float(de.stopTime), float(de.stepSize)) == (0.0, duration, 1e-4)
    cs = md.coSimulation
    assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate and cs.canHandleVariableCommunicationStepSize
    assert not cs.canBeInstantiatedOnlyOncePerProcess
    units = {u.name for u in md.unitDefinitions}
    var = {v.name: v for v in md.modelVariables}
    for v in md.modelVariables:
        assert v.description, v.name
        if v.type == "Real":
            assert v.unit in units, v.name
    expected = {fmu_driver.INPUTS[i]: "m" if i < 12 else "m/s" if i < 24 else "m/s2" for i in range(36)}
    expected.update(
        {
            n: "N" if ".F" in n else "N.m"
            for n in OUTPUTS
            if n.count(".") == 2 and n[0] == "c" and n.split(".")[1] in "AB"
        }
    )
    expected.update(
        {
            "contact.max_penetration": "m",
            "contact.dissipated_energy": "J",
            "casing.E": "Pa",
            "cable.d": "m",
            "casing.alpha": "1/s",
            "casing.beta": "s",
            "contact.friction": "1",
            "solver.dt": "s",
            "casing.rho": "kg/m3",
            "contact.damping": "kg/s",
        }
    )
    for name, unit in expected.items():
        assert var[name].unit == unit, name
    causality = {n: v.causality for n, v in var.items()}
    assert all(causality[n] == "input" for n in fmu_driver.INPUTS)
    assert all(causality[n] == "output" for n in OUTPUTS)
    assert var["contact.active"].type == "Integer" and var["contact.enabled"].type == "Boolean"
    # the outputs' types and the FMU's own parameters' words are the model schema's
    assert [n for n in OUTPUTS if var[n].type == "Integer"] == list(INTEGER_OUTPUTS)
    assert var["contact.enabled"].description == lookup("contact.enabled").description
    assert var["solver.dt"].description.startswith(lookup("scenario.dt").description + " inside the FMU")
    assert var["model_file"].type == "String" and var["model_file"].start == ""
    params = cc.load_model().parameters()
    for key, value in params.items():  # every numeric model key, same start value
        assert causality[key] == "parameter" and float(var[key].start) == float(value), key
    outputs = [u.variable.name for u in md.outputs]
    assert sorted(outputs) == sorted(OUTPUTS)
    assert sorted(u.variable.name for u in md.initialUnknowns) == sorted(OUTPUTS)
    assert all(u.dependencies == [] for u in md.outputs)  # no direct feedthrough
    with zipfile.ZipFile(fmu) as z:
        files = set(z.namelist())
        doc = z.read("documentation/index.html").decode()
    assert {
        "documentation/index.html",
        "documentation/externalDependencies.txt",
        "documentation/geometry.png",
        "model.png",
        "resources/cablecasing_core/timedomain/engine.py",
        "resources/cablecasing_core/timedomain/support_motion.py",
        "resources/cablecasing_core/model/specimens/default.toml",
        "resources/CableCasing.py",
        "resources/python-environment.txt",
        "resources/cablecasing_fmi2_bridge.py",
    } <= files
    assert not any("__pycache__" in f for f in files)
    # the numba cache compiled at build time ships in one place (a first start loads it)
    shipped = [f for f in files if f.endswith((".nbi", ".nbc"))]
    assert shipped and all(f.startswith("resources/numba_cache/") for f in shipped)
    assert any("run_steps" in f for f in shipped)
    assert all(name in doc for name in ("casing.A.vx", "cable.B.Mz", "contact.friction", "geometry.png", "N.m"))
    assert "<td>casing.nu</td><td>parameter</td><td>Real</td><td>1</td><td>0.3</td><td>-0.999 .. 0.4999</td>" in doc
    assert "<td>scenario.drive</td><td>parameter</td><td>Boolean</td><td></td><td>false</td>" in doc
    # its prose says what docs/fmu.md says (review W W1: it gave the old second-order extrapolation,
    # "a parameter whose value differs from its start value overrides", and "scenario.dt never")
    text, docs = " ".join(doc.split()), " ".join((ROOT / "docs" / "fmu.md").read_text().split())
    for said, in_docs in (
        ("(u + v h + a h&sup2;/2 + j h&sup3;/6, v + a h + j h&sup2;/2, a + j h)",
         "(u + v h + a h²/2 + j h³/6, v + a h"),
        ("0.9&nbsp;% at 800 Hz and 2.1&nbsp;% at 1 kHz", "0.9 % at 800 Hz and 2.1 % at 1 kHz"),
        ("even when set to its start value", "Setting a parameter to the built-in value overrides"),
        ("<code>scenario.dt</code>, set without <code>solver.dt</code>, is the internal step",
         "`scenario.dt`, set without `solver.dt`, is the internal step"),
    ):  # fmt: skip
        assert said in text and in_docs in docs, said
    assert "differs from its start value" not in text and "never:" not in text


def test_build_is_reproducible(tmp_path, kernels_cache_copy):
    """Two builds from the same sources and the same numba cache are the same file, byte for byte.
    The builds read a copy of this user's kernels' cache (the build ships what it holds), to which
    no other process (another test worker) can add kernels between the two."""
    import os

    cache = kernels_cache_copy()
    for name in ("one.fmu", "two.fmu"):
        subprocess.run(
            [sys.executable, str(ROOT / "build_fmu.py"), "--out", str(tmp_path / name)],
            check=True,
            cwd=ROOT,
            capture_output=True,
            env=dict(os.environ, NUMBA_CACHE_DIR=str(cache)),
        )
    assert (tmp_path / "one.fmu").read_bytes() == (tmp_path / "two.fmu").read_bytes()


# ------------------------------------------------------------------------------ physics through the FMU
def peak_frequencies(f, mag):
    """Resonance peaks (Hz) of |H|: prominent local maxima, refined by a parabola through the
    log-magnitude at the peak line and its two neighbours."""
    idx = find_peaks(np.log(mag), prominence=np.log(1.5))[0]
    lm = np.log(mag)
    df = f[1] - f[0]
    num = lm[idx - 1] - lm[idx + 1]
    den = lm[idx - 1] - 2 * lm[idx] + lm[idx + 1]
    return f[idx] + 0.5 * df * num / den


@pytest.mark.parametrize("d", ["x", "y", "z"])
def test_trfam_through_the_fmu(fmu, tmp_path, d, run):
    """Periodic random motion of casing.A.<d> (10-1000 Hz, 1 s period, with velocity and
    acceleration inputs), contact off, communication step 1e-4 s. With casing.alpha = 60 1/s (set
    through the FMU) every mode decays faster than exp(-30 t): after a 0.02 s fade-in and 0.3 s the
    response is periodic to 1e-4, so H1 over exactly one period (boxcar window, no leakage, no
    noise) is the transfer function itself and must equal the core's frequency-domain TRFAM."""
    alpha, period, settle = 60.0, 1.0, 0.3
    table, acc_at = multisine(f"casing.A.{d}", period, H, cycles=2)
    table = table[: int(round((0.02 + settle + period) / H))]
    res = run(
        tmp_path,
        "run",
        fmu,
        inputs=table,
        outputs=[f"casing.B.F{d}"],
        params={"contact.enabled": False, "casing.alpha": alpha},
    )
    assert np.all(res["status"] == 0)
    n = int(round(period / H))
    r0 = int(round(0.02 / H))
    force = -res["out"][-n:, 0]  # reaction on the body (TRFAM's sign) = -output
    times = np.arange(len(table) - n, len(table)) + 1  # output k is at t_(k+1)
    acc = acc_at(times - r0)
    f, Pxy = csd(acc, force, fs=1 / H, window="boxcar", nperseg=n, detrend=False)
    _, Pxx = welch(acc, fs=1 / H, window="boxcar", nperseg=n, detrend=False)
    band = (f >= 20) & (f <= 800)
    f = f[band]
    H_fmu = Pxy[band] / Pxx[band]
    m = cc.load_model().with_overrides({"casing.alpha": alpha})
    H_core = cc.trfam(m, f"casing.A.{d}", f"casing.B.{d}", f, "viscous")
    mag = np.abs(H_core)
    # away from anti-resonances: lines within 5 Hz of a local minimum of |TRFAM| are left out
    minima = f[find_peaks(-np.log(mag), prominence=np.log(1.5))[0]]
    keep = np.all(np.abs(f[:, None] - minima[None, :]) > 5.0, axis=1) if len(minima) else np.ones(len(f), bool)
    rel = np.abs(np.abs(H_fmu) / mag - 1)
    # the reconstruction's gain is 1 + 1.1 % at 800 Hz, Newmark's phase error (w dt)^2/12 < 3e-4
    # and the residual transient 1e-4: 5 % leaves room only for a real discrepancy
    assert keep.mean() > 0.8
    assert np.max(rel[keep]) < 0.05, f"worst {rel[keep].max():.3f} at {f[keep][np.argmax(rel[keep])]} Hz"
    pc, pf = peak_frequencies(f, mag), peak_frequencies(f, np.abs(H_fmu))
    assert len(pc) >= 3 and len(pc) == len(pf), (pc, pf)
    assert np.max(np.abs(pc - pf)) <= 1.0, (pc, pf)


CONTACT_RUN = 0.04  # s: the default scenario's first contact is at 0.024 s


@pytest.fixture(scope="module")
def contact_case(core_run):
    """The default scenario (random casing A z, cable A axial 50 Hz, contact with friction), its
    input table and the core's own run of it."""
    model = cc.load_model()
    table = scenario_table(model, CONTACT_RUN)
    return model, table, core_run(model, table)


def test_contact_run_equals_the_core(fmu, tmp_path, contact_case, run):
    model, table, ref = contact_case
    res = run(tmp_path, "run", fmu, inputs=table)
    assert np.all(res["status"] == 0) and res["init_status"] == 0
    active = ref[:, OUTPUTS.index("contact.active")]
    assert active.max() >= 1 and ref[:, OUTPUTS.index("contact.dissipated_energy")][-1] > 0
    # the same engine on the same motion: equal to round-off (a few ulps of each output's scale)
    scale = np.max(np.abs(ref), axis=0) + 1e-300
    assert np.max(np.abs(res["out"] - ref) / scale) < 1e-12


def test_state_get_set_serialize_and_reset(fmu, tmp_path, contact_case, run):
    model, table, ref = contact_case
    res = run(tmp_path, "state", fmu, inputs=table)
    assert np.all(res["status"] == 0)
    n = len(table) // 2
    assert np.array_equal(res["first"], ref[:n]) or np.max(np.abs(res["first"] - ref[:n])) < 1e-9
    assert np.array_equal(res["a"], res["b"])  # set state, same steps: bit-identical
    assert np.array_equal(res["a"], res["c"])  # serialised into a new instance: bit-identical
    assert np.array_equal(res["a"], res["e"])  # ... also one built with other parameters
    assert np.array_equal(np.vstack([res["first"], res["a"]]), res["d"])  # after fmi2Reset
    assert res["a"][:, OUTPUTS.index("contact.active")].max() >= 1  # the state includes contacts


def test_a_seed_beyond_fmi_integers_is_refused_not_wrapped(fmu, tmp_path, contact_case, run):
    """FMI 2.0's Integer is 32-bit; the model file's seeds go to 2**63 - 1. A model file whose seed
    does not fit is refused at initialisation, naming the key (fmi2GetInteger read 5e9 as
    705032704), and the master is told."""
    import cablecasing_core as cc

    data = cc.load_model().data
    model = cc.model_from_dict({**data, "scenario": {**data["scenario"], "seed": 5_000_000_000}})
    path = tmp_path / "big_seed.toml"
    path.write_text(model.to_toml())
    _, table, _ = contact_case
    res = run(tmp_path, "run", fmu, inputs=table[:2], params={"model_file": str(path)})
    assert int(res["init_status"]) == 3
    assert "scenario.seed = 5000000000: must be within FMI 2.0's Integer range" in " ".join(res["log"]), res["log"]


def test_a_state_of_an_fmu_built_for_another_model_is_refused(fmu, installed_fmu, tmp_path, contact_case, run):
    """The default FMU's state set into an instance of the installed specimen's FMU (the same
    variables, another model): fmi2Error naming why, and that instance goes on as if it had never
    seen it, to the bit. (It was taken: the outputs became a mix of the two models.)"""
    model, table, _ = contact_case
    res = run(tmp_path, "foreign_state", fmu, inputs=table[:40], fmu2=str(installed_fmu))
    assert int(res["set_status"]) == 3
    assert "an FMU built for another model" in " ".join(res["log"]), res["log"]
    assert np.all(res["two_status"] == 0) and np.array_equal(res["two"], res["alone"])


def test_two_instances_are_independent(fmu, tmp_path, contact_case, run, core_run):
    model, table, _ = contact_case
    table = table[: int(0.03 / H)]
    p1 = {"contact.friction": 0.05}
    p2 = {"contact.friction": 0.3, "casing.E": 6e9, "geometry.n_elements": 30}
    both = run(tmp_path, "two", fmu, inputs=table, p1=p1, p2=p2)
    alone1 = run(tmp_path, "run", fmu, inputs=table, params=p1)
    alone2 = run(tmp_path, "run", fmu, inputs=table, params=p2)
    assert np.array_equal(both["o1"], alone1["out"]) and np.array_equal(both["o2"], alone2["out"])
    assert not np.allclose(both["o1"], both["o2"])
    # and p2 really is the core's model with those parameters
    ref2 = core_run(model.with_overrides(p2), table)
    assert np.max(np.abs(alone2["out"] - ref2) / (np.max(np.abs(ref2), axis=0) + 1e-300)) < 1e-12


def test_any_communication_step(fmu, tmp_path, run):
    """Steps that are not multiples of solver.dt (and shorter than it) against the engine driven by
    the exact motion: a 60 Hz harmonic of casing.A.y, contact off. The reconstruction errs by at
    most x^2 = 1.8e-3 in the support's acceleration at a step's end and x^4/8 in its displacement
    (x = w h at the longest step, docs/fmu.md), below the 0.5 % allowed."""
    model = cc.load_model()
    w, amp = 2 * np.pi * 60.0, 2e-5
    steps = np.tile([1e-4, 3.7e-5, 6e-6, 1.13e-4], 250)
    t = np.concatenate([[0.0], np.cumsum(steps)[:-1]])
    ramp = 1 - np.exp(-((t / 0.01) ** 2))  # not exact derivatives: only the motion's samples matter
    c = CHANNELS.index("casing.A.y")
    table = np.zeros((len(t), 3 * NCH))

    def exact(tt):
        tt = np.atleast_1d(tt)
        s = 1 - np.exp(-((tt / 0.01) ** 2))
        ds = 2 * tt / 0.01**2 * np.exp(-((tt / 0.01) ** 2))
        dds = (2 / 0.01**2 - 4 * tt**2 / 0.01**4) * np.exp(-((tt / 0.01) ** 2))
        u0, v0, a0 = amp * np.sin(w * tt), amp * w * np.cos(w * tt), -amp * w * w * np.sin(w * tt)
        return u0 * s, v0 * s + u0 * ds, a0 * s + 2 * v0 * ds + u0 * dds

    table[:, c], table[:, NCH + c], table[:, 2 * NCH + c] = exact(t)
    del ramp
    res = run(
        tmp_path,
        "steps",
        fmu,
        inputs=table,
        steps=steps.tolist(),
        outputs=["casing.B.Fy"],
        params={"contact.enabled": False},
    )
    assert np.all(res["status"] == 0)

    def motion(tt):
        z = np.zeros((len(tt), NCH))
        out = [z, z.copy(), z.copy()]
        for o, x in zip(out, exact(tt)):
            o[:, c] = x
        return tuple(out)

    eng = Engine(model, contact=False, ledger=False)
    ref = np.zeros(len(steps))
    for k, h in enumerate(steps):
        eng.advance(float(h), motion)
        ref[k] = eng.outputs()["casing.B.Fy"]
    err = np.abs(res["out"][:, 0] - ref)
    assert np.max(err) < 5e-3 * np.max(np.abs(ref))


def test_the_masters_clock_is_the_fmus_whatever_its_rounding(fmu, tmp_path, run):
    """Three masters' clocks over the same 300 input rows (the default scenario, contact off): t_k =
    k H from 0 (the reference); t_k = 1000 s + k H, whose steps t_(k+1) - t_k differ from H by
    ulp(1000 s) = 1.1e-13 s (1.1e-8 solver.dt: a clock's rounding, no time to integrate; a step of
    its own would cancel digits as (dt / 1e-13 s)**2); and t_k = k h with h = 1e-5 (1 + 5e-10)
    s, whose rest of 5e-10 solver.dt each step the FMU's time must not drift from. Every step is
    taken, and the outputs equal the reference's to 1e-7 of their RMS (the reconstruction of a step
    of H (1 + 1e-9) on a linear model)."""
    model = cc.load_model()
    table = scenario_table(model, 300 * H)
    p = {"contact.enabled": False}
    outs = ["casing.B.Fz", "casing.A.Fy"]
    k = np.arange(len(table) + 1)
    ref = run(tmp_path, "clock", fmu, inputs=table, times=(k * H).tolist(), outputs=outs, params=p)
    late = run(tmp_path, "clock", fmu, inputs=table, times=(1000.0 + k * H).tolist(), outputs=outs, params=p)
    assert np.all(ref["status"] == 0) and np.all(late["status"] == 0), late["log"]
    rms = np.sqrt(np.mean(ref["out"] ** 2, axis=0))
    assert np.all(np.abs(late["out"] - ref["out"]) <= 1e-7 * rms)
    h = 1e-5 * (1 + 5e-10)  # (one row per step: the first 3000 rows of a scenario on the step of 1e-5)
    fine = scenario_table(model, 3000 * 1e-5, h=1e-5)
    drift = run(tmp_path, "clock", fmu, inputs=fine, times=(np.arange(3001) * h).tolist(), outputs=outs, params=p)
    assert np.all(drift["status"] == 0), drift["log"]


def test_errors_are_reported_and_the_process_goes_on(fmu, tmp_path, contact_case, run):
    model, table, ref = contact_case
    res = run(tmp_path, "errors", fmu, inputs=table[:5])
    discard, error = 2, 3  # fmi2Discard, fmi2Error

    def logged(key, *words):
        text = " ".join(res[f"{key}_log"])
        return all(w in text for w in words)

    assert res["nan_status"] == discard and logged("nan", "casing.A.z", "nan", "finite")
    assert res["inf_status"] == discard and logged("inf", "cable.B.vy", "inf")
    assert np.all(res["after_nan_status"] == 0)  # the instance goes on after a refused step
    assert res["wrong_time_status"] == discard and logged("wrong_time", "t =")
    assert res["badparam_init_status"] == error  # initialisation fails, naming the parameter
    assert logged(
        "badparam_init", "error:", "casing.E", "-1.0", "must be a number in (0, 1e+16] in Pa"
    )  # (bounded since issue 26)
    assert res["badparam_status"] == error and logged("badparam", "did not initialise", "casing.E", "-1.0")
    assert np.all(res["badgap_status"] == [error, error]) and logged("badgap", "casing.d_inner", "cable.d")
    assert np.all(res["badfile_status"] == [error, error]) and logged(
        "badfile", "model_file", "/nonexistent/model.toml"
    )
    assert np.all(res["baddt_status"] == [error, error]) and logged("baddt", "solver.dt", "-1e-05")
    assert res["tinydt_status"] == error and logged("tinydt", "solver.dt = 1e-12: must be a number in [1e-10, 1]")
    # the model's own scenario on a grid whose Nyquist frequency (500 Hz) lies inside its random band
    assert res["coarsedrive_status"] == error and logged("coarsedrive", "solver.dt = 0.001: must resolve the random")
    assert res["blowup_status"] == discard and logged("blowup", "penetration", "rolled back")
    assert np.all(res["after_blowup_status"] == 0)  # the failed step was rolled back whole
    np.testing.assert_array_equal(res["after_blowup_out"], ref[4])
    # later, the message words the step that blew up (it once read the state the roll-back restored:
    # the step before's time, node 0 and a penetration of 0 m); asked for again, the FMU asks to end
    # (fmi2Terminated, so that a master such as fmusim that repeats a discarded step stops); a step it
    # can take clears that
    t0 = 5 * 1e-4
    m = re.search(r"at t = ([0-9.e-]+) s, cable node \d+: penetration ([0-9.e-]+) m", " ".join(res["late_blowup0_log"]))
    assert m and t0 < float(m.group(1)) <= t0 + 1e-4 + 1e-12 and float(m.group(2)) > 0.0015, res["late_blowup0_log"]
    assert [int(res[f"late_blowup{k}_status"]) for k in range(3)] == [discard, discard, 0]
    assert "asked for again with the same inputs" in " ".join(res["late_blowup1_log"])
    assert res["late_blowup_terminated"].tolist() == [False, True, False]
    # unreadable serialised bytes: fmi2DeSerializeFMUstate fails (fmi2Error, logged), the instance goes on
    assert np.all(res["badstate_status"] == [error, 0])
    assert logged("badstate", "error:", "not a serialised CableCasing FMU state")
    assert np.all(res["fresh_status"] == 0)
    np.testing.assert_array_equal(res["fresh_out"], ref[:5])  # start time 0.25 s changes nothing


def _test_extra_installs(name):
    """Whether pyproject.toml's extra ``test`` installs the package ``name`` on this Python (its
    requirement's environment marker, e.g. ``python_version >= '3.11'``, holds here)."""
    try:
        import tomllib
    except ModuleNotFoundError:  # (Python 3.10)
        import tomli as tomllib
    from packaging.requirements import Requirement

    pyproject = tomllib.loads((Path(__file__).resolve().parents[2] / "pyproject.toml").read_text())
    wanted = [Requirement(r) for r in pyproject["project"]["optional-dependencies"]["test"]]
    return any(r.name == name and (r.marker is None or r.marker.evaluate({"extra": "test"})) for r in wanted)


@pytest.mark.skipif(
    not _test_extra_installs("libcosimpy"),
    reason="libcosimpy>=0.0.6 has no release for this Python: the [test] extra installs it from Python 3.11 on",
)
def test_libcosim_gives_the_same_outputs_as_fmpy(fmu, tmp_path, contact_case, run):
    """A second importer: OSP's libcosim (C++, FMI Library) through libcosimpy. libcosim counts time
    in integer nanoseconds and passes doStep(t_k, t_(k+1) - t_k) with t_k = k 1e5 / 1e9 in double,
    steps that differ from 1e-4 s in the last bits; given the same steps, fmpy must give the same
    bits. Where the [test] extra installs libcosimpy (Python 3.11 on), a missing one fails the test."""
    import libcosimpy  # noqa: F401

    model, table, ref = contact_case
    params = {"contact.friction": 0.2}
    res = run(tmp_path, "libcosim", fmu, inputs=table, params=params)
    times = np.arange(len(table) + 1) * 100000 / 1e9
    fm = run(tmp_path, "steps", fmu, inputs=table, params=params, steps=np.diff(times).tolist())
    assert np.all(res["ok"]) and np.all(fm["status"] == 0)
    assert np.array_equal(res["out"], fm["out"])
    assert fm["out"][:, OUTPUTS.index("contact.active")].max() >= 1


def test_numba_cache_outlives_the_unpacked_fmu(fmu, tmp_path, run):
    """Two fresh processes, two fresh unpack folders: the second loads every kernel from the
    per-user cache (no compilation), and the model's code and cache live outside the unpacked FMU
    (a host may delete that folder after the run)."""
    run(tmp_path, "cache", fmu)  # compiles if this FMU's kernels are not cached yet
    res = run(tmp_path, "cache", fmu)
    assert res["status"] == 0
    assert res["misses"] == 0 and res["run_steps_hits"] >= 1
    assert not str(res["package_file"]).startswith(str(res["unzip"]))
    assert not str(res["cache_path"]).startswith(str(res["unzip"]))


@pytest.mark.parametrize("params", [None, {"model_file": "installed"}, {"loads.gravity.z": -9.81}])
def test_first_start_on_an_empty_cache_compiles_nothing(fmu, tmp_path, run, params):
    """A user who never ran the FMU (an empty per-user cache folder): the machine code compiled
    when the FMU was built ships inside it and is loaded, so the first start compiles no kernel:
    for the base model, the installed specimen (gravity, tension, regularised friction) and the
    base model with gravity, whose kernels differ."""
    import os

    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["XDG_CACHE_HOME"] = str(tmp_path / "empty-cache")
    res = run(tmp_path, "cache", fmu, env=env, **({"params": params} if params else {}))
    assert res["status"] == 0
    assert res["misses"] == 0 and res["run_steps_hits"] >= 1, res["log"]
    assert str(res["cache_path"]).startswith(str(tmp_path / "empty-cache"))
    assert any("files copied from the FMU" in line for line in res["log"])
    # (its own copy of the package: a Python host's later import gets it, and the FMU says so)
    assert any("cablecasing_core imported from this FMU" in line for line in res["log"]), res["log"]


def test_a_first_start_that_must_compile_says_so(fmu, tmp_path, run):
    """Without fitting machine code (here: the FMU without its shipped cache, an empty per-user
    cache) numba compiles the kernels on the first start, and the FMU logs it while it happens.
    Compiled or loaded, the kernels are the same arithmetic: the installed specimen's chaotic
    contact run (0.02 s) in the compiling process equals, to the bit, the same run in a process that
    loads the machine code the FMU ships (a fused multiply-add that only inlining creates made the
    two differ at the rounding level, which the contacts grew to 3e-4 N in 0.02 s; _compile_options.py)."""
    import os

    stripped = tmp_path / "stripped.fmu"
    with zipfile.ZipFile(fmu) as src, zipfile.ZipFile(stripped, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            if not info.filename.startswith("resources/numba_cache/"):
                dst.writestr(info, src.read(info.filename))
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["XDG_CACHE_HOME"] = str(tmp_path / "empty-cache")
    model = cc.load_model("installed")
    t = 1e-4 * np.arange(200)
    rows = np.hstack(scenario_motion(model)(t))
    job = dict(inputs=rows, params={"model_file": "installed"}, outputs=["casing.B.Fz", "casing.A.Fy"])
    res = run(tmp_path, "cache", stripped, env=env, **job)
    assert res["status"] == 0 and res["misses"] >= 1
    said = [line for line in res["log"] if "compiling the model's numba kernels for this machine" in line]
    assert len(said) == 1, res["log"]
    # (and where they go: the per-user folder, which later starts load them from)
    assert f"this takes 30-60 s, and later starts load them from {tmp_path / 'empty-cache'}" in said[0]
    run(tmp_path, "cache", fmu, **job)  # compiles what the shipped cache lacks for this specimen, if anything
    loaded = run(tmp_path, "cache", fmu, **job)
    assert loaded["status"] == 0 and loaded["misses"] == 0
    np.testing.assert_array_equal(res["out"], loaded["out"])


def test_a_host_that_imported_the_package_first_is_told_whether_it_is_the_fmus_code(fmu, tmp_path, run):
    """A Python host that imported cablecasing_core itself before loading the FMU (the demo does):
    that copy is used; the FMU says so as information when its sources are the FMU's own, and
    warns when they differ (another version: the results are that copy's)."""
    import shutil

    root = Path(__file__).resolve().parents[2]
    same = run(tmp_path, "preimported", fmu, package_parent=str(root))
    line = [m for m in same["log"] if "was already imported" in m]
    assert same["status"] == 0 and len(line) == 1 and line[0].startswith("ok: "), same["log"]
    assert "its Python sources are the FMU's own" in line[0]
    assert not any("imported from this FMU" in m for m in same["log"])
    assert any("model code the host's cablecasing_core" in m for m in same["log"]), same["log"]

    other = tmp_path / "other"
    shutil.copytree(root / "cablecasing_core", other / "cablecasing_core", ignore=shutil.ignore_patterns("__pycache__"))
    with open(other / "cablecasing_core" / "errors.py", "a") as f:
        f.write("\n# another version\n")
    diff = run(tmp_path, "preimported", fmu, package_parent=str(other))
    line = [m for m in diff["log"] if "was already imported" in m]
    assert diff["status"] == 0 and len(line) == 1 and line[0].startswith("warning: "), diff["log"]
    assert "its sources differ" in line[0]


def test_scenario_drive_runs_the_cores_scenario(fmu, tmp_path, run):
    """scenario.drive = true, inputs at zero: the supports follow the model's own scenario (random
    casing A z and the cable's 50 Hz axial drive), and the FMU's support forces after each
    communication step are the core's run of that scenario (cc.simulate) at the same times, to the
    bit: the same motion on the same grid, the same kernels."""
    model = cc.load_model()
    n = 400
    res = run(tmp_path, "run", fmu, inputs=np.zeros((n, 3 * NCH)), params={"scenario.drive": True})
    assert np.all(res["status"] == 0) and res["init_status"] == 0
    forces = cc.simulate(model, duration=n * H).support_forces[9::10]
    assert len(forces) == n and np.max(np.abs(forces)) > 0.1
    assert res["out"][:, OUTPUTS.index("contact.active")].max() >= 1
    assert np.array_equal(res["out"][:, :24], forces)


def test_a_restored_state_brings_back_its_phase_and_a_tiny_step_moves_the_clock(fmu, tmp_path, run):
    """FMI 2.0, 2.1.8: fmi2SetFMUstate makes the saved state the FMU's state, its life-cycle phase
    too. A state saved while instantiated, restored after a step, lets the master set up,
    initialise and step again (the same outputs: the FMU is deterministic); one saved in
    initialisation mode exits it again with the parameter it held. A step of 1e-15 s (below
    1e-6 solver.dt, the rounding of a clock) returns fmi2OK, moves fmi2LastSuccessfulTime
    by it, and the next step from there is taken (it was discarded as out of time)."""
    outs = ["casing.B.Fz", "casing.A.Fx"]
    table = scenario_table(cc.load_model(), 3 * H)
    res = run(tmp_path, "phases", fmu, inputs=table, h=H, outputs=outs)
    assert res["first_step"] == 0 and res["restore_instantiated"] == 0, res["log"]
    assert np.all(res["again"] == 0), res["log"]
    np.testing.assert_array_equal(res["again_out"], res["first_out"])
    assert res["restore_initialization"] == 0 and np.all(res["init_again"] == 0), res["log"]
    assert res["friction_after"] == 0.3
    assert res["tiny"] == 0 and res["after_tiny"] == 0, res["log"]
    assert res["tiny_time"] == res["tiny_master"] == H + 1e-15


def test_instances_started_at_once_on_threads_share_one_load(fmu, tmp_path, run):
    """A master with a thread pool instantiates on several threads at once, in a process that never
    loaded the FMU and with an empty per-user cache: both load (one of them loads the code, the
    other waits for it), a third run after fmpy deleted both unpack folders still loads, all three
    records are the same, and the host's own warnings are still shown (the FMU's capture of the
    model's warnings is one at a time: two at once could restore each other's hooks)."""
    import os

    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["XDG_CACHE_HOME"] = str(tmp_path / "empty-cache")
    outs = ["casing.B.Fz"]
    res = run(tmp_path, "threads", fmu, env=env, outputs=outs)
    assert list(res["errors"]) == [""], res["errors"]
    assert res["t0"].shape == res["after"].shape and res["t0"].size > 0
    np.testing.assert_array_equal(res["t0"], res["after"])
    np.testing.assert_array_equal(res["t1"], res["after"])
    assert "the host's own warning" in str(res["host_warning"])
