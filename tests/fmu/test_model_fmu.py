"""An FMU built for a model file (``build_fmu.py --model FILE``): examples/clipped_specimen.toml
(two clips along the casing, the one at 0.55 m excited through its support channels
``dash.x/.y/.z``).

Its modelDescription lists the model's inputs and outputs from the schema; driven through fmpy,
its outputs (support and clip forces) are the core's on the same inputs; an excited clip moves the
casing as the frequency-domain TRFAM predicts; a ``model_file`` with other clip channels is
refused at initialisation. The FMU is built once per session (``model_fmu`` in conftest.py), and
each run is a fresh process of fmu_driver.py.
"""

import zipfile

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.model.schema import OUTPUTS, input_spec, inputs_of, output_spec, outputs_of
from cablecasing_core.timedomain.scenario import scenario_motion

pytestmark = pytest.mark.slow  # every test runs the FMU in fresh processes

H = 1e-4  # communication step (s)


def test_model_description_lists_the_models_channels_and_outputs(model_fmu, fmu):
    """(a) Inputs exactly ``inputs_of(model)`` (the 12 support channels' u, then the clip's
    dash.x/.y/.z, then v, then a), outputs exactly ``outputs_of(model)`` (OUTPUTS, then the two
    clips' Fx .. Mz), each with the schema's unit and description and consecutive value
    references; the parameters start at the model file's values; GUID and documentation its own."""
    from fmpy import read_model_description
    from fmpy.validation import validate_fmu

    path, toml, model = model_fmu
    assert validate_fmu(str(path)) == []
    md = read_model_description(str(path))
    var = {v.name: v for v in md.modelVariables}
    inputs = [v for v in md.modelVariables if v.causality == "input"]
    outputs = [v for v in md.modelVariables if v.causality == "output"]
    assert [v.name for v in inputs] == list(inputs_of(model)) and len(inputs) == 45
    assert [v.name for v in outputs] == list(outputs_of(model)) and len(outputs) == len(OUTPUTS) + 12
    assert {"dash.x", "dash.vy", "dash.az", "casing.clip0.Fx", "casing.clip1.Mz"} <= set(var)
    for v in inputs:
        assert (v.unit, v.description) == input_spec(v.name), v.name
    for v in outputs:
        unit, text = output_spec(v.name)
        assert v.description == text and (v.type == "Integer" or v.unit == unit), v.name
    refs = [v.valueReference for v in inputs + outputs]
    assert refs == list(range(refs[0], refs[0] + len(refs)))  # (the binary's buffers)
    assert sorted(u.variable.name for u in md.outputs) == sorted(outputs_of(model))
    for key, value in model.parameters().items():
        assert float(var[key].start) == float(value), key
    assert float(var["contact.friction"].start) == 0.12  # the model file's, not the specimen's 0.15
    plain = read_model_description(str(fmu))
    assert md.guid != plain.guid and md.coSimulation.modelIdentifier == plain.coSimulation.modelIdentifier
    assert "clipped_specimen.toml" in md.description
    with zipfile.ZipFile(path) as z:
        assert z.read("resources/model/clipped_specimen.toml") == toml.read_bytes()
        doc = z.read("documentation/index.html").decode()
    assert "clipped_specimen.toml" in doc and "dash.ax" in doc and "casing.clip1.Fz" in doc


def test_driven_on_the_clip_channel_it_equals_the_core(model_fmu, tmp_path, fmu_driver, core_run):
    """(b) The model's own scenario (random casing A z, the cable's 50 Hz axial drive, and dash.y
    at 150 Hz on the excited clip) sampled as the FMU's 45 inputs, with contact, 0.04 s: every
    output (support forces, contact, both clips' forces) equals the core's Engine driven by the
    same reconstruction (the same kernels on the same numbers: round-off at most, 1e-12 of each
    output's scale)."""
    path, _, model = model_fmu
    names, outs = list(inputs_of(model)), list(outputs_of(model))
    t = H * np.arange(400)
    table = np.hstack(scenario_motion(model)(t))
    assert table.shape == (400, 45) and np.any(table[:, names.index("dash.ay")])
    res = fmu_driver.run(tmp_path, "run", path, inputs=table, h=H, outputs=outs, input_names=names)
    assert res["init_status"] == 0 and np.all(res["status"] == 0)
    ref = core_run(model, table)
    assert ref[:, outs.index("contact.active")].max() >= 1  # contact happened
    clip = ref[:, len(OUTPUTS) :]
    assert np.max(np.abs(clip[:, 6:9])) > 1e-3  # the excited clip carries force
    scale = np.max(np.abs(ref), axis=0) + 1e-300
    assert np.max(np.abs(res["out"] - ref) / scale) < 1e-12


def test_the_binary_takes_the_models_buffers_and_refuses_other_references(model_fmu, tmp_path, fmu_driver):
    """The C binary reads and writes the two buffers by the first value references and counts the
    slave gives it (45 inputs, 39 outputs here): the last input and the last output are read
    there, and a reference just past them (a parameter), far beyond any, or a write to an output
    is fmi2Error with a message naming the reference (the buffers' bounds hold)."""
    from fmpy import read_model_description

    path, _, model = model_fmu
    var = {v.name: v.valueReference for v in read_model_description(str(path)).modelVariables}
    last_in, last_out = var[inputs_of(model)[-1]], var[outputs_of(model)[-1]]
    assert (last_in, last_out) == (44, 83)
    refs = [[last_in, last_out], [last_out + 1], [10**6], [2**32 - 1]]
    res = fmu_driver.run(tmp_path, "references", path, references=refs, input_names=list(inputs_of(model)))
    error = 3  # fmi2Error
    assert list(res["get_status"]) == [0, error, error, error]
    assert list(res["set_status"]) == [error, error, error, error]
    assert "value reference 83: casing.clip1.Mz (Real, output)" in " ".join(res["log0"])
    assert "value reference 84" in " ".join(res["log1"])
    for k, vr in ((2, 10**6), (3, 2**32 - 1)):
        assert f"value reference {vr}: no variable" in " ".join(res[f"log{k}"])


def test_it_and_the_plain_fmu_run_side_by_side_in_one_process(model_fmu, fmu, tmp_path, fmu_driver):
    """Their GUIDs differ, so one host process loads both (the bridge keeps a slave module per
    GUID): stepped alternately, each gives exactly what it gives alone (0.02 s with contact)."""
    path, _, model = model_fmu
    names, outs = list(inputs_of(model)), list(outputs_of(model))
    t = H * np.arange(200)
    table2 = np.hstack(scenario_motion(model)(t))
    table = np.hstack(scenario_motion(cc.load_model())(t))
    np.save(tmp_path / "table2.npy", table2)
    both = fmu_driver.run(
        tmp_path, "two", fmu, inputs=table, h=H, outputs=list(OUTPUTS), fmu2=str(path),
        inputs2=str(tmp_path / "table2.npy"), input_names2=names, outputs2=outs,
    )  # fmt: skip
    alone = fmu_driver.run(tmp_path, "run", fmu, inputs=table, h=H, outputs=list(OUTPUTS))
    alone2 = fmu_driver.run(tmp_path, "run", path, inputs=table2, h=H, outputs=outs, input_names=names)
    assert np.array_equal(both["o1"], alone["out"]) and np.array_equal(both["o2"], alone2["out"])
    assert np.max(np.abs(both["o2"][:, len(OUTPUTS) :])) > 1e-3  # (the second one's clip forces)


def test_the_installation_example_builds_and_its_mount_keys_are_parameters(tmp_path):
    """examples/installation.toml (isolated ends, two clips without excitation): its FMU validates,
    has the 36 inputs and 27 + 12 outputs, and the isolators' keys as parameters with their SI
    units (N/m, N.m/rad, N.s/m, N.m.s/rad: each with a UnitDefinitions entry)."""
    import subprocess
    import sys
    from pathlib import Path

    from fmpy import read_model_description
    from fmpy.validation import validate_fmu

    root = Path(__file__).resolve().parents[2]
    toml, path = root / "examples" / "installation.toml", tmp_path / "installation.fmu"
    subprocess.run(
        [sys.executable, str(root / "build_fmu.py"), "--model", str(toml), "--output", str(path)],
        check=True, capture_output=True, cwd=root,
    )  # fmt: skip
    assert validate_fmu(str(path)) == []
    md = read_model_description(str(path))
    var = {v.name: v for v in md.modelVariables}
    model = cc.load_model(toml)
    assert [v.name for v in md.modelVariables if v.causality == "input"] == list(inputs_of(model))
    assert [v.name for v in md.modelVariables if v.causality == "output"] == list(outputs_of(model))
    assert len(outputs_of(model)) == len(OUTPUTS) + 12
    units = {
        "casing.isolator.A.stiffness.axial": "N/m",
        "casing.isolator.B.rotational_stiffness.lateral_1": "N.m/rad",
        "casing.isolator.A.damping.lateral_2": "N.s/m",
        "casing.isolator.B.rotational_damping.axial": "N.m.s/rad",
    }
    for name, unit in units.items():
        assert var[name].causality == "parameter" and var[name].unit == unit, name
    assert float(var["casing.isolator.A.stiffness.axial"].start) == 4.0e5  # the file's value
    assert {u.name for u in md.unitDefinitions} >= set(units.values())


def test_the_default_experiment_runs_the_models_own_duration(tmp_path):
    """The DefaultExperiment of an FMU built for a model file ends at that model's
    ``scenario.duration`` (examples/installation.toml with ``duration = 0.375`` s, not the schema's
    default 1 s), from 0 s, in the FMU's communication step (fmu_src/CableCasing.py's
    ``COMMUNICATION_STEP``, 1e-4 s). Exact equality: 0.375 is a double the build writes as is."""
    import subprocess
    import sys
    from pathlib import Path

    from fmpy import read_model_description

    from cablecasing_core.model.schema import lookup

    root = Path(__file__).resolve().parents[2]
    text = (root / "examples" / "installation.toml").read_text()
    assert "\nduration = 1.0\n" in text
    toml, path = tmp_path / "short.toml", tmp_path / "short.fmu"
    toml.write_text(text.replace("\nduration = 1.0\n", "\nduration = 0.375\n", 1))
    duration = float(cc.load_model(toml).scenario["duration"])
    assert duration == 0.375 != lookup("scenario.duration").default  # (else this test could not tell)
    subprocess.run(
        [sys.executable, str(root / "build_fmu.py"), "--model", str(toml), "--output", str(path)],
        check=True, capture_output=True, cwd=root,
    )  # fmt: skip
    de = read_model_description(str(path)).defaultExperiment
    assert (float(de.startTime), float(de.stopTime), float(de.stepSize)) == (0.0, duration, 1e-4)


def test_a_model_file_that_does_not_load_is_refused_at_build(tmp_path):
    """``build_fmu.py --model`` with a bad file stops before it builds anything, naming the key."""
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    text = (root / "examples" / "clipped_specimen.toml").read_text()
    assert "E = 5.0e9" in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("E = 5.0e9", "E = -1.0", 1))  # the casing's modulus
    proc = subprocess.run(
        [sys.executable, str(root / "build_fmu.py"), "--model", str(bad), "--output", str(tmp_path / "x.fmu")],
        capture_output=True, text=True, cwd=root,
    )  # fmt: skip
    assert proc.returncode != 0 and "casing.E" in proc.stderr and "bad.toml" in proc.stderr, proc.stderr
    assert not list(tmp_path.glob("x.fmu*"))  # nothing written


def harmonic_table(names, channel, f, amp, n, ramp=0.02):
    """Inputs (n, len(names)) at t = k h: ``channel`` moves as amp sin(2 pi f t) (m), faded in over
    ``ramp`` s by a half-cosine, with its exact velocity and acceleration (product rule)."""
    t = H * np.arange(n)
    w = 2 * np.pi * f
    x = np.minimum(t / ramp, 1.0)
    inside = x < 1
    r = 0.5 * (1 - np.cos(np.pi * x))
    dr = np.where(inside, 0.5 * np.pi / ramp * np.sin(np.pi * x), 0.0)
    ddr = np.where(inside, 0.5 * (np.pi / ramp) ** 2 * np.cos(np.pi * x), 0.0)
    u, v, a = amp * np.sin(w * t), amp * w * np.cos(w * t), -amp * w * w * np.sin(w * t)
    table = np.zeros((n, len(names)))
    d = channel[-1]
    table[:, names.index(channel)] = u * r
    table[:, names.index(f"{channel[:-1]}v{d}")] = v * r + u * dr
    table[:, names.index(f"{channel[:-1]}a{d}")] = a * r + 2 * v * dr + u * ddr
    return table


def test_an_excited_clip_moves_the_casing_as_the_trfam_predicts(model_fmu, tmp_path, fmu_driver):
    """(c) Contact off, casing.alpha = 60 1/s set through the FMU (every mode decays faster than
    exp(-30 t)): dash.y moved at 150 Hz through the FMU's inputs. With the clip at rest every
    output stays exactly 0; moved, the force through both clips and at both casing ends is in
    steady state (after 0.3 s the transient is below exp(-9) = 1e-4) the TRFAM's from the port
    dash.y times the acceleration amplitude. Tolerance 5e-4: the reconstruction's error of the
    component at 150 Hz is ~1e-5 (docs/fmu.md), Newmark's error against the TRFAM
    5e-5 (measured with the exact motion), the transient 1e-4. The force through the excited clip
    itself is sampled at the step ends, where the support's velocity is the Taylor target
    v + a h + j h^2/2 (the jerk j from the last two acceleration inputs), v times the nodal gain
    g = (1 + ix + ix (1 - e^{-ix})/2) e^{-ix} = 1 + 5i x^3/12 + O(x^4), x = wh (the reconstruction's
    error at the aliases of w folded back by the sampling, docs/fmu.md): through the clip's damper
    c (isotropic, N.s/m) that is c i w u0 (g - 1), which the prediction includes (without it the
    error is 1.6e-4 of the force, as large as the others')."""
    path, _, model = model_fmu
    names, outs = list(inputs_of(model)), list(outputs_of(model))
    f0, u0, n = 150.0, 2e-6, 4000
    params = {"contact.enabled": False, "casing.alpha": 60.0}
    pairs = [("casing.clip1.Fy", "dash.y"), ("casing.clip0.Fy", "casing.clip0.y"), ("casing.B.Fy", "casing.B.y")]
    pairs += [("casing.A.Fy", "casing.A.y"), ("casing.B.Fz", "casing.B.z")]
    watch = [o for o, _ in pairs]
    rest = fmu_driver.run(
        tmp_path, "run", path, inputs=np.zeros((500, len(names))), h=H, outputs=outs, input_names=names, params=params
    )
    assert rest["init_status"] == 0 and np.all(rest["status"] == 0)
    assert not np.any(rest["out"])  # nothing moves the casing: every output exactly 0
    table = harmonic_table(names, "dash.y", f0, u0, n)
    res = fmu_driver.run(tmp_path, "run", path, inputs=table, h=H, outputs=watch, input_names=names, params=params)
    assert res["init_status"] == 0 and np.all(res["status"] == 0)
    t = H * (np.arange(n) + 1)  # output k is at t_(k+1)
    last = t > 0.3
    w = 2 * np.pi * f0
    basis = np.column_stack([np.sin(w * t[last]), np.cos(w * t[last])])
    m = model.with_overrides({"casing.alpha": 60.0})
    c = model.data["casing"]["clip"][1]["damping"]
    assert np.ptp(c) == 0  # (isotropic: the same in global y as in the clip's own axes)
    c = float(np.ravel(c)[0])
    for k, (out, port) in enumerate(pairs):
        (a, b), *_ = np.linalg.lstsq(basis, res["out"][last, k], rcond=None)
        Fc = cc.trfam(m, "dash.y", port, [f0], damping="viscous")[0] * w**2 * u0
        assert abs(Fc) > 1e-4, out  # (a force the casing's ends and the other clip really feel)
        if port == "dash.y":  # the sampled support velocity's excess through the clip's own damper
            x = w * H
            g = (1 + 1j * x + 1j * x * (1 - np.exp(-1j * x)) / 2) * np.exp(-1j * x)
            Fc -= c * 1j * w * u0 * (g - 1)
        assert abs((a + 1j * b) - Fc) < 5e-4 * abs(Fc), (out, a + 1j * b, Fc)


def test_a_model_file_with_other_clip_channels_is_refused(model_fmu, tmp_path, fmu_driver, clipped_specimen):
    """(e) ``model_file`` set at run time: the built file with another friction is accepted (its
    channels are the FMU's) and the friction is in force; the built-in specimen (no clips), and a
    model whose excited clip has another name, are refused at initialisation with fmi2Error and
    a message naming the channels; so is one with a third clip (the outputs differ)."""
    import copy

    path, toml, model = model_fmu
    names = list(inputs_of(model))
    data = copy.deepcopy(clipped_specimen.data)
    data["contact"]["friction"] = 0.3
    same = tmp_path / "same.toml"
    same.write_text(cc.model_from_dict(data).to_toml())
    other = copy.deepcopy(clipped_specimen.data)
    other["casing"]["clip"][1]["excitation"] = "bracket"
    other["scenario"]["excitation"]["dash_shake"]["target"] = "bracket.y"
    renamed = tmp_path / "renamed.toml"
    renamed.write_text(cc.model_from_dict(other).to_toml())
    three = copy.deepcopy(clipped_specimen.data)
    three["casing"]["clip"].append({"at": 0.75, "stiffness": 1e4})
    more = tmp_path / "more.toml"
    more.write_text(cc.model_from_dict(three).to_toml())
    empty = np.zeros((1, len(names)))

    def init(model_file):
        return fmu_driver.run(
            tmp_path, "run", path, inputs=empty, h=H, outputs=["contact.friction"], input_names=names,
            params={"model_file": str(model_file)},
        )  # fmt: skip

    ok = init(same)
    assert ok["init_status"] == 0 and ok["status"][0] == 0 and ok["out"][0, 0] == 0.3
    error = 3  # fmi2Error
    for model_file, words in (
        ("default", ["model_file 'default' has no excited clip", "clipped_specimen.toml", "dash.x, dash.y, dash.z"]),
        (renamed, ["bracket.x, bracket.y, bracket.z", "dash.x, dash.y, dash.z"]),
        (more, ["3 clips", "clipped_specimen.toml with 2"]),
    ):
        res = init(model_file)
        text = " ".join(res["log"])
        assert res["init_status"] == error and res["status"][0] == error, text
        assert all(w in text for w in words), (words, text)


def test_a_model_whose_excitation_reads_a_csv_file_ships_it_and_drives_from_it(tmp_path, fmu_driver):
    """An FMU built for a model file whose scenario reads a CSV table (from a subfolder) ships the
    table beside the file and reads its own copies: with scenario.drive on and zero inputs, and the
    original file and table deleted, its support forces are the core's run of the same scenario
    (cc.simulate, made while the table was there) to the bit. The table's 80 Hz displacement at
    casing end B changes those forces (against the same model without it), so a table not read,
    or read from elsewhere, would not pass."""
    import subprocess
    import sys
    import zipfile
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    text = (root / "cablecasing_core" / "model" / "specimens" / "default.toml").read_text()
    (tmp_path / "tables").mkdir()
    table = tmp_path / "tables" / "shake.csv"
    t = np.linspace(0.0, 1.0, 2001)
    table.write_text(
        "time_s,displacement_m\n" + "".join(f"{float(a)!r},{float(1e-5 * np.sin(160 * np.pi * a))!r}\n" for a in t)
    )
    toml = tmp_path / "shaken.toml"
    shake = '[scenario.excitation.shake]\ntarget = "casing.B.y"\nkind = "csv"\nfile = "tables/shake.csv"\n'
    toml.write_text(text + "\n" + shake)
    n = 200
    ref = cc.simulate(cc.load_model(toml), duration=n * H).support_forces[9::10]
    plain = cc.simulate(cc.load_model(), duration=n * H).support_forces[9::10]
    fy = OUTPUTS.index("casing.B.Fy")
    assert np.max(np.abs(ref[:, fy] - plain[:, fy])) > 1e-3 * np.max(np.abs(ref[:, fy]))  # the table acts
    path = tmp_path / "shaken.fmu"
    subprocess.run(
        [sys.executable, str(root / "build_fmu.py"), "--model", str(toml), "--output", str(path)],
        check=True, capture_output=True, cwd=root,
    )  # fmt: skip
    with zipfile.ZipFile(path) as z:
        assert z.read("resources/model/tables/shake.csv") == table.read_bytes()
    table.unlink()  # the FMU must read its own copies
    toml.unlink()
    res = fmu_driver.run(
        tmp_path, "run", path, inputs=np.zeros((n, 36)), h=H, outputs=list(OUTPUTS), params={"scenario.drive": True}
    )
    assert res["init_status"] == 0 and np.all(res["status"] == 0), res["log"]
    assert np.array_equal(res["out"][:, :24], ref)
