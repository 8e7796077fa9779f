"""Where the kernels' machine code goes when the usual folder cannot be written (review AL, M1 and
L4): a read-only installation used with a read-only HOME (a service account, a container user)
falls back to a folder of the user's own in the temporary folder; with no writable folder at all
the kernels load what a read-only cache holds and compile the rest without saving, or compile
uncached; each case warns once, naming the folders and NUMBA_CACHE_DIR. numba's "cannot cache
function ...: no locator available" was an internal error of every time-domain command.

Each case runs in a process of its own (the folder is chosen once per process, when the kernels
are imported), from a read-only copy of the package, without the superuser's permission override
(``unprivileged``)."""

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

import cablecasing_core as cc
from cablecasing_core.timedomain.kernels import _numba_cache, kernels_cache_dir

ROOT = Path(__file__).resolve().parents[2]

# Runs the command line (arguments after the first two), then calls a kernel no run has compiled
# (hermite_cubics: numba compiles it and tries to save it), and prints what numba did.
SCRIPT = """
import json, sys, tempfile
if sys.argv[1]:
    tempfile.tempdir = sys.argv[1]  # (the temporary folder of this process, as TMPDIR would give it)
from cablecasing_core.cli import main
status = main(sys.argv[2:]) if sys.argv[2:] else 0
from cablecasing_core.timedomain.kernels import _hermite_interpolation as h, run_steps, _numba_cache
h.hermite_cubics(0.5)
count = lambda counter: sum(counter.values())
print(json.dumps({
    "status": status, "mode": _numba_cache.cache_choice().mode, "folder": _numba_cache.kernels_cache_dir(),
    "run_steps_hits": count(run_steps.stats.cache_hits), "run_steps_misses": count(run_steps.stats.cache_misses),
    "cubics_misses": count(h.hermite_cubics.stats.cache_misses), "cubics_path": h.hermite_cubics.stats.cache_path,
}))
"""
SIMULATE = ["simulate", "--duration", "0.002", "--out", "r.csv", "--no-progress"]


@pytest.fixture(scope="module")
def warm_kernels():
    """The folder of this process's kernels cache after a short simulation of the built-in specimen
    (compiled now if it was not cached): a copy of it spares a case's process the compilation."""
    cc.simulate(cc.load_model(), duration=0.002)
    return Path(kernels_cache_dir())


@pytest.fixture
def installed(tmp_path):
    """A read-only copy of the package (as a system-wide installation), a read-only HOME and a
    working folder: (the folder to put on PYTHONPATH, HOME, the working folder)."""
    site = tmp_path / "site"
    shutil.copytree(ROOT / "cablecasing_core", site / "cablecasing_core", ignore=shutil.ignore_patterns("__pycache__"))
    home, cwd = tmp_path / "home", tmp_path / "work"
    home.mkdir()
    cwd.mkdir()
    return site, home, cwd


def run(prefix, site, home, cwd, tempdir, args, env=None):
    """SCRIPT in a fresh process with only PATH, HOME and PYTHONPATH (the package's copy) set;
    returns (its answer, its stderr)."""
    base = {"PATH": "/usr/bin:/bin", "HOME": str(home), "PYTHONPATH": str(site), **(env or {})}
    proc = subprocess.run(
        [*prefix, sys.executable, "-c", SCRIPT, str(tempdir or ""), *args],
        env=base,
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1]), proc.stderr


def warnings_of(stderr):
    return [line for line in stderr.splitlines() if "compiled kernels" in line]


def test_a_read_only_installation_and_home_cache_the_kernels_in_a_temporary_folder_of_the_users_own(
    installed, warm_kernels, read_only, unprivileged, tmp_path
):
    """The review's case: read-only package, read-only HOME, no NUMBA_CACHE_DIR. The command runs
    (status 0), says once that ~/.cache/cablecasing/numba cannot be written and where the machine
    code goes, <TMPDIR>/cablecasing-<uid>/numba (created 0700), and loads it from there: seeded
    here with this process's cache, the run compiles nothing."""
    site, home, cwd = installed
    tmp = tmp_path / "tmp"
    folder = tmp / f"cablecasing-{os.getuid()}" / "numba" / warm_kernels.name
    shutil.copytree(warm_kernels, folder)
    os.chmod(tmp / f"cablecasing-{os.getuid()}", 0o700)
    read_only(site, home)
    said, stderr = run(unprivileged, site, home, cwd, None, SIMULATE, env={"TMPDIR": str(tmp)})
    assert said["status"] == 0 and (cwd / "r.csv").is_file()
    assert said["mode"] == "write" and said["folder"] == str(folder)
    assert said["run_steps_hits"] >= 1 and said["run_steps_misses"] == 0  # (loaded: the seeded machine code)
    assert said["cubics_path"] == str(folder)  # (and saved there:)
    assert any(p.name.startswith("_hermite_interpolation.hermite_cubics") for p in folder.iterdir())
    (line,) = warnings_of(stderr)
    assert line.startswith("cablecasing: warning: the model's compiled kernels are cached in " + str(folder))
    assert f"{home}/.cache/cablecasing/numba (Permission denied) cannot be written" in line
    assert "NUMBA_CACHE_DIR" in line


def test_with_no_writable_folder_the_kernels_load_a_read_only_cache_and_save_nothing(
    installed, warm_kernels, read_only, unprivileged, tmp_path
):
    """Nothing writable (HOME, the temporary folder, NUMBA_CACHE_DIR), but a full cache in the
    read-only HOME (an image prepared in advance): the run loads it, a kernel it lacks is compiled
    and not saved (numba's save would raise on the read-only folder), and the warning says so."""
    site, home, cwd = installed
    folder = home / ".cache" / "cablecasing" / "numba" / warm_kernels.name
    shutil.copytree(warm_kernels, folder, ignore=shutil.ignore_patterns("_hermite_interpolation.hermite_cubics*"))
    (tmp_path / "tmp").mkdir()
    (tmp_path / "numba").mkdir()
    read_only(site, home, tmp_path / "tmp", tmp_path / "numba")
    before = sorted(p.name for p in folder.iterdir())
    said, stderr = run(
        unprivileged, site, home, cwd, tmp_path / "tmp", SIMULATE, env={"NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    )
    assert said["status"] == 0 and (cwd / "r.csv").is_file()
    assert said["mode"] == "read" and said["folder"] == str(folder)
    assert said["run_steps_hits"] >= 1 and said["run_steps_misses"] == 0
    assert said["cubics_misses"] == 1  # compiled, and not saved:
    assert sorted(p.name for p in folder.iterdir()) == before
    (line,) = warnings_of(stderr)
    assert f"NUMBA_CACHE_DIR={tmp_path / 'numba'} (Permission denied)" in line
    assert f"{tmp_path / 'tmp'}/cablecasing-{os.getuid()} (Permission denied)" in line
    assert f"the machine code in {folder} is loaded" in line and "set NUMBA_CACHE_DIR to a writable folder" in line


def test_with_no_folder_at_all_the_kernels_compile_uncached(installed, read_only, unprivileged, tmp_path):
    """Nothing writable and no cache anywhere: a kernel compiles without a cache (no "no locator
    available" error), and the warning says that every process compiles."""
    site, home, cwd = installed
    (tmp_path / "tmp").mkdir()
    read_only(site, home, tmp_path / "tmp")
    said, stderr = run(unprivileged, site, home, cwd, tmp_path / "tmp", [])
    assert said["mode"] == "none" and said["folder"] is None
    assert said["cubics_misses"] == 1 and said["cubics_path"] is None
    (line,) = warnings_of(stderr)
    assert "no folder for the model's compiled kernels can be written" in line
    assert f"{home}/.cache/cablecasing/numba (Permission denied)" in line and "compiled in every process" in line


def test_the_users_cache_folder_follows_xdg_cache_home_with_or_without_platformdirs(monkeypatch, tmp_path):
    """XDG_CACHE_HOME places the caches whether platformdirs is installed or not (without it, it was
    ignored: review AL, L4); with it, the folder is platformdirs' own. The FMU's bridge takes the
    rule from this same file (its cache_bases), so the two agree by construction."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setitem(sys.modules, "platformdirs", None)  # (import platformdirs raises ImportError)
    assert _numba_cache.user_cache_base() == str(tmp_path / "xdg" / "cablecasing")
    monkeypatch.setenv("XDG_CACHE_HOME", "  ")  # (blank: as unset, platformdirs' rule)
    assert _numba_cache.user_cache_base() == os.path.join(os.path.expanduser("~"), ".cache", "cablecasing")
    monkeypatch.delitem(sys.modules, "platformdirs")
    platformdirs = pytest.importorskip("platformdirs")
    if sys.platform.startswith("linux"):
        for value in (str(tmp_path / "xdg"), ""):
            monkeypatch.setenv("XDG_CACHE_HOME", value)
            assert _numba_cache.user_cache_base() == platformdirs.user_cache_dir("cablecasing", appauthor=False)

    import importlib.util

    spec = importlib.util.spec_from_file_location("bridge", ROOT / "fmu_src" / "cablecasing_fmi2_bridge.py")
    bridge = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bridge)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setitem(sys.modules, "platformdirs", None)
    assert next(bridge._cache_module(str(ROOT)).cache_bases()) == (str(tmp_path / "xdg" / "cablecasing"), None)


def test_the_temporary_fallback_is_used_only_when_it_is_the_users_own(monkeypatch, tmp_path):
    """<temp>/cablecasing-<uid> is created 0700; one that others or its group may write, or a link, is refused
    with its reason (numba loads its machine code with pickle: a folder another user can write
    would run their code)."""
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    base = tmp_path / f"cablecasing-{os.getuid()}"
    assert list(_numba_cache.cache_bases())[1] == (str(base), None)
    assert base.stat().st_mode & 0o777 == 0o700
    for mode in (0o777, 0o775, 0o770, 0o720):  # (others, or the group alone, may write: refused alike)
        base.chmod(mode)
        where, why = list(_numba_cache.cache_bases())[1]
        assert where == str(base) and why is not None and "not this user's own" in why, oct(mode)
    base.chmod(0o755)  # (others may read it, not write it: taken)
    assert list(_numba_cache.cache_bases())[1] == (str(base), None)
    base.rmdir()
    (tmp_path / "elsewhere").mkdir()
    base.symlink_to(tmp_path / "elsewhere")
    assert "is not a folder" in list(_numba_cache.cache_bases())[1][1]


def test_the_temporary_fallback_is_never_the_working_folder_nor_in_a_folder_others_may_rename_it_from(
    monkeypatch, tmp_path
):
    """Review AO, M2: with no usable temporary folder, tempfile.gettempdir() gives the working
    folder, and the caches (pickled machine code, the FMU's imported copy of its code) went to
    <cwd>/cablecasing-<uid>. And in a temporary folder others may write without the sticky bit,
    another user can rename this user's checked folder away and put their own in its place. Both
    are refused, with the reason; a sticky folder, or one only its owner may write, is taken."""
    uid = os.getuid()
    for name in ("TMPDIR", "TEMP", "TMP"):
        monkeypatch.delenv(name, raising=False)
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    monkeypatch.setattr(tempfile, "tempdir", str(work))  # (what gettempdir() gives when no temp folder works)
    where, why = list(_numba_cache.cache_bases())[1]
    assert where == str(work / f"cablecasing-{uid}") and "is the working folder" in why
    assert not (work / f"cablecasing-{uid}").exists()
    shared = tmp_path / "shared"
    shared.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(shared))
    for mode, refused in ((0o777, True), (0o775, True), (0o1777, False), (0o755, False)):
        shared.chmod(mode)
        where, why = list(_numba_cache.cache_bases())[1]
        assert where == str(shared / f"cablecasing-{uid}"), mode
        assert (why is not None and "neither sticky nor writable by its owner alone" in why) == refused, (mode, why)
        assert (shared / f"cablecasing-{uid}").is_dir() != refused, mode
        if not refused:
            (shared / f"cablecasing-{uid}").rmdir()
    if uid == 0:  # (a folder of another user's, only its owner may write: that user could rename ours away)
        os.chown(shared, 65534, 65534)
        why = list(_numba_cache.cache_bases())[1][1]
        assert why is not None and "neither sticky nor writable by its owner alone" in why


def test_the_temporary_folder_is_created_only_when_the_folders_before_it_fail(monkeypatch, tmp_path):
    """Review AO, L1: every process created <temp>/cablecasing-<uid> (empty), even with a writable
    per-user cache folder or NUMBA_CACHE_DIR. The folders are offered one at a time, the temporary
    one checked and created only when asked for."""
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setitem(sys.modules, "platformdirs", None)
    base = tmp_path / f"cablecasing-{os.getuid()}"
    bases = _numba_cache.cache_bases()
    assert next(bases) == (str(tmp_path / "xdg" / "cablecasing"), None) and not base.exists()
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "numba"))
    roots = _numba_cache.cache_roots()
    assert next(roots) == (str(tmp_path / "numba"), None) and next(roots)[0] == str(
        tmp_path / "xdg" / "cablecasing" / "numba"
    )
    assert not base.exists()
    assert next(roots) == (str(base / "numba"), None) and base.is_dir()


def test_a_read_only_cache_of_the_kernels_seeds_the_writable_folder_used_after_it(
    installed, warm_kernels, read_only, unprivileged, tmp_path
):
    """Review AO, M1: a read-only HOME holding a full cache (a container image warmed in advance)
    and a writable, empty temporary folder: the machine code was compiled again into the temporary
    folder (54 s), the baked one ignored. Now the temporary folder is seeded from it: nothing is
    compiled, and what is compiled later is saved there."""
    site, home, cwd = installed
    baked = home / ".cache" / "cablecasing" / "numba" / warm_kernels.name
    shutil.copytree(warm_kernels, baked, ignore=shutil.ignore_patterns("_hermite_interpolation.hermite_cubics*"))
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    read_only(site, home)
    said, stderr = run(unprivileged, site, home, cwd, None, SIMULATE, env={"TMPDIR": str(tmp)})
    folder = tmp / f"cablecasing-{os.getuid()}" / "numba" / warm_kernels.name
    assert said["status"] == 0 and said["mode"] == "write" and said["folder"] == str(folder)
    assert said["run_steps_hits"] >= 1 and said["run_steps_misses"] == 0  # (the baked machine code, copied)
    assert said["cubics_misses"] == 1 and said["cubics_path"] == str(folder)  # (not baked: compiled, saved here)
    assert {p.name for p in baked.iterdir()} <= {p.name for p in folder.iterdir()}
    (line,) = warnings_of(stderr)
    assert f"cached in {folder}" in line


def test_seeding_never_pairs_a_cache_index_with_another_caches_machine_code(tmp_path):
    """Review AP, N3: numba's data files (.nbc) hold no key: its index (.nbi) says which file holds the machine
    code of which signature, numbered in the order they were compiled. So a seed copies a function's index together
    with its data files, the index last, and only where the target has no index of that function: an index of the
    target's own (newer kernels compiled since) is kept, and a data file it lacks (a save cut between index and
    data) is not filled with another cache's code of that number; data files with no index (orphans) are replaced."""
    src, dst = tmp_path / "src", tmp_path / "dst"
    src.mkdir()
    dst.mkdir()
    for name in ("k.nbi", "k.1.nbc", "k.2.nbc", "m.nbi", "m.1.nbc", "other.txt"):
        (src / name).write_bytes(b"shipped " + name.encode())
    (dst / "k.nbi").write_bytes(b"own index")  # (refers to k.1.nbc, k.2.nbc and a k.3.nbc the seed lacks)
    (dst / "k.1.nbc").write_bytes(b"own code")
    (dst / "m.1.nbc").write_bytes(b"orphan")  # (no index refers to it)
    assert _numba_cache.seed_cache(str(src), str(dst)) == 2  # (m.nbi and m.1.nbc)
    got = {p.name: p.read_bytes() for p in dst.iterdir()}
    assert got == {
        "k.nbi": b"own index",
        "k.1.nbc": b"own code",
        "m.nbi": b"shipped m.nbi",
        "m.1.nbc": b"shipped m.1.nbc",
    }, got
    assert _numba_cache.seed_cache(str(src), str(dst)) == 0  # (seeded: nothing more to copy)
