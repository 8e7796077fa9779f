"""A kill (SIGTERM) or a closed terminal (SIGHUP) during a write stops the command line as Ctrl-C does,
a write the system fails (a full disk) is one line naming the option, not an internal error, and a
file written over keeps its permissions; in each case the previous file is bitwise intact and no
temporary part file is left behind. `pool` refuses an output that is one of its own inputs."""

import errno
import io
import os
import signal
import stat
import subprocess
import sys
import time

import numpy as np
import pytest

from cablecasing_core.cli import main

TRFAM = ["trfam", "--fmin", "10", "--fmax", "12", "--df", "1"]  # (three frequencies: quick, no time domain)


def _one_line(capsys):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


def _writes_then(monkeypatch, module, name, exc):
    """``module.name`` (a writer taking a path) writes half its file, then ``exc()`` is raised."""
    real = getattr(module, name)

    def half_then_raise(file, *args, **kwargs):
        real(file, *args, **kwargs)
        with open(file, "r+b") as fh:
            fh.truncate(max(os.path.getsize(file) // 2, 1))
        raise exc()

    monkeypatch.setattr(module, name, half_then_raise)


@pytest.mark.parametrize("name", ["SIGTERM", "SIGHUP"])
def test_a_signal_in_the_middle_of_a_write_stops_as_ctrl_c_does(tmp_path, capsys, monkeypatch, name):
    """In this process: the signal arrives while savetxt writes; the handler raises in the main thread,
    the part file is removed, the status is 128 + the signal's number, and the handlers are restored."""
    sig = getattr(signal, name)
    out = tmp_path / "t.csv"
    old = os.urandom(3000) + b"\nan earlier result\n"
    out.write_bytes(old)
    real = np.savetxt

    def signalled(file, *args, **kwargs):
        real(file, *args, **kwargs)
        os.kill(os.getpid(), sig)  # (delivered to the main thread at the next bytecode)
        time.sleep(5)
        pytest.fail("the signal did not stop the write")

    def not_main_s(signum, frame):  # (the handler before main: a command line without its own failed here)
        pytest.fail(f"{name} did not reach the command line's handler")

    monkeypatch.setattr(np, "savetxt", signalled)
    before = signal.signal(sig, not_main_s)
    try:
        assert main([*TRFAM, "--out", str(out)]) == 128 + sig
        assert signal.getsignal(sig) is not_main_s  # (restored)
    finally:
        signal.signal(sig, before)
    assert _one_line(capsys) == f"cablecasing: terminated ({name}): stopped: the previous {out} kept as it was"
    assert out.read_bytes() == old and sorted(p.name for p in tmp_path.iterdir()) == ["t.csv"]


# (run in a process of its own: savetxt writes its file, then waits for the signal in the middle of the write)
_SLOW_WRITE = """
import sys, time
import numpy as np
real = np.savetxt
def slow(file, *args, **kwargs):
    real(file, *args, **kwargs)
    time.sleep(120)
np.savetxt = slow
from cablecasing_core.cli import main
sys.exit(main(sys.argv[1:]))
"""


def _a_written_part_file(folder):
    """Whether ``folder`` holds a non-empty .part.csv. The writer's mkstemp makes an empty one and
    removes it at once, so one listed may be gone before its size is read: that one does not count."""
    for p in folder.iterdir():
        if p.name.endswith(".part.csv"):
            try:
                if p.stat().st_size > 0:
                    return True
            except FileNotFoundError:
                pass
    return False


@pytest.mark.slow
@pytest.mark.parametrize("name", ["SIGTERM", "SIGHUP"])
def test_kill_or_a_closed_terminal_during_a_write_leaves_no_part_file(tmp_path, name):
    """`kill` (SIGTERM) and a hang-up (SIGHUP) sent to the command line while its output is half
    written: one line, status 143 or 129, the earlier file intact, no hidden .t.*.part.csv left
    (it was left, tens of MB for a long record, while SIGINT removed it)."""
    sig = getattr(signal, name)
    (tmp_path / "t.csv").write_text("OLD\n")
    proc = subprocess.Popen(
        [sys.executable, "-c", _SLOW_WRITE, *TRFAM, "--out", "t.csv"],
        cwd=tmp_path,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # (its own process group: no signal of the test's terminal reaches it)
    )
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not _a_written_part_file(tmp_path):
        assert proc.poll() is None, proc.stderr.read()
        time.sleep(0.05)
    os.kill(proc.pid, sig)
    err = proc.communicate(timeout=60)[1].strip().splitlines()
    assert proc.returncode == 128 + sig, err
    assert err == [f"cablecasing: terminated ({name}): stopped: the previous t.csv kept as it was"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.csv"]
    assert (tmp_path / "t.csv").read_text() == "OLD\n"


def _full():
    return OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


@pytest.mark.parametrize("old", [True, False])
def test_a_full_disk_during_the_write_is_one_line_naming_the_option(tmp_path, capsys, monkeypatch, old):
    out = tmp_path / "t.csv"
    if old:
        out.write_bytes(b"an earlier table\n" * 100)
    _writes_then(monkeypatch, np, "savetxt", _full)
    assert main([*TRFAM, "--out", str(out)]) == 1
    kept = "the previous file is kept as it was" if old else "no file was made"
    assert _one_line(capsys) == (
        f"cablecasing: error: --out = '{out}': could not be written (No space left on device); {kept}"
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == (["t.csv"] if old else [])
    if old:
        assert out.read_bytes() == b"an earlier table\n" * 100


def _pyuff_fails_in_its_second_dataset(monkeypatch, exc):
    """pyuff writes the first dataset, then ``exc()`` is raised inside its writer of dataset 58, where
    its bare ``except:`` turns it into ``Exception("Error writing data-set #58")``."""
    from pyuff.datasets import dataset_58

    real, calls = dataset_58._opt_fields, []

    def second_fails(*args, **kwargs):
        calls.append(1)
        if len(calls) > 1:
            raise exc()
        return real(*args, **kwargs)

    monkeypatch.setattr(dataset_58, "_opt_fields", second_fails)


def _binary_writer_fails_in_its_second_dataset(monkeypatch, exc):
    """The binary writer (the command line's) writes the first dataset and half the second, then
    ``exc()`` is raised."""
    from cablecasing_core import uff

    real, calls = uff._write_58b, []

    def second_fails(fh, d):
        calls.append(1)
        if len(calls) > 1:
            fh.write(b"half a dataset")
            raise exc()
        return real(fh, d)

    monkeypatch.setattr(uff, "_write_58b", second_fails)


@pytest.mark.parametrize("exc,code", [(_full, 1), (KeyboardInterrupt, 130)])
def test_a_full_disk_or_ctrl_c_during_a_uff_write_is_not_an_internal_error(tmp_path, capsys, monkeypatch, exc, code):
    """A failed write (a full disk) of the command line's binary UFF is one line naming the option,
    a Ctrl-C an interruption; the earlier file is intact and no part file is left."""
    from cablecasing_core.identification.uff_io import Record, write_uff

    out = tmp_path / "r.uff"
    write_uff(out, [Record("time", np.arange(4.0), np.ones(4), "before")])
    old = out.read_bytes()
    _binary_writer_fails_in_its_second_dataset(monkeypatch, exc)
    assert main(["simulate", "--duration", "0.001", "--no-progress", "--out", str(out)]) == code
    line = _one_line(capsys)
    if code == 1:
        assert line == (
            f"cablecasing: error: --out = '{out}': could not be written (No space left on device); the previous "
            "file is kept as it was"
        )
    else:
        assert line == f"cablecasing: interrupted: the run was stopped: the previous {out} kept as it was"
    assert out.read_bytes() == old and sorted(p.name for p in tmp_path.iterdir()) == ["r.uff"]


@pytest.mark.parametrize("exc", [_full, KeyboardInterrupt])
def test_a_full_disk_or_ctrl_c_inside_pyuff_is_what_it_was(tmp_path, monkeypatch, exc):
    """pyuff (the ASCII form, ``binary=False``) reports a failed write and a Ctrl-C as a bare
    Exception: the cause is raised instead (a WriteError, an OSError; a KeyboardInterrupt)."""
    from cablecasing_core.files import WriteError
    from cablecasing_core.identification.uff_io import Record, write_uff

    out = tmp_path / "r.uff"
    out.write_bytes(b"OLD")
    records = [Record("time", np.arange(4.0), np.full(4, float(k)), f"r{k}") for k in range(2)]
    _pyuff_fails_in_its_second_dataset(monkeypatch, exc)
    with pytest.raises(WriteError if exc is _full else KeyboardInterrupt) as err:
        write_uff(out, records, binary=False)
    if exc is _full:
        assert err.value.errno == errno.ENOSPC and err.value.kept
    assert out.read_bytes() == b"OLD" and sorted(p.name for p in tmp_path.iterdir()) == ["r.uff"]


# (a file-size limit: the kernel refuses the write past it, EFBIG, as a full disk refuses it, with no root;
# matplotlib's font cache is built before the limit, else a fresh machine's first run fails to write it)
_LIMITED = """
import resource, signal, sys
import matplotlib.font_manager  # (its font cache, built on a fresh machine's first import, is no output of ours)
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
resource.setrlimit(resource.RLIMIT_FSIZE, (20000, 20000))
from cablecasing_core.cli import main
sys.exit(main(sys.argv[1:]))
"""


@pytest.mark.slow
@pytest.mark.parametrize("out", ["t.csv", "t.uff", "t.png"])
def test_a_write_the_kernel_refuses_is_one_line(tmp_path, out):
    flag = "--plot" if out.endswith(".png") else "--out"
    (tmp_path / out).write_bytes(b"OLD\n")
    p = subprocess.run(
        [sys.executable, "-c", _LIMITED, "trfam", flag, out], cwd=tmp_path, capture_output=True, text=True
    )
    assert p.returncode == 1 and p.stderr.strip().splitlines() == [
        f"cablecasing: error: {flag} = '{out}': could not be written (File too large); the previous file is kept "
        "as it was"
    ], p.stderr
    assert sorted(q.name for q in tmp_path.iterdir()) == [out] and (tmp_path / out).read_bytes() == b"OLD\n"


@pytest.mark.parametrize("mode", [0o600, 0o640, 0o444])
def test_a_file_written_over_keeps_its_permissions(tmp_path, capsys, mode):
    out = tmp_path / "t.csv"
    out.write_text("old\n")
    out.chmod(mode)
    assert main([*TRFAM, "--out", str(out)]) == 0
    assert stat.S_IMODE(out.stat().st_mode) == mode and out.read_text().startswith("frequency_hz,")
    new = tmp_path / "new.csv"  # (a new file: the umask's default, as any program's)
    assert main([*TRFAM, "--out", str(new)]) == 0
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(new.stat().st_mode) == 0o666 & ~umask


def _parts(tmp_path):
    from cablecasing_core.studies import Ensemble

    for k, seeds in enumerate(((1, 2), (3, 4)), 1):
        for suffix, friction in (("", {}), ("_against", {"contact.friction": 0.2})):
            levels = np.array([[0.1], [0.2]]) * (k + len(suffix))
            args = (np.array(seeds), "casing.B.Fz", ("oct1",), np.array([11.0]), np.array([22.0]), levels)
            Ensemble(*args, friction, np.zeros((2, 0)), {"duration": 1.0}).save(tmp_path / f"e{k}{suffix}.csv")
    return {p.name: p.read_bytes() for p in tmp_path.iterdir()}


@pytest.mark.parametrize(
    "argv,message",
    [
        (["e1.csv", "e2.csv", "--out", "e1.csv"], "--out = 'e1.csv': must not name an input of pool: it is a file it "),
        (["e1.csv", "e2.csv", "--out", "./e2.csv"], "--out = './e2.csv': must not name an input of pool: it is e2.csv"),
        (
            ["e2.csv", "--against", "e1_against.csv", "--out", "e1.csv"],
            "--out = 'e1.csv': must not name an input of pool: its _against twin e1_against.csv is an --against file",
        ),
    ],
)
def test_pool_refuses_an_output_that_is_one_of_its_parts(tmp_path, capsys, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    before = _parts(tmp_path)
    assert main(["pool", *argv]) == 2
    line = _one_line(capsys)
    assert line.startswith(f"cablecasing: error: {message}") and line.endswith("which it would write over"), line
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before


SIMULATE = ["simulate", "--duration", "0.002", "--no-progress", "--out", "t.csv"]  # (prints, then saves)


class _ReaderLeft(io.StringIO):
    """A standard output whose reader has gone (``| head`` after its line): every write fails."""

    def write(self, text):
        raise BrokenPipeError(errno.EPIPE, "Broken pipe")

    def fileno(self):
        raise io.UnsupportedOperation("fileno")


def test_a_reader_that_leaves_early_does_not_stop_the_output_files(tmp_path, monkeypatch):
    """`cablecasing simulate ... --out t.csv | head -1`: the command prints its summary before it saves;
    once the reader is gone it goes on without printing and writes its file, status 0 (it stopped at
    the first print, status 0, and the file was never written)."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "stdout", _ReaderLeft())
    assert main(SIMULATE) == 0
    assert (tmp_path / "t.csv").stat().st_size > 0


@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", "--duration", "0.002", "--out", "t.csv"],  # (its progress bar, on stderr, before it saves)
        ["ensemble", "--seeds", "2", "--duration", "0.16", "--out", "t.csv"],  # (a warning, then its bar)
    ],
    ids=["simulate", "ensemble"],
)
def test_a_closed_pipe_on_standard_error_does_not_stop_the_output_files(tmp_path, argv):
    """`cablecasing ensemble ... --out t.csv 2>&1 | head -1`: through a real pipe whose reading end is
    closed before the command writes to stderr (a progress bar, a warning), the command goes on and
    writes its file, status 0 (it stopped at the first write to stderr, status 0, no file)."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "cablecasing_core", *argv],
        cwd=tmp_path,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    proc.stderr.close()
    assert proc.wait(timeout=300) == 0
    assert (tmp_path / "t.csv").stat().st_size > 0


@pytest.mark.parametrize(
    "argv,status,written",
    [
        (["simulate", "--duration", "0.002", "--out", "t.csv"], 0, True),  # (its progress bar goes nowhere)
        (["simulate", "no_such_model.toml"], 2, False),  # (an error: its status, though its line goes nowhere)
    ],
    ids=["run", "error"],
)
def test_a_command_started_with_standard_error_closed_runs_and_keeps_its_status(tmp_path, argv, status, written):
    """`cablecasing ... 2>&-` (a daemon without stderr: Python's sys.stderr is None): the command
    runs, writes its files and returns its status; the wrapper of stderr wrote to None, so an error
    ended as an AttributeError with status 1, and a progress bar stopped the run."""
    code = f"import sys; from cablecasing_core.cli import main; sys.exit(main({argv!r}))"
    res = subprocess.run(
        f'"{sys.executable}" -c "{code}" 2>&-', shell=True, cwd=tmp_path, stdout=subprocess.DEVNULL, timeout=300
    )
    assert res.returncode == status
    assert (tmp_path / "t.csv").exists() == written


def test_a_broken_pipe_that_stopped_the_work_is_not_success(tmp_path, capsys, monkeypatch):
    """A BrokenPipeError that reaches the command line (a pipe of the command's own, not stdout or
    stderr) stopped the work: one line and status 1, never 0."""
    from cablecasing_core.cli import simulate

    def pipe_closed(args):
        raise BrokenPipeError(errno.EPIPE, "Broken pipe")

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(simulate, "cmd_simulate", pipe_closed)
    assert main(SIMULATE) == 1
    assert "a pipe the command wrote to was closed" in _one_line(capsys)


@pytest.mark.slow
def test_a_closed_pipe_on_standard_output_leaves_no_message_and_the_file_written(tmp_path):
    """The same through a real pipe whose reading end is closed before the command prints: status 0,
    the file written, and nothing on stderr (Python's own flush at exit finds /dev/null, not the pipe)."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "cablecasing_core", *SIMULATE],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    proc.stdout.close()
    with proc.stderr:
        err = proc.stderr.read().decode()
    assert proc.wait(timeout=300) == 0, err
    assert err == "" and (tmp_path / "t.csv").stat().st_size > 0
