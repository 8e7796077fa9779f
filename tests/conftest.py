"""Fixtures shared by the tests: beam models with closed-form answers, and the built FMU.

Tests take what they share from here as fixtures (no module of the tests imports another: pytest
runs with ``--import-mode=importlib``). Areas: model/, frequency/, timedomain/, identification/, docs/,
studies/, fmu/, cli/, benchmarks/. Tests that take more than a few seconds on a warm numba cache, or start
processes (the FMU, dask clusters, the demo), are marked ``slow``; ``make test-fast`` leaves them out.
"""

import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

from cablecasing_core import model_from_dict

ROOT = Path(__file__).resolve().parent.parent
STEEL = dict(E=2.1e11, nu=0.3, rho=7850.0)  # Pa, -, kg/m3: the beams' material


@pytest.fixture(scope="session", autouse=True)
def temporary_files_under_pytests_own_folder(tmp_path_factory):
    """Every temporary file of the run, in this process and in the processes it starts that keep
    its environment, goes below pytest's own temporary folder (which pytest prunes to the last three
    runs), not /tmp: fmpy's ``extract`` makes a folder it never removes, and its ``simulate_fmu``
    removes its unpack folder only when the run does not raise (~11 MB of FMU each; about 54 per run
    of the suite were left in /tmp). The C hosts' plain environment does not keep it; they leave
    nothing behind."""
    folder = tmp_path_factory.mktemp("tmpdir")
    saved_env, saved_tempdir = os.environ.get("TMPDIR"), tempfile.tempdir
    os.environ["TMPDIR"], tempfile.tempdir = str(folder), str(folder)
    yield folder
    tempfile.tempdir = saved_tempdir
    if saved_env is None:
        os.environ.pop("TMPDIR", None)
    else:
        os.environ["TMPDIR"] = saved_env


@pytest.fixture
def unprivileged():
    """The command prefix that starts a process for which a folder made read-only (``chmod a-w``)
    is read-only: [] for an ordinary user; for root (who writes anywhere), setpriv without the
    capabilities that override file permissions. The test is skipped when root has no setpriv."""
    if not hasattr(os, "geteuid") or os.geteuid() != 0:
        return []
    setpriv = shutil.which("setpriv")
    if setpriv is None:
        pytest.skip("running as root without setpriv: a read-only folder would still be writable to the process")
    return [setpriv, "--bounding-set=-dac_override,-dac_read_search", "--"]


@pytest.fixture
def read_only():
    """``read_only(*paths)``: the folders (and all below them) made read-only (``chmod a-w``); made
    writable for their owner again after the test, so that pytest can remove them."""
    done = []

    def chmod(*paths):
        for path in paths:
            walked = list(os.walk(path))
            for root, _, files in walked:
                for name in files:
                    os.chmod(os.path.join(root, name), os.stat(os.path.join(root, name)).st_mode & ~0o222)
            for root, _, _ in reversed(walked):  # (a folder after what is in it)
                os.chmod(root, os.stat(root).st_mode & ~0o222)
            done.append(path)

    yield chmod
    for path in done:
        for root, _, files in os.walk(path):
            os.chmod(root, os.stat(root).st_mode | 0o200)
            for name in files:
                os.chmod(os.path.join(root, name), os.stat(os.path.join(root, name)).st_mode | 0o200)


@pytest.fixture(autouse=True)
def a_process_that_said_no_model_warning_yet(monkeypatch):
    """Each test sees the model's warnings as a fresh process would: a model's own warnings are said
    once per process (errors.warn_once_per_process), and a test that runs a command in this process
    would otherwise not hear a warning another test's model said before it."""
    from cablecasing_core import errors

    monkeypatch.setattr(errors, "_SAID_ONCE", set())


@pytest.fixture(scope="session")
def beam_model():
    """``beam_model(points, n_elements, d=0.01, supports=("clamped", "free"), curve="polyline",
    **material)``: a cable-only model (solid circular section of diameter d, m; steel unless
    ``material`` says otherwise: E Pa, nu, rho kg/m3, alpha, beta, loss_factor) along ``points`` (m)."""

    def build(points, n_elements, d=0.01, supports=("clamped", "free"), curve="polyline", **material):
        body = dict(STEEL, d=d, alpha=0.0, beta=0.0, loss_factor=0.0, supports={"A": supports[0], "B": supports[1]})
        body.update(material)
        return model_from_dict(
            {
                "geometry": {"points": [list(map(float, p)) for p in points], "n_elements": n_elements, "curve": curve},
                "cable": body,
            }
        )

    return build


@pytest.fixture(scope="session")
def straight(beam_model):
    """``straight(L=1.0, n=40, **kw)``: a straight beam_model along x, L in m, n elements."""

    def build(L=1.0, n=40, **kw):
        return beam_model([[0, 0, 0], [L, 0, 0]], n, **kw)

    return build


@pytest.fixture(scope="session")
def arc_points():
    """``arc_points(R, theta, n)``: n+1 points on a circular arc of radius R (m) and opening angle
    theta (rad) in the x-y plane."""

    def points(R, theta, n):
        a = np.linspace(0.0, theta, n + 1)
        return np.column_stack([R * np.sin(a), R * (1 - np.cos(a)), np.zeros_like(a)])

    return points


@pytest.fixture
def paper_bodies():
    """``{"casing": {...}, "cable": {...}}``: the two bodies' materials as a model file's tables (fresh
    copies, to change freely), without damping but for the loss factors. The casing's section is the
    paper's Table 2 (I = 2.7261e-10 m4, rho = 4850 kg/m3, d_2 = 0.0095 m outer, d_5 = 0.004 m inner),
    E = 5 GPa, nu 0.3, loss factor 0.05; the cable a 3 mm steel wire, E = 55 GPa, rho = 7850 kg/m3,
    nu 0.3, loss factor 0.02 (the built-in specimen's moduli)."""
    undamped = {"alpha": 0.0, "beta": 0.0}
    return {
        "casing": {"E": 5e9, "nu": 0.3, "rho": 4850.0, **undamped, "loss_factor": 0.05, "d_outer": 0.0095,
                   "d_inner": 0.004, "I": 2.7261e-10},
        "cable": {"E": 5.5e10, "nu": 0.3, "rho": 7850.0, "d": 0.003, **undamped, "loss_factor": 0.02},
    }  # fmt: skip


@pytest.fixture(scope="session")
def drive_casing_b_120hz():
    """``drive_casing_b_120hz(n, h=1e-4)``: an FMU's input table (n, 3 x len(CHANNELS)), the rows at
    t = k h (s), k = 0..n-1: casing end B moving in y as 2e-5 sin(2 pi 120 t) m, with its velocity
    (m/s) and acceleration (m/s2) in the second and third blocks of columns, every other input 0;
    zero displacement at t = 0."""
    from cablecasing_core.model.schema import CHANNELS

    def table(n, h=1e-4):
        t = h * np.arange(n)
        w = 2 * np.pi * 120.0
        out = np.zeros((n, 3 * len(CHANNELS)))
        c = CHANNELS.index("casing.B.y")
        out[:, c] = 2e-5 * np.sin(w * t)
        out[:, len(CHANNELS) + c] = 2e-5 * w * np.cos(w * t)
        out[:, 2 * len(CHANNELS) + c] = -2e-5 * w * w * np.sin(w * t)
        return out

    return table


@pytest.fixture(scope="session")
def clipped_specimen():
    """examples/clipped_specimen.toml: the built-in specimen held by two clips along its casing
    (0.30 m: fixed; 0.55 m: excited, its support the channels ``dash.x/.y/.z``), its own scenario
    also shaking ``dash.y`` (harmonic 150 Hz, 2 um), friction 0.12: a Model with 15 support
    channels and 27 + 12 outputs."""
    from cablecasing_core import load_model

    return load_model(ROOT / "examples" / "clipped_specimen.toml")


@pytest.fixture(scope="session")
def build_fmu():
    """The module build_fmu.py, imported from the checkout's root (it is not installed)."""
    sys.path.insert(0, str(ROOT))
    try:
        import build_fmu
    finally:
        sys.path.remove(str(ROOT))
    return build_fmu


@pytest.fixture(scope="session")
def fmu(build_fmu):
    """dist/CableCasing.fmu, built (in a separate process) if missing or older than any of its sources."""
    newest = max(p.stat().st_mtime for p in build_fmu.sources())
    # make test's workers (pytest-xdist) ask for it at once: one builds while the others wait on the
    # lock, then find it up to date; the demo (tests/cli/test_demo.py) builds it under the same lock
    with build_fmu.default_fmu_lock() as path:
        if not path.exists() or path.stat().st_mtime < newest:
            subprocess.run([sys.executable, str(ROOT / "build_fmu.py")], check=True, cwd=ROOT)
    return path


@pytest.fixture
def drawn(monkeypatch):
    """The figures the package draws (cablecasing_core.plotting's and nvh.plots' save_figure), kept
    open in this list instead of written, and closed after the test."""
    import matplotlib.pyplot as plt

    import cablecasing_core.nvh.plots as nvh_plots
    import cablecasing_core.plotting as plotting

    figs = []
    for module in (plotting, nvh_plots):
        monkeypatch.setattr(module, "save_figure", lambda fig, path: figs.append(fig))
    yield figs
    for fig in figs:
        plt.close(fig)
