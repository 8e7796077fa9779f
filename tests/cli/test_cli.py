"""The command line: modes, trfam, errors (run in-process through cli.main)."""

import json

import numpy as np
import pytest

from cablecasing_core import load_model, natural_frequencies, trfam
from cablecasing_core.cli import main


def test_modes_json(capsys):
    assert main(["modes", "--count", "4", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    m = load_model()
    for body in ("casing", "cable"):
        np.testing.assert_allclose(out[body], natural_frequencies(m, body, 4), rtol=1e-12)


def test_trfam_csv(tmp_path):
    out = tmp_path / "t.csv"
    png = tmp_path / "t.png"
    assert (
        main(
            [
                "trfam",
                "--input",
                "casing.A.y",
                "--output",
                "casing.B.y",
                "--fmin",
                "10",
                "--fmax",
                "20",
                "--df",
                "0.5",
                "--out",
                str(out),
                "--plot",
                str(png),
                "--damping",
                "structural",
            ]
        )
        == 0
    )
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert data.dtype.names == ("frequency_hz", "re_kg", "im_kg", "magnitude_kg", "phase_deg")
    H = trfam(load_model(), "casing.A.y", "casing.B.y", data["frequency_hz"], "structural")
    np.testing.assert_allclose(data["re_kg"] + 1j * data["im_kg"], H, rtol=1e-8)
    assert png.stat().st_size > 1000


def test_bad_model_exits_nonzero(tmp_path, capsys):
    p = tmp_path / "m.toml"
    p.write_text(load_model().to_toml().replace("E = 5000000000.0", "Ee = 5000000000.0"))
    assert main(["modes", str(p)]) == 2
    assert "casing.Ee" in capsys.readouterr().err


def test_simulate_cli_writes_csv(tmp_path, capsys):
    out = tmp_path / "r.csv"
    assert main(["simulate", "--duration", "0.002", "--out", str(out)]) == 0
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert len(data) == 200 and "casingBFz_N" in data.dtype.names
    assert main(["simulate", "--duration", "-1"]) == 2
    assert "duration" in capsys.readouterr().err


def test_simulate_cli_refuses_output_paths_before_the_run(tmp_path, capsys):
    assert main(["simulate", "--duration", "1.0", "--out", str(tmp_path / "r.txt")]) == 2
    assert "--out" in capsys.readouterr().err
    assert main(["simulate", "--duration", "1.0", "--plot", str(tmp_path / "no" / "r.png")]) == 2
    assert "existing folder" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())


def test_simulate_cli_model_dt_npz_plot_and_blow_up(tmp_path, capsys):
    """The CLI is a shell over cc.simulate: the same histories for the same model file and dt; a
    duration that is not a whole number of steps ends on it; a blow-up exits with status 2 and the
    error's when, where and what."""
    import cablecasing_core as cc

    model = load_model().with_overrides({"contact.friction": 0.1})
    p = tmp_path / "m.toml"
    p.write_text(model.to_toml())
    out, png = tmp_path / "r.npz", tmp_path / "r.png"
    assert (
        main(["simulate", str(p), "--duration", "0.0030025", "--dt", "2e-5", "--out", str(out), "--plot", str(png)])
        == 0
    )
    z = np.load(out)
    ref = cc.simulate(model, duration=0.0030025, dt=2e-5)
    assert len(z["time"]) == 151 and z["time"][-1] == 0.0030025 and z["time"][-2] == pytest.approx(0.003)
    np.testing.assert_array_equal(z["support_forces"], ref.support_forces)
    np.testing.assert_array_equal(z["contact_time"], ref.contact_time)
    assert png.stat().st_size > 10_000
    capsys.readouterr()
    soft = model.with_overrides(
        {
            "contact.law": "linear",
            "contact.stiffness": 1.0,
            "scenario.excitation.cable_axial.amplitude": 0.0,
            "scenario.excitation.casing_random.rms": 5000.0,
        }
    )
    p.write_text(soft.to_toml())
    assert main(["simulate", str(p), "--duration", "0.05"]) == 2
    err = capsys.readouterr().err
    assert "penetration" in err and "exceeds the cable radius" in err and "at t = " in err
