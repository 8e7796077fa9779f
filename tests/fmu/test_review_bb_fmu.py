"""What a C master's review of the FMU against the FMI 2.0.x state machine found (review BB):
fmi2SetDebugLogging's categories logStatusWarning and logStatusDiscard switch their messages per
instance (BB5); a NULL output argument is fmi2Error with a message naming the call and the argument,
in every state (BB6); the status functions answer before initialisation, as docs/fmu.md says (BB4).

Through tests/fmu/status_args_host.c, compiled here, run on the FMU unpacked, in the plain
environment of an engineer's C host (HOME and PATH only), as tests/fmu/test_plain_c_host.py does."""

import re
import subprocess
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # every test starts a process that loads the FMU

HERE = Path(__file__).resolve().parent


@pytest.fixture(scope="module")
def host(fmu, tmp_path_factory, plain_env, compiled_c_host):
    """``run(mode)``: status_args_host.c, compiled, on the FMU unpacked, in the plain environment;
    its stdout (the process must end with status 0: no crash)."""
    head, md = compiled_c_host(fmu, tmp_path_factory.mktemp("status_args_host"), HERE / "status_args_host.c", ["-Wall"])
    vr = {v.name: v.valueReference for v in md.modelVariables}
    names = ["casing.A.z", "casing.B.Fz", "contact.active", "contact.enabled", "model_file"]

    def run(mode):
        proc = subprocess.run(
            head + [mode] + [str(vr[n]) for n in names], capture_output=True, text=True, env=plain_env, timeout=600
        )
        assert proc.returncode == 0 and proc.stdout.endswith("end\n"), proc.stdout[-3000:] + proc.stderr[-3000:]
        return proc.stdout

    return run


def test_set_debug_logging_switches_each_category_per_instance(host):
    """One run per instance logs one warning, one discard and one error (and informational lines with
    logging on); what reaches the logger follows the categories set before it (BB5: logStatusWarning
    and logStatusDiscard returned fmi2OK and changed nothing). Defaults: warnings, discards and errors
    whatever loggingOn; no category: the informational messages only; logStatusError and
    logStatusFatal accepted, errors still logged; an unknown category changes nothing; one instance's
    setting leaves another's alone."""
    out = host("logging")
    runs = {
        m[0]: dict(info=int(m[1]), warning=int(m[2]), discard=int(m[3]), error=int(m[4]))
        for m in re.findall(r"^run (\S+) info (\d+) warning (\d+) discard (\d+) error (\d+)$", out, re.M)
    }
    sets = [int(s) for s in re.findall(r"^set (-?\d+)$", out, re.M)]
    assert sets == [0, 0, 0, 0, 0, 0, 0, 0, 0, 3, 0], out  # (the unknown category: fmi2Error)
    info_on = runs["on"]["info"]
    assert info_on >= 3, runs  # the tolerance said unused, the two lines of the timing report
    want = {
        "off": (0, 1, 1),
        "on": (info_on, 1, 1),
        "discard_off": (info_on, 1, 0),
        "warning_off": (0, 0, 1),
        "both_off_discard_on": (0, 0, 1),
        "errors_off": (0, 1, 1),
        "none_off": (0, 1, 1),
        "none_on": (info_on, 0, 0),
        "logall_off": (0, 1, 1),
        "bad_category": (0, 1, 1),
        "quiet": (0, 1, 0),
        "loud": (0, 1, 1),
    }
    got = {k: (v["info"], v["warning"], v["discard"]) for k, v in runs.items()}
    assert got == want
    assert all(v["error"] == 1 for v in runs.values()), runs  # errors always


# the argument each call of status_args_host.c passes as NULL
NULL_ARGUMENT = {
    "GetReal(c, &vr_out, 1, NULL)": "value",
    "GetReal(c, NULL, 1, &r)": "vr",
    "GetInteger(c, &vr_int, 1, NULL)": "value",
    "GetBoolean(c, &vr_bool, 1, NULL)": "value",
    "GetString(c, &vr_str, 1, NULL)": "value",
    "SetReal(c, &vr_z, 1, NULL)": "value",
    "SetInteger(c, NULL, 1, &i)": "vr",
    "SetBoolean(c, &vr_bool, 1, NULL)": "value",
    "SetString(c, &vr_str, 1, NULL)": "value",
    "GetStatus(c, fmi2DoStepStatus, NULL)": "value",
    "GetRealStatus(c, fmi2LastSuccessfulTime, NULL)": "value",
    "GetIntegerStatus(c, fmi2LastSuccessfulTime, NULL)": "value",
    "GetBooleanStatus(c, fmi2Terminated, NULL)": "value",
    "GetStringStatus(c, fmi2PendingStatus, NULL)": "value",
    "GetFMUstate(c, NULL)": "FMUstate",
    "SerializedFMUstateSize(c, st, NULL)": "size",
    "SerializeFMUstate(c, st, NULL, size)": "serializedState",
    "DeSerializeFMUstate(c, NULL, size, &st2)": "serializedState",
    "DeSerializeFMUstate(c, bytes, size, NULL)": "FMUstate",
    "SetFMUstate(c, NULL)": "FMUstate",  # (the state handles: input, BF4)
    "SerializedFMUstateSize(c, NULL, &size)": "FMUstate",
    "SerializeFMUstate(c, NULL, bytes, size)": "FMUstate",
}


def test_a_null_output_argument_is_an_error_naming_the_call_and_the_argument_in_every_state(host):
    """Every exported function that takes an output pointer or array (and the setters' arrays), with
    NULL there, in each state: fmi2Error, one logger line naming the function and the argument, never
    the life cycle (BB6: fmi2GetFMUstate(c, NULL) said '... is not allowed when the FMU is initialised',
    fmi2GetRealStatus(c, fmi2LastSuccessfulTime, NULL) returned fmi2Discard, 'only
    fmi2LastSuccessfulTime is available'; fmi2SerializedFMUstateSize and fmi2SerializeFMUstate said
    nothing); the instance goes on (a step after them, a getter after fmi2Terminate)."""
    out = host("nullargs")
    seen = re.findall(r"^null (\S+) (.+?) -> (-?\d+) lines (\d+): (.*)$", out, re.M)
    states = ["instantiated", "initialization", "stepping", "terminated"]
    assert [(s, c) for s, c, *_ in seen] == [(s, c) for s in states for c in NULL_ARGUMENT], out
    for state, call, status, lines, message in seen:
        function = "fmi2" + call.split("(")[0]
        assert (int(status), int(lines)) == (3, 1), (state, call, status, lines, message)
        assert message.startswith(f"{function}: the argument {NULL_ARGUMENT[call]} ") and "NULL" in message, (
            state,
            call,
            message,
        )
        assert "not allowed" not in message and "available" not in message, (state, call, message)
    assert "after stepping step -> 0" in out and "after terminated get -> 0" in out, out


def test_the_status_functions_answer_before_initialisation(host):
    """FMI 2.0.x, 4.2.4, allows fmi2Get*Status only after initialisation; the FMU answers earlier too,
    with what holds for an instance that has not stepped (BB4, docs/fmu.md "Statuses for careless
    masters"): no step pending, fmi2LastSuccessfulTime the start time set so far (0 before
    fmi2SetupExperiment, then its 0.25 s exactly: nothing is added to it), not terminated. After a step
    of 1e-4 s it is 0.2501 s to 1e-15 s (ten internal steps of 1e-5 s summed: a few ulps of 0.25)."""
    out = host("status")
    got = {
        (m[0], m[1]): (int(m[2]), float(m[3]))
        for m in re.findall(r"^status (\S+) (\S+) -> (-?\d+) value (\S+)$", out, re.M)
    }
    for state, start in (("instantiated", 0.0), ("setup", 0.25), ("initialization", 0.25)):
        assert got[(state, "doStep")] == (0, 0.0)
        assert got[(state, "lastSuccessfulTime")] == (0, start)
        assert got[(state, "terminated")] == (0, 0.0)
    assert "step -> 0" in out, out
    status, t = got[("stepping", "lastSuccessfulTime")]
    assert status == 0 and t == pytest.approx(0.2501, abs=1e-15)
