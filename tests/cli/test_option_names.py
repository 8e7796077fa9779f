"""An error in what a user typed names the option they typed (``--freqs``, ``--resolution``), not a
parameter of the function behind it (``freqs_hz``, ``freq_resolution_hz``) nor another option, and is
one line with exit status 2 before any work: the regression data of a review of the command line."""

import json

import numpy as np
import pytest

from cablecasing_core.cli import main


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
    return tmp_path


# (argv, the start of the message after "error: ", the internal names it must not show)
CASES = [
    (["spectrum", "r.csv", "--kind", "apparent-mass", "--input", "nope"], "--input = 'nope': must be a column of r"),
    (["identify", "damping", "r.csv", "--freqs", "0"], "--freqs = 0.0: every frequency must lie in the open interval"),
    (["identify", "damping", "r.csv", "--count", "100000"], "--count = 100000: must be at most "),
    (["identify", "damping", "r.csv", "--noise-floor", "-1"], "--noise-floor = -1.0: must be a positive number"),
    (["identify", "damping", "r.csv", "--channel", "nope"], "--channel = 'nope': must be one of casing.B.Fz"),
    (["identify", "damping", "dir.uff"], "file = 'dir.uff': is a folder, not a UFF file"),
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
]
INTERNAL = ("freqs_hz", "f_res_hz", "freq_resolution_hz", "modes =", "count =", "skip =", "duration =", "path =")


@pytest.mark.parametrize("argv,message", CASES, ids=[" ".join(c[0]) for c in CASES])
def test_an_error_names_the_option_typed(files, capsys, argv, message):
    before = sorted(p.name for p in files.iterdir())
    code = main(argv)
    out, err = capsys.readouterr()
    err = err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    line = err[0].split("error: ", 1)[1]
    assert line.startswith(message), line
    assert not any(line.startswith(name) or f" {name}" in line for name in INTERNAL), line
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
    assert len(head) == 2
