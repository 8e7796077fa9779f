"""A property-based test (hypothesis) of the model file through the command line (issue 26): the
built-in model with its keys, types and magnitudes (1e-300 to 1e300) mutated, keys removed and
added, and bytes of its text replaced, gives either exit status 2 with one error line (warnings
aside) or finite results; never a traceback or an internal error, each case within bounded time
and memory (tracemalloc counts numpy's arrays). Issue 35: the same of a mounted model
(examples/installation.toml with gravity and a tension) whose isolators, clips, segments, supports
and loads are mutated, through ``geometry``, ``static`` and ``modes``."""

import json
import os
import time
import tracemalloc
from importlib import resources
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cablecasing_core.cli import main
from cablecasing_core.model.load import tomllib
from cablecasing_core.model.model import _to_toml  # (the TOML writer of Model.to_toml)

TEXT = resources.files("cablecasing_core.model").joinpath("specimens/default.toml").read_text()
MOUNTED_TEXT = (Path(__file__).resolve().parents[2] / "examples" / "installation.toml").read_text() + (
    "\n[loads]\ngravity = [0.0, 0.0, -9.81]\ncable_tension = 2.0\n"
)
BASE = tomllib.loads(TEXT)
# per case, a guard against a run the limits let grow without bound (hours), not a speed test: a
# modes run and a 20-step simulate take about 1 s, so 600 s fails no case because a machine is slow
# or loaded, while a case that runs for hours (what the limits are there to refuse) still fails
SECONDS = 600.0
BYTES = 1.5e9  # per case: the specimen needs about 50 MB; the limits refuse anything near the machine's


def _leaves(node, prefix=()):
    for k, v in node.items():
        if isinstance(v, dict):
            yield from _leaves(v, prefix + (k,))
        else:
            yield prefix + (k,)


LEAVES = list(_leaves(BASE))


def _get(path, base=BASE):
    node = base
    for k in path:
        node = node[k]
    return node


NUMERIC = [p for p in LEAVES if isinstance(_get(p), (int, float)) and not isinstance(_get(p), bool)]
SECTIONS = [p[:-1] for p in LEAVES if len(p) > 1]

magnitudes = st.builds(
    lambda m, e, s: s * m * 10.0**e, st.floats(1.0, 9.99), st.integers(-300, 299), st.sampled_from([1.0, -1.0])
)
values = st.one_of(
    magnitudes,
    st.integers(-(2**70), 2**70),
    st.sampled_from([0, 1, -1, 0.0, float("nan"), float("inf"), -float("inf"), True, False, "", "spline"]),
    st.text(max_size=12),
    st.lists(magnitudes, max_size=4),
    st.lists(st.lists(magnitudes, min_size=3, max_size=3), max_size=3),
    st.dictionaries(st.sampled_from(["A", "B", "x"]), st.sampled_from(["clamped", "free", 1.0]), max_size=2),
)
scaled = st.tuples(st.just("set"), st.sampled_from(NUMERIC), magnitudes)  # (most cases: a number's size)
slips = st.tuples(st.just("scale"), st.sampled_from(NUMERIC), st.integers(-8, 8))  # (a slip of units: x 10^k)
edits = st.one_of(
    scaled,
    slips,
    slips,
    slips,
    st.tuples(st.just("set"), st.sampled_from(LEAVES), values),
    st.tuples(st.just("delete"), st.sampled_from(LEAVES), st.none()),
    st.tuples(st.just("add"), st.sampled_from(SECTIONS), st.tuples(st.sampled_from(["zz", "E", "n"]), values)),
)
byte_edits = st.lists(st.tuples(st.integers(0, len(TEXT.encode()) - 1), st.binary(min_size=1, max_size=3)), max_size=3)


def _apply(data, edit):
    kind, path, value = edit
    node = data
    for k in path[:-1] if kind != "add" else path:
        if not isinstance(node.get(k), dict):
            return
        node = node[k]
    if kind == "set":
        node[path[-1]] = value
    elif kind == "scale" and path[-1] in node:
        v = node[path[-1]]
        node[path[-1]] = v * 10**value if isinstance(v, int) and value >= 0 else v * 10.0**value
    elif kind == "delete":
        node.pop(path[-1], None)
    else:
        node[value[0]] = value[1]


def _edited(tmp_path, base, edit_list):
    """The model file (a path in ``tmp_path``) of the tables ``base`` with ``edit_list`` applied."""
    data = json.loads(json.dumps(base))
    for e in edit_list:
        _apply(data, e)
    p = tmp_path / "m.toml"
    p.write_text(_to_toml(data))
    return p


def _check(argv, capsys):
    tracemalloc.start()
    t0 = time.perf_counter()
    try:
        code = main(argv)
    finally:
        elapsed = time.perf_counter() - t0
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert peak < BYTES, (argv, peak)
    assert elapsed < SECONDS, (argv, elapsed)  # (the hang guard above)
    errors = [line for line in lines if not line.startswith("cablecasing: warning: ")]
    if os.environ.get("FUZZ_LOG"):
        with open(os.environ["FUZZ_LOG"], "a") as fh:
            fh.write(f"{argv[0]} {code} {elapsed:.2f} {(errors or lines or [''])[0][:150]}\n")
    if code == 2:
        assert len(errors) == 1 and errors[0].startswith("cablecasing: error: ") and len(errors[0]) < 800, lines
        return False
    assert code == 0 and not errors, (code, lines)
    return out


def _settings(n):
    return settings(
        max_examples=n,
        deadline=None,
        derandomize=True,  # (the same cases each run: a failure is a bug to reproduce, not a flake)
        database=None,
        suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
    )


def _run_both(path, capsys):
    """modes, then (when the model loads) 20 steps of simulate: one error line or finite numbers."""
    out = _check(["modes", str(path), "--count", "3", "--json"], capsys)
    if out is False:
        return
    freqs = json.loads(out)
    assert all(f == f and abs(f) != float("inf") for fs in freqs.values() for f in fs), freqs
    out = _check(["simulate", str(path), "--dt", "1e-5", "--duration", "2e-4", "--no-progress"], capsys)
    if out is not False:
        assert "nan" not in out and "inf" not in out, out


@_settings(int(os.environ.get("FUZZ_N", 60)))
@given(edit_list=st.lists(edits, min_size=1, max_size=2))
@pytest.mark.slow  # 60 cases of modes and simulate, up to about 1 s each
def test_a_model_file_with_mutated_keys_types_and_magnitudes_gives_one_error_line_or_finite_results(
    tmp_path, capsys, edit_list
):
    _run_both(_edited(tmp_path, BASE, edit_list), capsys)


@_settings(30)
@given(flips=byte_edits.filter(bool))
def test_a_model_file_with_replaced_bytes_gives_one_error_line_or_finite_results(tmp_path, capsys, flips):
    raw = bytearray(TEXT.encode())
    for pos, b in flips:
        raw[pos : pos + len(b)] = b
    p = tmp_path / "m.toml"
    p.write_bytes(bytes(raw))
    _check(["modes", str(p), "--count", "3", "--json"], capsys)


# ------------------------------------------------------------------ issue 35: a mounted model
MOUNTED = tomllib.loads(MOUNTED_TEXT)
MOUNTED_LEAVES = [p for p in _leaves(MOUNTED) if p[0] != "scenario"]
MOUNTED_NUMERIC = [
    p for p in MOUNTED_LEAVES if isinstance(_get(p, MOUNTED), (int, float)) and not isinstance(_get(p, MOUNTED), bool)
]
plausible = st.floats(0.005, 0.6)  # m (most cases: a route that loads, so that static and modes run)
lengths = st.one_of(plausible, plausible, plausible, magnitudes, st.sampled_from([0.0, 1e-300, 1e-9, 1e-6, 200.0]))
directions = st.sampled_from([[0, 1, 0], [0, 0, 1], [1, 0, 0], [0, 0, 0], [0, 1e-170, 0], [-1, 1, 0]])
segment = st.one_of(
    st.builds(lambda L: {"straight": L}, lengths),
    st.builds(
        lambda R, a, t: {"bend": {"radius": R, "angle_deg": a, "toward": t}},
        lengths,
        st.one_of(st.floats(1.0, 120.0), st.floats(-10.0, 400.0), st.sampled_from([90.0, 180.0, 270.0, 359.999])),
        directions,
    ),
)
springs = st.one_of(st.floats(0.0, 1e7), st.floats(0.0, 1e7), magnitudes, st.just(0.0))  # N/m, N.m/rad
stiffness = st.one_of(springs, st.lists(springs, min_size=3, max_size=3))
clip = st.fixed_dictionaries(
    {"at": st.one_of(st.floats(-0.1, 1.2), st.floats(-0.1, 1.2), magnitudes), "stiffness": stiffness},
    optional={
        "rotational_stiffness": stiffness,
        "damping": st.one_of(magnitudes, st.just(0.0)),
        "excitation": st.sampled_from(["dash", "casing", "x.y", ""]),
    },
)
support_kinds = st.sampled_from(["clamped", "isolator", "free", "pinned"])
mounted_edits = st.one_of(
    st.tuples(st.just("set"), st.sampled_from(MOUNTED_NUMERIC), magnitudes),
    st.tuples(st.just("set"), st.sampled_from(MOUNTED_NUMERIC), st.just(0.0)),
    st.tuples(st.just("scale"), st.sampled_from(MOUNTED_NUMERIC), st.integers(-8, 8)),
    st.tuples(st.just("set"), st.sampled_from(MOUNTED_LEAVES), values),
    st.tuples(st.just("delete"), st.sampled_from(MOUNTED_LEAVES), st.none()),
    st.tuples(st.just("set"), st.just(("geometry", "segments")), st.lists(segment, min_size=1, max_size=5)),
    st.tuples(st.just("set"), st.just(("casing", "clip")), st.lists(clip, max_size=3)),
    st.tuples(st.just("set"), st.just(("loads", "gravity")), st.lists(magnitudes, min_size=3, max_size=3)),
    st.tuples(st.just("set"), st.just(("loads", "cable_tension")), st.one_of(magnitudes, st.floats(0.0, 300.0))),
    st.tuples(st.just("set"), st.sampled_from([("casing", "supports", "A"), ("casing", "supports", "B"),
                                               ("cable", "supports", "A"), ("cable", "supports", "B")]), support_kinds),
    st.tuples(st.just("set"), st.sampled_from([("casing", "isolator", "A", "stiffness"),
                                               ("casing", "isolator", "B", "rotational_stiffness")]), stiffness),
)  # fmt: skip


@_settings(int(os.environ.get("FUZZ_N", 40)))
@given(edit_list=st.lists(mounted_edits, min_size=1, max_size=3))
@pytest.mark.slow  # 40 cases of geometry, static and modes of a 64-element mounted model, about 2 s each
def test_a_mounted_model_with_mutated_isolators_clips_segments_and_loads_gives_one_error_line_or_finite_results(
    tmp_path, capsys, edit_list
):
    p = _edited(tmp_path, MOUNTED, edit_list)
    out = _check(["geometry", str(p), "--json"], capsys)
    if out is False:
        return
    assert "NaN" not in out and "Infinity" not in out.replace('"load_N": null', ""), out
    out = _check(["static", str(p), "--json"], capsys)
    if out is not False:
        assert "NaN" not in out and "Infinity" not in out, out
    out = _check(["modes", str(p), "--count", "3", "--json"], capsys)
    if out is not False:
        freqs = json.loads(out)
        assert all(f == f and abs(f) != float("inf") for fs in freqs.values() for f in fs), freqs
