"""An unexpected exception (a bug) as the command line shows it: one line with the exception's type
and its message cut short, status 1, the traceback only with CABLECASING_TRACEBACK; a MemoryError
(no bug) one line of its own, status 2. The text is ``errors.internal_error_text``, the FMU's too
(tests/fmu/test_internal_error_fmu.py)."""

import pytest

from cablecasing_core.cli import main
from cablecasing_core.errors import INTERNAL_EXCERPT, internal_error_text

LONG = "first line\nsecond line " + "x" * 500  # (a message of two lines and 523 characters)


def test_the_text_is_one_line_with_the_type_and_the_message_cut_short(monkeypatch):
    monkeypatch.delenv("CABLECASING_TRACEBACK", raising=False)
    text = internal_error_text(ValueError(LONG), report=" with the command", note="; parameters set: a = 1")
    assert "\n" not in text
    head, _, rest = text.partition(" (a bug; please report it with the command; ")
    assert head.startswith("ValueError: first line second line xxx") and head.endswith("(523 characters)"), head
    assert len(head) <= len("ValueError: ") + INTERNAL_EXCERPT  # (the excerpt's own limit)
    assert rest == "CABLECASING_TRACEBACK=1 shows the traceback); parameters set: a = 1"
    said = internal_error_text(MemoryError())
    assert said.startswith("out of memory (MemoryError): ") and "a bug" not in said and "geometry.n_elements" in said


def test_with_cablecasing_traceback_the_traceback_follows(monkeypatch):
    monkeypatch.setenv("CABLECASING_TRACEBACK", "1")
    try:
        raise KeyError("k")
    except KeyError as exc:
        lines = internal_error_text(exc).splitlines()
    assert lines[0].startswith("KeyError: 'k' (a bug; please report it; ")
    assert lines[1] == "Traceback (most recent call last):" and lines[-1] == "KeyError: 'k'"


def _failing(monkeypatch, exc):
    """``cablecasing modes`` with the natural frequencies raising ``exc``."""
    from cablecasing_core.frequency import modal

    def fail(*a, **k):
        raise exc

    monkeypatch.setattr(modal, "natural_frequencies", fail)


@pytest.mark.parametrize("traceback", [False, True])
def test_a_bug_in_a_command_is_one_line_and_status_1(capsys, monkeypatch, traceback):
    _failing(monkeypatch, ValueError(LONG))
    if traceback:
        monkeypatch.setenv("CABLECASING_TRACEBACK", "1")
    else:
        monkeypatch.delenv("CABLECASING_TRACEBACK", raising=False)
    assert main(["modes"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err[0].startswith("cablecasing: internal error: ValueError: first line second line xxx"), err
    assert err[0].endswith(
        "(523 characters) (a bug; please report it with the command; CABLECASING_TRACEBACK=1 shows the traceback)"
    ), err[0]
    if traceback:  # (then Python's traceback, which ends with the whole message)
        assert err[1] == "Traceback (most recent call last):" and err[-1] == "second line " + "x" * 500, err
    else:
        assert len(err) == 1, err


def test_out_of_memory_in_a_command_is_one_line_and_status_2(capsys, monkeypatch):
    monkeypatch.delenv("CABLECASING_TRACEBACK", raising=False)
    _failing(monkeypatch, MemoryError())
    assert main(["modes"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"cablecasing: error: {internal_error_text(MemoryError())}"], err


WARNING_MADE_AN_ERROR = "cablecasing: error: (a warning made an error by -W error / PYTHONWARNINGS): "


@pytest.mark.parametrize(
    "python_options,env,argv,said",
    [
        (["-W", "error"], {}, ["trfam", "--df", "5", "--out", "t.csv"], "UserWarning: --df = 5 Hz is wider than half"),
        (
            [],
            {"PYTHONWARNINGS": "error"},
            ["modes", "--set", "geometry.n_elements=3"],
            "ModelPropertyWarning: geometry.n_elements = 3: the contact is sought at the cable's 4 nodes",
        ),
    ],
    ids=["-W error", "PYTHONWARNINGS"],
)
def test_a_warning_made_an_error_is_one_line_and_status_2_not_a_bug(tmp_path, python_options, env, argv, said):
    """Under -W error or PYTHONWARNINGS=error the command's own warnings (here a coarse TRFAM grid, a
    mesh too coarse for the contact) become exceptions: they stop the command as bad input does, one
    line naming the warning, status 2, nothing written; they were 'internal error ... (a bug; please
    report it ...)', status 1 (review AL L1). Without the setting the same command warns and runs."""
    import os
    import subprocess
    import sys

    def run(options, extra):
        cmd = [sys.executable, *options, "-m", "cablecasing_core", *argv]
        proc = subprocess.run(cmd, cwd=tmp_path, env={**os.environ, **extra}, capture_output=True, text=True)
        return proc.returncode, proc.stderr.strip().splitlines()

    code, err = run(python_options, env)
    assert code == 2 and len(err) == 1 and err[0].startswith(WARNING_MADE_AN_ERROR + said), err
    assert "a bug" not in err[0] and list(tmp_path.iterdir()) == []
    code, err = run([], {})
    assert code == 0 and any(line.startswith("cablecasing: warning: " + said.split(": ", 1)[1]) for line in err), err
