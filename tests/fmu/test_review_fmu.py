"""What a review of the FMU in C hosts found (docs/fmu.md, "Statuses for careless masters" and
"Messages you may see"): a step past the master's stopTime is fmi2Error (FMI 2.0, 2.1.6), a step
that lands on it by the master's sums is taken; the log's doStep timing counts only steps taken; a
support set free that the model's scenario drives runs without scenario.drive (as the core on the
model without that excitation, to the bit) and is refused, naming the support, with it; an
isolator support and an Integer out of range are refused in the FMU's words (its variables, its
modelDescription's range); a finite input whose reconstructed motion overflows is named as the
host gave it; model_file's description names the built-in specimens. The FMU runs in a fresh
process (tests/fmu/fmu_driver.py's Instance, fmpy's FMU2Slave with the log captured). Also the
core's refusal of a tension on a casing without stiffness (structure/buckling.py)."""

import copy
import json
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.model.schema import OUTPUTS

pytestmark = pytest.mark.slow  # the FMU in a fresh process

HERE = Path(__file__).resolve().parent
H = 1e-4
N = 20  # steps of the free-support run

# The host: one process, each case its own instance; prints {case: {status..., log}} as JSON.
HOST = r"""
import json, sys
import numpy as np
sys.path.insert(0, sys.argv[3])
from fmu_driver import INPUTS, Instance

fmu, table = sys.argv[1], np.load(sys.argv[2])
INSTALLATION = sys.argv[3] + "/../../examples/installation.toml"
res = {}

def log(inst):
    out = [m for s, m in inst.log]
    inst.log.clear()
    return out

# stopTime: ten steps of 1e-4 s summed by the master (t ends at 0.0010000000000000002) are taken,
# the next one, past stopTime = 0.001 s, is fmi2Error; a step ending at stopTime - h/2 then is taken
inst = Instance(fmu, name="stop", initialize=False)
inst.fmu.setupExperiment(startTime=0.0, stopTime=0.001)
inst.fmu.enterInitializationMode()
inst.fmu.exitInitializationMode()
res["stop_steps"] = [inst.step(table[0], 1e-4) for _ in range(10)]
res["stop_t"] = inst.t
log(inst)
res["past_stop"] = Instance.call(inst.fmu.doStep, inst.t, 1e-4)
res["past_stop_log"] = log(inst)
res["last_time"] = inst.fmu.getRealStatus(2)  # fmi2LastSuccessfulTime
inst.free()

# a master that sets no stopTime steps on
inst = Instance(fmu, name="nostop")
res["no_stop_steps"] = [inst.step(table[0], 1e-4) for _ in range(12)]
inst.free()

# the timing report counts steps taken: refused calls alone leave it out, with two steps it says 2
for name, good in (("refused_only", 0), ("refused_and_two", 2)):
    inst = Instance(fmu, name=name, initialize=False)
    inst.fmu.setupExperiment(startTime=0.0, stopTime=10.0)
    inst.fmu.enterInitializationMode()
    inst.fmu.exitInitializationMode()
    statuses = [Instance.call(inst.fmu.doStep, 0.0, h) for h in (0.0, -1e-4)]
    statuses.append(Instance.call(inst.fmu.doStep, 5.0, 1e-4))  # at the wrong time
    statuses.append(Instance.call(inst.fmu.doStep, 0.0, 11.0))  # past stopTime
    statuses += [inst.step(table[0], 1e-4) for _ in range(good)]
    log(inst)
    inst.fmu.terminate()
    res[name] = statuses
    res[name + "_log"] = log(inst)
    inst.fmu.freeInstance()

# parameters that the review found refused in words a C host's user cannot act on
cases = {
    "casing_free": {"casing.supports.A": "free"},
    "cable_free": {"cable.supports.A": "free"},
    "casing_free_drive": {"casing.supports.A": "free", "scenario.drive": True},
    "cable_free_drive_installed": {"cable.supports.A": "free", "scenario.drive": True, "model_file": "installed"},
    "isolator": {"casing.supports.A": "isolator"},
    "seed": {"scenario.seed": -1},
    "excitation_seed": {"scenario.excitation.casing_random.seed": -1},
    # a second review: a support set clamped where the model file has an isolator; a key of an
    # excitation the model file does not have (as a master writing every start value sets it),
    # without and with scenario.drive; scenario.dt without scenario.drive (the internal step)
    "isolator_clamped": {"model_file": INSTALLATION, "casing.supports.A": "clamped"},
    "missing_excitation": {"model_file": INSTALLATION, "scenario.excitation.casing_random.rms": 5.0},
    "missing_excitation_drive": {
        "model_file": INSTALLATION, "scenario.excitation.casing_random.rms": 5.0, "scenario.drive": True
    },
    "missing_excitation_bad": {"model_file": INSTALLATION, "scenario.excitation.casing_random.rms": -5.0},
    "coarse_scenario_dt": {"scenario.dt": 1e-3},
    "scenario_dt": {"scenario.dt": 2e-5},
}
for name, params in cases.items():
    inst = Instance(fmu, name=name, params=params)
    res[name] = inst.status_init
    res[name + "_log"] = [m for s, m in inst.log if s >= 2]
    try:  # (the parameter in force, also after a refused initialisation)
        res[name + "_dt"] = inst.fmu.getReal([inst.var["solver.dt"].valueReference])[0]
    except Exception as exc:
        res[name + "_dt"] = repr(exc)
    if name in ("isolator_clamped", "missing_excitation", "scenario_dt"):
        res[name + "_steps"] = [inst.step(row, 1e-4) for row in table[:2]]
    if name == "isolator_clamped":  # on to N steps, its outputs for the core's on the model with end A clamped
        res[name + "_more"] = [inst.step(row, 1e-4) for row in table[2:]]
    if name in ("isolator_clamped", "scenario_dt"):
        res[name + "_out"] = inst.get(sys.argv[4].split(",")).tolist()
    if name == "casing_free":  # its run, for the core's
        out, status = [], []
        for row in table:
            status.append(inst.step(row, 1e-4))
            out.append(inst.get(sys.argv[4].split(",")).tolist())
        res["casing_free_out"], res["casing_free_status"] = out, status
    inst.free()

# a finite input whose motion over the step overflows
inst = Instance(fmu, name="huge")
res["huge_first"] = inst.step(table[0], 1e-4)
row = np.zeros(len(INPUTS))
row[INPUTS.index("casing.A.z")] = 1e300
log(inst)
res["huge"] = inst.step(row, 1e-4)
res["huge_log"] = log(inst)
inst.free()
print(json.dumps(res))
"""


@pytest.fixture(scope="module")
def host(fmu, tmp_path_factory, drive_casing_b_120hz):
    path = tmp_path_factory.mktemp("review") / "inputs.npy"
    np.save(path, drive_casing_b_120hz(N, H))
    proc = subprocess.run(
        [sys.executable, "-c", HOST, str(fmu), str(path), str(HERE), ",".join(OUTPUTS)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_a_step_past_the_stop_time_is_an_error_one_that_lands_on_it_is_not(host):
    """FMI 2.0, 2.1.6: with stopTimeDefined, computing past stopTime is fmi2Error. Ten steps of
    1e-4 s summed by the master end at 0.0010000000000000002 s, stopTime = 0.001 s within the
    rounding of a clock: taken. The eleventh is refused, naming stopTime, and the FMU stays at its
    last time; a master without stopTime steps on."""
    assert host["stop_steps"] == [0] * 10 and host["stop_t"] > 0.001
    assert host["past_stop"] == 3, host["past_stop_log"]
    text = " ".join(host["past_stop_log"])
    assert "past stopTime = 0.001 s" in text and "fmi2SetupExperiment" in text, text
    assert host["last_time"] == pytest.approx(0.001, rel=1e-12)
    assert host["no_stop_steps"] == [0] * 12


def test_refused_do_step_calls_are_not_counted_in_the_timing_report(host):
    """A step of 0 or -1e-4 s (fmi2Error), at the wrong time (fmi2Discard) or past stopTime
    (fmi2Error) is not a step: alone they leave the terminate log's timing lines out (counts zero),
    and beside two steps taken the lines count two."""
    assert host["refused_only"] == [3, 3, 2, 3]
    text = " ".join(host["refused_only_log"])
    assert "doStep calls took" not in text and "calls took longer" not in text, text
    assert host["refused_and_two"] == [3, 3, 2, 3, 0, 0]
    text = " ".join(host["refused_and_two_log"])
    assert "2 doStep calls took" in text and " of 2 calls took longer than their communication step" in text, text


def _without_excitation(model, name):
    data = copy.deepcopy(model.data)
    del data["scenario"]["excitation"][name]
    return cc.model_from_dict(data)


def test_a_free_support_that_the_scenario_drives_runs_without_scenario_drive(host, core_run, drive_casing_b_120hz):
    """casing.supports.A = 'free' (an allowed value) with scenario.drive off: the scenario does not
    run, so its excitation of casing.A.z is not checked against the support; the run equals the
    core's on the model without that excitation, to the bit. The same for cable.supports.A."""
    assert host["casing_free"] == 0 and host["cable_free"] == 0, (host["casing_free_log"], host["cable_free_log"])
    assert host["casing_free_status"] == [0] * N
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = _without_excitation(cc.load_model(), "casing_random").with_overrides({"casing.supports.A": "free"})
    ref = core_run(model, drive_casing_b_120hz(N, H))
    np.testing.assert_array_equal(np.array(host["casing_free_out"]), ref)


def test_a_free_support_that_the_scenario_drives_is_refused_with_scenario_drive_naming_the_support(host):
    for case, support, target in (
        ("casing_free_drive", "casing.supports.A", "casing.A.z"),
        ("cable_free_drive_installed", "cable.supports.A", "cable.A.axial"),
    ):
        assert host[case] == 3
        text = " ".join(host[case + "_log"])
        assert f"invalid parameter {support} = 'free'" in text, text
        assert "scenario.drive = true" in text and f"drives support {support.replace('supports.', '')}" in text, text
        assert "scenario.excitation." not in text and f"targets '{target}'" in text, text
    assert "built-in specimen's scenario" in " ".join(host["casing_free_drive_log"])
    assert "built-in specimen 'installed'" in " ".join(host["cable_free_drive_installed_log"])


def test_an_isolator_support_says_its_table_comes_from_a_model_file(host):
    assert host["isolator"] == 3
    text = " ".join(host["isolator_log"])
    assert "casing.supports.A = 'isolator'" in text and "not a parameter of this FMU" in text, text
    assert "model_file" in text and "[casing.isolator.A]" in text and "None" not in text, text


def test_a_support_set_clamped_drops_the_model_file_s_isolator_table(host, core_run, drive_casing_b_120hz):
    """examples/installation.toml holds casing end A in an isolator; casing.supports.A = 'clamped'
    leaves the isolator's table behind (no FMU parameter could remove it), and the run steps: its
    outputs after N steps are, to the bit, the core's on that file with end A clamped and its
    isolator's table removed by hand (a support left an isolator passed before)."""
    from cablecasing_core.timedomain.engine import Engine

    assert host["isolator_clamped"] <= 1, host["isolator_clamped_log"]  # (a warning: its clips have no outputs)
    assert not any("isolator" in m for m in host["isolator_clamped_log"]), host["isolator_clamped_log"]
    assert host["isolator_clamped_steps"] == [0, 0] and host["isolator_clamped_more"] == [0] * (N - 2)
    path = HERE.parents[1] / "examples" / "installation.toml"
    data = cc.load_model(path).to_dict()
    data["casing"]["supports"]["A"] = "clamped"
    del data["casing"]["isolator"]["A"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = cc.model_from_dict(data, base_dir=str(path.parent))
        names = Engine(model, ledger=False).output_names
        ref = core_run(model, drive_casing_b_120hz(N, H))[-1]
    np.testing.assert_array_equal(host["isolator_clamped_out"], [ref[names.index(n)] for n in OUTPUTS])


def test_a_key_of_an_excitation_the_model_file_lacks(host):
    """A master writing every start value sets scenario.excitation.casing_random.rms for a model file
    whose only excitation is 'shaker': without scenario.drive the scenario does not run and the key
    is left out (its value still checked against the schema); with it, an fmi2Error names the key
    and the model's excitations, not a key the master never set."""
    assert host["missing_excitation"] <= 1 and host["missing_excitation_steps"] == [0, 0], host[
        "missing_excitation_log"
    ]
    assert host["missing_excitation_drive"] == 3
    text = " ".join(host["missing_excitation_drive_log"])
    assert "scenario.excitation.casing_random.rms = 5.0: belongs to the excitation 'casing_random'" in text, text
    assert "(its excitations: shaker)" in text and ".kind" not in text, text
    assert host["missing_excitation_bad"] == 3
    assert "scenario.excitation.casing_random.rms = -5.0" in " ".join(host["missing_excitation_bad_log"])


def test_scenario_dt_is_the_internal_step_when_solver_dt_is_unset(host, core_run, drive_casing_b_120hz):
    """docs/fmu.md: solver.dt, unset, is the model's scenario.dt, the master's when it set it: the
    outputs of two steps with scenario.dt = 2e-5 s are, to the bit, the core's at dt = 2e-5 s (an FMU
    that said 2e-5 s and stepped at 1e-5 s passed before). Without scenario.drive the scenario's random
    band (to 1000 Hz) does not run, so a step of 1e-3 s is not refused for its Nyquist frequency."""
    assert host["scenario_dt"] == 0 and host["scenario_dt_dt"] == 2e-5 and host["scenario_dt_steps"] == [0, 0]
    model = cc.load_model().with_overrides({"scenario.dt": 2e-5})
    ref = core_run(model, drive_casing_b_120hz(2, H), dt=2e-5)[-1]
    np.testing.assert_array_equal(host["scenario_dt_out"], ref[: len(OUTPUTS)])
    assert host["coarse_scenario_dt"] == 0 and host["coarse_scenario_dt_dt"] == 1e-3, host["coarse_scenario_dt_log"]
    assert host["seed_dt"] == 1e-5  # (unset: the built-in specimen's scenario.dt)


def test_an_integer_out_of_range_quotes_the_model_descriptions_range(host, fmu):
    from fmpy import read_model_description

    var = {v.name: v for v in read_model_description(fmu).modelVariables}
    for case, key in (("seed", "scenario.seed"), ("excitation_seed", "scenario.excitation.casing_random.seed")):
        assert host[case] == 3
        text = " ".join(host[case + "_log"])
        lo, hi = var[key].min, var[key].max
        assert f"{key} = -1: must be a whole number in [{lo}, {hi}]" in text, text
        assert hi == "2147483647" and "9223372036854775807" not in text, text


def test_a_finite_input_whose_motion_overflows_is_named_as_given(host):
    """casing.A.z = 1e300 m (velocity and acceleration 0): fmi2Discard naming the input the host
    gave, not a NaN acceleration it never gave."""
    assert host["huge_first"] == 0 and host["huge"] == 2
    text = " ".join(host["huge_log"])
    assert text.startswith("input casing.A.z = 1e+300 m at t = 0.0001 s"), text
    assert "casing.A.vz = 0.0 m/s" in text and "discarded" in text, text


def test_model_file_description_names_the_built_in_specimens(fmu):
    from fmpy import read_model_description

    var = {v.name: v for v in read_model_description(fmu).modelVariables}
    text = var["model_file"].description
    assert "'default'" in text and "'installed'" in text, text


@pytest.mark.parametrize("E", [5e-324, 1e-320])
def test_a_casing_without_stiffness_under_tension_names_its_modulus(E):
    """The installed specimen (10 N of cable tension) with casing.E = 5e-324 Pa (within the key's
    range): the tension is refused naming the casing's stiffness, with no '(none found)' load and
    no empty field."""
    from cablecasing_core.timedomain.engine import Engine

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = cc.load_model("installed").with_overrides({"casing.E": E})
        with pytest.raises(cc.ModelError) as err:
            Engine(model, ledger=False)
    text = str(err.value)
    assert err.value.key == "loads.cable_tension", text
    assert f"casing.E = {E!r} Pa" in text and "buckling load" in text, text
    assert "; ;" not in text and "(none found)" not in text and "()" not in text, text
