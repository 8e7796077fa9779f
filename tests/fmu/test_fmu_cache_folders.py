"""The FMU where the usual cache folder cannot be written (review AL, M1): a read-only HOME (a
service account, a container user). The FMU starts, loads the machine code it ships, and says in
its log which folder cannot be written and what to set; with HOME read-only it returned NULL from
fmi2Instantiate with numba's "no locator available", or compiled every kernel."""

import os


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
