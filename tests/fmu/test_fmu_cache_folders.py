"""The FMU where the usual cache folder cannot be written (review AL, M1 and M2): a read-only HOME
(a service account, a container user), a read-only unpack folder, no writable folder at all. The
FMU starts, loads the machine code it ships instead of compiling it again (170 s in the review),
and says in its log which folder cannot be written and what to set; with HOME read-only it
returned NULL from fmi2Instantiate with numba's "no locator available", or compiled and blamed
"this CPU, Python and numba"."""

import importlib.util
import os
import time
from pathlib import Path

from cablecasing_core.timedomain.kernels._numba_cache import CacheChoice

ROOT = Path(__file__).resolve().parents[2]


def host_env(home):
    """The test's environment with HOME ``home`` and no other say on where caches go."""
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "XDG_CACHE_HOME")}
    env["HOME"] = str(home)
    return env


def test_a_read_only_home_caches_in_a_folder_of_the_users_own_seeded_from_the_fmu(
    fmu, tmp_path, fmu_driver, unprivileged, read_only
):
    """HOME read-only, unpack folder writable: the code's lasting copy and the kernels' cache go to
    <temp>/cablecasing-<uid>, seeded with the machine code the FMU ships, so nothing is compiled;
    the log names the folder that cannot be written and NUMBA_CACHE_DIR."""
    home = tmp_path / "home"
    home.mkdir()
    read_only(home)
    res = fmu_driver.run(tmp_path, "cache", fmu, h=1e-4, env=host_env(home), prefix=unprivileged)
    assert res["status"] == 0
    assert res["misses"] == 0 and res["run_steps_hits"] >= 1, res["log"]
    base = str(tmp_path / f"cablecasing-{os.getuid()}")  # (the driver's temporary folder is tmp_path)
    assert str(res["cache_path"]).startswith(base + "/numba/kernels-")
    assert str(res["package_file"]).startswith(base + "/fmu/")
    assert any("files copied from the FMU" in m and "(0 files" not in m for m in res["log"]), res["log"]
    said = [m for m in res["log"] if "compiled kernels" in m]
    assert len(said) == 1 and said[0].startswith("warning: "), res["log"]
    assert f"{home}/.cache/cablecasing/numba (Permission denied) cannot be written" in said[0]
    assert "NUMBA_CACHE_DIR" in said[0]


def test_a_read_only_unpack_folder_with_nothing_writable_runs_the_kernels_it_ships(
    fmu, tmp_path, fmu_driver, unprivileged, read_only
):
    """HOME, the temporary folder and the unpack folder read-only: the FMU imports its code from
    the unpack folder and loads the shipped machine code from there, read only (nothing compiled);
    both are said, with the folders that cannot be written."""
    home, tmp = tmp_path / "home", tmp_path / "tmp"
    home.mkdir()
    tmp.mkdir()
    read_only(home, tmp)
    res = fmu_driver.run(
        tmp_path, "cache", fmu, h=1e-4, env=host_env(home), prefix=unprivileged, read_only_unpack=True, tempdir=str(tmp)
    )
    assert res["status"] == 0
    assert res["misses"] == 0 and res["run_steps_hits"] >= 1, res["log"]
    shipped = os.path.join(str(res["unzip"]), "resources", "numba_cache", "kernels-")
    assert str(res["cache_path"]).startswith(shipped)
    copy = [m for m in res["log"] if "cannot write a lasting copy" in m]
    assert len(copy) == 1 and f"{home}/.cache/cablecasing/fmu: Permission denied" in copy[0], res["log"]
    said = [m for m in res["log"] if "compiled kernels" in m]
    assert len(said) == 1 and said[0].startswith("warning: no folder for the model's compiled kernels"), res["log"]
    assert f"the machine code in {res['cache_path']} is loaded" in said[0] and "NUMBA_CACHE_DIR" in said[0]


def test_the_compile_notice_says_whether_later_starts_load_what_it_compiles():
    """The notice that the kernels compile ends with what becomes of them: loaded by later starts
    from the per-user folder; from a fallback while it lasts, naming the folder that cannot be
    written; lost with the unpack folder (fmusim deletes it); or never saved. It said "this takes
    30-60 s once, later starts load them" in every case, and blamed only the CPU, Python and numba."""
    spec = importlib.util.spec_from_file_location("bridge", ROOT / "fmu_src" / "cablecasing_fmi2_bridge.py")
    bridge = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bridge)
    ro = [("/home/u/.cache/cablecasing/numba", "Permission denied")]
    resources = "/tmp/fmu/resources"

    def fate(folder, mode, preferred, tried):
        return bridge._compile_fate(CacheChoice(folder, mode, preferred, tried), [folder or ""], resources)

    assert fate("/home/u/.cache/cablecasing/numba/kernels-1", "write", True, []) == (
        "and later starts load them from /home/u/.cache/cablecasing/numba/kernels-1"
    )
    fallback = fate("/tmp/cablecasing-1/numba/kernels-1", "write", False, ro)
    assert "later starts load them from /tmp/cablecasing-1/numba/kernels-1 while it lasts" in fallback
    assert "/home/u/.cache/cablecasing/numba (Permission denied) cannot be written" in fallback
    unpacked = fate(resources + "/numba_cache/kernels-1", "write", False, ro)
    assert "saved in the unpack folder" in unpacked and "compiles them again at every start" in unpacked
    assert "(Permission denied)" in unpacked and "NUMBA_CACHE_DIR" in unpacked
    for mode, folder in (("read", resources + "/numba_cache/kernels-1"), ("none", None)):
        never = fate(folder, mode, False, ro)
        assert "every start compiles them again: nothing can be saved" in never, mode
        assert "(Permission denied) cannot be written" in never and "NUMBA_CACHE_DIR" in never


def test_copies_of_the_fmus_code_unused_for_weeks_are_deleted_but_never_one_in_use(tmp_path):
    """<cache>/fmu holds one copy of the FMU's code per GUID (review AL, L5: 224 copies, 487 MB on
    the project's machine). A load deletes the copies whose last use (their marker's mtime, renewed
    at each load) is older than PRUNE_AFTER_DAYS, unless a process holds them (a shared lock on the
    marker for as long as it has the FMU loaded), and copies stopped half-way more than a day ago."""
    spec = importlib.util.spec_from_file_location("bridge", ROOT / "fmu_src" / "cablecasing_fmi2_bridge.py")
    bridge = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bridge)
    root = tmp_path / "fmu"
    old = time.time() - (bridge.PRUNE_AFTER_DAYS + 1) * 86400
    for name in ("unused", "recent", "held", "mine", "older_fmu"):
        (root / name / "cablecasing_core").mkdir(parents=True)
        # (an FMU built before the copies were locked wrote an empty marker: it may be in use unlocked)
        (root / name / ".complete").write_bytes(b"" if name == "older_fmu" else bridge.LOCKED_MARK)
        if name != "recent":
            os.utime(root / name / ".complete", (old, old))
    # copies stopped half-way (or a prune's renamed copy) two days ago go; one another process is writing now (its
    # folder's mtime renewed by each entry it adds, .complete the last) stays: the age, not a lock, guards it
    for name, when in ((".half.abc.tmp", old), (".g.456.old", time.time() - 2 * 86400), (".g.123.tmp", None)):
        (root / name / "cablecasing_core").mkdir(parents=True)
        if when is not None:
            os.utime(root / name, (when, when))
    assert bridge._hold(str(root / "held"))  # (as another process that has that FMU loaded)
    assert time.time() - (root / "held" / ".complete").stat().st_mtime < 60  # (its last use: now)
    os.utime(root / "held" / ".complete", (old, old))
    try:
        bridge._prune_copies(str(root), "mine")
        assert sorted(p.name for p in root.iterdir()) == [".g.123.tmp", "held", "mine", "older_fmu", "recent"]
    finally:
        for fd in bridge._HELD:
            os.close(fd)


def test_a_copy_is_written_with_the_lock_aware_marker_and_a_filesystem_without_locks_is_not_waited_on(
    tmp_path, monkeypatch
):
    """A copy the bridge writes carries LOCKED_MARK (the prune takes only such copies); _hold retries
    the shared lock only while a prune holds its exclusive one (EWOULDBLOCK): on a filesystem without
    flock (ENOLCK, EOPNOTSUPP: some FUSE mounts) it tried 200 times, 2 s, at every first start."""
    import errno
    import fcntl

    spec = importlib.util.spec_from_file_location("bridge", ROOT / "fmu_src" / "cablecasing_fmi2_bridge.py")
    bridge = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bridge)
    resources = tmp_path / "resources"
    (resources / "pkg").mkdir(parents=True)
    (resources / "pkg" / "a.py").write_text("x = 1\n")
    calls = []

    def no_locks(fd, op):
        calls.append(op)
        raise OSError(errno.ENOLCK, "No locks available")

    monkeypatch.setattr(fcntl, "flock", no_locks)
    try:
        dest, tried = bridge._stable_copy(str(resources), "guid", ["pkg"], iter([(str(tmp_path / "base"), None)]))
        assert dest == str(tmp_path / "base" / "fmu" / "guid") and tried == []
        assert (Path(dest) / ".complete").read_bytes() == bridge.LOCKED_MARK
        assert (Path(dest) / "pkg" / "a.py").read_text() == "x = 1\n"
        assert calls == [fcntl.LOCK_SH | fcntl.LOCK_NB]  # (one try: no retry on ENOLCK)
    finally:
        for fd in bridge._HELD:
            os.close(fd)
