"""What review AZ found where one schema gives the FMU's parameters, the command line's --set and the
core (docs/fmu.md, "Parameters in force", "Messages you may see", "The FMU file"):

* AZ1: a derived parameter (a random excitation's seed the model leaves to scenario.seed, solver.dt
  from scenario.dt) written with exactly its start value follows its source, so a master that writes
  every start value and changes the source gets the core's run of that change, to the bit; its getter
  returns the value in force; another value still overrides it;
* AZ2: every Real start in the modelDescription reads back as the model file's double (repr, not
  pythonfmu's 16 digits): scenario.dt = 1/30000;
* AZ3: a conflict between keys names the parameter the master set and the model's key it conflicts
  with, as the command line does (the core's model.changes.with_changes);
* BA2: a model file rewritten under its name between runs (fmi2Reset) is read again by the getters.

The FMU runs in a fresh process (tests/fmu/fmu_driver.py's Instance and fmpy's simulate_fmu), which
does not import cablecasing_core first, so it runs its own bundled copy."""

import json
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.model.schema import OUTPUTS

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
T, H = 0.02, 1e-4
SEED = "scenario.excitation.casing_random.seed"

# The host: every parameter's start value from the modelDescription written, plus a change; the
# outputs of simulate_fmu (scenario.drive, zero inputs), the getters and the logs, as JSON and npz.
HOST = r"""
import json, sys
import numpy as np
sys.path.insert(0, sys.argv[3])
import fmpy
from fmpy import extract, read_model_description
from fmu_driver import Instance

fmu, out, T, H = sys.argv[1], sys.argv[2], 0.02, 1e-4
unzip = extract(fmu)
md = read_model_description(unzip)
conv = {"Real": float, "Integer": int, "Boolean": lambda s: s in ("true", "1"), "String": str}
starts = {
    v.name: conv[v.type](v.start) for v in md.modelVariables if v.causality == "parameter" and v.start is not None
}
outs = [v.name for v in md.modelVariables if v.causality == "output"]
SEED = "scenario.excitation.casing_random.seed"
runs, res = {}, {"starts": {k: starts[k] for k in ("scenario.seed", SEED, "scenario.dt", "solver.dt")}}
cases = {
    "seed7": {"scenario.seed": 7},
    "seed7_explicit3": {"scenario.seed": 7, SEED: 3},
    "dt2e-5": {"scenario.dt": 2e-5},
}
for name, change in cases.items():
    sv = dict(starts, **change)
    sv["scenario.drive"] = True
    r = fmpy.simulate_fmu(unzip, stop_time=T, output_interval=H, start_values=sv, output=outs)
    runs[name] = np.array([r[n] for n in outs]).T.astype(float)

# the getters of the derived parameters, in Initialization Mode and after
for name, change in cases.items():
    inst = Instance(fmu, name="get_" + name, initialize=False, unzip=unzip)
    inst.fmu.setupExperiment(startTime=0.0)
    inst.fmu.enterInitializationMode()
    inst.set(dict(starts, **change))
    vr = [inst.var[k].valueReference for k in (SEED, "scenario.seed")]
    got = {"init": inst.fmu.getInteger(vr), "init_solver_dt": inst.fmu.getReal([inst.var["solver.dt"].valueReference])}
    got["exit"] = Instance.call(inst.fmu.exitInitializationMode)
    got["after"] = inst.fmu.getInteger(vr)
    got["after_solver_dt"] = inst.fmu.getReal([inst.var["solver.dt"].valueReference])
    # after initialisation: the start value of a seed that follows its source is the value in force
    # (accepted), another value is a change (refused)
    got["write_start_after"] = inst.set({SEED: starts[SEED]})
    got["write_other_after"] = inst.set({SEED: 11})
    res["get_" + name] = got
    inst.free()

# conflicts between keys (AZ3): only the change (a master that also writes casing.d_inner's start value
# set it, and is told so: the key refused is then one it set), scenario.drive for the band's
for name, change in {
    "d_outer": {"casing.d_outer": 0.0035},
    "cable_d": {"cable.d": 0.0045},
    "dt_band": {"scenario.dt": 1e-3, "scenario.drive": True},
}.items():
    inst = Instance(fmu, name=name, params=change, unzip=unzip)
    res[name] = [inst.status_init, [m for s, m in inst.log if s >= 2]]
    inst.free()
# a model file rewritten under its name between two runs of one instance (fmi2Reset), as a study that
# writes its next model file does: the getters read the new file, as the engine does (review BA2)
moving = sys.argv[4] + "/moving.toml"
inst = Instance(fmu, name="moving", initialize=False, unzip=unzip)
res["moving"] = []
for text in (open(sys.argv[4] + "/seed3.toml").read(), open(sys.argv[4] + "/seed41.toml").read()):
    with open(moving, "w") as f:
        f.write(text)
    inst.fmu.setupExperiment(startTime=0.0)
    inst.fmu.enterInitializationMode()
    inst.set({"model_file": moving})
    vr = [inst.var[k].valueReference for k in (SEED, "scenario.seed")]
    got = [inst.fmu.getInteger(vr), Instance.call(inst.fmu.exitInitializationMode), inst.fmu.getInteger(vr)]
    res["moving"].append(got)
    inst.fmu.terminate()
    inst.fmu.reset()
inst.fmu.freeInstance()
np.savez(out, **runs)
print(json.dumps(res))
"""


@pytest.fixture(scope="module")
def host(fmu, tmp_path_factory):
    """The host's results: (JSON, {case: outputs (n, outputs)}) for the FMU under test."""
    folder = tmp_path_factory.mktemp("az")
    out = folder / "runs.npz"
    script = folder / "host.py"
    script.write_text(HOST)
    for seed in (3, 41):  # (the model files the host writes in turn under one name)
        text = cc.load_model().with_overrides({"scenario.seed": seed}).to_toml()
        (folder / f"seed{seed}.toml").write_text(text)
    done = subprocess.run(
        [sys.executable, str(script), str(fmu), str(out), str(HERE), str(folder)],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1]), dict(np.load(out))


def core(model):
    """The core's run of ``model`` sampled as the FMU's outputs (docs/fmu.md, "Simulate with fmpy":
    the picked record at the communication points); every output but the dissipated energy."""
    rec = cc.simulate(model, duration=T).records(H, decimation="pick")
    return np.array([rec.column(n) for n in OUTPUTS[:-1]]).T


@pytest.mark.slow
def test_every_start_value_written_and_a_changed_seed_is_the_cores_run_of_that_seed(host):
    res, runs = host
    base = cc.load_model()
    assert res["starts"] == {"scenario.seed": 1, SEED: 1, "scenario.dt": 1e-5, "solver.dt": 1e-5}
    seed7 = core(base.with_overrides({"scenario.seed": 7}))
    assert not np.array_equal(seed7, core(base))  # (the change matters: the test can tell)
    # the same code on the same inputs: equal to the bit (the review found 0 differing values)
    np.testing.assert_array_equal(runs["seed7"][:, :-1], seed7)
    explicit = core(base.with_overrides({"scenario.seed": 7, SEED: 3}))
    np.testing.assert_array_equal(runs["seed7_explicit3"][:, :-1], explicit)
    assert not np.array_equal(explicit, seed7)


@pytest.mark.slow
def test_every_start_value_written_and_a_changed_scenario_dt_steps_at_it(host):
    res, runs = host
    changed = cc.load_model().with_overrides({"scenario.dt": 2e-5})
    np.testing.assert_array_equal(runs["dt2e-5"][:, :-1], core(changed))
    got = res["get_dt2e-5"]
    assert got["init_solver_dt"] == [2e-5] and got["after_solver_dt"] == [2e-5], got


@pytest.mark.slow
def test_the_getter_of_a_derived_seed_returns_the_value_in_force(host):
    res, _ = host
    # [casing_random.seed, scenario.seed]: the first random excitation takes scenario.seed itself
    assert res["get_seed7"]["init"] == [7, 7] and res["get_seed7"]["after"] == [7, 7], res["get_seed7"]
    assert res["get_seed7"]["exit"] == 0
    assert res["get_seed7_explicit3"]["init"] == [3, 7] and res["get_seed7_explicit3"]["after"] == [3, 7]
    for case in ("get_seed7", "get_seed7_explicit3"):  # (fmi2OK = 0, fmi2Error = 3)
        assert res[case]["write_other_after"] == 3, res[case]
    assert res["get_seed7"]["write_start_after"] == 0  # (it follows scenario.seed: no change)
    assert res["get_seed7_explicit3"]["write_start_after"] == 3  # (it would undo the explicit 3)


@pytest.mark.slow
def test_a_model_file_rewritten_under_its_name_is_read_again_after_a_reset(host):
    """Review BA2: the slave kept its copy of a model file's values by path, so after fmi2Reset and the
    file rewritten (seed 3 -> 41) its getters still said 3 while the engine ran 41. [casing_random.seed,
    scenario.seed] in Initialization Mode, fmi2ExitInitializationMode's status, the same after."""
    res, _ = host
    assert res["moving"] == [[[3, 3], 0, [3, 3]], [[41, 41], 0, [41, 41]]], res["moving"]


def _cli_message(capsys, sets):
    from cablecasing_core.cli import main

    code = main(["simulate", "--duration", "0.001", *[f"--set={k}={v}" for k, v in sets.items()]])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    return err[0]


@pytest.mark.slow
@pytest.mark.parametrize(
    "case, sets",
    [
        ("d_outer", {"casing.d_outer": 0.0035}),
        ("cable_d", {"cable.d": 0.0045}),
        ("dt_band", {"scenario.dt": 0.001}),
    ],
)
def test_a_conflict_names_the_parameter_set_as_the_command_line_does(host, capsys, case, sets):
    res, _ = host
    status, errors = res[case]
    assert status == 3 and len(errors) == 1, res[case]
    ((key, value),) = sets.items()
    assert errors[0].startswith(f"invalid parameter {key} = {value}: conflicts with "), errors
    # the command line's message of the same change, after its prefix (--set)
    cli = _cli_message(capsys, sets)
    assert cli.startswith(f"cablecasing: error: --set {key} = "), cli
    assert errors[0].partition(": conflicts with ")[2] == cli.partition(": conflicts with ")[2], (errors, cli)
    assert "invalid parameter scenario.excitation" not in errors[0]


# ------------------------------------------------------------------ AZ2: Real starts that need 17 digits
def test_every_real_start_reads_back_as_the_model_files_double(tmp_path, build_fmu):
    """The modelDescription of an FMU built for a model file (build_fmu.py's own steps: the slave for
    that base model, pythonfmu's XML of it, complete_description), without the archive and its
    compiled kernels: every Real start is the model's value as the same double."""
    odd = {"scenario.dt": 1 / 30000, "contact.friction": 0.1 + 0.2}  # (17 significant digits each)
    assert all(float(f"{v:.16g}") != v for v in odd.values())  # (pythonfmu's text is another double)
    model = cc.load_model().with_overrides(odd)
    (tmp_path / "model").mkdir()
    (tmp_path / "model" / "dt30k.toml").write_text(model.to_toml())
    slave = build_fmu.load_slave().CableCasing(instance_name="az2", resources=str(tmp_path))
    raw = ET.tostring(slave.to_xml())  # (what pythonfmu's builder writes: instance.to_xml())
    xml = build_fmu.complete_description(
        raw, slave.units, "guid", "2026-01-01T00:00:00Z", "dt30k.toml", slave.ranges, build_fmu.real_starts(slave)
    )
    values = model.parameters()
    checked = 0
    for sv in ET.fromstring(xml).find("ModelVariables").findall("ScalarVariable"):
        real, name = sv.find("Real"), sv.get("name")
        if real is None or real.get("start") is None:
            continue
        want = 0.0 if sv.get("causality") == "input" else model.scenario["dt"] if name == "solver.dt" else values[name]
        assert float(real.get("start")) == want, (name, real.get("start"), want)
        checked += 1
    # every input, every float key of the model and solver.dt
    assert checked == 36 + sum(isinstance(v, float) for v in values.values()) + 1
    starts = {sv.get("name"): sv.find("Real").get("start") for sv in ET.fromstring(xml).iter("ScalarVariable")
              if sv.find("Real") is not None}  # fmt: skip
    assert starts["scenario.dt"] == starts["solver.dt"] == "3.3333333333333335e-05"
    assert starts["contact.friction"] == "0.30000000000000004"
