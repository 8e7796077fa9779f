"""The command line: modes, trfam, errors (run in-process through cli.main)."""

import json
import subprocess
import sys
import warnings

import numpy as np
import pytest

from cablecasing_core import load_model, natural_frequencies, simulate, trfam
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
    # (the table is written with 10 significant digits: 5e-10)
    np.testing.assert_allclose(data["re_kg"] + 1j * data["im_kg"], H, rtol=1e-8)
    assert png.stat().st_size > 1000


def test_bad_model_exits_nonzero(tmp_path, capsys):
    p = tmp_path / "m.toml"
    p.write_text(load_model().to_toml().replace("E = 5000000000.0", "Ee = 5000000000.0"))
    assert main(["modes", str(p)]) == 2
    assert "casing.Ee" in capsys.readouterr().err


def test_simulate_cli_writes_csv_with_the_output_names_and_decimates(tmp_path, capsys):
    import cablecasing_core as cc
    from cablecasing_core.model.schema import SUPPORT_OUTPUTS
    from cablecasing_core.records import read_records

    out, every = tmp_path / "r.csv", tmp_path / "e.csv"
    assert main(["simulate", "--duration", "0.002", "--out", str(out), "--no-progress"]) == 0
    header = out.read_text().splitlines()[0].split(",")
    assert header[:2] == ["time [s]", "casing.A.Fx [N]"] and "casing.B.Mz [N.m]" in header  # as the README
    assert "contact.active [1]" in header and "casing.A.az [m/s2]" in header  # and the driven input
    rec = read_records(out)
    ref = cc.simulate(load_model(), duration=0.002)
    assert len(rec.time) == 201 and rec.time[0] == 0 and rec.time[-1] == 0.002  # t = 0, dt, ..., T
    assert np.all(rec.column("casing.B.Fz")[0] == 0)  # the state it starts from: at rest
    # (the record's CSV keeps 9 significant digits: 5e-9; atol for the force's zeros)
    np.testing.assert_allclose(rec.column("casing.B.Fz")[1:], ref.support_force("casing.B.Fz"), rtol=1e-8, atol=1e-17)
    assert rec.column("casing.B.Fz [N]") is rec.column("casing.B.Fz_N")  # the header form and the old form
    # --output-interval --decimation pick: every 10th sample of the same grid, t = 0 to T
    args = ["simulate", "--duration", "0.002", "--out", str(every), "--output-interval", "1e-4", "--no-progress"]
    assert main([*args, "--decimation", "pick"]) == 0
    dec = read_records(every)
    np.testing.assert_array_equal(dec.time, rec.time[::10])
    assert dec.time[0] == 0 and dec.time[-1] == 0.002
    for name in SUPPORT_OUTPUTS[:6]:
        np.testing.assert_array_equal(dec.column(name), rec.column(name)[::10])
    assert main(args) == 0  # the default filters: the same grid, other values
    filt = read_records(every)
    np.testing.assert_array_equal(filt.time, dec.time)
    assert not np.array_equal(filt.column("casing.B.Fz"), dec.column("casing.B.Fz"))
    assert main(["simulate", "--duration", "0.002", "--output-interval", "1.5e-5"]) == 2
    assert "whole number of time steps" in capsys.readouterr().err
    assert main(["simulate", "--duration", "0.002", "--output-interval", "3e-4"]) == 2  # 0.002 / 3e-4 = 6.67
    assert "must divide the duration (0.002 s) into whole intervals" in capsys.readouterr().err
    assert main(["simulate", "--duration", "-1"]) == 2
    assert "duration" in capsys.readouterr().err


def test_the_energy_printout_says_what_each_figure_is(capsys):
    assert main(["simulate", "--duration", "0.003", "--no-contact", "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "-0 " not in out and "-0\n" not in out  # contact dissipation without contact is 0, not -0
    assert "dissipated in the contacts      0  (work of the contact forces" in out
    assert "split" not in out and "its parts" not in out  # nothing to split without contact
    assert main(["simulate", "--duration", "0.03", "--no-progress"]) == 0  # contacts from 0.024 s
    out = capsys.readouterr().out
    assert "its parts, from their powers: contact damping" in out and "the normal forces' own work" in out


def test_uff_round_trip_of_a_time_record_and_a_trfam_written_by_the_cli(tmp_path):
    """UFF 58 files written by 'simulate --out x.uff' and 'trfam --out t.uff' read back by pyuff
    itself: the functions, their types, DOFs, units and values (binary doubles: exact)."""
    import pyuff

    from cablecasing_core.model.schema import SUPPORT_OUTPUTS
    from cablecasing_core.timedomain.simulation import SimulationResult

    uff, npz = tmp_path / "r.uff", tmp_path / "r.npz"
    for path in (uff, npz):
        assert main(["simulate", "--duration", "0.002", "--out", str(path), "--no-progress"]) == 0
    ref = SimulationResult.load(npz)
    sets = pyuff.UFF(str(uff)).read_sets()
    by_name = {s["id1"].strip(): s for s in sets}
    assert all(s["func_type"] == 1 and s["type"] == 58 for s in sets)
    fz = by_name["casing.B.Fz"]
    assert (fz["rsp_node"], fz["rsp_dir"], fz["ordinate_spec_data_type"]) == (2, 3, 9)  # casing B, +Z, force
    assert fz["ordinate_axis_units_lab"].strip() == "N" and fz["abscissa_axis_units_lab"].strip() == "s"
    for name in SUPPORT_OUTPUTS:  # (the record's first row is t = 0, the state it starts from)
        np.testing.assert_array_equal(by_name[name]["data"][1:], ref.support_force(name))
    np.testing.assert_allclose(by_name["casing.B.Fz"]["x"][1:], ref.time, rtol=1e-12)
    assert by_name["casing.B.Fz"]["x"][0] == 0
    assert by_name["casing.A.az"]["ordinate_spec_data_type"] == 12  # the driven input, an acceleration

    t = tmp_path / "t.uff"
    args = ["trfam", "--input", "casing.A.z", "--output", "casing.B.z", "--fmin", "10", "--fmax", "50"]
    assert main(args + ["--df", "0.5", "--out", str(t), "--damping", "structural"]) == 0
    frf = pyuff.UFF(str(t)).read_sets(0)  # (one set: a dict)
    assert frf["func_type"] == 4 and (frf["rsp_node"], frf["rsp_dir"], frf["ref_node"], frf["ref_dir"]) == (2, 3, 1, 3)
    assert (frf["ordinate_spec_data_type"], frf["orddenom_spec_data_type"]) == (9, 12)  # force / acceleration
    f = np.arange(10.0, 50.25, 0.5)
    np.testing.assert_allclose(frf["x"], f, rtol=1e-12)
    np.testing.assert_array_equal(frf["data"], trfam(load_model(), "casing.A.z", "casing.B.z", f, "structural"))


def test_every_command_that_reads_records_reads_csv_npz_and_uff(tmp_path, capsys):
    for suffix in ("csv", "npz", "uff"):
        assert main(["simulate", "--duration", "0.15", "--out", str(tmp_path / f"r.{suffix}"), "--no-progress"]) == 0
    capsys.readouterr()
    tables = {}
    for suffix in ("csv", "npz", "uff"):
        assert main(["bands", str(tmp_path / f"r.{suffix}"), "--column", "casing.B.Fz"]) == 0
        out = [s for s in capsys.readouterr().out.splitlines() if not s.startswith("#")]  # (the notes vary)
        assert out[0] == "band,f_centre [Hz],f_low [Hz],f_high [Hz],rms [N],level [dB re 1 N]"
        tables[suffix] = np.array([[float(v) for v in row.split(",")[1:]] for row in out[1:]])
        assert main(["spectrum", str(tmp_path / f"r.{suffix}"), "--kind", "apparent-mass", "--fmax", "500"]) == 0
        assert "apparent mass (H1)" in capsys.readouterr().out
    np.testing.assert_array_equal(tables["npz"], tables["uff"])  # both exact doubles
    np.testing.assert_allclose(tables["csv"], tables["npz"], rtol=1e-6)  # 9 digits in the CSV
    (tmp_path / "bad.csv").write_bytes((tmp_path / "r.npz").read_bytes())
    assert main(["bands", str(tmp_path / "bad.csv")]) == 2  # a binary file named .csv: a message, no traceback
    assert "is not a UTF-8 text CSV file" in capsys.readouterr().err
    assert main(["bands", str(tmp_path / "r.csv"), "--column", "casing.B.Fq"]) == 2
    assert "casing.B.Fz" in capsys.readouterr().err  # the columns are listed by their names


def test_every_help_shows_the_defaults(capsys):
    from cablecasing_core.cli import build_parser

    def parsers(p, path=()):
        yield path, p
        for a in p._actions:
            if a.__class__.__name__ == "_SubParsersAction":
                for name, sp in a.choices.items():
                    yield from parsers(sp, path + (name,))

    n = 0
    for path, p in parsers(build_parser()):
        text = " ".join(p.format_help().split())
        for a in p._actions:
            d = a.default
            if not a.option_strings or d is None or d is False or d == [] or d == "==SUPPRESS==" or a.help is None:
                continue  # (`is`: a default of 0 must be shown, and 0 == False)
            assert "default" in (a.help or "") or f"(default: {a.default})" in text, (path, a.option_strings)
            n += 1
    assert n > 40


def test_the_helps_restate_the_cores_constants_from_the_core(monkeypatch):
    """The helps that restate a fact of the core (the least skip, the dB references, Table 3's range,
    the IEC bands' default range) write it from the core's constant when shown
    (``helptext.API_TEXTS``): no placeholder is left in any help, each help shows the constant's
    value, and a changed constant changes the help (a literal in the help would not follow)."""
    from cablecasing_core.cli import build_parser
    from cablecasing_core.cli.helptext import API_TEXTS
    from cablecasing_core.nvh import bands, spectra
    from cablecasing_core.timedomain import start_skip

    def helps():
        def parsers(p):
            yield p
            for a in p._actions:
                if a.__class__.__name__ == "_SubParsersAction":
                    for sp in a.choices.values():
                        yield from parsers(sp)

        return {id(p): " ".join(p.format_help().split()) for p in parsers(build_parser())}

    def fresh():  # (each text is read once per process, when first shown)
        for text in API_TEXTS.values():
            text.__dict__.pop("value", None)

    fresh()
    texts = " ".join(helps().values())
    assert not any(mark in texts for mark in API_TEXTS), [m for m in API_TEXTS if m in texts]
    assert "(default: 0.05 s, or" in texts and "default: 0.05 s lengthened" in texts
    assert "1 N, 1 N.m, 1e-06 m/s2, 1e-09 m/s, 1e-12 m" in texts and "octaves 11-5680 Hz" in texts
    assert "10 Hz for octave and third" in texts and "all; 20000 Hz" in texts
    monkeypatch.setattr(start_skip, "LEAST_SKIP", 0.125)
    monkeypatch.setattr(spectra, "REFERENCES", {"N": 2.0, "1": 1.0})
    monkeypatch.setattr(bands, "TABLE3_UPPER", (*bands.TABLE3_UPPER[:-1], 6000.0))
    monkeypatch.setattr(bands, "IEC_F_MIN", 12.5)
    fresh()
    try:
        texts = " ".join(helps().values())
    finally:
        fresh()
    assert "(default: 0.125 s, or" in texts and "default: 0.125 s lengthened" in texts and "0.05 s" not in texts
    assert "default: by unit, 2 N; docs/nvh.md" in texts and "octaves 11-6000 Hz" in texts
    assert "12.5 Hz for octave and third" in texts


def test_an_interrupt_prints_one_line_and_leaves_the_earlier_file(tmp_path, capsys, monkeypatch):
    from cablecasing_core.timedomain.engine import Engine

    out = tmp_path / "r.csv"
    out.write_text("an earlier result\n")

    def interrupted(self, h, motion):
        raise KeyboardInterrupt

    monkeypatch.setattr(Engine, "advance", interrupted)
    assert main(["simulate", "--duration", "0.01", "--out", str(out)]) == 130
    err = capsys.readouterr().err
    # (the message says what was kept, issue 26)
    assert f"cablecasing: interrupted: the run was stopped: the previous {out} kept as it was" in err
    assert "Traceback" not in err
    assert out.read_text() == "an earlier result\n" and sorted(p.name for p in tmp_path.iterdir()) == ["r.csv"]


def test_an_interrupted_write_leaves_the_earlier_file(tmp_path):
    from cablecasing_core.files import atomic_path

    p = tmp_path / "x.npz"
    np.savez(p, a=np.arange(3))
    with pytest.raises(KeyboardInterrupt), atomic_path(p) as tmp:
        np.savez(tmp, a=np.arange(5))
        raise KeyboardInterrupt
    assert np.load(p)["a"].tolist() == [0, 1, 2] and sorted(q.name for q in tmp_path.iterdir()) == ["x.npz"]


def test_a_model_without_excitation_warns_in_one_line(tmp_path, capsys):
    from cablecasing_core.model import model_from_dict

    data = load_model().to_dict()  # (a model is read-only: a mutable copy)
    data["scenario"]["excitation"] = {}
    p = tmp_path / "m.toml"
    p.write_text(model_from_dict(data).to_toml())
    assert main(["simulate", str(p), "--duration", "0.001", "--no-progress"]) == 0
    err = capsys.readouterr().err
    assert err.startswith("cablecasing: warning: the model") and "has no excitation" in err and ".py" not in err


def test_no_contact_draws_no_histogram():
    import matplotlib.pyplot as plt

    from cablecasing_core.plotting import plot_contact_histogram

    fig, ax = plt.subplots()
    plot_contact_histogram(ax, np.linspace(0, 0.85, 36), np.zeros(36), np.ones(36))
    assert len(ax.patches) == 0 and "no contact" in ax.texts[0].get_text()
    plt.close(fig)


def test_simulate_cli_refuses_output_paths_before_the_run(tmp_path, capsys):
    assert main(["simulate", "--duration", "1.0", "--out", str(tmp_path / "r.txt")]) == 2
    assert "--out" in capsys.readouterr().err
    assert main(["simulate", "--duration", "1.0", "--plot", str(tmp_path / "no" / "r.png")]) == 2
    assert "existing folder" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())


def test_simulate_cli_model_dt_npz_plot_and_blow_up(tmp_path, capsys):
    """The CLI is a shell over cc.simulate: the same histories for the same model file and dt; a
    duration that is not a whole number of steps ends on it (the run), while its record ends at the
    last whole step (the shorter last one is off the grid); a blow-up exits with status 2 and the
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
    from cablecasing_core.timedomain.simulation import SimulationResult

    z = SimulationResult.load(out)
    ref = cc.simulate(model, duration=0.0030025, dt=2e-5)
    assert len(ref.time) == 151 and ref.time[-1] == 0.0030025 and ref.whole_steps == 150
    assert len(z.time) == 150 and z.time[-1] == pytest.approx(0.003)
    np.testing.assert_array_equal(z.support_forces, ref.support_forces[:150])
    np.testing.assert_array_equal(z.contact_time, ref.contact_time)
    assert "the record ends at the last whole step, t = 0.003 s" in capsys.readouterr().out
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


def test_simulate_says_how_many_steps_were_recomputed_in_sub_steps(capsys, tmp_path):
    """The summary's first line names the steps recomputed around stick-slip events, as many as the
    core's run of the same model counts (SimulationResult.solver; docs/time_domain.md); with the
    regularised friction law (the installed specimen's) it says there are no such events."""
    from importlib import resources

    text = resources.files("cablecasing_core.model").joinpath("specimens/installed.toml").read_text()
    text = text.replace('friction_law = "regularized"', 'friction_law = "switch"')
    (tmp_path / "switch.toml").write_text(text)
    assert main(["simulate", str(tmp_path / "switch.toml"), "--duration", "0.01", "--no-progress"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    model = load_model(tmp_path / "switch.toml")
    assert model.contact["friction_law"] == "switch"
    n = simulate(model, duration=0.01).solver["refined_steps"]
    assert n > 0
    assert first == (
        f"simulated 0.01 s in 1000 steps, {n} of them recomputed, each in 8 sub-steps, around stick-slip events"
    )
    assert main(["simulate", "installed", "--duration", "0.01", "--no-progress"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first == "simulated 0.01 s in 1000 steps, friction regularised (no stick-slip events)"
    assert simulate(load_model("installed"), duration=0.01).solver["refined_steps"] == 0


def test_simulate_says_what_the_event_tolerance_did(capsys):
    """``--set contact.event_tolerance=1e-9`` (a model change on the command line, as in a model
    file): the summary's first line adds the steps recomputed for their estimated local error and
    the largest estimate kept, the core's own counts (docs/time_domain.md, "A tolerance instead of a
    bare step"), and stderr the core's warnings; a value the schema refuses is named with the flag,
    before anything runs."""
    argv = ["simulate", "installed", "--duration", "0.01", "--no-progress", "--set", "contact.event_tolerance=1e-9"]
    assert main(argv) == 0
    said_cli = capsys.readouterr()
    first = said_cli.out.splitlines()[0]
    model = load_model("installed").with_overrides({"contact.event_tolerance": 1e-9})
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        solver = simulate(model, duration=0.01).solver
    # the core's warnings (here the tolerance not met in the worst sub-steps, 1.03e-9 m) one line each
    warned = [line for line in said_cli.err.splitlines() if line.startswith("cablecasing: warning: ")]
    assert warned == [f"cablecasing: warning: {w.message}" for w in said]
    assert bool(said) == (not solver["tolerance_met"])
    n, worst = solver["tolerance_steps"], solver["max_local_error"]
    assert n > 0 and n == solver["refined_steps"] and solver["event_steps"] == 0 and worst > 0.0
    assert first == (
        "simulated 0.01 s in 1000 steps, friction regularised (no stick-slip events), "
        f"{n} recomputed, each in 8 sub-steps, for contact.event_tolerance = 1e-09 m "
        f"(largest estimated local displacement error of a step or sub-step kept {worst:.3g} m, a sub-step's, above "
        "the tolerance)"
    )
    assert main(["simulate", "installed", "--no-progress", "--set", "contact.event_tolerance=-1"]) == 2
    err = capsys.readouterr().err
    assert "--set contact.event_tolerance" in err and "-1" in err, err


def test_ensembles_run_in_parts_pool_with_their_against_parts(tmp_path, capsys, monkeypatch):
    """docs/studies.md, "Ensembles run in parts", and docs/time_domain.md's time-step comparison: the
    --against parts of another scenario.dt were refused ('its dt is 5e-06, theirs 1e-05'), though
    that Δt is what they compare. A setting that differs without an override still is."""
    import dataclasses

    from cablecasing_core.studies import load_ensemble

    monkeypatch.chdir(tmp_path)
    run = ["--seeds", "2", "--duration", "0.1", "--skip", "0", "--against", "scenario.dt=2e-5"]
    for first, out in (("1", "part1.csv"), ("3", "part2.csv")):
        assert main(["ensemble", *run, "--first-seed", first, "--out", out]) == 0
    capsys.readouterr()
    parts = ["part1.csv", "part2.csv", "--against", "part1_against.csv", "part2_against.csv"]
    assert main(["pool", *parts, "--out", "all.csv"]) == 0
    out = capsys.readouterr().out
    assert "# relative change of the mean level with {'scenario.dt': 2e-05} (paired on the same seeds)" in out
    assert list(load_ensemble("all_against.csv").seeds) == [1, 2, 3, 4]
    # the base parts run with a step of their own (--set scenario.dt=1e-5), as in docs/time_domain.md
    base = load_ensemble("part1.csv")
    dataclasses.replace(base, overrides={"scenario.dt": 1e-5}).save("set.csv")
    assert main(["pool", "set.csv", "--against", "part1_against.csv"]) == 0
    capsys.readouterr()
    # refused: a step the --against parts do not declare, a skip of their own
    against = load_ensemble("part1_against.csv")
    dataclasses.replace(against, overrides={}).save("undeclared.csv")
    dataclasses.replace(against, settings={**against.settings, "skip": 0.01}).save("skip.csv")
    refused = {"undeclared.csv": "its dt is 2e-05, theirs 1e-05", "skip.csv": "its skip is 0.01, theirs 0.0"}
    for name, said in refused.items():
        assert main(["pool", "part1.csv", "--against", name]) == 2
        err = capsys.readouterr().err
        assert f"--against = '{name}': must be run with the settings of the files it is compared with: {said}" in err


def test_a_study_whose_every_run_is_infeasible_says_so(tmp_path, capsys):
    """The cable's diameter varied above the casing's bore (4 mm in the built-in specimen): every
    sample is infeasible, no run starts, and the command says that (not that the runs failed)."""
    argv = ["study", "--vary", "cable.d=0.005:0.01", "--samples", "3", "--duration", "0.2", "--scheduler", "serial"]
    assert main([*argv, "--out", str(tmp_path / "st")]) == 1
    err = capsys.readouterr().err
    # (the first with its sample's parameters)
    assert "error: every run was infeasible; the first: sample 0 (cable.d = " in err, err
    assert "): infeasible: cable.d = " in err, err


def test_the_options_take_their_choices_and_defaults_from_the_api_when_used(capsys):
    """The choices and defaults the parser takes from the API (helptext.FromApi) are the API's
    constants; building the parser imports none of their modules (a fresh process), and a value
    outside the choices is refused by argparse, listing them."""
    code = (
        "import sys\n"
        "from cablecasing_core.cli import build_parser\n"
        "build_parser()\n"
        "print(sorted(m for m in ('cablecasing_core.frequency.trfam', 'cablecasing_core.studies', "
        "'cablecasing_core.identification') if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]", out
    from cablecasing_core.frequency.trfam import DAMPING_MODELS

    with pytest.raises(SystemExit) as e:
        main(["trfam", "--damping", "nope"])
    assert e.value.code == 2
    shown = ", ".join(map(repr, DAMPING_MODELS))
    assert f"argument --damping: invalid choice: 'nope' (choose from {shown})" in capsys.readouterr().err
