"""An error in what a user typed names the option they typed (``--freqs``, ``--resolution``), not a
parameter of the function behind it (``freqs_hz``, ``freq_resolution_hz``) nor another option, and is
one line with exit status 2 before any work: the regression data of a review of the command line."""

import json

import numpy as np
import pytest

from cablecasing_core.cli import main
from cablecasing_core.studies import Ensemble


@pytest.fixture
def files(tmp_path, monkeypatch):
    """In an empty folder: r.csv, a record of two decaying modes (50, 120 Hz) at 4096 Hz with an input
    column; frf.csv, an FRF with resonances at 50 and 150 Hz; a folder dir.uff; a file not.folder."""
    from cablecasing_core.timedomain import simulation

    monkeypatch.setattr(simulation.Engine, "advance", lambda *a, **k: pytest.fail("a run started"))
    monkeypatch.chdir(tmp_path)
    t = np.arange(8192) / 4096.0
    rng = np.random.default_rng(1)
    x = np.exp(-2 * t) * np.sin(2 * np.pi * 50 * t) + 0.5 * np.exp(-4 * t) * np.sin(2 * np.pi * 120 * t)
    a = rng.standard_normal(t.size)
    rows = "\n".join(f"{ti:.17g},{xi:.17g},{ai:.17g}" for ti, xi, ai in zip(t, x, a))
    (tmp_path / "r.csv").write_text("time [s],casing.B.Fz [N],casing.A.az [m/s2]\n" + rows + "\n")
    f = np.arange(10.0, 300.0, 0.5)
    H = sum(1.0 / (fn**2 - f**2 + 0.02j * fn**2) for fn in (50.0, 150.0))
    (tmp_path / "frf.csv").write_text(
        "frequency_hz,re_H,im_H\n" + "\n".join(f"{a:.17g},{h.real:.17g},{h.imag:.17g}" for a, h in zip(f, H)) + "\n"
    )
    (tmp_path / "dir.uff").mkdir()
    (tmp_path / "not.folder").write_text("a file\n")
    levels = rng.random((3, 9))  # (an ensemble CSV: a seed column, then the band levels)
    Ensemble(np.arange(1, 4), "casing.B.Fz", tuple(f"oct{k}" for k in range(1, 10)), t[1:10], t[2:11], levels).save(
        tmp_path / "ens.csv"
    )
    return tmp_path


# (argv, the start of the message after "error: ", the internal names it must not show)
CASES = [
    (["spectrum", "r.csv", "--kind", "apparent-mass", "--input", "nope"], "--input = 'nope': must be a column of r"),
    (["bands", "r.csv", "--kind", "octave", "--fmin", "30000"], "--fmin = 30000.0: must be at most --fmax, by default"),
    (["identify", "damping", "r.csv", "--freqs", "0"], "--freqs = 0.0: every frequency must lie in the open interval"),
    (["identify", "damping", "r.csv", "--count", "100000"], "--count = 100000: must be at most "),
    (["identify", "damping", "r.csv", "--noise-floor", "-1"], "--noise-floor = -1.0: must be a positive number"),
    (["identify", "damping", "r.csv", "--channel", "nope"], "--channel = 'nope': must be 0..1 or a name in the file"),
    (["identify", "damping", "dir.uff"], "file = 'dir.uff': must be a regular file (not a folder or a device)"),
    (["identify", "loss-factor", "frf.csv", "--freqs", "1e9"], "--freqs = 1000000000.0: must lie inside the FRF's"),
    (["identify", "loss-factor", "frf.csv", "--count", "1000"], "--count = 1000: the FRF has only 2 resonance peak"),
    (["identify", "loss-factor", "dir.uff"], "file = 'dir.uff': is a folder, not a UFF file"),
    (["identify", "modulus", "frf.csv", "--modes", "1", "--resolution", "-1"], "--resolution = -1.0: must be a posi"),
    (["identify", "modulus", "frf.csv", "--modes", "0"], "--modes = 0: must be an integer >= 1"),
    (["identify", "modulus", "frf.csv", "--modes", "1", "--degree", "-5"], "--degree = -5: must be -1 (no smoothing)"),
    (["identify", "modulus", "frf.csv", "--modes", "1", "2", "3", "4"], "--modes = [1, 2, 3, 4]: the FRF has only 2"),
    (["study", "--scheduler", "serial", "--skip", "-1"], "--skip = -1.0: must be zero or a positive number of s"),
    (["study", "--scheduler", "serial", "--duration", "nan"], "--duration = nan: must be a positive number of s"),
    (["study", "--scheduler", "serial", "--duration", "1e5"], "--duration = 100000.0: with dt = 1e-05 s"),
    (["study", "--scheduler", "serial", "--out", "not.folder"], "--out = 'not.folder': must be a folder"),
    (["pool", "nope.csv"], "file = 'nope.csv': does not exist"),
    (["simulate", "--duration", "1e5", "--no-progress"], "--duration = 100000.0: with dt = 1e-05 s"),
    (["ensemble", "--seeds", "2", "--skip", "-1"], "--skip = -1.0: must be zero or a positive number of s"),
    (["ensemble", "--seeds", "2", "--duration", "1e5"], "--duration = 100000.0: with dt = 1e-05 s"),
    (["report", "--duration", "1e5", "--out", "rep"], "--duration = 100000.0: with dt = 1e-05 s"),
    # a positional argument by its name in --help, not the function's model_file or prefix
    (["modes", "nope.toml"], "MODEL = 'nope.toml': must be a readable TOML file (No such file or directory)"),
    (["report", "nope.toml", "--out", "rep"], "MODEL = 'nope.toml': must be a readable TOML file"),
    (["simulate", "nope.toml", "--no-progress"], "MODEL = 'nope.toml': must be a readable TOML file"),
    (["study", "nope.toml", "--scheduler", "serial"], "MODEL = 'nope.toml': must be a readable TOML file"),
    (["keys", "contcat"], "PREFIX = 'contcat': matches no key of the model file; did you mean 'contact'"),
    (["keys", "zzzz"], "PREFIX = 'zzzz': matches no key of the model file; its sections are cable, casing, contact"),
    # a change that makes a value of the model file invalid: named as the change, with what it conflicts with
    (
        ["simulate", "--set", "scenario.dt=1e-3", "--no-progress"],
        "--set scenario.dt = 1e-3: conflicts with scenario.excitation.casing_random.band = [10.0, 1000.0] of the "
        "model <built-in>: must resolve the random excitation scenario.excitation.casing_random's band up to 1000 Hz: "
        "its Nyquist frequency 1 / (2 dt) must lie above the band, so dt < 0.0005 s",
    ),
    (
        ["ensemble", "--seeds", "2", "--against", "cable.d=0.02"],
        "--against cable.d = 0.02: conflicts with casing.d_inner = 0.004 of the model <built-in>: must be larger "
        "than cable.d = 0.02 m",
    ),
    (["simulate", "--set", "casing.d_inner=0.001", "--no-progress"], "--set casing.d_inner = 0.001: must be larger"),
    # --workers sizes a local cluster only; a varied seed set by hand is named as the option, before any run
    (["study", "--scheduler", "serial", "--workers", "0"], "--workers = 0: must be an integer >= 1"),
    (["ensemble", "--seeds", "2", "--workers", "2"], "--workers = 2: is the number of workers of a local cluster"),
    (
        ["ensemble", "--seeds", "2", "--against", "scenario.excitation.casing_random.seed=3"],
        "--against scenario.excitation.casing_random.seed = 3: must not set the seeds that the ensemble varies",
    ),
    (
        ["ensemble", "--seeds", "2", "--set", "scenario.excitation.casing_random.seed=3"],
        "--set scenario.excitation.casing_random.seed = 3: must not set the seeds",
    ),
    # an ensemble CSV is no time record
    (["bands", "ens.csv"], "RECORD = 'ens.csv': is an ensemble CSV (band levels per seed, written by 'cablecasing "),
    (["spectrum", "ens.csv"], "RECORD = 'ens.csv': is an ensemble CSV (band levels per seed, written by 'cablecasing "),
]
INTERNAL = (
    *("freqs_hz", "f_res_hz", "freq_resolution_hz", "modes =", "count =", "skip =", "duration =", "path ="),
    *("model_file", "prefix =", "bounds =", "seed =", "--set scenario.excitation", "n_workers", "overrides"),
)


@pytest.mark.parametrize("argv,message", CASES, ids=[" ".join(c[0]) for c in CASES])
def test_an_error_names_the_option_typed(files, capsys, argv, message):
    before = sorted(p.name for p in files.iterdir())
    code = main(argv)
    out, err = capsys.readouterr()
    err = err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    line = err[0].split("error: ", 1)[1]
    assert line.startswith(message), line
    # (an internal name nowhere, but where the option the user typed is itself spelled so: --set KEY)
    assert not any((line.startswith(name) or f" {name}" in line) and name not in message for name in INTERNAL), line
    assert out == ""  # (before any work: a study's header is not printed)
    assert sorted(p.name for p in files.iterdir()) == before  # (nothing created)


def test_a_loss_factor_hint_names_the_options(files, capsys):
    assert main(["identify", "loss-factor", "frf.csv", "--count", "3"]) == 2
    err = capsys.readouterr().err
    assert "give the resonances themselves (--freqs) or a smaller --count" in err and "f_res_hz" not in err


def test_modes_beyond_a_bodys_degrees_of_freedom_warn(capsys):
    assert main(["modes", "--count", "100000", "--json"]) == 0
    out, err = capsys.readouterr()
    counts = {body: len(f) for body, f in json.loads(out).items()}
    assert counts and all(n < 100000 for n in counts.values())
    assert err.strip().splitlines() == [
        f"cablecasing: warning: --count = 100000: the {body} of <built-in> has only {n} modes (one per free degree "
        f"of freedom of its 35 elements); all {n} are printed"
        for body, n in counts.items()
    ]
    assert main(["modes", "--count", "3"]) == 0 and capsys.readouterr().err == ""


def test_a_study_says_the_size_it_resumes_at(tmp_path, capsys, monkeypatch):
    """`study --samples 2` in the folder of a study of 38 base points resumes at 304 runs (a study is
    never shrunk): the header says 304, not the 16 that --samples 2 rounds up to."""
    from cablecasing_core import studies

    (tmp_path / "st").mkdir()
    (tmp_path / "st" / "study.csv").write_text("index,status\n")
    (tmp_path / "st" / "study.csv.meta.json").write_text(json.dumps({"n_base": 38}))
    monkeypatch.setattr(studies, "run_study", lambda *a, **k: pytest.fail("stop here"))
    with pytest.raises(pytest.fail.Exception):
        main(["study", "--samples", "2", "--scheduler", "serial", "--out", str(tmp_path / "st")])
    head = capsys.readouterr().out.splitlines()
    assert head[1].startswith(
        f"#   304 runs: 38 base points x 8, the size of the study in {tmp_path / 'st' / 'study.csv'}: --samples 2 "
        "asks for 16 runs, and a study is never shrunk"
    ), head
    # (and what excitation each sample runs: the model's own seed, named)
    assert len(head) == 3 and head[2].startswith(
        "#   each sample: one run on the model's own random excitation (scenario.excitation.casing_random.seed = 1)"
    ), head


def test_bands_of_an_ensemble_csv_names_pool(files, capsys):
    """It read the seed column as the time axis: '--skip = 0.05: must leave at least 16 samples of the
    2 s record ens.csv (3 samples at dt = 1 s)'."""
    assert main(["bands", "ens.csv"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith("not a time record: 'cablecasing pool ens.csv' prints its statistics"), err


@pytest.mark.parametrize(
    "argv,message",
    [
        (
            ["--vary", "casing.E=2e9:1e10"],
            "--vary = ['casing.E']: must name the parameters of the study in {csv} in its order, ['casing.E', "
            "'contact.friction'] (its columns and design follow that order), to resume it; or choose another --out",
        ),
        (
            ["--vary", "contact.friction=0.05:0.2", "--vary", "casing.E=2e9:1e10"],
            "--vary = ['contact.friction', 'casing.E']: must name the parameters of the study in {csv} in its order",
        ),
        (
            ["--vary", "casing.E=2e9:1e10", "--vary", "contact.friction=0.05:0.2", "--seed", "2"],
            "--seed = 2: must be what the study in {csv} was run with, 0, to resume it; or choose another --out",
        ),
        (
            ["--vary", "casing.E=2e9:1e10", "--vary", "contact.friction=0.05:0.2", "--duration", "0.45"],
            "--duration = 0.45: must be what the study in {csv} was run with, 0.5, to resume it",
        ),
    ],
)
def test_a_study_that_would_not_resume_names_the_option_before_its_header(tmp_path, capsys, monkeypatch, argv, message):
    """A study in --out of other parameters printed the study's header, then 'bounds = [...]'."""
    from cablecasing_core import studies

    st = tmp_path / "st"
    st.mkdir()
    (st / "study.csv").write_text("index,status\n")
    meta = {"seed": 0, "bounds": {"casing.E": [2e9, 1e10], "contact.friction": [0.05, 0.2]}}
    meta["evaluate_kwargs"] = {"model_file": None, "duration": 0.5, "skip": 0.05}  # (4 lines in oct1: no warning)
    (st / "study.csv.meta.json").write_text(json.dumps(meta))
    monkeypatch.setattr(studies, "run_study", lambda *a, **k: pytest.fail("a study started"))
    assert main(["study", "--duration", "0.5", *argv, "--scheduler", "serial", "--out", str(st)]) == 2
    out, err = capsys.readouterr()
    err = err.strip().splitlines()
    assert out == "" and len(err) == 1, err
    assert err[0].startswith(f"cablecasing: error: {message.format(csv=st / 'study.csv')}"), err
