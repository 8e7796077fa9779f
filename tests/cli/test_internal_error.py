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
