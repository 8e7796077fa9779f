"""A fuzz review of the FMU's parameter interface, through fmpy (tests/fmu/fmu_probe.py: a host
process of its own, which a crash would end) and fmusim (a C host, in the plain environment): every
parameter the modelDescription declares set to edge values (NaN, +-inf, 0, negative, huge, the
nearest double outside its declared min and max, empty strings, words no enumeration has, model
files that are missing, folders, empty, binary or invalid), alone and in random combinations, and
stepped. Expected, whatever the value: never fmi2Fatal and never a dead host; a value outside what
the modelDescription declares refused (fmi2Error at the set or at fmi2ExitInitializationMode) with
a message naming the variable, the value and what is allowed; and any fmi2Error or fmi2Discard with
a message of its own, never an internal error."""

import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

pytestmark = pytest.mark.slow  # the FMU in processes of its own

INT_MIN, INT_MAX = -(2**31), 2**31 - 1
FATAL = 4
# What a refusal says besides the variable and the value: what is allowed (the model schema's
# "must be ...", the FMU's own "... must be fmi2True (1) or fmi2False (0)", "its [geometry] table is
# required")
ALLOWED_WORDS = ("must", "required")


@pytest.fixture(scope="module")
def parameters(fmu):
    """The FMU's parameters as the modelDescription declares them: {name: (type, min, max)}."""
    from fmpy import read_model_description

    md = read_model_description(str(fmu))
    out = {}
    for v in md.modelVariables:
        if v.causality == "parameter":
            conv = float if v.type == "Real" else int
            out[v.name] = (v.type, None if v.min is None else conv(v.min), None if v.max is None else conv(v.max))
    return out


@pytest.fixture(scope="module")
def model_files(tmp_path_factory):
    """model_file values that give no model: missing (absolute, relative), a folder, /dev/null, an
    empty file, a binary one, invalid TOML, a model with a NaN modulus, a name too long for a path."""
    folder = tmp_path_factory.mktemp("model_files")
    (folder / "empty.toml").write_text("")
    (folder / "binary.toml").write_bytes(bytes(range(256)))
    (folder / "broken.toml").write_text("x = [")
    specimen = Path(__file__).resolve().parents[2] / "cablecasing_core" / "model" / "specimens" / "default.toml"
    (folder / "nan_modulus.toml").write_text(specimen.read_text().replace("E = 5.0e9", "E = nan", 1))
    assert "E = nan" in (folder / "nan_modulus.toml").read_text()
    names = ["missing.toml", "empty.toml", "binary.toml", "broken.toml", "nan_modulus.toml"]
    return ["", str(folder)] + [str(folder / n) for n in names] + ["no/such/model.toml", "/dev/null", "x" * 5000]


def edge_values(kind, lo, hi):
    """The values outside what the modelDescription declares for a number, Boolean or word
    parameter (each must be refused), and a few inside (0, -1 where the range holds them)."""
    if kind == "Real":
        values = [math.nan, math.inf, -math.inf, 0.0, -1.0, -1e308, 1e308]
        values += [] if lo is None else [float(np.nextafter(lo, -math.inf))]
        values += [] if hi is None else [float(np.nextafter(hi, math.inf))]
        return values
    if kind == "Integer":
        return (
            [0, -1, INT_MIN, INT_MAX]
            + ([] if lo is None else [lo - 1])
            + ([] if hi is None or hi == INT_MAX else [hi + 1])
        )
    if kind == "Boolean":
        return [0, 1, 2, -1]
    return ["", "bogus", "CLAMPED", " hertz", "/nonexistent/model.toml", "y" * 5000]


def allowed(kind, lo, hi, value):
    """Whether ``value`` lies inside what the modelDescription declares (a word key's words are not
    in it: None, "the FMU decides")."""
    if kind == "Real":
        return math.isfinite(value) and (lo is None or value >= lo) and (hi is None or value <= hi)
    if kind == "Integer":
        return (lo is None or value >= lo) and (hi is None or value <= hi)
    if kind == "Boolean":
        return value in (0, 1)
    return None


def shown(value):
    """How a message shows ``value``: repr for numbers and words (a long one by its start)."""
    if isinstance(value, str):
        return value[:40]
    return repr(float(value)) if isinstance(value, float) else str(value)


def check_case(name, value, res, log, declared=None):
    """The oracle of one case (``res``: the probe's answer, ``log``: its messages): never fatal; a
    refusal (fmi2Error at the set or at initialisation) says why in a message naming the variable
    and the value; a value outside the declared range is refused; a step refused (fmi2Discard,
    fmi2Error) has a message of its own; no internal error anywhere."""
    statuses = res["set"] + [res["init"]] + res["steps"]
    assert FATAL not in statuses, (name, value, statuses, log)
    for _, _s, m in log:
        assert "a bug; please report it" not in m and "internal error" not in m, (name, value, m)
    refused = max(res["set"] + [res["init"]]) >= 3
    if refused:
        errors = [m for _, s, m in log if s >= 3]
        assert errors, (name, value, log)
        named = [m for m in errors if name in m and shown(value) in m and any(w in m for w in ALLOWED_WORDS)]
        assert named, (name, value, errors)
    elif declared is False:
        pytest.fail(f"{name} = {value!r} is outside the modelDescription's range but was accepted: {log}")
    if any(s >= 2 for s in res["steps"]):
        assert any(s >= 2 for _, s, m in log), (name, value, res, log)


def test_every_parameter_at_its_edges(fmu, parameters, model_files, fmu_probe):
    """Each parameter alone at each of its edge values, in an instance of its own, two steps of
    1e-4 s: every value outside the modelDescription's declaration (NaN, +-inf, beyond min or max by
    one double, an Integer past 32 bits' end, a Boolean not 0 or 1, a word no enumeration has, a
    model_file that gives no model) is refused naming the variable, the value and what is allowed;
    the others run, and what they refuse they name."""
    host = fmu_probe()
    cases = [(n, v) for n, (kind, lo, hi) in parameters.items() if n != "model_file" for v in edge_values(kind, lo, hi)]
    cases += [("model_file", path) for path in model_files]
    accepted = []
    for name, value in cases:
        kind, lo, hi = parameters[name]
        res = host.call("case", fmu=str(fmu), params={name: value}, h=1e-4, n=2)
        log = host.call("log")["log"]
        declared = allowed(kind, lo, hi, value)
        if name == "model_file":
            declared = value == ""  # (only the empty string, the base model, gives a model here)
        check_case(name, os.path.basename(value) if name == "model_file" else value, res, log, declared)
        if max(res["set"] + [res["init"]]) < 3:
            accepted.append((name, value))
    # (the words no enumeration has are refused at the set: no word parameter accepted one of them)
    assert not [c for c in accepted if parameters[c[0]][0] == "String" and c[0] != "model_file"], accepted
    assert ("model_file", "") in accepted


def test_a_parameter_set_through_another_type_is_refused_by_name(fmu, parameters, fmu_probe):
    """fmi2SetReal on an Integer, fmi2SetInteger on a Real, fmi2SetBoolean on a String, fmi2SetString
    on a Boolean: fmi2Error naming the variable and its type; the instance still initialises with
    the value it had (the set did nothing)."""
    host = fmu_probe()
    for name, kind in (("geometry.n_elements", "Real"), ("casing.E", "Integer"), ("contact.law", "Boolean"),
                       ("contact.enabled", "String")):  # fmt: skip
        value = {"Real": 1.5, "Integer": 3, "Boolean": 1, "String": "true"}[kind]
        res = host.call("case", fmu=str(fmu), params={name: value}, kinds={name: kind})
        log = host.call("log")["log"]
        assert res["set"] == [3] and res["init"] == 0 and res["steps"] == [0, 0], (name, res, log)
        (text,) = [m for _, s, m in log if s == 3]
        article = "an" if kind == "Integer" else "a"
        assert (
            f"cannot set {article} {kind} through" in text and f"{name} ({parameters[name][0]}, parameter)" in text
        ), text


# ------------------------------------------------------------------------------ random combinations
# Values inside the declared ranges that keep one case short: at most 100 elements (2000 take 90 s
# to initialise), internal steps of at least 1e-6 s (1e-10 s would be 1e6 steps per doStep).
FAST = {"geometry.n_elements": (1, 100), "solver.dt": (1e-6, 1.0), "scenario.dt": (1e-6, 1.0)}
WORDS = ["clamped", "isolator", "free", "routing", "straight", "hertz", "linear", "hunt_crossley", "switch",
         "regularized", "spline", "polyline", "installed", "default", "", "bogus"]  # fmt: skip


@st.composite
def combination(draw, parameters):
    """1 to 3 distinct parameters, each an edge value or a value inside its declared range."""
    names = draw(st.lists(st.sampled_from(sorted(parameters)), min_size=1, max_size=3, unique=True))
    out = {}
    for name in names:
        kind, lo, hi = parameters[name]
        lo, hi = FAST.get(name, (lo, hi))
        if kind == "String":
            inside = st.sampled_from(WORDS)
        elif kind == "Boolean":
            inside = st.sampled_from([0, 1])
        elif kind == "Integer":
            inside = st.integers(lo, hi)
        elif lo is not None and hi is not None and lo > 0:  # (log-uniform over decades)
            inside = st.floats(math.log10(lo), math.log10(hi)).map(lambda e: 10.0**e)
        else:
            inside = st.floats(lo, hi, allow_nan=False, allow_infinity=False)
        edges = [v for v in edge_values(kind, *parameters[name][1:]) if not isinstance(v, str) or len(v) < 100]
        out[name] = draw(st.one_of(inside, st.sampled_from(edges)))
    return out


def test_random_combinations_never_end_fatal_and_say_what_they_refuse(fmu, parameters, fmu_probe):
    """100 random combinations of 1-3 parameters (edge values and values inside the ranges), each in
    an instance of its own, two steps of 1e-4 s with the supports at rest: never fmi2Fatal, never a
    dead host, never an internal error; what initialisation refuses names one of the parameters
    set (the key, or for a vector's component its vector, or the list of the parameters set when
    the model cannot be built: a static state that does not converge), and a refused step says why."""
    host = fmu_probe()

    @settings(
        max_examples=100,
        deadline=None,
        derandomize=True,
        database=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )
    @given(params=combination(parameters))
    @example(params={"loads.gravity.x": 10000.0, "cable.E": 5e-324})  # (the fuzz found: cases of the next test)
    @example(params={"casing.d_outer": 1.0, "loads.gravity.z": -10000.0})
    @example(params={"contact.enabled": 2, "scenario.dt": 1.0})
    def run(params):
        res = host.call("case", fmu=str(fmu), params=params, h=1e-4, n=2)
        log = host.call("log")["log"]
        statuses = res["set"] + [res["init"]] + res["steps"]
        assert FATAL not in statuses, (params, statuses, log)
        for _, _s, m in log:
            assert "a bug; please report it" not in m and "internal error" not in m, (params, m)
        keys = [k for k, s in zip(params, res["set"]) if s < 3]  # (the ones the set took)
        names = keys + [k.rsplit(".", 1)[0] for k in keys]
        if res["init"] >= 3:
            errors = [m for _, s, m in log if s >= 3]
            assert any(n in m for m in errors for n in names), (params, errors)
        for k, s in zip(params, res["set"]):
            if s >= 3:
                assert any(k in m for _, s2, m in log if s2 >= 3), (params, log)
        if any(s >= 2 for s in res["steps"]):
            assert any(s >= 2 for _, s, m in log), (params, res, log)

    run()


def test_what_the_fuzz_found_is_named(fmu, fmu_probe):
    """The combinations the fuzz found that ended as internal errors or named nothing:
    cable.E = 5e-324 (inside its declared min) under gravity made the static state's solve a
    LinAlgError, said as "a bug"; it names cable.E now. A static state that does not converge
    (casing.I = 5e-324 under gravity: a casing without bending stiffness) is the model's failure, not
    a bug, and lists the parameters set. scenario.dt = 1.0 s, inside its range, makes a step of 1e-4
    s too short for the internal step: the refusal names solver.dt and that its value is
    scenario.dt's."""
    host = fmu_probe()
    res = host.call("case", fmu=str(fmu), params={"loads.gravity.x": 10000.0, "cable.E": 5e-324})
    errors = [m for _, s, m in host.call("log")["log"] if s == 3]
    assert res["init"] == 3 and errors[0].startswith(
        "invalid parameter cable.E = 5e-324: makes the cable's stiffness matrix singular in double precision"
    ), errors
    res = host.call("case", fmu=str(fmu), params={"loads.gravity.x": 10.0, "casing.I": 5e-324})
    errors = [m for _, s, m in host.call("log")["log"] if s == 3]
    assert res["init"] == 3 and errors[0].startswith("the model cannot be built: the static state did not converge")
    assert errors[0].endswith("; parameters set: loads.gravity.x = 10.0, casing.I = 5e-324"), errors
    res = host.call("case", fmu=str(fmu), params={"scenario.dt": 1.0}, h=1e-4, n=1)
    said = [m for _, s, m in host.call("log")["log"] if s == 2]
    assert res["init"] == 0 and res["steps"] == [2], res
    assert "solver.dt = 1.0 s (the model's scenario.dt, as set: solver.dt is not set)" in said[0], said


# ------------------------------------------------------------------------------ a C host


@pytest.mark.parametrize(
    "name, value, said",
    [
        ("casing.E", "nan", "casing.E = nan: must be a finite number in (0, 1e+16] in Pa"),
        ("casing.E", "-inf", "casing.E = -inf: must be a finite number in (0, 1e+16] in Pa"),
        (
            "contact.friction",
            "10.000000000000002",
            "contact.friction = 10.000000000000002: must be a number in [0, 10]",
        ),
        ("solver.dt", "0", "solver.dt = 0.0: must be a number in [1e-10, 1]"),
        ("geometry.n_elements", "2147483647", "geometry.n_elements = 2147483647: must be a whole number in [1, 2000]"),
        ("scenario.seed", "-1", "scenario.seed = -1: must be a whole number in [0, 2147483647]"),
        ("contact.law", "bogus", "contact.law = 'bogus': must be one of 'hertz', 'linear', 'hunt_crossley'"),
        ("model_file", "/nonexistent/model.toml", "model_file = '/nonexistent/model.toml': must be a readable TOML"),
    ],
)
def test_fmusim_in_the_plain_environment_refuses_them_by_name(c_hosts, fmu, tmp_path, plain_env, name, value, said):
    """fmusim (a C host, the FMU starting Python itself) with one bad start value: it stops with its
    own exit status for a failed FMI call (not killed by a signal, no core), and its log holds the
    FMU's message naming the variable, the value and what is allowed."""
    log = tmp_path / "log.txt"
    proc = subprocess.run(
        [str(c_hosts / "fmusim"), "--interface-type", "cs", "--stop-time", "0.001", "--output-interval", "1e-4",
         "--start-value", name, value, "--log-file", str(log), "--output-file", str(tmp_path / "out.csv"),
         str(fmu)],
        env=plain_env, capture_output=True, text=True, timeout=300, cwd=tmp_path,
    )  # fmt: skip
    assert proc.returncode > 0 and proc.returncode < 128, (proc.returncode, proc.stderr[-2000:])
    text = log.read_text()
    assert said in text, text[-3000:]
    assert "Fatal" not in text and "a bug" not in text, text[-3000:]
