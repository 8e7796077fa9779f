"""The installed specimen's energy ledger as printed (review AE D2): the energy stored at t = 0 (its
static state) and the constant loads' work are rows of `simulate`'s ledger and of `energies`, so the
printed rows balance; and the kept-prestress warning's frequency shift of a tensioned body (D4)."""

import re

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion
from cablecasing_core.timedomain.static_state import _frequency_effect


def test_the_start_energy_is_what_the_static_state_holds_and_the_printed_rows_balance(capsys):
    """`start_energy` equals the energy held at t = 0 before any step (kinetic, strain with the
    static state's, contact), to the bit; `simulate installed` prints it and the loads' work, and its
    printed rows add up to the residual (1e-8 of the supports' work) within their rounding: each is
    printed to 4 digits, up to 5e-4 of the largest for each of the two large ones (stored at t = 0
    and strain now), so 1e-3 of the largest."""
    model = cc.load_model("installed")
    eng = Engine(model, ledger=True)
    e0 = eng.energies()
    held = e0["kinetic"] + e0["strain"] + e0["contact_potential"]
    assert held > 0.1  # J: the static state's strain energy (0.229 J)
    eng.advance(0.005, scenario_motion(model))
    e = eng.energies()
    assert e["start_energy"] == held
    assert main(["simulate", "installed", "--duration", "0.02", "--no-progress"]) == 0
    out = capsys.readouterr().out

    def row(label):
        line = next(x for x in out.splitlines() if x.strip().startswith(label))
        return float(line.split(label, 1)[1].split()[0])

    start, sup, loads = row("stored at t = 0"), row("supplied by the supports"), row("supplied by the constant loads")
    ray, con = row("dissipated by Rayleigh damping"), row("dissipated in the contacts")
    now = next(x for x in out.splitlines() if x.strip().startswith("stored now:"))
    stored = sum(float(x) for x in re.findall(r"(?:kinetic|strain|contact) ([-+0-9.e]+)", now))
    balance = stored - (start + sup + loads - ray - con)
    assert abs(balance) < 1e-3 * max(abs(start), abs(sup)), (balance, out)
    assert "supplied by the constant loads" in out and loads < 0.0  # (the weight lifted by the drive, -0.0013 J)


def test_the_frequency_shift_of_a_tensioned_body_counts_its_tension():
    """f = f0 sqrt(1 + N0 / P_cr): a K_G off by 1.71 P_cr shifts the lowest frequency of a cable
    under +10 N with P_cr = 8.78 N by 1.71 / (2 (1 + 10 / 8.78)) = 0.40, not the 0.86 of a body
    without it; a compressed one keeps 1 / (2 (1 - P / P_cr))."""
    assert _frequency_effect(1.71, 10.0, 8.78) == pytest.approx(1.71 / (2 * (1 + 10 / 8.78)))
    assert _frequency_effect(0.1, -10.0, 50.0) == pytest.approx(0.1 / (2 * (1 - 10 / 50)))
    assert np.isinf(_frequency_effect(0.1, 1.0, 0.0))
