"""The band advice of ``cablecasing geometry`` (structure/route_summary.py, ``band_advice``): the bending
wavelength at the excitation's top against the dispersion relation by hand and against the modes of a
clamped-clamped beam, the elements per wavelength against how far those modes have converged,
Newmark's period error against the average acceleration rule stepped by hand, and which models warn."""

import importlib.resources
import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from cablecasing_core import load_model, model_from_dict
from cablecasing_core.cli import main
from cablecasing_core.frequency.modal import modes
from cablecasing_core.structure.assembly import assemble_body
from cablecasing_core.structure.route_summary import (
    ADVISED_PER_WAVELENGTH,
    MIN_PER_WAVELENGTH,
    band_advice,
    band_advice_warnings,
    bending_wavelength,
    excitation_top,
)
from cablecasing_core.timedomain.accuracy import newmark_period_error, step_for_period_error

ROOT = Path(__file__).resolve().parents[2]
E, RHO, L = 2.1e11, 7850.0, 1.0  # Pa, kg/m3, m: a steel wire


def _wire(n, d, tension=0.0, f=None, dt=1e-5):
    """A straight steel cable of diameter d (m) along 1 m, clamped at both ends, n elements, under
    ``tension`` (N), driven by a harmonic at ``f`` (Hz) if given."""
    data = {
        "geometry": {"points": [[0, 0, 0], [L, 0, 0]], "n_elements": n, "curve": "polyline"},
        "cable": dict(E=E, nu=0.3, rho=RHO, d=d, supports={"A": "clamped", "B": "clamped"}),
        "loads": {"cable_tension": tension},
        "scenario": {"dt": dt},
    }
    if f is not None:
        data["scenario"]["excitation"] = {
            "h": {"target": "cable.A.y", "kind": "harmonic", "frequency": float(f), "amplitude": 1e-6}
        }
    return model_from_dict(data)


def _bending(model):
    """The frequencies (Hz) of a straight cable's bending modes in one plane: its modes without axial
    or torsional motion (those have u and the twist zero to rounding), each pair (y, z) once."""
    f, shapes = modes(model, "cable")
    share = (shapes[0::6] ** 2 + shapes[3::6] ** 2).sum(0) / (shapes**2).sum(0)
    return np.sort(f[share < 1e-6])[::2]


def test_the_wavelength_solves_the_dispersion_relation_of_a_beam_under_axial_force():
    """EI k^4 + P k^2 = rho A w^2, solved by hand (the closed form, and numpy's roots of the quartic),
    for the built-in specimen's cable and casing as the model file gives them (EI from E and the
    diameter or the effective I; rho A from the geometric area; P the tension, minus it on the
    casing), without a force (the beam's 2 pi (EI / (rho A w^2))^(1/4)), and with a tension that
    dominates (a string's sqrt(P / (rho A)) / f). Tolerances: rounding (1e-12), and for the string
    the beam's share, EI k^2 / P = 1.6e-3 of k^2."""
    m = load_model("installed")
    T, f = m.loads["cable_tension"], 2000.0
    w = 2 * np.pi * f
    cab, cas = m.data["cable"], m.data["casing"]
    hand = {
        "cable": (cab["E"] * np.pi * cab["d"] ** 4 / 64, cab["rho"] * np.pi * cab["d"] ** 2 / 4, T),
        "casing": (cas["E"] * cas["I"], cas["rho"] * np.pi * (cas["d_outer"] ** 2 - cas["d_inner"] ** 2) / 4, -T),
    }
    got = band_advice(m.with_overrides({"scenario.excitation.casing_random.band": [10.0, f]}))
    assert got["f_top_hz"] == f
    for body, (EI, rhoA, P) in hand.items():
        k2 = (-P + math.sqrt(P * P + 4 * EI * rhoA * w * w)) / (2 * EI)
        roots = np.roots([EI, 0.0, P, 0.0, -rhoA * w * w])
        k = max(r.real for r in roots if abs(r.imag) < 1e-9 * abs(r))
        assert got["bodies"][body]["wavelength_m"] == pytest.approx(2 * np.pi / math.sqrt(k2), rel=1e-12)
        assert got["bodies"][body]["wavelength_m"] == pytest.approx(2 * np.pi / k, rel=1e-9)
        assert got["bodies"][body]["axial_force_N"] == P
        n = m.geometry["n_elements"]
        assert got["bodies"][body]["elements_per_wavelength"] == pytest.approx(2 * np.pi / k * n / 0.849947, rel=1e-5)
    # the compression shortens the casing's wave, the tension lengthens the cable's
    EI, rhoA, _ = hand["casing"]
    assert (
        bending_wavelength(EI, rhoA, -T, f) < bending_wavelength(EI, rhoA, 0.0, f) < bending_wavelength(EI, rhoA, T, f)
    )
    assert bending_wavelength(EI, rhoA, 0.0, f) == pytest.approx(2 * np.pi * (EI / (rhoA * w * w)) ** 0.25, rel=1e-12)
    EI, rhoA = hand["cable"][:2]
    P = 1e5  # N: a string's wave, k^2 = rho A w^2 / (P (1 + EI k^2 / P)), lambda longer by EI k^2 / (2 P)
    share = EI * rhoA * w * w / P**2  # (EI k^2 / P at the string's k, 1.9e-4)
    assert bending_wavelength(EI, rhoA, P, f) == pytest.approx(math.sqrt(P / rhoA) / f, rel=share)


def test_the_wavelength_counts_a_tensioned_clamped_beam_s_modes():
    """A clamped-clamped beam's mode j has k L close to (j + 1/2) pi, so below f lie floor(2 L / lambda(f)
    - 1/2) bending modes in a plane: counted on a 3 mm wire of 160 elements (converged: below) under 0
    and 300 N, the count follows the wavelength with the tension (P = +T on the cable) and not the one
    without it (one mode fewer at 500 and 1000 Hz)."""
    d = 0.003
    EI, rhoA = E * np.pi * d**4 / 64, RHO * np.pi * d**2 / 4
    for T in (0.0, 300.0):
        f_modes = _bending(_wire(160, d, T))
        for f in (500.0, 1000.0):
            lam = band_advice(_wire(160, d, T, f=f))["bodies"]["cable"]["wavelength_m"]
            assert lam == pytest.approx(bending_wavelength(EI, rhoA, T, f), rel=1e-12)
            assert np.count_nonzero(f_modes < f) == math.floor(2 * L / lam - 0.5), (T, f)
            if T:
                assert (
                    math.floor(2 * L / bending_wavelength(EI, rhoA, 0.0, f) - 0.5) == np.count_nonzero(f_modes < f) + 1
                )


def test_elements_per_wavelength_bound_the_error_of_a_clamped_beam_s_modes():
    """The advice's thresholds (route_summary, from docs/time_domain.md "The mesh": the specimen's modes
    at most 0.5-0.6 % high with 4 elements per wavelength, 1.7-2.5 % with 2.9, near 0.1 % with 6) hold on
    a straight clamped-clamped beam (10 mm steel, 1 m, 40 elements): each bending mode's error against
    160 elements (whose own error is (40/160)^4 = 1/256 of the 40 elements', so the reference is exact
    to 0.4 % of the error) stays below the figure of the elements per wavelength that band_advice
    gives at the mode's frequency; the advice warns exactly below 4; the n_elements it names for 6 per
    wavelength takes the mode at 2.9 per wavelength to within 0.15 %."""
    d = 0.01
    ref, coarse = _bending(_wire(160, d)), _bending(_wire(40, d))
    rows = []
    for j in range(5, 36):
        advice = band_advice(_wire(40, d, f=ref[j]))
        per = advice["bodies"]["cable"]["elements_per_wavelength"]
        err = coarse[j] / ref[j] - 1
        rows.append((per, err))
        assert err > 0  # (a consistent mass and Hermite cubics: the modes converge from above)
        bound = 0.0015 if per >= ADVISED_PER_WAVELENGTH else 0.006 if per >= MIN_PER_WAVELENGTH else 0.025
        if per >= 2.9:
            assert err < bound, (j, per, err)
        warned = [w for w in band_advice_warnings(advice) if "per wavelength" in w]  # (not the step's, above 5.5 kHz)
        assert bool(warned) == (per < MIN_PER_WAVELENGTH), (j, per, warned)
    pers = [p for p, _ in rows]
    assert min(pers) < 2.9 and max(pers) > ADVISED_PER_WAVELENGTH  # (the range covers every threshold)
    # the mode at about 2.9 per wavelength, meshed as the warning says
    j = 5 + int(np.argmin([abs(p - 2.9) for p in pers]))
    advice = band_advice(_wire(40, d, f=ref[j]))
    n = advice["n_elements_for_advised"]
    assert f"geometry.n_elements = {n} gives 6 on each" in band_advice_warnings(advice)[0]
    assert n == math.ceil(6 * L / advice["bodies"]["cable"]["wavelength_m"])
    assert _bending(_wire(n, d))[j] / ref[j] - 1 < 0.0015


def _newmark_period(w, dt, periods=400):
    """The period (s) of an undamped oscillator u'' = -w^2 u (u0 = 1, v0 = 0) stepped by hand with
    Newmark's average acceleration rule (gamma = 1/2, beta = 1/4): u1 = u0 + dt v0 + dt^2/4 (a0 + a1),
    v1 = v0 + dt/2 (a0 + a1), a1 = -w^2 u1; measured from the first and last upward zero crossings
    (linear interpolation: a sine is straight at its zero, so the crossing's error is O(dt^3))."""
    n = int(periods * 2 * np.pi / w / dt) + 2
    u, v = 1.0, 0.0
    a = -w * w * u
    us = np.empty(n)
    for i in range(n):
        us[i] = u
        u_new = (u + dt * v + dt * dt / 4 * a) / (1 + w * w * dt * dt / 4)
        a_new = -w * w * u_new
        v += dt / 2 * (a + a_new)
        u, a = u_new, a_new
    up = np.flatnonzero((us[:-1] < 0) & (us[1:] >= 0))
    t = (up - us[up] / (us[up + 1] - us[up])) * dt
    return (t[-1] - t[0]) / (len(t) - 1)


@pytest.mark.parametrize(("f", "dt"), [(1000.0, 1e-5), (2000.0, 1e-5), (5680.0, 1e-5), (2000.0, 2e-5)])
def test_the_period_error_is_newmark_s_on_a_single_oscillator(f, dt):
    """The oscillator's measured relative period error agrees with (2 pi f dt)^2 / 12 to within the
    next term of the series, (w dt)^2 / 15 of it (timedomain.accuracy.newmark_period_error: 0.1 % of itself at
    2 kHz and 1e-5 s, 0.8 % at 5680 Hz), plus 1e-3 of it for the crossings' timing."""
    w = 2 * np.pi * f
    measured = _newmark_period(w, dt) * f - 1
    said = float(newmark_period_error(f, dt))
    assert measured == pytest.approx(said, rel=(w * dt) ** 2 / 15 + 1e-3)
    assert measured == pytest.approx(w * dt / (2 * math.atan(w * dt / 2)) - 1, rel=1e-3)  # (the exact rate)


def test_the_advised_step_keeps_the_period_error_within_half_a_percent():
    """step_for_period_error gives a value of two significant digits with at most 0.5 %, and the next
    value of two digits would pass 0.5 %."""
    for f in (500.0, 1000.0, 2000.0, 3000.0, 7.0):
        dt = step_for_period_error(f, 0.005)
        assert float(f"{dt:.2g}") == dt
        assert (
            newmark_period_error(f, dt) <= 0.005 < newmark_period_error(f, dt + 10 ** (math.floor(math.log10(dt)) - 1))
        )


def test_the_band_s_top_is_the_highest_excitation_that_moves(tmp_path):
    """A random band to 800 Hz, a harmonic at 1200 Hz, an impulse of 0.5 ms (1/width = 2000 Hz), a
    harmonic of zero amplitude at 4000 Hz and a CSV table: the top is the impulse's, and the table is
    named as not counted (its content is not read)."""
    table = tmp_path / "drive.csv"
    table.write_text("time_s,u\n0,0\n0.001,1e-6\n0.002,0\n")
    data = load_model(None).to_dict()
    data["scenario"]["excitation"] = {
        "r": {"target": "casing.A.z", "kind": "random", "band": [10.0, 800.0], "rms": 1.0},
        "h": {"target": "cable.A.axial", "kind": "harmonic", "frequency": 1200.0, "amplitude": 1e-5},
        "i": {"target": "casing.A.y", "kind": "impulse", "width": 5e-4, "amplitude": 1e-5},
        "quiet": {"target": "casing.A.x", "kind": "harmonic", "frequency": 4000.0, "amplitude": 0.0},
        "table": {"target": "cable.A.x", "kind": "csv", "file": str(table)},
    }
    top = excitation_top(model_from_dict(data))
    assert top[0] == pytest.approx(2000.0, rel=1e-12) and "scenario.excitation.i," in top[1]
    assert band_advice(model_from_dict(data))["not_counted"] == ["scenario.excitation.table"]
    data["scenario"]["excitation"]["i"]["amplitude"] = 0.0
    assert excitation_top(model_from_dict(data))[0] == 1200.0
    del data["scenario"]["excitation"]["h"]
    assert excitation_top(model_from_dict(data))[0] == 800.0
    data["scenario"]["excitation"] = {"table": data["scenario"]["excitation"]["table"]}
    assert excitation_top(model_from_dict(data)) is None and band_advice(model_from_dict(data)) is None


@pytest.mark.parametrize(
    "source",
    [
        None,
        "installed",
        "examples/clipped_specimen.toml",
        "examples/installation.toml",
        "examples/straight_casing.toml",
    ],
)
def test_the_built_in_specimens_and_the_examples_do_not_warn(source):
    """At their defaults (1 kHz bands, a 2 ms impulse, 1e-5 s): 4.47-7.7 elements per wavelength (the
    least, clipped_specimen's cable on its longest element, 1.03 times the mean) and a period error of
    at most 0.033 %."""
    m = load_model(source if source is None or "/" not in source else ROOT / source)
    advice = band_advice(m)
    assert band_advice_warnings(advice) == []
    assert min(b["elements_per_wavelength"] for b in advice["bodies"].values()) > 4.4
    assert advice["period_error"] <= 3.3e-4


def test_a_2_khz_band_warns_in_geometry_and_not_at_load(tmp_path, capsys):
    """The review's case: the specimen driven to 2 kHz with a step of 4e-5 s. Loading the file says
    nothing of it (the advice is geometry's, as the bend's: a load warns in every command, modes and
    static included, which the scenario does not concern); `geometry` warns of both, naming the
    n_elements for 6 per wavelength (6 L / lambda of the cable, the shorter wave) and a step of 0.5 %,
    and its --json carries the figures."""
    m = load_model(None).with_overrides({"scenario.excitation.casing_random.band": [10.0, 2000.0], "scenario.dt": 4e-5})
    p = tmp_path / "m.toml"
    p.write_text(m.to_toml())
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        load_model(p)
    assert not [w for w in said if "per wavelength" in str(w.message) or "period error" in str(w.message)]
    advice = band_advice(m)
    cable = advice["bodies"]["cable"]
    assert cable["elements_per_wavelength"] == pytest.approx(4.60 / math.sqrt(2), rel=0.01)  # (lambda ~ f^-1/2)
    need = math.ceil(6 * 0.849947 / cable["wavelength_m"])
    assert main(["geometry", str(p)]) == 0
    cap = capsys.readouterr()
    assert f"geometry.n_elements = {need} gives 6 on each" in cap.err
    assert "fewer than 4 per wavelength" in cap.err
    assert "is 2.1 %, above 1 %: scenario.dt = 1.9e-05 s gives 0.5 %" in cap.err
    assert "  band top          2000 Hz: the upper edge of scenario.excitation.casing_random's random band" in cap.out
    assert main(["geometry", str(p), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)["band_advice"]
    assert out["n_elements_for_advised"] == need and out["dt_for_advised_s"] == 1.9e-5
    assert out["period_error"] == pytest.approx((2 * np.pi * 2000 * 4e-5) ** 2 / 12, rel=1e-12)


def test_with_clips_the_elements_per_wavelength_are_counted_on_the_longest_element():
    """geometry.nodes_at_clips (the default) cuts the route at the clips into spans of their own
    elements, which are not all the mean length: the advice counts the wavelength on the longest
    element, as the assembled casing has it, and its n_elements puts 6 on each body's wavelength on
    that mesh. Five clips on a straight 0.85 m route at 6 elements: one span of 0.265 m holds one
    element, 1.87 times the mean (the mean's count said 1.9 times too many per wavelength)."""
    data = load_model().to_dict()
    data["geometry"] = {"points": [[0.0, 0.0, 0.0], [0.85, 0.0, 0.0]], "curve": "polyline", "n_elements": 6}
    at = [0.85 * x for x in (0.14265, 0.23875, 0.39025, 0.70208, 0.84956)]  # (m)
    data["casing"]["clip"] = [{"at": a, "stiffness": [2.0e4, 5.0e4, 5.0e4]} for a in at]
    data["scenario"]["excitation"] = {
        "h": {"target": "casing.A.y", "kind": "harmonic", "frequency": 300.0, "amplitude": 1e-6}
    }
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = model_from_dict(data)
    advice = band_advice(model)
    # (the elements as assembled: a straight route, so the chords are the arc lengths, to rounding)
    longest = assemble_body(model, "casing", check_buckling=False).centerline.lengths.max()
    assert longest / (0.85 / 6) > 1.8  # (the case: far from equal elements)
    for body, b in advice["bodies"].items():
        assert b["elements_per_wavelength"] == pytest.approx(b["wavelength_m"] / longest, rel=1e-12), body
    shortest = min(b["wavelength_m"] for b in advice["bodies"].values())
    need = advice["n_elements_for_advised"]

    def longest_at(n):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m = model.with_overrides({"geometry.n_elements": n})
        return assemble_body(m, "casing", check_buckling=False).centerline.lengths.max()

    # 6 per wavelength on the advised mesh, and not on one element fewer (rel 1e-9: rounding of the chords)
    assert longest_at(need) * ADVISED_PER_WAVELENGTH <= shortest * (1 + 1e-9)
    assert longest_at(need - 1) * ADVISED_PER_WAVELENGTH > shortest * (1 + 1e-9)


def test_a_scenario_of_csv_tables_alone_is_named_not_counted_in_geometry(tmp_path, capsys):
    """Only a CSV excitation: no band top is known (the table is not read), and geometry says so
    naming the table, not that there is no excitation."""
    table = tmp_path / "drive.csv"
    table.write_text("time_s,u\n0,0\n0.001,1e-6\n0.002,0\n")
    text = (importlib.resources.files("cablecasing_core.model") / "specimens" / "default.toml").read_text()
    head = text.split("[scenario.excitation")[0]
    model = tmp_path / "tabled.toml"
    model.write_text(head + f'\n[scenario.excitation.table]\ntarget = "cable.A.x"\nkind = "csv"\nfile = "{table}"\n')
    assert band_advice(load_model(str(model))) is None
    assert main(["geometry", str(model)]) == 0
    out = capsys.readouterr().out
    assert "scenario.excitation.table (CSV tables) are the scenario's only excitations" in out, out
    # (review V, D10: the JSON said null with no reason; it says the text's)
    assert main(["geometry", str(model), "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got["band_advice"] is None
    why = "scenario.excitation.table (CSV tables) are the scenario's only excitations"
    assert got["band_advice_why"].startswith(why)
    assert main(["geometry", "--json"]) == 0  # (the built-in specimen: an advice, and no reason beside it)
    got = json.loads(capsys.readouterr().out)
    assert got["band_advice"]["f_top_hz"] > 0 and got["band_advice_why"] is None
