"""An unexpected exception inside the FMU's slave (a bug) is one line of its log at the status of the
call, in the words of ``errors.internal_error_text`` (the command line's too: tests/cli/test_internal_error.py):
fmi2Error when the model is built, with the parameters the master set; fmi2Discard for a step, the
FMU unchanged. The slave (fmu_src/CableCasing.py) runs in this process, driven through its fmi2_*
methods as the FMU's binary drives it."""

import importlib.util
from pathlib import Path

import pytest

from cablecasing_core.errors import internal_error_text

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def slave_module():
    spec = importlib.util.spec_from_file_location("cablecasing_slave_in_test", ROOT / "fmu_src" / "CableCasing.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _slave(module):
    slave = module.CableCasing(instance_name="bug", resources=None)
    log = []
    slave.attach_log_sink(lambda status, message: log.append((status, message)))
    return slave, log


def test_a_bug_while_the_model_is_built_is_one_line_at_fmi2error(slave_module, monkeypatch):
    monkeypatch.delenv("CABLECASING_TRACEBACK", raising=False)
    slave, log = _slave(slave_module)
    bug = ValueError("no such thing\nin two lines")

    def fail(*a, **k):
        raise bug

    monkeypatch.setattr(slave_module, "Engine", fail)
    vr = next(vr for vr, (key, _) in slave._param.items() if key == "casing.E")
    assert slave.fmi2_set("Real", [vr], [6e9]) == slave_module.OK
    slave.fmi2_enter_initialization_mode()
    assert slave.fmi2_exit_initialization_mode() == slave_module.ERROR
    errors = [m for s, m in log if s == slave_module.ERROR]
    assert errors == [
        "the model cannot be built: ValueError: no such thing in two lines (a bug; please report it; "
        "CABLECASING_TRACEBACK=1 shows the traceback); parameters set: casing.E = 6000000000.0"
    ], log
    assert errors[0] == "the model cannot be built: " + internal_error_text(bug, note=slave._set_text())


def test_a_bug_in_a_step_is_one_line_at_fmi2discard_and_the_step_is_not_taken(slave_module, monkeypatch):
    monkeypatch.delenv("CABLECASING_TRACEBACK", raising=False)
    slave, log = _slave(slave_module)
    slave.fmi2_enter_initialization_mode()
    assert slave.fmi2_exit_initialization_mode() == slave_module.OK
    assert slave.fmi2_do_step(0.0, 1e-4) == slave_module.OK

    def fail(*a, **k):
        raise KeyError("k")

    monkeypatch.setattr(slave._engine, "advance_reconstructed", fail)
    assert slave.fmi2_do_step(1e-4, 1e-4) == slave_module.DISCARD
    assert slave.last_successful_time() == pytest.approx(1e-4, abs=1e-15)  # (the FMU is where it was)
    assert log[-1] == (
        slave_module.DISCARD,
        "step from t = 0.0001 s over 0.0001 s discarded (state rolled back): KeyError: 'k' (a bug; please report "
        "it; CABLECASING_TRACEBACK=1 shows the traceback)",
    )
