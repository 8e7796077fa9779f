"""``cablecasing study`` on a model other than the built-in one, over parameters other than the
paper's: bounds from --vary and --vary-file checked against the model and the schema before any
run, the runs are what they claim to be, tables labelled by band, a non-zero exit when all fail."""

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.records import after_skip
from cablecasing_core.studies import load_results, octave_rms

CASING_ONLY = """
[geometry]
n_elements = 12
points = [[0.0, 0.0, 0.0], [0.3, 0.0, 0.0], [0.6, 0.1, 0.0]]

[casing]
E = 5.0e9
rho = 4850.0
d_outer = 0.0095
d_inner = 0.004
alpha = 11.1
beta = 4.23e-5

[scenario]
duration = 0.15
seed = 3

[scenario.excitation.shaker]
target = "casing.A.z"
kind = "random"
rms = 5.0
"""


@pytest.fixture
def other_model(tmp_path):
    p = tmp_path / "casing_only.toml"
    p.write_text(CASING_ONLY)
    return p


def test_a_study_of_another_model_over_other_parameters(other_model, tmp_path, capsys):
    out = tmp_path / "st"
    args = ["study", str(other_model), "--vary", "casing.E=2e9:1e10", "--vary", "casing.rho=4000:6000"]
    assert main(args + ["--samples", "8", "--scheduler", "serial", "--out", str(out)]) == 0
    text = capsys.readouterr()
    res = load_results(out / "study.csv")
    assert res.parameters == ("casing.E", "casing.rho") and len(res) == 8 and np.all(res.ok)  # 2 x (2 + 2)
    # a row is the model's run with that row's parameters: recomputed here with simulate + octave_rms
    model = cc.load_model(other_model)
    i = 5
    run = cc.simulate(model.with_overrides(dict(zip(res.parameters, res.X[i].tolist()))))
    keep = after_skip(run.time, 0.05)
    ref = octave_rms(run.support_force("casing.B.Fz")[keep], 1 / (run.time[1] - run.time[0]), "table3")
    np.testing.assert_array_equal(res.Y[i], ref.rms)
    # the tables name the bands with their edges, and the study is too small to mean much: it says so
    squeezed = " ".join(text.out.split())
    assert "band oct1 oct2 oct3" in squeezed and "11-22 22-44 44-88" in squeezed
    assert "no Sobol indices: they need 4 complete base points, this study has 2" in text.err
    assert "Pearson correlation" in text.out and "Spearman correlation" in text.out
    assert "indicative only" in text.err and (out / "correlations.png").stat().st_size > 10_000
    # --vary-file gives the same study (same bounds, same design): nothing is run again
    vary = tmp_path / "vary.toml"
    vary.write_text("casing.E = [2e9, 1e10]\ncasing.rho = [4000.0, 6000.0]\n")
    calls_before = (out / "study.csv").read_text()
    assert (
        main(
            [
                "study",
                str(other_model),
                "--vary-file",
                str(vary),
                "--samples",
                "8",
                "--scheduler",
                "serial",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    assert (out / "study.csv").read_text() == calls_before


@pytest.mark.parametrize(
    "vary, fragment",
    [
        ([], "the paper's six parameters are the default"),  # this model has no cable and no axial drive
        (["--vary", "cable.E=3e10:8e10"], "is not a numeric parameter of the model"),
        (["--vary", "casing.E=-1:1e10"], "allowed range"),
        (["--vary", "geometry.n_elements=10:20"], "continuous (float) keys only"),
        (["--vary", "casing.E=2e9"], "KEY=LOW:HIGH"),
        (["--vary", "casing.E=1e10:2e9"], "lower bound must be below"),
    ],
)
def test_bounds_are_checked_before_any_run(other_model, tmp_path, capsys, vary, fragment):
    out = tmp_path / "st"
    assert main(["study", str(other_model), *vary, "--samples", "8", "--scheduler", "serial", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert fragment in err and err.count("\n") == 1  # one line
    assert not out.exists()  # nothing written


def test_a_study_whose_settings_make_every_run_fail_is_refused_before_it_creates_anything(
    other_model, tmp_path, capsys
):
    # (issue 26: before, every sample ran in full and failed; now the settings are refused first)
    out = tmp_path / "st"
    args = ["study", str(other_model), "--vary", "casing.E=2e9:1e10", "--samples", "6", "--scheduler", "serial"]
    assert main(args + ["--duration", "0.05", "--out", str(out)]) == 2  # 0.05 s leaves nothing after skip
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        "cablecasing: error: --duration = 0.05: must leave at least 0.09091 s after skip = 0.05 s for band 'oct1' "
        "(11-22 Hz)"
    ]
    assert not out.exists()
    # a skip the user gave that leaves too little of the record is the option blamed, not --duration
    assert main(args + ["--duration", "0.2", "--skip", "0.3", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        "cablecasing: error: --skip = 0.3: must leave at least 0.09091 s of the 0.2 s record for band 'oct1' (11-22 Hz)"
    ]
    # (also a skip shorter than the record, where the record alone would do)
    assert main(args + ["--duration", "0.2", "--skip", "0.15", "--out", str(out)]) == 2
    assert "error: --skip = 0.15: must leave at least 0.09091 s of the 0.2 s record" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize(
    "given, said",
    [
        (
            ["--set", "scenario.duration=0.08", "--skip", "0"],
            "scenario.duration = 0.08: must leave at least 0.09091 s after skip = 0 s",
        ),
        (
            ["--set", "scenario.duration=0.1"],
            "scenario.duration = 0.1: must leave at least 0.09091 s after skip = 0.06 s",
        ),
        (["--set", "scenario.duration=0.1", "--against", "scenario.dt=5e-6"], "scenario.duration = 0.1: must leave"),
        (["--duration", "0.2", "--skip", "0.15", "--against", "scenario.dt=5e-6"], "--skip = 0.15: must leave"),
    ],
)
def test_an_ensemble_too_short_for_its_bands_blames_what_the_user_gave(given, said, capsys):
    """A record too short whatever the skip is the duration's fault (the model's, named by its key,
    when --duration is not given); a skip the user gave that leaves too little of a long enough
    record is the skip's; the default skip is never blamed as if given (also with --against, where
    both ensembles take the first's default skip). Refused before any run."""
    assert main(["ensemble", "--seeds", "2", *given]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("cablecasing: error: " + said), err


def test_a_study_of_a_built_in_specimen_by_name_runs_it_from_any_folder(tmp_path, monkeypatch, capsys):
    """``cablecasing study installed`` (docs/studies.md; here ``default``, the same path and a
    tenth of the cost) from a folder that holds no file of that name: the rows are the built-in
    specimen's runs, not a refusal of a file './default'."""
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "st"
    args = ["study", "default", "--vary", "contact.friction=0.05:0.2", "--samples", "6", "--duration", "0.1"]
    assert main(args + ["--skip", "0.0", "--scheduler", "serial", "--out", str(out)]) == 0
    assert "study of <built-in>:" in capsys.readouterr().out
    res = load_results(out / "study.csv")
    assert len(res) == 6 and np.all(res.ok)
    model = cc.load_model("default").with_overrides({"contact.friction": float(res.X[1, 0]), "scenario.duration": 0.1})
    run = cc.simulate(model)
    ref = octave_rms(run.support_force("casing.B.Fz"), 1 / (run.time[1] - run.time[0]), "table3")
    np.testing.assert_array_equal(res.Y[1], ref.rms)


def test_a_study_says_how_many_runs_warned_and_its_file_which(tmp_path, capsys):
    """A study whose runs warn (contact.damping of 5e4-2e5 kg/s on the built-in specimen, where the
    switch law's contact Newton does not converge in a few steps: docs/time_domain.md, "Contact",
    item 5) says each run's warnings and then how many runs warned; its CSV says which, word for
    word what the runs said."""
    out = tmp_path / "st"
    args = ["study", "default", "--vary", "contact.damping=5e4:2e5", "--samples", "6", "--duration", "0.1"]
    assert main(args + ["--skip", "0.0", "--scheduler", "serial", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    res = load_results(out / "study.csv")
    n = int(res.warned.sum())
    assert n >= 1 and f"{n} of 6 runs warned" in err, err
    for text in res.warnings[res.warned]:  # (each message said above, by this run or one that said it first)
        for m in text.split(" | "):
            assert "the contact Newton did not converge in" in m, text
            assert any(f"sample {j}: {m}" in err for j in res.index), (m, err)


def _without(modules, code, args, cwd):
    """``code`` (Python) with ``args`` in a new interpreter where ``modules`` cannot be imported (an
    install without the extra 'study'): (status, stdout, stderr lines)."""
    import subprocess
    import sys

    hide = f"import sys\nfor m in {tuple(modules)!r}: sys.modules[m] = None\n"
    proc = subprocess.run(
        [sys.executable, "-c", hide + code, *args], cwd=cwd, capture_output=True, text=True, timeout=120
    )
    return proc.returncode, proc.stdout, proc.stderr.strip().splitlines()


CLI = "from cablecasing_core.cli import main\nsys.exit(main(sys.argv[1:]))"
DASK = ("dask", "distributed")
STUDY = ["study", "--samples", "3", "--vary", "casing.E=2e9:1e10", "--duration", "0.16", "--out", "st"]
# (the packages with pyproject.toml's version ranges: the distribution cablecasing is not on the package index)
CHECKOUT = "(from a checkout: pip install '.[study]')"
EXTRA = f"which is not installed: pip install 'SALib>=1.5' {CHECKOUT}"
DASK_EXTRA = f"which is not installed: pip install 'dask[distributed]>=2024.1' {CHECKOUT}"


@pytest.mark.parametrize(
    "hidden,argv,message",
    [
        (
            ("SALib", *DASK),
            STUDY,
            "--scheduler = 'local': a study on a local dask cluster needs the optional packages SALib and "
            "dask[distributed], which are not installed: pip install 'SALib>=1.5' 'dask[distributed]>=2024.1' "
            + CHECKOUT,
        ),
        (
            DASK,
            STUDY,
            f"--scheduler = 'local': a study on a local dask cluster needs the optional package "
            f"dask[distributed], {DASK_EXTRA}; or --scheduler serial, which needs SALib only",
        ),
        (("SALib",), [*STUDY, "--scheduler", "serial"], f"study: needs the optional package SALib, {EXTRA}"),
        (
            DASK,
            ["ensemble", "--seeds", "2", "--duration", "0.16", "--scheduler", "local", "--out", "e.csv"],
            f"--scheduler = 'local': an ensemble on a local dask cluster needs the optional package dask[distributed], "
            f"{DASK_EXTRA}; or --scheduler serial, which needs no dask",
        ),
        (
            ("SALib",),
            ["report", "--duration", "0.16", "--seeds", "2", "--out", "rep"],
            f"--study-samples = 32: must be 0 (no study): a study needs the optional package SALib, {EXTRA}",
        ),
    ],
    ids=["study-local", "study-no-dask", "study-serial", "ensemble-local", "report"],
)
def test_a_study_without_its_extra_is_one_line_before_anything_is_made(tmp_path, hidden, argv, message):
    """Without dask or SALib (the extra 'study') a study, an ensemble on dask and a report with a study
    are refused with one line naming the packages and the extra, status 2, before any file or folder
    (an internal error, status 1, and an empty --out folder)."""
    code, out, err = _without(hidden, CLI, argv, tmp_path)
    assert (code, err) == (2, [f"cablecasing: error: {message}"]), (out, err)
    assert list(tmp_path.iterdir()) == []


def test_a_serial_study_needs_no_dask(tmp_path):
    """A serial study runs without dask installed (SALib only)."""
    code = (
        "from cablecasing_core.studies import run_study\n"
        "res = run_study('s.csv', 'cablecasing_core.studies._stand_ins:analytic_evaluate', n_samples=8, seed=1,\n"
        "    bounds={'casing.E': (2e9, 1e10), 'contact.friction': (0.05, 0.2)}, scheduler='serial')\n"
        "print(len(res.index), 'dask' in sys.modules and sys.modules['dask'] is not None)"
    )
    status, out, err = _without(DASK, code, [], tmp_path)
    assert status == 0, err
    assert out.split() == ["8", "False"]
