"""Build dist/CableCasing.fmu (FMI 2.0 co-simulation) from fmu_src/ with pythonfmu, then complete it.

pythonfmu writes the variables, the co-simulation capability flags and the Outputs. This script
copies the ``cablecasing_core`` package (with its numba cache locator) into ``resources/`` and then
rewrites the archive with what pythonfmu does not write:

* a unit on every Real variable and the ``UnitDefinitions`` (SI base-unit exponents);
* ``ModelStructure``: ``Outputs`` with ``dependencies=""`` (no direct feedthrough: an output is the
  result of the last step, not of the inputs set since) and ``InitialUnknowns`` (the outputs, which
  depend on the parameters: the reactions of an installed model's static state; no
  ``dependencies`` attribute, so on every known);
* ``documentation/index.html`` (model, variables with units, sign conventions, geometry figure),
  ``documentation/externalDependencies.txt`` and ``model.png``;
* a GUID derived from the content, a generation date from the newest source file and fixed
  timestamps in the zip, so that building twice from the same sources gives the same bytes.

With ``--model FILE.toml`` the FMU is built for that model file: the file (and the CSV files its
excitations read) ships in ``resources/model/`` and is the FMU's base model in place of the
built-in specimen, so the FMU's inputs and outputs are that model's (``model.schema.inputs_of``,
``outputs_of``: the excited clips' channels, the clips' forces), its parameters start at its
values, its GUID differs from every other model's, and its documentation names the file.

Usage: python build_fmu.py [--model FILE.toml | default | installed] [--output dist/CableCasing.fmu]

Bad input (a model file that does not load, an output that is no ``.fmu`` file) is one line on
stderr and exit status 2, as on the command line, before any folder or file is created.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime
import hashlib
import html
import json
import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import uuid
import zipfile
from pathlib import Path
from xml.etree import ElementTree as ET

ROOT = Path(__file__).resolve().parent
SLAVE = ROOT / "fmu_src" / "CableCasing.py"
BRIDGE = ROOT / "fmu_src" / "cablecasing_fmi2_bridge.py"
NATIVE = ROOT / "fmu_src" / "native" / "cablecasing_fmi2.c"
EXTRA_RESOURCES = [BRIDGE]
# the packages the FMU's Python code imports (their minimum versions are read from pyproject.toml)
RUNTIME_PACKAGES = ("numpy", "scipy", "numba")
PACKAGE = ROOT / "cablecasing_core"
IGNORE = shutil.ignore_patterns("__pycache__", "*.pyc", "*.nbi", "*.nbc", ".*")

# unit -> exponents of the SI base units (FMI 2.0 BaseUnit attributes); every unit the model schema uses
# must be here (tests/fmu/test_unit_definitions.py)
UNITS = {
    "1": {},
    "m": {"m": 1},
    "m/s": {"m": 1, "s": -1},
    "m/s2": {"m": 1, "s": -2},
    "s": {"s": 1},
    "1/s": {"s": -1},
    "Hz": {"s": -1},
    "rad": {"rad": 1},
    "N": {"kg": 1, "m": 1, "s": -2},
    "N.m": {"kg": 1, "m": 2, "s": -2},
    "J": {"kg": 1, "m": 2, "s": -2},
    "Pa": {"kg": 1, "m": -1, "s": -2},
    "kg/m3": {"kg": 1, "m": -3},
    "kg/s": {"kg": 1, "s": -1},
    "s/m": {"s": 1, "m": -1},
    "N/m": {"kg": 1, "s": -2},
    "N.s/m": {"kg": 1, "s": -1},
    "N.m/rad": {"kg": 1, "m": 2, "s": -2, "rad": -1},
    "N.m.s/rad": {"kg": 1, "m": 2, "s": -1, "rad": -1},
    "m4": {"m": 4},
}


def sources():
    """Every file the FMU is built from (for the staleness check of the tests, and the date)."""
    files = [
        p
        for p in PACKAGE.rglob("*")
        if p.is_file() and p.suffix in (".py", ".toml", ".csv") and "__pycache__" not in p.parts
    ]
    return sorted(files + [SLAVE, NATIVE, *EXTRA_RESOURCES, ROOT / "pyproject.toml", Path(__file__).resolve()])


#: The FMU ``make fmu``, the demo and the tests share: the default output.
DEFAULT_FMU = ROOT / "dist" / "CableCasing.fmu"


@contextlib.contextmanager
def default_fmu_lock():
    """Hold the lock on :data:`DEFAULT_FMU` (``dist/.CableCasing.fmu.lock``, made with its folder)
    while the block runs: whoever rebuilds or reads that file under it (the tests' ``fmu`` fixture,
    examples/demo.py) sees no other such process replace it meanwhile (pytest-xdist's workers: the
    demo's test compares the checksum the demo recorded with the file). A process that ends
    releases it. (fcntl's flock, not the filelock package: the FMU is linux64 only; a build that
    does not take it, such as ``python build_fmu.py`` itself, is not held back.)"""
    import fcntl

    DEFAULT_FMU.parent.mkdir(exist_ok=True)
    with open(DEFAULT_FMU.parent / f".{DEFAULT_FMU.name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield DEFAULT_FMU


def load_slave():
    """The slave class, imported from fmu_src (variables, units and descriptions for the docs)."""
    sys.path.insert(0, str(SLAVE.parent))
    try:
        import CableCasing
    finally:
        sys.path.remove(str(SLAVE.parent))
    return CableCasing


# ------------------------------------------------------------------------------------ model description
def real_starts(slave):
    """{name: start} of every Real variable of the slave instance ``slave`` that has a start value
    (inputs and parameters): the values its getters give, which pythonfmu writes as the start."""
    from pythonfmu import Real

    return {
        v.name: float(v.getter())
        for v in slave.vars.values()
        if isinstance(v, Real) and v.causality.name in ("input", "parameter")
    }


def complete_description(xml_bytes, units, guid, date, model_name=None, ranges=None, starts=None):
    """The modelDescription.xml with units, the parameters' min and max (``ranges``: name -> (min,
    max), the model schema's allowed values), every Real's start (``starts``: name -> value,
    :func:`real_starts`), UnitDefinitions, ModelStructure, GUID and date (and, for an FMU built for a
    model file, its name in the description). Real numbers are written by ``repr``, the shortest
    text that reads back as the same double: pythonfmu writes a start with 16 significant digits,
    which is another double for a value that needs 17 (a model file's ``scenario.dt = 1/30000``)."""
    root = ET.fromstring(xml_bytes)
    root.set("guid", guid)
    if model_name:
        root.set("description", f"{root.get('description')}; built for the model file {model_name}")
    root.set("generationDateAndTime", date)
    used = set()
    for sv in root.find("ModelVariables").findall("ScalarVariable"):
        real = sv.find("Real")
        if real is not None:
            unit = units[sv.get("name")]
            if unit not in UNITS:
                raise SystemExit(f"variable {sv.get('name')}: unit {unit!r} has no UnitDefinitions entry")
            real.set("unit", unit)
            used.add(unit)
        number = real if real is not None else sv.find("Integer")
        if real is not None and real.get("start") is not None and starts is not None:
            if sv.get("name") not in starts:
                raise SystemExit(f"variable {sv.get('name')}: no start value to write")
            real.set("start", repr(float(starts[sv.get("name")])))  # (repr, as min and max below)
        for attr, bound in zip(("min", "max"), (ranges or {}).get(sv.get("name"), (None, None))):
            if bound is not None:  # (repr: the shortest text that reads back as the same double)
                number.set(attr, repr(float(bound)) if real is not None else str(int(bound)))
        if not sv.get("description"):
            raise SystemExit(f"variable {sv.get('name')} has no description")
    for old in root.findall("UnitDefinitions"):
        root.remove(old)
    defs = ET.Element("UnitDefinitions")
    for unit in sorted(used):
        e = ET.SubElement(defs, "Unit", name=unit)
        ET.SubElement(e, "BaseUnit", {k: str(v) for k, v in UNITS[unit].items()})
    kids = [k.tag for k in root]
    root.insert(kids.index("CoSimulation") + 1, defs)

    variables = root.find("ModelVariables").findall("ScalarVariable")
    outputs = [str(i + 1) for i, sv in enumerate(variables) if sv.get("causality") == "output"]
    ms = root.find("ModelStructure")
    for child in list(ms):
        ms.remove(child)
    node = ET.SubElement(ms, "Outputs")
    for index in outputs:  # (no direct feedthrough: the result of the last step, not of the inputs set since)
        ET.SubElement(node, "Unknown", index=index, dependencies="")
    node = ET.SubElement(ms, "InitialUnknowns")
    for index in outputs:  # (no dependencies attribute: the static reactions depend on the parameters)
        ET.SubElement(node, "Unknown", index=index)
    ET.indent(root, space="  ")
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True) + b"\n"


# ------------------------------------------------------------------------------------ documentation
def variable_rows(slave_module, resources):
    slave = slave_module.CableCasing(instance_name="documentation", resources=str(resources))
    rows = []
    for v in slave.vars.values():
        start = ""
        if v.causality.name in ("parameter", "input"):
            value = v.getter()
            # as the modelDescription writes it: true/false, a string bare, a number by Python's shortest repr
            start = str(value).lower() if isinstance(value, bool) else value if isinstance(value, str) else repr(value)
        lo, hi = slave.ranges.get(v.name, (None, None))
        allowed = (
            ""
            if lo is None and hi is None
            else f"{'-inf' if lo is None else repr(lo)} .. {'inf' if hi is None else repr(hi)}"
        )
        rows.append((v.name, v.causality.name, type(v).__name__, slave.units[v.name], start, allowed, v.description))
    return rows


def write_documentation(folder, rows, model_file=None):
    """documentation/: index.html (the model, the variables), the geometry figure and
    externalDependencies.txt, of the built-in specimen or of ``model_file`` (a Path)."""
    import cablecasing_core as cc
    from cablecasing_core.plotting import plot_geometry
    from cablecasing_core.structure.geometry import centerline_of
    from cablecasing_core.structure.route_summary import geometry_summary

    folder.mkdir(parents=True, exist_ok=True)
    model = cc.load_model(model_file) if model_file else cc.load_model()
    plot_geometry(centerline_of(model), folder / "geometry.png")
    gap = model.radial_gap
    if model_file:
        clips = model.data.get("casing", {}).get("clip", [])
        excited = [c["excitation"] for c in clips if "excitation" in c]
        geometry = f"""<h2>The model file: {html.escape(model_file.name)}</h2>
<p>This FMU was built for the model file <code>{html.escape(model_file.name)}</code> (shipped in
<code>resources/model/</code>; built from <code>{html.escape(str(model_file))}</code>), which is its
base model in place of the built-in specimen: every parameter starts at that file's value, and its
inputs and outputs are that model's: the 12 support channels, {len(excited)} excited clip(s)
({html.escape(", ".join(excited) or "none")}: inputs <code>&lt;name&gt;.x</code>, <code>.vx</code>,
<code>.ax</code>, ... of the clip's support) and the force and moment through each of its {len(clips)}
clip(s) (<code>casing.clip&lt;i&gt;.Fx</code> .. <code>Mz</code>, what the casing exerts through the clip
on its support). A <code>model_file</code> set at run time overrides the base model only if it has the
same excited clips and the same number of clips; another is refused at initialisation (fmi2Error).</p>
<p><img src="geometry.png" alt="centerline of the model, ends A and B marked" width="480"></p>
<p>Centerline of the model ({geometry_summary(model)["length_m"]:.4g} m; radial gap {gap * 1e3:.2f} mm).
Support A is at the start of the route, B at its end.</p>"""
    else:
        geometry = """<h2>Default geometry</h2>
<p><img src="geometry.png" alt="centerline of the built-in specimen, ends A and B marked" width="480"></p>
<p>Centerline of the built-in specimen (0.85 m; two 60&deg; bends of radius 0.15 m and 0.20 m in
different planes). Support A is at the origin, B at the other end.</p>"""
    table = "\n".join("<tr>" + "".join(f"<td>{html.escape(str(x))}</td>" for x in r) + "</tr>" for r in rows)
    (folder / "index.html").write_text(f"""<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>CableCasing FMU</title>
<style>body{{font-family:sans-serif;max-width:60em;margin:auto}} td,th{{border:1px solid #999;padding:2px 6px}}
table{{border-collapse:collapse;font-size:90%}} code{{background:#eee}}</style></head><body>
<h1>CableCasing &mdash; gear-shift cable in a curved casing (FMI 2.0 co-simulation)</h1>

<h2>The model</h2>
<p>Vibration transmission over a spatially curved steel cable sliding inside a curved casing
(Otrin and Boltezar). Both bodies are 3D Euler&ndash;Bernoulli beams on the same centerline, meshed
with 12-DOF elements, with Rayleigh damping C = &alpha;M + &beta;K. They are coupled by contact across
the radial gap ({"this model" if model_file else "built-in specimen"}: {gap * 1e3:.2f} mm): penalty method
with the Hertz law, contact damping while the penetration grows, Coulomb friction with stick and slip.
Time integration: Newmark average acceleration with internal step <code>solver.dt</code>; the contact forces are solved
implicitly at the end of each internal step. The four ends (casing A/B, cable A/B) are supports
(clamped, free, or on the model's elastic isolators) whose translations follow the inputs; their rotations are held at
zero.
The FMU is a thin adapter over the Python package <code>cablecasing_core</code>, bundled in
<code>resources/</code>. All quantities are SI.</p>

{geometry}

<h2>Sign conventions and meaning of the outputs</h2>
<ul>
<li>Inputs are the support displacement (m), velocity (m/s) and acceleration (m/s2) along the
<em>global</em> axes, relative to the reference position.</li>
<li>Outputs <code>&lt;body&gt;.&lt;A|B&gt;.F*</code> and <code>.M*</code> are the force (N) and moment
(N.m) the body exerts <em>on</em> the support, in global axes: the negative of the reaction the
support applies to the body (the one used by the apparent mass TRFAM). A rigid mass m moved with
acceleration a gives F = &minus;m a.</li>
<li><code>contact.active</code>: cable nodes in contact (stick or slip); <code>contact.max_penetration</code>
(m): largest penetration into the wall; <code>contact.dissipated_energy</code> (J): energy dissipated
in the contacts since t = 0, the contact forces' work less the energy they store (damping and friction,
and on a curved casing's mesh the normal forces' own work).</li>
<li>Outputs are the values at the end of the last communication step; they do not depend directly
on inputs set since (no direct feedthrough).</li>
</ul>

<h2>Motion inside a communication step</h2>
<p>The master gives u, v, a at the start t of each step [t, t+h]. The FMU extrapolates them to t+h
by Taylor to third order, (u + v h + a h&sup2;/2 + j h&sup3;/6, v + a h + j h&sup2;/2, a + j h), with the
jerk j = (a &minus; a_prev)/(t &minus; t_prev) from the acceleration inputs of the last two communication
points (j = 0 at the first step), and follows the quintic Hermite polynomial from the support state it
reached at t (continuous displacement, velocity and acceleration) to that target. Connect the
velocity and acceleration inputs: if they stay 0 the motion is held piecewise and lags. For a
harmonic input the reconstructed motion's gain is within 1.8e-4 of 1 at 300 Hz, 0.9&nbsp;% at 800 Hz
and 2.1&nbsp;% at 1 kHz with h = 1e-4 s. Any step size works: the engine takes steps of
<code>solver.dt</code> and a shorter last one.</p>

<h2>Parameters</h2>
<p>Every numeric key of the model is a parameter under its dotted name. Every parameter the master
sets overrides the model (the built-in one, or the TOML file named by <code>model_file</code>), even
when set to its start value: with a model file, set only what you change (a master that writes every
start value replaces the model file's values with the built-in specimen's). A derived parameter,
<code>solver.dt</code> (from <code>scenario.dt</code>) or a random excitation's seed that the model
leaves to <code>scenario.seed</code>, written with exactly its start value follows its source instead:
only another value overrides it, so writing every start value and <code>scenario.seed = 7</code> runs
seed 7. A getter returns the value in force. <code>scenario.*</code> keys describe the model's own
excitation: they act when <code>scenario.drive</code> is true (the FMU then drives its supports with
it), and not otherwise; <code>scenario.dt</code>, set without <code>solver.dt</code>, is the internal step.
Parameters are fixed: set them before
<code>fmi2ExitInitializationMode</code>.</p>

<h2>Errors</h2>
<p>Every problem is reported to the master's logger, naming the variable, the value and what is
allowed, and gets the status it deserves; the FMU never returns fmi2Fatal and never ends the host
process. An invalid parameter makes <code>fmi2ExitInitializationMode</code> return fmi2Error (and every
later <code>fmi2DoStep</code>, until the FMU is reset); a non-finite input, a step that would
penetrate the wall beyond the cable radius, a step longer than one million internal steps or a
step at another time than the FMU's returns fmi2Discard and is rolled back whole, so the master
may retry; calls the life cycle does not allow (a step after <code>fmi2Terminate</code>) and
improper arguments (NaN times, NULL or non-UTF-8 strings) return fmi2Error. Errors and warnings
are logged whether or not logging is on; a problem that keeps the FMU from starting (no suitable
Python, a missing package) is also written to stderr.</p>

<h2>Variables</h2>
<table><tr><th>name</th><th>causality</th><th>type</th><th>unit</th><th>start</th><th>min .. max</th>
<th>description</th></tr>
{table}
</table>
</body></html>
""")
    ver = f"{sys.version_info.major}.{sys.version_info.minor}"
    (
        folder / "externalDependencies.txt"
    ).write_text(f"""CableCasing.fmu runs Python code: the model package cablecasing_core (inside resources/).

The host needs CPython {ver} (64-bit, with its shared library) and the packages
{runtime_requirements().replace(";", ", ")} in that Python.

Linux (binaries/linux64, this project's own binary):
  - In a Python host (fmpy, libcosimpy, a pytest run) the FMU uses the host's interpreter.
  - In any other host (a C or C++ system simulator, fmusim, the FMU Compliance Checker) it starts
    CPython itself: the interpreter named by the environment variable CABLECASING_PYTHON (the path
    of a python{ver} executable, for example a virtual environment's bin/python), else the one
    recorded when the FMU was built (resources/python-environment.txt), else python{ver} on PATH.
    No LD_PRELOAD, PYTHONHOME or PYTHONPATH is needed; PYTHONHOME and PYTHONPATH are ignored.
  - The FMU logs which interpreter it uses. If it finds none, or a package is missing or too old,
    fmi2Instantiate fails with one message (to the logger and to stderr) that says what is missing
    and how to fix it.
  - glibc 2.34 or newer.

Windows (binaries/win64): pythonfmu's binary, not tested by this project: python3{sys.version_info.minor}.dll must be
found (its folder on PATH) and the packages above importable (PYTHONHOME/PYTHONPATH).
macOS: no binary is provided.

On the first start the FMU copies its Python code to the per-user cache folder
(~/.cache/cablecasing/fmu/<GUID>) and the numba machine code compiled when it was built to
~/.cache/cablecasing/numba (or NUMBA_CACHE_DIR); a CPU, Python or numba that does not fit the
shipped code is compiled there once (30-60 s, logged while it happens). Where that folder cannot
be written (a read-only HOME), it uses <TMPDIR or /tmp>/cablecasing-<uid> instead, and says so in
its log. Copies of the code unused for 14 days are deleted; the whole folder may be deleted
whenever no FMU is running (docs/fmu.md, "Caches").
""")


# ------------------------------------------------------------------------------------ native binary
def compile_native(out):
    """Compile ``fmu_src/native/cablecasing_fmi2.c`` into the Linux binary ``out``. The build
    Python's headers give the PyConfig layout; ``-Wl,--no-undefined`` proves that the binary
    leaves no Python symbol to the dynamic loader (it resolves them with dlsym at run time).
    Returns False (and says why) without a C compiler: the FMU then keeps pythonfmu's binary."""
    if not sys.platform.startswith("linux"):
        return False
    compiler = os.environ.get("CC") or shutil.which("gcc") or shutil.which("cc")
    if not compiler:
        print(
            "warning: no C compiler (gcc/cc): binaries/linux64 is pythonfmu's, which needs LD_PRELOAD of "
            "libpython in non-Python hosts (docs/fmu.md)",
            file=sys.stderr,
        )
        return False
    import fmpy

    headers = Path(fmpy.__file__).parent / "c-code"  # the FMI 2.0 headers (fmi2Functions.h, ...)
    cmd = [
        compiler,
        "-O2",
        "-fPIC",
        "-shared",
        "-fvisibility=hidden",
        "-Wall",
        "-Wextra",
        "-Werror",
        "-Wno-format-truncation",
        f"-I{sysconfig.get_paths()['include']}",
        f"-I{headers}",
        "-o",
        str(out),
        str(NATIVE),
        "-ldl",
        "-lpthread",
        "-Wl,--no-undefined",
    ]
    subprocess.run(cmd, check=True)
    return True


def runtime_requirements():
    """'numpy>=1.24;scipy>=1.11;numba>=0.59': the FMU's runtime packages as pyproject.toml asks."""
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib
    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    reqs = []
    for name in RUNTIME_PACKAGES:
        spec = next((d for d in deps if d.split(">")[0].split("=")[0].split(";")[0].strip() == name), name)
        reqs.append(spec.split(";")[0].replace(" ", ""))
    return ";".join(reqs)


def environment_record(guid, version, model_name=None):
    """resources/python-environment.txt: the interpreter the FMU's binary starts in a host without
    Python (this build's), the packages it needs, the GUID the binary checks and the name of the
    model file the FMU was built for (``model_name``; empty for the built-in specimen), which the
    FMU's first log message names."""
    lib = Path(sysconfig.get_config_var("LIBDIR") or "") / (sysconfig.get_config_var("INSTSONAME") or "")
    lines = {
        "executable": sys.executable,
        "libpython": str(lib),
        "python": f"{sys.version_info.major}.{sys.version_info.minor}",
        "version": version,
        "requirements": runtime_requirements(),
        "guid": guid,
        "model": model_name or "",
    }
    return "".join(f"{k}={v}\n" for k, v in lines.items()).encode()


WARM_UP = """
import importlib.util, json, os, sys
stage = sys.argv[1]
sys.path.insert(0, stage)
spec = importlib.util.spec_from_file_location("_cablecasing_warm_slave", os.path.join(stage, "CableCasing.py"))
mod = importlib.util.module_from_spec(spec)
spec.loader.exec_module(mod)


def check(status, what):
    # (explicit, not assert: python -O would drop the call itself and ship no compiled kernels)
    if status != 0:
        raise SystemExit(f"the bundled slave's {what} returned status {status}, not 0 (fmi2OK)")


# the kernels' variants of the base model, of the base model with gravity and, for the FMU of the
# built-in specimen, of the installed specimen (gravity, tension, regularised friction; an FMU built
# for a model file takes only model files with its own channels): a first start with any of these
# compiles nothing
variants = [(None, None, None), ("Real", "loads.gravity.z", -9.81)]
if not mod.CableCasing(instance_name="warm-up", resources=stage).base_file:
    variants.append(("String", "model_file", "installed"))
for kind, key, value in variants:
    slave = mod.CableCasing(instance_name="warm-up", resources=stage)
    if key is not None:
        vr = next(vr for vr, (k, _) in slave._param.items() if k == key)
        check(slave.fmi2_set(kind, [vr], [value]), f"fmi2Set{kind} of {key}")
    check(slave.fmi2_exit_initialization_mode(), "fmi2ExitInitializationMode")
    slave.inputs_buffer[2] = 1e-4
    t = 0.0
    for h in (1e-4, 1e-4, 3.7e-5):
        check(slave.fmi2_do_step(t, h), f"fmi2DoStep at t = {t!r} s")
        t += h
import cablecasing_fmi2_bridge

choice = sys.modules["cablecasing_core.timedomain.kernels._numba_cache"].cache_choice()
print(json.dumps({"folders": cablecasing_fmi2_bridge.kernel_cache_dirs(), "mode": choice.mode, "note": choice.note()}))
"""


def compiled_kernels(entries):
    """The numba cache of the kernels the FMU runs, as resources/numba_cache/<folder>/<file>
    entries: the slave is unpacked from ``entries`` into a folder and steps a few times in a
    subprocess (compiling, or loading what this user's cache already holds); the cache folders of
    the bundled package's kernels are shipped, so that a first start elsewhere loads them. The
    subprocess runs without PYTHONOPTIMIZE (numba keys its cache on the bytecode: kernels compiled
    under -O would not fit a host's ordinary Python). Stops the build (SystemExit) when the slave
    does not run, cannot save what it compiles (no writable cache folder: the kernels' warning names
    the folders, NUMBA_CACHE_DIR), or saved no kernel's machine code (no index file, ``.nbi``)."""
    out = {}
    env = {k: v for k, v in os.environ.items() if k != "PYTHONOPTIMIZE"}
    with tempfile.TemporaryDirectory(prefix="cablecasing_warm_") as stage:
        for name, data in entries.items():
            if name.startswith("resources/"):
                path = Path(stage) / name[len("resources/") :]
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_bytes(data)
        res = subprocess.run([sys.executable, "-c", WARM_UP, stage], capture_output=True, text=True, env=env)
        if res.returncode != 0:
            raise SystemExit(f"the bundled slave does not run (warm-up of the numba cache failed):\n{res.stderr}")
        said = json.loads(res.stdout.strip().splitlines()[-1])
        folders = said["folders"]
        if said["mode"] != "write":  # (what it compiled is not saved, and a read-only cache may lack some)
            raise SystemExit(f"the warm-up cannot save the compiled kernels: {said['note']}")
        for folder in folders:
            for f in sorted(Path(folder).iterdir()):
                if f.suffix in (".nbi", ".nbc"):
                    out[f"resources/numba_cache/{Path(folder).name}/{f.name}"] = f.read_bytes()
    if not any(name.endswith(".nbi") for name in out):
        raise SystemExit(
            f"the warm-up saved no compiled kernels (no .nbi file in {', '.join(folders) or 'any cache folder'}): "
            "the FMU would compile them at every first start"
        )
    return out


# ------------------------------------------------------------------------------------ build
def model_files(model_file):
    """{path inside resources/model/: bytes} of an FMU built for ``model_file`` (a Path): the file
    itself and the CSV files its excitations read (at their paths relative to the file's folder,
    where the model finds them again). Raises ModelError naming the problem: a model file that
    does not load, or a CSV file outside the model file's folder."""
    import cablecasing_core as cc

    model = cc.load_model(model_file)
    files = {model_file.name: model_file.read_bytes()}
    for name, e in model.scenario.get("excitation", {}).items():
        if "file" in e:
            path = Path(e["file"]).resolve()
            try:
                rel = path.relative_to(model_file.parent)
            except ValueError:
                raise cc.ModelError(
                    f"scenario.excitation.{name}.file",
                    str(path),
                    f"must be inside the model file's folder {model_file.parent}: the FMU ships it beside the model "
                    "file, so give it a path relative to that folder, inside it",
                ) from None
            files[rel.as_posix()] = path.read_bytes()
    return files


def model_path(name):
    """The model file of ``--model``: a TOML path, or the name of a built-in specimen (``default``,
    ``installed``: its file in the package), as every command of the CLI takes it; None for None."""
    from cablecasing_core.model import specimen_names

    if name is None:
        return None
    if name in specimen_names():
        return PACKAGE / "model" / "specimens" / f"{name}.toml"
    return Path(name).resolve()


def check_inputs(model, out):
    """Check the build's inputs before anything is created: the model file loads (with its CSV
    files, inside its folder) and the output is a ``.fmu`` file that can be written (no folder or
    device there). Raises ModelError naming the option or key."""
    import cablecasing_core as cc

    if model is not None:
        model_files(model)
    if out.suffix != ".fmu":
        raise cc.ModelError("--output", str(out), "must end in .fmu")
    if out.exists() and not out.is_file():
        raise cc.ModelError("--output", str(out), "must be a regular file or none yet (it is a folder or a device)")


def build(out, model_file=None):
    """Write the FMU to ``out``: of the built-in specimen, or built for ``model_file`` (a TOML
    path: its channels, outputs and parameters; see the module docstring). Returns the path."""
    from pythonfmu.builder import FmuBuilder

    from cablecasing_core.files import atomic_path

    out = Path(out).resolve()
    out.parent.mkdir(parents=True, exist_ok=True)
    model_file = Path(model_file).resolve() if model_file else None
    shipped = model_files(model_file) if model_file else {}
    srcs = sources()
    digest = hashlib.sha256()
    for p in srcs:
        digest.update(str(p.relative_to(ROOT)).encode() + b"\0" + p.read_bytes())
    for name in sorted(shipped):  # (an FMU for another model file, or none, has another GUID)
        digest.update(b"model/" + name.encode() + b"\0" + shipped[name])
    guid = str(uuid.uuid5(uuid.NAMESPACE_URL, "cablecasing-fmu:" + digest.hexdigest()))
    epoch = int(os.environ.get("SOURCE_DATE_EPOCH", max(p.stat().st_mtime for p in srcs)))
    when = datetime.datetime.fromtimestamp(epoch, datetime.timezone.utc)
    date = when.strftime("%Y-%m-%dT%H:%M:%SZ")
    zip_time = max((1980, 1, 1, 0, 0, 0), when.timetuple()[:6])

    slave_module = load_slave()
    with tempfile.TemporaryDirectory(prefix="cablecasing_fmu_") as tmp:
        tmp = Path(tmp)
        shutil.copytree(PACKAGE, tmp / "cablecasing_core", ignore=IGNORE)
        project = [tmp / "cablecasing_core", *EXTRA_RESOURCES]
        if shipped:  # resources/model/: the slave's base model (CableCasing.base_model_file)
            for name, data in shipped.items():
                (tmp / "model" / name).parent.mkdir(parents=True, exist_ok=True)
                (tmp / "model" / name).write_bytes(data)
            project.append(tmp / "model")
        doc = tmp / "documentation"
        write_documentation(doc, variable_rows(slave_module, tmp), model_file)
        raw = FmuBuilder.build_FMU(
            SLAVE,
            dest=tmp / "raw",
            project_files=project,
            documentation_folder=doc,
            canGetAndSetFMUstate=True,
            canSerializeFMUstate=True,
            canHandleVariableCommunicationStepSize=True,
            canBeInstantiatedOnlyOncePerProcess=False,
            needsExecutionTool=True,
        )
        described = slave_module.CableCasing(instance_name="units", resources=str(tmp))
        with zipfile.ZipFile(raw) as src:
            entries = {i.filename: src.read(i.filename) for i in src.infolist() if not i.is_dir()}
        entries = {k: v for k, v in entries.items() if "__pycache__" not in k}
        entries["modelDescription.xml"] = complete_description(
            entries["modelDescription.xml"],
            described.units,
            guid,
            date,
            model_file.name if model_file else None,
            described.ranges,
            real_starts(described),
        )
        if compile_native(tmp / "CableCasing.so"):
            entries["binaries/linux64/CableCasing.so"] = (tmp / "CableCasing.so").read_bytes()
        entries["resources/python-environment.txt"] = environment_record(
            guid, slave_module.CableCasing.version, model_file.name if model_file else None
        )
        entries.update(compiled_kernels(entries))
        entries["model.png"] = (doc / "geometry.png").read_bytes()
        # (written to a temporary file of its own beside it, synced and renamed: two builds at once, or one
        # stopped, never leave a partial FMU)
        with atomic_path(out) as part, zipfile.ZipFile(part, "w", zipfile.ZIP_DEFLATED) as dst:
            for name in sorted(entries):
                info = zipfile.ZipInfo(name, date_time=zip_time)
                info.compress_type = zipfile.ZIP_DEFLATED
                info.external_attr = (0o755 if name.startswith("binaries/") else 0o644) << 16
                dst.writestr(info, entries[name])
    return out


def main(argv=None):
    # (python -OO strips docstrings: __doc__ is None then)
    p = argparse.ArgumentParser(description=(__doc__ or "Build dist/CableCasing.fmu").splitlines()[0])
    p.add_argument(
        "--model",
        metavar="FILE.toml",
        help="build the FMU for this model file or built-in specimen (default, installed): its channels "
        "(excited clips), outputs (clip forces) and parameter values (default: the built-in specimen)",
    )
    p.add_argument(
        "--output",
        "--out",
        dest="out",
        metavar="PATH.fmu",
        help="FMU file to write (default: dist/CableCasing.fmu, or dist/CableCasing-<model file's stem>.fmu "
        "with --model)",
    )
    args = p.parse_args(argv)
    import warnings

    import cablecasing_core as cc

    warnings.showwarning = lambda message, *a, **k: print(f"build_fmu.py: warning: {message}", file=sys.stderr)

    model = model_path(args.model)
    default = f"CableCasing-{model.stem}.fmu" if model else "CableCasing.fmu"
    out = Path(args.out or ROOT / "dist" / default).resolve()
    try:
        check_inputs(model, out)  # (before any folder or file is created)
    except cc.CableCasingError as exc:  # bad input: one line, exit status 2 (as the command line)
        where = f"--model {args.model}: " if model is not None and getattr(exc, "key", "") != "--output" else ""
        print(f"build_fmu.py: error: {where}{exc}", file=sys.stderr)
        return 2
    out = build(out, model)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
