"""What an FMU integrator's earlier reviews left (docs/fmu.md, "Messages you may see"): an FMU built
for a model file names it in its first message; numba's compile notice is said once per process,
not by every live instance; position inputs that set the casing's and the cable's supports at one
end apart across the route by more than the radial gap warn once, naming them. The FMUs run in a
host process of their own (tests/fmu/fmu_probe.py through the ``fmu_probe`` fixture)."""

import os
import re

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.structure.geometry import centerline_of

pytestmark = pytest.mark.slow  # the FMU in a process of its own

H = 1e-4


def messages(log, instance=None, containing=""):
    """(status, message) of the log's entries of ``instance`` (any when None) that contain ``containing``."""
    return [(s, m) for name, s, m in log if (instance is None or name == instance) and containing in m]


def test_an_fmu_built_for_a_model_file_names_it_in_its_first_message(fmu, installed_fmu, fmu_probe):
    """Two FMUs in one process, the plain one and the one built for the installed specimen: the
    first message of each says which it is (its base model), not only the instance name."""
    host = fmu_probe()
    host.call("instantiate", name="plain", fmu=str(fmu))
    host.call("instantiate", name="built", fmu=str(installed_fmu))
    log = host.call("log")["log"]
    first = {name: next(m for n, s, m in log if n == name) for name in ("plain", "built")}
    assert first["plain"].startswith(f"CableCasing.fmu {cc.__version__} (FMI 2.0): "), first
    assert first["built"].startswith(
        f"CableCasing.fmu {cc.__version__} built for the model file installed.toml (FMI 2.0): "
    ), first
    for name in ("plain", "built"):
        host.call("free", name=name)


def test_numba_compiling_is_said_once_per_process_not_by_every_instance(fmu, installed_fmu, fmu_probe, tmp_path):
    """An empty per-user cache (so what numba compiles is not loaded from an earlier run), two live
    instances (of two FMUs, each with a bridge module of its own), and numba compiling a kernel of the
    model for argument types it has not seen, then a function of the host's own: the notice is said
    once, as a warning in the first instance's log, nothing in the second's, nothing for the host's
    own code. With the first instance freed, another compilation gives the second instance one short
    line (info) that points at the first's log."""
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["XDG_CACHE_HOME"] = str(tmp_path / "empty-cache")
    host = fmu_probe(env=env)
    for name, path in (("one", fmu), ("two", installed_fmu)):
        host.call("instantiate", name=name, fmu=str(path))
    host.call("log")
    host.call("compile")
    log = host.call("log")["log"]
    said = messages(log, containing="compil")
    assert len(said) == 1 and messages(log, "one", "compiling the model's numba kernels for this machine"), log
    status, text = said[0]
    assert status == 1 and "said once per process" in text and "accept_rows" in text, text
    host.call("free", name="one")
    host.call("compile")
    log = host.call("log")["log"]
    assert [(s, m.split(";")[0]) for s, m in messages(log, containing="compil")] == [
        (0, "compiling more of the model's numba kernels (first: accept_rows)")
    ], log
    assert messages(log, "two", "in the log of instance 'one'"), log
    host.call("free", name="two")


@pytest.fixture(scope="module")
def ends():
    """The built-in specimen's radial gap (m) and the unit tangents of its route at ends A and B,
    from the core's centerline (the cable and the casing share it, and their end nodes)."""
    model = cc.load_model()
    t = centerline_of(model).tangents
    return model.radial_gap, {"A": t[0] / np.linalg.norm(t[0]), "B": t[-1] / np.linalg.norm(t[-1])}


def across(ends, end, offset):
    """The part (m) of an offset (m, global) of the casing's support against the cable's at ``end``
    normal to the route's tangent there."""
    t = ends[1][end]
    d = np.asarray(offset, float)
    return float(np.linalg.norm(d - (d @ t) * t))


def test_end_supports_set_apart_across_the_gap_warn_once_naming_the_inputs(fmu, fmu_probe, ends):
    """casing.A.y ramped to 1 mm while cable.A stays at 0 presses the cable into the casing's wall at
    end A (the bodies share their end node; the gap is 0.5 mm): a kN force, and one warning, at
    fmi2Warning through the host's logger, naming the inputs, their values and the gap, with every
    step still fmi2OK; later offsets of the same instance say nothing more. 0.4 mm stays within the
    gap: no warning, a few N. Only the part across the route counts: cable.B.z = 0.99 mm is 0.497 mm
    across the tangent at B (0.25, 0.43, 0.86), within the gap, while 1.005 mm is 0.505 mm, past it;
    casing.A.x, along the route at A, slides. With contact off nothing presses: no warning."""
    gap = ends[0]
    assert gap == 0.0005
    assert across(ends, "B", [0, 0, -0.99e-3]) < 0.995 * gap < 1.005 * gap < across(ends, "B", [0, 0, -1.005e-3])
    assert across(ends, "A", [1e-3, 0, 0]) < 0.03 * gap
    host = fmu_probe()
    results = {}
    cases = {
        "A1mm": ({"casing.A.y": 1e-3}, {}),
        "A0.4mm": ({"casing.A.y": 0.4e-3}, {}),
        "Bin": ({"cable.B.z": 0.99e-3}, {}),
        "Bout": ({"cable.B.z": 1.005e-3}, {}),
        "axial": ({"casing.A.x": 1e-3}, {}),
        "off": ({"casing.A.y": 1e-3}, {"contact.enabled": False}),
    }
    for key, (offset, params) in cases.items():
        host.call("instantiate", name=key, fmu=str(fmu))
        assert host.call("initialize", name=key, params=params)["init"] == 0
        statuses, force = [], 0.0
        for k in range(1, 101):  # (ramped over 10 ms: no jump of the supports)
            res = host.call("step", name=key, inputs={n: v * min(1.0, k / 80) for n, v in offset.items()}, h=H,
                            outputs=["casing.A.Fy"])  # fmt: skip
            statuses += res["steps"]
            force = max(force, abs(res["outputs"][0]))
        if key == "A1mm":  # (later offsets, at the other end too: said once per instance)
            statuses += host.call("step", name=key, inputs={"cable.B.y": 2e-3}, h=H, n=5)["steps"]
        host.call("free", name=key)
        log = host.call("log")["log"]
        results[key] = (statuses, force, messages(log, key, "apart across the route"))
    for key, (statuses, _force, said) in results.items():
        assert set(statuses) == {0}, (key, statuses)
        assert len(said) == (1 if key in ("A1mm", "Bout") else 0), (key, said)
    assert results["A1mm"][1] > 1000.0 and results["A0.4mm"][1] < 10.0, {k: r[1] for k, r in results.items()}
    for key, end, name in (("A1mm", "A", "casing.A.y"), ("Bout", "B", "cable.B.z")):
        ((status, text),) = results[key][2]
        # (said at the first step whose ramped input puts the ends past the gap: that input's value)
        value = float(re.search(rf"{name} = (\S+) m", text).group(1))
        offset = np.zeros(3)
        offset["xyz".index(name[-1])] = value if name.startswith("casing") else -value
        assert status == 1 and f"supports at end {end} {across(ends, end, offset) * 1e3:.4g} mm apart" in text, text
        before = offset * (1 - 1 / (80 * abs(value) / cases[key][0][name]))  # (the ramp's step before it)
        assert across(ends, end, before) <= gap < across(ends, end, offset), text
        other = name.replace("casing", "cable") if name.startswith("casing") else name.replace("cable", "casing")
        assert f"{other} = 0.0 m" in text and "more than the radial gap 0.5 mm" in text, text
