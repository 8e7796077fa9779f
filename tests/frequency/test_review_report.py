"""Defects of the report and the frequency response found by a review: the modes of a coarse mesh in
the report, a model with a cable but no casing, a TRFAM grid that misses resonance peaks, the
scalogram's natural frequencies and harmonics, ``--out``, a mode count beyond a body's modes, and
non-physical TRFAM frequencies."""

import copy
import warnings

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelError, ModelWarning
from cablecasing_core.files import output_folder
from cablecasing_core.frequency.modal import frequencies_up_to, mode_count
from cablecasing_core.frequency.trfam import MAX_FREQUENCY_HZ, MIN_FREQUENCY_HZ, half_power_bandwidths


def coarse(n_elements=2):
    """The built-in specimen meshed with ``n_elements`` elements (6 (n + 1) - 12 modes per clamped body)."""
    return cc.load_model().with_overrides({"geometry.n_elements": n_elements})


def cable_only(n_elements=6):
    """The specimen without its casing (and contact), its random excitation moved to cable.A.z."""
    d = copy.deepcopy(cc.load_model().data)
    del d["casing"], d["contact"]
    exc = d["scenario"]["excitation"]
    exc["cable_random"] = {**exc.pop("casing_random"), "target": "cable.A.z"}
    d["geometry"]["n_elements"] = n_elements
    return cc.model_from_dict(d, source="cable only")


@pytest.fixture
def quick_report(monkeypatch):
    """write_report with the time-domain runs and the figures drawn from them replaced by stubs: the
    modes.csv, parameters, TRFAM figure and what the scalogram and the page are given stay real."""
    from cablecasing_core import report
    from cablecasing_core.report import figures, page

    seen = {}
    monkeypatch.setattr(report, "run_variant", lambda *a, **k: None)
    for name in ("time_figure", "contact_figures", "band_figure", "psd_figure", "clear_study"):
        monkeypatch.setattr(figures, name, lambda *a, **k: None)
    monkeypatch.setattr(figures, "apparent_mass_figure", lambda *a, **k: None)
    monkeypatch.setattr(figures, "rms_table", lambda *a, **k: [])
    monkeypatch.setattr(
        figures,
        "scalogram_figure",
        lambda vs, path, natural, harmonics, skip, info=None: seen.update(natural=natural, harmonics=harmonics),
    )
    monkeypatch.setattr(page, "render", lambda *a: seen.update(harmonics_page=a[9]) or "<html></html>")
    return report.write_report, seen


# ------------------------------------------------------------------ 1: fewer than 10 modes per body
@pytest.mark.filterwarnings("ignore:geometry.n_elements = 2")  # (the loader's: contact on so coarse a mesh)
def test_the_report_writes_the_modes_a_coarse_body_has(tmp_path, quick_report):
    write_report, _ = quick_report
    model = coarse(2)
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        write_report(tmp_path / "r", model=model, duration=0.2, skip=0.06, seeds=2, study_samples=0, progress=False)
    lines = (tmp_path / "r" / "modes.csv").read_text().splitlines()
    assert lines[0] == "mode,casing [Hz],cable [Hz]"
    # clamped at both ends: 6 DOFs at each of the 3 nodes less the 12 clamped = 6 modes per body
    assert len(lines) == 1 + 6 == 1 + mode_count(model, "casing")
    got = np.array([[float(x) for x in line.split(",")[1:]] for line in lines[1:]])
    expected = np.column_stack([cc.natural_frequencies(model, b) for b in ("casing", "cable")])
    np.testing.assert_array_equal(got, expected)  # (written with repr: the same doubles)
    assert not [w for w in said if "count =" in str(w.message)]  # (the report asks for no more than exist)


# ------------------------------------------------------------------ 2: a cable without a casing
def test_a_cable_only_ensemble_asks_for_no_contact_times():
    """Contact needs both bodies: the cable-only ensemble runs (it failed with KeyError
    'evaluate returned no value for contact_time_0 ...')."""
    e = cc.studies.seed_ensemble(cable_only(), [1, 2], output="cable.B.Fz", duration=0.15)
    assert e.levels.shape == (2, 9) and e.contact_time.shape[1] == 0
    assert np.all(e.levels > 0)


def test_the_report_refuses_a_model_without_a_casing_before_writing(tmp_path):
    out = tmp_path / "r"
    with pytest.raises(ModelError) as err:
        cc.report.write_report(out, model=cable_only(), duration=0.2, seeds=2, study_samples=0, progress=False)
    assert err.value.key == "model" and "must have a casing" in str(err.value) and "casing.B.Fz" in str(err.value)
    assert not out.exists()


# ------------------------------------------------------------------ 3: a grid that misses peaks
def test_the_bandwidths_are_the_closed_forms():
    """Structural: eta f_n; viscous: 2 zeta f_n, zeta = alpha / (2 omega) + beta omega / 2 (a body
    without prestress or mounts: exact)."""
    m = cc.load_model()
    spec = m.bodies["cable"]
    fn, bs = half_power_bandwidths(m, "cable", "structural", 10.0, 200.0)
    np.testing.assert_array_equal(fn, [f for f in cc.natural_frequencies(m, "cable", 40) if 10 <= f <= 200])
    np.testing.assert_allclose(bs, spec.loss(fn) * fn, rtol=1e-9)  # (phi^T K phi / omega^2 = 1 to round-off)
    _, bv = half_power_bandwidths(m, "cable", "viscous", 10.0, 200.0)
    w = 2 * np.pi * fn
    np.testing.assert_allclose(bv, 2 * (spec.alpha / (2 * w) + spec.beta * w / 2) * fn, rtol=1e-9)
    assert not np.any(half_power_bandwidths(m, "cable", "none", 10.0, 200.0)[1])


def test_a_grid_wider_than_half_the_bandwidth_misses_the_peak_by_the_closed_form():
    """Near a resonance of half-power bandwidth b, |H| = peak / sqrt(1 + (2 (f - f_n) / b)^2); a grid
    of step df lands at worst df/2 from the peak: 1/sqrt(1 + (df/b)^2) of it. The cable's mode at
    20.15 Hz (eta = 0.02, b = 0.403 Hz), every offset of the grid tried: ``grid_peak_height``."""
    from cablecasing_core.frequency.trfam import PEAK_GRID_SHARE, FrequencyResponse, grid_peak_height
    from cablecasing_core.structure.assembly import assemble_body

    m = cc.load_model()
    (fn,), (b,) = half_power_bandwidths(m, "cable", "structural", 19.0, 21.5)
    system = assemble_body(m, "cable")
    fr, j, q = FrequencyResponse(system), system.prescribed_index("A", 1), system.prescribed_index("B", 1)

    def trfam_y(f):  # (cc.trfam(m, "cable.A.y", "cable.B.y", f, "structural"), its modal basis built once)
        return fr.support_forces(f, "structural", rows=[q], cols=[j])[:, 0, 0] / -((2 * np.pi * f) ** 2)

    fine = np.arange(19.0, 21.5, 0.0005)
    H = np.abs(trfam_y(fine))
    np.testing.assert_allclose(H, np.abs(cc.trfam(m, "cable.A.y", "cable.B.y", fine, "structural")), rtol=1e-12)
    above = fine[H >= H.max() / np.sqrt(2)]
    assert above[-1] - above[0] == pytest.approx(b, rel=0.06)  # (the other modes' background: 4 %)
    for df in (b / 2, 0.5, 1.0):
        worst = min(np.abs(trfam_y(np.arange(19.0 + o, 21.5, df))).max() for o in np.linspace(0.0, df, 21))
        bound = grid_peak_height(df, b)
        assert bound <= worst / H.max() <= bound + 0.05  # (the bound of one mode; the background adds < 5 %)
    # so df <= b/2 keeps every peak within 1 - 1/sqrt(1 + 0.5^2) = 11 %
    assert 1 - grid_peak_height(PEAK_GRID_SHARE * b, b) == pytest.approx(1 - 1 / np.sqrt(1.25), rel=1e-12)
    assert grid_peak_height(0.1, 0.0) == 0.0  # (an undamped mode's infinite peak)


def run_trfam(tmp_path, capsys, *extra):
    out = tmp_path / "t.csv"
    args = ["trfam", "--input", "cable.A.z", "--output", "cable.B.z", "--damping", "structural", "--out", str(out)]
    assert main(args + list(extra)) == 0
    return np.loadtxt(out, delimiter=",", skiprows=1), capsys.readouterr().err


def test_the_trfam_command_warns_of_a_grid_that_misses_a_peak(tmp_path, capsys):
    m = cc.load_model()
    fn = cc.natural_frequencies(m, "cable", 3)[2]
    b = 0.02 * fn  # eta f_n (cable.loss_factor = 0.02)
    table, err = run_trfam(tmp_path, capsys, "--fmin", "19", "--fmax", "21.5", "--df", "0.5")  # (the review's grid)
    assert "--df = 0.5 Hz is wider than half the half-power bandwidth of 1 of the 1 mode(s) of the cable" in err
    assert f"at {fn:.6g} Hz, is {b:.4g} Hz wide" in err and "--df 0.201 or less" in err and 0.201 <= b / 2
    fine, _ = run_trfam(tmp_path, capsys, "--fmin", "19", "--fmax", "21.5", "--df", "0.001")
    # the grid's nearest point, d = 0.153 Hz from the peak, reads the one mode's 1/sqrt(1 + (2 d/b)^2) = 0.796
    # of it, less the other modes' background (5.8 % here; the test above bounds it at 5 % of the peak): 8 %
    d = np.abs(table[:, 0] - fn).min()
    assert table[:, 3].max() / fine[:, 3].max() == pytest.approx(1 / np.sqrt(1 + (2 * d / b) ** 2), rel=0.08)
    assert table[:, 3].max() / fine[:, 3].max() >= 1 / np.sqrt(1 + (0.5 / b) ** 2)
    at_half, err = run_trfam(tmp_path, capsys, "--fmin", "19", "--fmax", "21.5", "--df", "0.201")
    assert err == "" and at_half[:, 3].max() / fine[:, 3].max() >= 1 / np.sqrt(1.25)
    _, err = run_trfam(tmp_path, capsys, "--df", "37")  # (10 to 1000 Hz: skips every resonance)
    assert "--df = 37 Hz is wider than half the half-power bandwidth of 26 of the 26 mode(s)" in err
    _, err = run_trfam(tmp_path, capsys, "--fmin", "19", "--fmax", "21.5", "--damping", "none")
    assert f"--damping none, so the TRFAM is infinite at the natural frequency {fn:.6g} Hz" in err
    assert "no grid resolves such a peak" in err
    _, err = run_trfam(tmp_path, capsys, "--fmin", "21", "--fmax", "40")  # (no mode in the range)
    assert err == ""


def test_the_reports_trfam_grid_resolves_every_peak():
    """A loss factor of 0.002 makes the casing's peaks 20 times narrower than the 0.25 Hz grid can
    resolve below 250 Hz; the grid's added points keep each within 3 % (one within b/8 of it)."""
    from cablecasing_core.report.figures import TRFAM_HZ, trfam_grid

    m = cc.load_model().with_overrides({"casing.loss_factor": 0.002})
    grid = trfam_grid(m, "casing")
    assert set(TRFAM_HZ) <= set(grid)
    fn, b = half_power_bandwidths(m, "casing", "structural", 20.0, 100.0)
    for f, w in zip(fn, b):
        near = np.linspace(f - w, f + w, 2001)
        H = np.abs(cc.trfam(m, "casing.A.z", "casing.B.z", near, "structural"))
        if H.max() < 10 * np.median(H):
            continue  # (a mode that z does not see)
        on = grid[(grid >= f - w) & (grid <= f + w)]
        got = np.abs(cc.trfam(m, "casing.A.z", "casing.B.z", on, "structural")).max()
        assert got >= H.max() / np.sqrt(1 + (1 / 4) ** 2) * 0.999  # 1/sqrt(1 + (b/8 / (b/2))^2) = 97 %
        base = np.abs(cc.trfam(m, "casing.A.z", "casing.B.z", TRFAM_HZ[np.abs(TRFAM_HZ - f) < 1], "structural"))
        assert base.max() < 0.9 * H.max()  # (the 0.25 Hz grid alone misses it)


# ------------------------------------------------------------------ 4, 5: the scalogram's lines
def test_the_scalogram_gets_every_mode_and_harmonic_to_2000_hz(tmp_path, quick_report):
    write_report, seen = quick_report
    model = cc.load_model()
    write_report(tmp_path / "r", model=model, duration=0.2, skip=0.06, seeds=2, study_samples=0, progress=False)
    every = cc.natural_frequencies(model, "casing")  # (all 204: an independent list)
    np.testing.assert_array_equal(seen["natural"], every[(every >= 20) & (every <= 2000)])
    assert max(seen["natural"]) > 1900  # (it stopped at mode 40, 1461 Hz)
    drive = model.scenario["excitation"]["cable_axial"]["frequency"]  # 50 Hz
    expected = [k * drive for k in range(1, int(2000 // drive) + 1)]
    assert seen["harmonics"] == seen["harmonics_page"] == expected and len(expected) == 40
    from cablecasing_core.report.page import _harmonics_note

    note = _harmonics_note(expected)
    assert "(50, 100, 150, 200, 250, 300, 350, 400, ... Hz: 8 drawn of the 40 up to 2000 Hz)" in note
    assert _harmonics_note([50.0, 100.0]) == "; dotted red: the drive and its harmonics (50, 100 Hz)"


def test_frequencies_up_to_are_those_of_all_modes():
    m = coarse(10)
    every = cc.natural_frequencies(m, "cable")
    for f_max in (30.0, 500.0, 1e5):
        np.testing.assert_array_equal(frequencies_up_to(m, "cable", f_max), every[every <= f_max])


# ------------------------------------------------------------------ 6: --out
def test_output_folder_refuses_an_empty_path_and_a_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ModelError, match=r"^--out = '': must name a folder \(an empty path would write"):
        output_folder("--out", "", "report.html")
    (tmp_path / "afile").write_text("x")
    with pytest.raises(ModelError, match=r"^--out = 'afile': is an existing file, not a folder"):
        output_folder("--out", "afile", "report.html")
    with pytest.raises(ModelError, match=r"^--out = 'afile/sub': lies under afile, an existing file, not a folder"):
        output_folder("--out", "afile/sub", "report.html")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]
    assert output_folder("--out", "new/sub", "report.html").is_dir()


def test_the_report_command_refuses_an_empty_out(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["report", "--out", "", "--no-progress"]) == 2
    assert "--out = '': must name a folder" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------ 7: a count beyond the modes
def test_natural_frequencies_warn_of_a_count_beyond_the_modes():
    m = cc.load_model()
    n = 6 * (35 + 1) - 12  # 36 nodes, both ends clamped
    with pytest.warns(ModelWarning, match=f"count = 1000000: the casing of <built-in> has only {n} modes"):
        assert len(cc.natural_frequencies(m, "casing", 10**6)) == n == mode_count(m, "casing")
    with pytest.warns(ModelWarning, match="all 204 are returned"):
        assert cc.modes(m, "casing", 205)[1].shape == (6 * 36, n)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cc.natural_frequencies(m, "casing", n)


# ------------------------------------------------------------------ 8: non-physical frequencies
@pytest.mark.parametrize(
    "freqs, said",
    [
        ([1e300], "freqs_hz = 1e+300: every frequency must lie from 1e-06 to 1e+06 Hz"),
        ([1e-300], "freqs_hz = 1e-300: every frequency must lie from 1e-06 to 1e+06 Hz"),
        ([10.0, 1.1e6], "freqs_hz = 1100000.0: every frequency must lie"),
        (True, "freqs_hz = True: must be frequencies in Hz (numbers, not True or False)"),
        ([True, 2.0], "freqs_hz = [True, 2.0]: must be frequencies in Hz"),
        (np.array([False]), "freqs_hz = [False]: must be frequencies in Hz"),
    ],
)
def test_trfam_refuses_non_physical_frequencies(freqs, said):
    m = cc.load_model()
    for call in (
        lambda: cc.trfam(m, "casing.A.z", "casing.B.z", freqs),
        lambda: cc.trfam_matrix(m, "casing", "A", "B", freqs),
    ):
        with pytest.raises(ModelError) as err:
            call()
        assert str(err.value).startswith(said)


def test_trfam_at_its_limits_is_finite_and_the_cli_shares_them(tmp_path, capsys):
    m = cc.load_model()
    H = cc.trfam(m, "casing.A.z", "casing.B.z", [MIN_FREQUENCY_HZ, MAX_FREQUENCY_HZ])
    assert np.all(np.isfinite(H))
    assert main(["trfam", "--fmin", "1e-7", "--fmax", "1"]) == 2
    assert "--fmin = 1e-07: must be a number in [1e-06, 1e+06] in Hz" in capsys.readouterr().err
