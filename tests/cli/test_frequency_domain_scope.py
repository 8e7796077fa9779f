"""``modes`` and ``trfam`` are of each body alone (no contact between the cable and the casing) and,
on an installed model, about the route with the cable's tension as a prestress, not about the
static state: the code does so (checked against the same model without contact, without gravity
and without tension), and the commands' help and output say so in one line (review AN, B1: the
cable's 8.4 Hz of an installed route read as the installed cable's)."""

import json
from pathlib import Path

import numpy as np

from cablecasing_core import load_model, natural_frequencies
from cablecasing_core.cli import main
from cablecasing_core.files import read_csv_table
from cablecasing_core.frequency.modal import frequency_domain_scope

STRAIGHT = Path(__file__).resolve().parents[2] / "examples" / "straight_casing.toml"


def test_the_modes_of_an_installed_model_leave_out_the_contact_and_the_static_state_but_not_the_tension():
    installed = load_model("installed")
    f = {b: natural_frequencies(installed, b, 6) for b in ("casing", "cable")}
    # the static state (its contact forces on the wall, gravity's sag) does not enter: the same
    # model without contact and without gravity has the same modes, to round-off (1e-12)
    bare = installed.with_overrides({"contact.enabled": False, "loads.gravity": [0.0, 0.0, 0.0]})
    for b in f:
        np.testing.assert_allclose(natural_frequencies(bare, b, 6), f[b], rtol=1e-12)
    # the tension does (K_G): without it the cable's first mode falls by far more than round-off
    # (a taut cable of 0.1-0.3 N.m2 bending stiffness: the tension dominates its low modes)
    slack = installed.with_overrides({"loads.cable_tension": 0.0})
    assert natural_frequencies(slack, "cable", 1)[0] < 0.9 * f["cable"][0]


def test_the_scope_line_names_what_the_model_has():
    installed = load_model("installed")
    line = frequency_domain_scope(installed)
    T = installed.loads["cable_tension"]
    assert line.startswith("each body alone on its supports and mounts: no contact between the cable and the casing")
    assert f"loads.cable_tension = {T:g} N" in line and "static state" in line
    assert "static state" not in frequency_domain_scope(load_model())  # (the built-in specimen: not installed)
    assert frequency_domain_scope(load_model(STRAIGHT)) is None  # (a casing alone: nothing left out)


def test_modes_and_trfam_print_the_line_and_their_help_says_it(capsys, tmp_path):
    assert main(["modes", "installed", "--count", "2"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "# " + frequency_domain_scope(load_model("installed"))
    assert out[1] == "casing: natural frequencies (Hz)"

    assert main(["modes", str(STRAIGHT), "--count", "2"]) == 0  # (no cable: no line)
    assert capsys.readouterr().out.startswith("casing: natural frequencies (Hz)")

    assert main(["modes", "installed", "--count", "2", "--json"]) == 0  # (JSON stays JSON)
    assert set(json.loads(capsys.readouterr().out)) == {"casing", "cable"}

    assert main(["trfam", "installed", "--fmin", "10", "--fmax", "12", "--df", "1"]) == 0
    text = capsys.readouterr().out
    assert text.startswith("# each body alone on its supports and mounts: no contact")
    table = tmp_path / "t.csv"  # (the printed table still reads as a CSV table: '#' lines are skipped)
    table.write_text(text)
    assert read_csv_table(table)[1].shape == (3, 5)

    for command in ("modes", "trfam"):
        try:
            main([command, "--help"])
        except SystemExit:
            pass
        assert "no contact between the cable and the casing" in " ".join(capsys.readouterr().out.split())
