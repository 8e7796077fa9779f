"""Build dist/CableCasing.fmu from fmu_src/ with pythonfmu, then complete its model description.

pythonfmu writes the variables, the co-simulation flags and the Outputs; this script adds what it
does not: units with UnitDefinitions, InitialUnknowns, the documentation (index.html,
externalDependencies.txt) and model.png. The package cablecasing_core goes into resources/.

Usage: python build_fmu.py [--out dist]
"""
import argparse
import shutil
import sys
import tempfile
import zipfile
from pathlib import Path
from xml.etree import ElementTree as ET

ROOT = Path(__file__).resolve().parent
UNITS = {  # unit name -> SI base exponents (kg, m, s)
    "m": dict(m=1), "m/s": dict(m=1, s=-1), "m/s2": dict(m=1, s=-2), "N": dict(kg=1, m=1, s=-2),
    "N.m": dict(kg=1, m=2, s=-2), "J": dict(kg=1, m=2, s=-2), "s": dict(s=1), "Pa": dict(kg=1, m=-1, s=-2),
    "kg/m3": dict(kg=1, m=-3), "kg/s": dict(kg=1, s=-1), "N/m": dict(kg=1, s=-2), "m4": dict(m=4),
    "1/s": dict(s=-1), "Hz": dict(s=-1), "1": {},
}


def unit_of(name):
    """SI unit of a variable, from its name."""
    last = name.split(".")[-1]
    if name.startswith(("casing.", "cable.")) and len(name.split(".")) == 3 and name.split(".")[1] in "AB":
        if last in ("Fx", "Fy", "Fz"):
            return "N"
        if last in ("Mx", "My", "Mz"):
            return "N.m"
        return {"v": "m/s", "a": "m/s2"}.get(last[0] if len(last) == 2 else "", "m")
    table = {"E": "Pa", "rho": "kg/m3", "d": "m", "d_outer": "m", "d_inner": "m", "I": "m4", "alpha": "1/s",
             "beta": "s", "stiffness": "N/m", "damping": "kg/s", "stick_velocity": "m/s", "dt": "s",
             "duration": "s", "ramp": "s", "rms": "m/s2", "frequency": "Hz", "amplitude": "m", "width": "s",
             "start": "s", "max_penetration": "m", "dissipated_energy": "J"}
    return table.get(last, "1")


def complete_description(xml_bytes):
    root = ET.fromstring(xml_bytes)
    units = set()
    mv = root.find("ModelVariables")
    for sv in mv.findall("ScalarVariable"):
        real = sv.find("Real")
        if real is not None:
            u = unit_of(sv.get("name"))
            real.set("unit", u)
            units.add(u)
    ud = ET.Element("UnitDefinitions")
    for u in sorted(units):
        e = ET.SubElement(ud, "Unit", name=u)
        if UNITS[u]:
            ET.SubElement(e, "BaseUnit", **{k: str(v) for k, v in UNITS[u].items()})
    # UnitDefinitions comes before LogCategories / DefaultExperiment / ModelVariables
    kids = list(root)
    pos = next(i for i, k in enumerate(kids) if k.tag in ("LogCategories", "DefaultExperiment", "ModelVariables"))
    root.insert(pos, ud)
    ms = root.find("ModelStructure")
    outputs = ms.find("Outputs")
    if outputs is not None and ms.find("InitialUnknowns") is None:
        ini = ET.SubElement(ms, "InitialUnknowns")
        for u in outputs.findall("Unknown"):
            ET.SubElement(ini, "Unknown", index=u.get("index"))
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)


def documentation(folder, variables):
    import cablecasing_core as cc
    from cablecasing_core.geometry import centerline_of
    from cablecasing_core.plotting import plot_geometry

    folder.mkdir(parents=True, exist_ok=True)
    plot_geometry(centerline_of(cc.load_model()), folder / "geometry.png")
    rows = "\n".join(f"<tr><td>{n}</td><td>{c}</td><td>{t}</td><td>{unit_of(n)}</td><td>{d}</td></tr>"
                     for n, c, t, d in variables)
    (folder / "index.html").write_text(f"""<!doctype html><html><head><meta charset="utf-8"><title>CableCasing FMU</title></head><body>
<h1>CableCasing</h1>
<p>Vibration model of a gear-shift cable sliding in a curved casing (Otrin and Boltezar): both bodies are
spatially curved 3D Euler-Bernoulli beams (12-DOF elements) clamped at supports that move with the inputs;
Newmark (average acceleration) time integration; contact across the radial gap by the penalty method (Hertz
law), contact damping while compressing, Coulomb friction with stick-slip. SI units.</p>
<h2>Sign conventions</h2>
<p>Inputs are support displacements (m), velocities (m/s) and accelerations (m/s2) in global axes; support
rotations are held at zero. Outputs are the force (N) and moment (N.m) that each body exerts <em>on</em> its
support, in global axes (the negative of the reaction acting on the body). Inside a communication step the
support motion is a quintic Hermite from the state reached at the step start to the Taylor extrapolation
u + v h + a h^2/2 of the inputs; connect velocity and acceleration for accuracy.</p>
<h2>Default geometry</h2><img src="geometry.png" alt="centerline of the built-in specimen">
<h2>Variables</h2><table border="1"><tr><th>name</th><th>causality</th><th>type</th><th>unit</th><th>description</th></tr>
{rows}</table></body></html>""")
    (folder / "externalDependencies.txt").write_text(
        "This FMU runs Python code (pythonfmu). The host needs:\n"
        f"- CPython {sys.version_info.major}.{sys.version_info.minor} (the version the FMU was built with; "
        "the binary links against its libpython)\n"
        "- the packages numpy, scipy and numba installed in that Python environment\n"
        "The model package cablecasing_core is inside resources/.\n\n"
        "Loading from a non-Python host (e.g. a C/C++ or Java FMI importer): make the Python shared library\n"
        "findable (LD_LIBRARY_PATH on Linux, PATH on Windows) and set PYTHONHOME/PYTHONPATH to the environment\n"
        "that holds numpy, scipy and numba; then load the FMU like any other. The first instantiation compiles\n"
        "the numba kernels into NUMBA_CACHE_DIR (default ~/.cache/cablecasing/numba); later ones reuse them.\n")


def build(out_dir):
    from pythonfmu.builder import FmuBuilder

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        pkg = Path(tmp) / "cablecasing_core"
        shutil.copytree(ROOT / "cablecasing_core", pkg, ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
        sys.path.insert(0, str(ROOT / "fmu_src"))
        from CableCasing import CableCasing  # noqa: E402  (only to list the variables for the docs)

        slave = CableCasing(instance_name="doc")
        variables = [(v.name, v.causality.name, type(v).__name__, v.description or "") for v in slave.vars.values()]
        doc = Path(tmp) / "documentation"
        documentation(doc, variables)
        fmu = FmuBuilder.build_FMU(ROOT / "fmu_src" / "CableCasing.py", dest=out_dir, project_files=[pkg],
                                   documentation_folder=doc, canGetAndSetFMUstate=True, canSerializeFMUstate=True)
        # rewrite the archive with the completed description and model.png
        tmp_fmu = Path(tmp) / "fmu.zip"
        with zipfile.ZipFile(fmu) as src, zipfile.ZipFile(tmp_fmu, "w", zipfile.ZIP_DEFLATED) as dst:
            for item in src.infolist():
                data = src.read(item.filename)
                if item.filename == "modelDescription.xml":
                    data = complete_description(data)
                dst.writestr(item.filename, data)
            dst.write(doc / "geometry.png", "model.png")
        shutil.copy(tmp_fmu, fmu)
    return fmu


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--out", default=str(ROOT / "dist"))
    print(f"wrote {build(p.parse_args().out)}")
