"""The force an end or all the mounts receive (docs/nvh.md, "Net forces and paths"): a record's
derived columns ``net.<A|B>.<c>`` (casing + cable at that end), ``paths.<F>`` (every end and clip)
and ``a+b``, checked against independent computations: the bodies' weight and the tension by
hand at rest, the TRFAM (a frequency-domain solve) with contact off, and band levels of a
synthetic record whose sum is known; and the report's net.B.Fz beside casing.B.Fz."""

import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelError
from cablecasing_core.records import Records, read_records, write_records
from cablecasing_core.studies import octave_rms

G = 9.81  # m/s2
#: Mass per length (kg/m) of the specimens' casing (rho 4850 kg/m3, d 9.5/4 mm) and cable (7850 kg/m3, 3 mm).
CASING_KG_M = 4850.0 * np.pi / 4 * (0.0095**2 - 0.004**2)
CABLE_KG_M = 7850.0 * np.pi / 4 * 0.003**2


def at_rest(data, duration):
    """The record of ``data`` (a model's dict) without its excitations, run for ``duration`` s: its
    static state, held (docs/installed.md, "At rest it stays at rest")."""
    data["scenario"]["excitation"] = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (a model without excitation warns that it stays at rest)
        return cc.simulate(cc.model_from_dict(data), duration=duration).records()


def test_the_sum_over_every_path_at_rest_is_the_weight_by_hand():
    """examples/installation.toml (isolated ends, two clips, a route of straights and two bends)
    with gravity: the cable lies on the wall at rest, and every path's force together is the two
    bodies' weight, g (m_casing + m_cable) per metre times the length of the elements. The nodes
    lie on the exact arcs and the elements are chords, shorter than their arc h by h^3 / (24 R^2):
    the length is 0.9825 m less arc h^2 / (24 R^2) for each bend (1.2e-4 m, 1.2e-4 of the weight).
    What is left, the elements that straddle a bend's end and the O(h^4) terms, is below 1e-5 of
    the weight; held at rest the record moves by less than 1e-7 of it. The paths' x and y vanish
    (the balance of the static state, 1e-10 N). Without the clips or the cable the sum would miss
    a third of the weight or more."""
    data = cc.load_model(Path(__file__).parents[2] / "examples" / "installation.toml").to_dict()
    data["loads"] = {"gravity": [0.0, 0.0, -G]}
    rec = at_rest(data, 0.002)
    h = 0.98252 / 64  # m, the elements' arc length (64 elements over the route)
    bends = ((0.15, np.pi / 3), (0.20, np.pi / 3))  # (radius m, angle rad)
    length = 0.15 + 0.15 + 0.316 + sum(R * a * (1 - h**2 / (24 * R**2)) for R, a in bends)
    weight = G * (CASING_KG_M + CABLE_KG_M) * length
    assert rec.column("contact.active")[0] > 0  # (the cable on the wall: contact forces, internal)
    np.testing.assert_allclose(rec.column("paths.Fz"), -weight, rtol=2e-5)
    assert np.max(np.abs(rec.column("paths.Fx"))) < 1e-6 * weight
    assert np.max(np.abs(rec.column("paths.Fy"))) < 1e-6 * weight
    assert rec.terms("paths.Fz") == (
        "casing.A.Fz",
        "casing.B.Fz",
        "cable.A.Fz",
        "cable.B.Fz",
        "casing.clip0.Fz",
        "casing.clip1.Fz",
    )
    # the same paths named one by one, through the ends' net forces: a sum of sums
    mine = rec.column("net.A.Fz + net.B.Fz + casing.clip0.Fz + casing.clip1.Fz")
    np.testing.assert_allclose(mine, rec.column("paths.Fz"), rtol=1e-14)
    assert abs(rec.column("casing.clip0.Fz")[0]) > 0.2 * weight  # (a path that matters)


def test_the_tension_loops_through_each_end_and_cancels_in_its_net_force():
    """A straight clamped route (0.5 m along x) with gravity and a cable tension T = 10 N: the cable
    pulls each support towards the other with T, the casing pushes it away with T (its compression
    -T, held by clamped ends), so cable.B.Fx = -T, casing.B.Fx = +T and net.B.Fx = 0 (and the
    opposite at A); by symmetry each end's net force carries half the weight, g (m_c + m_w) L / 2.
    To the static solver's tolerance (1e-10 of the largest load)."""
    T, L = 10.0, 0.5
    data = cc.load_model().to_dict()
    data["geometry"] = {"points": [[0.0, 0.0, 0.0], [L, 0.0, 0.0]], "n_elements": 20, "curve": "polyline"}
    data["loads"] = {"gravity": [0.0, 0.0, -G], "cable_tension": T}
    data["contact"]["friction_law"] = "regularized"
    rec = at_rest(data, 0.001)
    tol = 1e-8 * T
    for end, sign in (("B", 1.0), ("A", -1.0)):
        np.testing.assert_allclose(rec.column(f"casing.{end}.Fx"), sign * T, atol=tol)
        np.testing.assert_allclose(rec.column(f"cable.{end}.Fx"), -sign * T, atol=tol)
        np.testing.assert_allclose(rec.column(f"net.{end}.Fx"), 0.0, atol=tol)
        np.testing.assert_allclose(rec.column(f"net.{end}.Fz"), -G * (CASING_KG_M + CABLE_KG_M) * L / 2, rtol=1e-8)
    assert rec.unit("net.B.Mx") == "N.m" and rec.unit("net.B.Fx") == "N"


def test_the_net_end_force_with_contact_off_is_minus_the_sum_of_the_bodies_trfams():
    """Contact off, the built-in specimen's casing and cable both driven at A in z by one harmonic
    motion (130 Hz; the shifter housing and the lever moving together): in the steady state each
    body's force at B over the acceleration is minus its TRFAM (the TRFAM is the support's force on
    the body, the record the body's on the support), and net.B.Fz is minus their sum, in magnitude
    and phase. The Rayleigh alpha is raised to 200 1/s in both bodies (the TRFAM takes it too) so
    that the start's free vibration decays by e^(-100 t) before the 20 periods compared. Within
    2e-3: Newmark's period error (omega dt)^2 / 12 = 6e-6 at 130 Hz, times the nearest resonance's
    amplification, and what is left of the transient. The cable's share is 15 % of the casing's: a
    difference instead of the sum, or one sign of the two, is off by 30 %."""
    f0, duration = 130.0, 0.2
    data = cc.load_model().to_dict()
    data["contact"]["enabled"] = False
    for body in ("casing", "cable"):
        data[body]["alpha"] = 200.0
    data["scenario"]["excitation"] = {
        "housing": {"target": "casing.A.z", "kind": "harmonic", "frequency": f0, "amplitude": 1e-5},
        "lever": {"target": "cable.A.z", "kind": "harmonic", "frequency": f0, "amplitude": 1e-5},
    }
    model = cc.model_from_dict(data)
    rec = cc.simulate(model, duration=duration).records()
    window = rec.time > duration - 20 / f0 + 1e-9  # (20 whole periods: 2000 samples)
    phasor = np.exp(-2j * np.pi * f0 * rec.time[window])

    def amplitude(name):
        return 2 * np.mean(rec.column(name)[window] * phasor)

    a = amplitude("casing.A.az")
    np.testing.assert_array_equal(rec.column("casing.A.az"), rec.column("cable.A.az"))
    H_casing = cc.trfam(model, "casing.A.z", "casing.B.z", [f0])[0]
    H_cable = cc.trfam(model, "cable.A.z", "cable.B.z", [f0])[0]
    for name, H in (("casing.B.Fz", H_casing), ("cable.B.Fz", H_cable), ("net.B.Fz", H_casing + H_cable)):
        assert abs(amplitude(name) / a / -H - 1) < 2e-3, name
    assert abs(H_cable) > 0.1 * abs(H_casing)


# ------------------------------------------------------------------ a synthetic record: the spectrum of a sum
FS = 1e4
T = np.arange(20000) / FS  # 2 s: 100 Hz and 250 Hz on FFT lines (0.5 Hz)


def tones(path):
    """A record whose casing.B.Fz and cable.B.Fz carry one 5 N tone at 100 Hz with opposite signs
    (a loop through both bodies) and 0.4 N and 0.3 N in phase at 250 Hz: their sum holds 0.7 N at
    250 Hz alone."""
    loop = 5.0 * np.sin(2 * np.pi * 100 * T)
    own = np.sin(2 * np.pi * 250 * T)
    rec = Records(T, {"casing.B.Fz": loop + 0.4 * own, "cable.B.Fz": -loop + 0.3 * own}, {})
    write_records(path, rec)
    return path


def test_the_bands_of_the_net_force_are_those_of_the_summed_samples(tmp_path, capsys):
    """net.B.Fz's octave 4 (88-177 Hz) holds nothing (the loop cancels to round-off: under 1e-9 N
    of the 5 N tone) and its octave 5 (177-355 Hz) the 0.7 N tone's RMS 0.7/sqrt(2) (a tone on a
    line of a record of whole periods, through Hann's window: to round-off); the sum of the two
    columns' band powers would give 5 N at 100 Hz and 0.5/sqrt(2) at 250 Hz. The CSV's 9 digits
    bound the sum's error by 5e-9 of the 5 N."""
    path = tones(tmp_path / "r.csv")
    assert main(["bands", str(path), "--column", "net.B.Fz", "--skip", "0", "--out", str(tmp_path / "b.csv")]) == 0
    out = capsys.readouterr().out
    assert "net.B.Fz after 0 s" in out
    rows = {r.split(",")[0]: r.split(",") for r in (tmp_path / "b.csv").read_text().splitlines()[1:]}
    assert float(rows["oct4"][4]) < 1e-7
    assert float(rows["oct5"][4]) == pytest.approx(0.7 / np.sqrt(2), rel=1e-6)
    rec = read_records(path)
    power = sum(octave_rms(rec.column(c), FS, beyond_nyquist="drop").mean_square for c in ("casing.B.Fz", "cable.B.Fz"))
    assert np.sqrt(power[3]) == pytest.approx(5.0, rel=1e-3)  # (what the sum of the spectra would say)
    # the '+' form is the same column; spectrum integrates the summed samples' PSD to the same RMS
    assert main(["spectrum", str(path), "--column", "casing.B.Fz+cable.B.Fz", "--fmin", "200", "--fmax", "300"]) == 0
    rms = float(re.search(r"# casing.B.Fz\+cable.B.Fz: RMS (\S+) N", capsys.readouterr().out)[1])
    assert rms == pytest.approx(0.7 / np.sqrt(2), rel=1e-3)  # (Welch's PSD of the tone's lines over 200-300 Hz)


def test_a_derived_column_is_refused_naming_what_the_record_lacks(tmp_path, capsys):
    """An FMU's outputs written with casing.B.Fz alone have no net force at B; terms of different
    units, a term named twice, a paths moment and clips that skip an index are refused, each naming
    the column as asked (the option on the command line)."""
    path = tmp_path / "fmu.csv"
    write_records(path, Records(T, {"casing.B.Fz": np.sin(T), "casing.A.az": np.cos(T)}, {"casing.A.az": "m/s2"}))
    assert main(["bands", str(path), "--column", "net.B.Fz"]) == 2
    err = capsys.readouterr().err
    assert "--column = 'net.B.Fz': is the sum casing.B.Fz + cable.B.Fz, but cable.B.Fz is not a column of" in err
    rec = read_records(path)
    with pytest.raises(ModelError, match=r"^name = 'casing.B.Fz\+casing.A.az': adds columns of different units"):
        rec.column("casing.B.Fz+casing.A.az")
    with pytest.raises(ModelError, match=r"names casing.B.Fz twice"):
        rec.column("casing.B.Fz+casing.B.Fz [N]")
    with pytest.raises(ModelError, match=r"^output = 'casing.B.Fz\+': must be columns joined by '\+'"):
        rec.column("casing.B.Fz+", "output")
    ends = {f"{b}.{s}.Mz": np.sin(T) for b in ("casing", "cable") for s in "AB"}
    with pytest.raises(ModelError, match=r"^name = 'paths.Mz': must be a force, .* do not add"):
        Records(T, ends).column("paths.Mz")
    forces = {f"{b}.{s}.Fz": np.sin(T) for b in ("casing", "cable") for s in "AB"}
    gap = Records(T, {**forces, "casing.clip0.Fz": T, "casing.clip2.Fz": T})
    with pytest.raises(ModelError, match=r"holds casing.clip2.Fz but not casing.clip1.Fz"):
        gap.column("paths.Fz")
    assert "net.B.Fz" not in rec.columns  # (nothing added by a refusal)


def test_a_derived_column_is_a_column_of_the_record_once_asked_for(tmp_path):
    """Asked for, net.B.Fz is added to the Records (its unit, its terms), so a file written from it
    holds it and reads it back as a column; a real column of that name comes first."""
    rec = read_records(tones(tmp_path / "r.csv"))
    net = rec.column("net.B.Fz")
    np.testing.assert_array_equal(net, rec.column("casing.B.Fz") + rec.column("cable.B.Fz"))
    assert rec.units["net.B.Fz"] == "N" and rec.derived == {"net.B.Fz": ("casing.B.Fz", "cable.B.Fz")}
    write_records(tmp_path / "n.npz", rec)
    back = read_records(tmp_path / "n.npz")
    assert "net.B.Fz" in back.names and back.terms("net.B.Fz") == ("net.B.Fz",)
    own = Records(T, {"casing.B.Fz": T, "cable.B.Fz": T, "net.B.Fz": 3 * T})
    np.testing.assert_array_equal(own.column("net.B.Fz"), 3 * T)


# ------------------------------------------------------------------ the report: net.B.Fz beside casing.B.Fz
def test_the_report_shows_the_net_force_at_b_as_bands_gives_it(tmp_path, capsys):
    """The report's reference record with the cable drive (0.2 s, seed 1): its net.B.Fz band levels
    are what `bands --column net.B.Fz --skip S` gives from the saved record (to its 6 printed
    digits), its casing.B.Fz ones what `bands` gives of casing.B.Fz, the page's table shows them
    with their difference in dB, and bands_net_B.csv holds them at full precision."""
    from cablecasing_core.report import figures, page
    from cablecasing_core.report.runs import NET_OUTPUT, OUTPUT, run_variant, variants

    skip = 0.06
    var = variants(cc.load_model(), tmp_path, 1)[1]
    assert var.key == "drive"
    run_variant(var, 0.2, [1], skip, progress=False)
    for name in (OUTPUT, "cable.B.Fz", NET_OUTPUT):
        assert main(["bands", str(var.record), "--column", name, "--skip", str(skip)]) == 0
        printed = [r.split(",") for r in capsys.readouterr().out.splitlines() if r.startswith("oct")]
        np.testing.assert_allclose(var.net_bands[name].rms, [float(r[4]) for r in printed], rtol=1e-5)
    net, casing = var.net_bands[NET_OUTPUT].rms, var.net_bands[OUTPUT].rms
    assert np.max(np.abs(20 * np.log10(net / casing))) > 3  # (what casing.B.Fz alone misses, by a few dB)
    rows = figures.net_table([var], tmp_path / "bands_net_B.csv")
    assert rows == [var]
    lines = (tmp_path / "bands_net_B.csv").read_text().splitlines()
    assert lines[0] == "variant,band,f_low [Hz],f_high [Hz],casing.B.Fz [N],cable.B.Fz [N],net.B.Fz [N]"
    assert [float(x) for x in lines[4].split(",")[4:]] == [var.net_bands[n].rms[3] for n in var.net_bands]
    html = "\n".join(page.net_parts([var], {"skip": skip}))
    cells = re.findall(r"<td[^>]*>(.*?)</td>", re.search(r"<tr><td>oct4</td>(.*?)</tr>", html)[1])
    assert cells[1:4] == [page._g(var.net_bands[n].rms[3], 4) for n in var.net_bands]
    assert cells[4] == f"{20 * np.log10(net[3] / casing[3]):+.1f}"
    assert "net.B.Fz = casing.B.Fz + cable.B.Fz" in html


@pytest.mark.filterwarnings("ignore:.*fewer than 4 FFT lines")  # (0.2 s records: octaves 1-2 are not the point)
def test_the_report_gives_the_net_force_at_b_as_an_ensemble_paired_with_casing(tmp_path):
    """With seeds, the report's net.B.Fz table holds net.B.Fz's ensemble means (of the same runs as
    casing.B.Fz's ensemble, each member the summed forces of that seed's run) with their intervals,
    and their ratio to casing.B.Fz's means in dB with the paired interval (paired_difference)."""
    from cablecasing_core.report import page
    from cablecasing_core.report.runs import NET_OUTPUT, OUTPUT, run_variant, variants
    from cablecasing_core.studies import paired_difference, seed_ensemble

    skip, seeds = 0.06, [1, 2, 3]
    var = variants(cc.load_model(), tmp_path, 1)[1]
    run_variant(var, 0.2, seeds, skip, progress=False)
    net, casing = var.net_ensemble, var.ensemble
    assert net.output == NET_OUTPUT and casing.output == OUTPUT and np.array_equal(net.seeds, seeds)
    alone = seed_ensemble(var.model, seeds, output=NET_OUTPUT, duration=0.2, skip=skip)  # (runs of their own)
    np.testing.assert_array_equal(net.levels, alone.levels)  # (the same runs, bit for bit)
    html = "\n".join(page.net_parts([var], {"skip": skip}))
    assert "ensemble means" in html and "paired" in html
    pd = paired_difference(net.levels, casing.levels)
    lo, hi = net.ci(0.95)
    for b in (3, 5):  # (oct4, oct6: bands with a response)
        cells = re.findall(r"<td[^>]*>(.*?)</td>", re.search(rf"<tr><td>oct{b + 1}</td>(.*?)</tr>", html)[1])
        assert cells[1] == page._g(net.mean[b], 4)
        assert cells[2] == f"{page._g(lo[b], 3)} to {page._g(hi[b], 3)}"
        assert cells[3] == f"{20 * np.log10(net.mean[b] / casing.mean[b]):+.1f}"  # (1 + r is the ratio of means)
        r_lo, r_hi = (x[b] for x in pd.ci(0.95))
        assert cells[4] == " to ".join(f"{20 * np.log10(1 + r):+.1f}" if r > -1 else "-inf" for r in (r_lo, r_hi))
    # the page's first lines (review AA L15): the strongest band of casing.B.Fz's ensemble, as its table gives it
    glance = "\n".join(page.glance_parts([var], {"skip": skip}))
    b = int(np.argmax(casing.mean))
    lo, hi = (x[b] for x in casing.ci(0.95))
    assert f"strongest in oct{b + 1} " in glance and f"{page._g(casing.mean[b], 4)} N (95 % interval " in glance
    assert f"{page._g(lo, 3)} to {page._g(hi, 3)} N, 3 seeds)" in glance and "after 0.06 s" in glance
    bare = variants(cc.load_model(), tmp_path, 1)[0]  # (no drive: cable.B.Fz is 0, net.B.Fz is casing.B.Fz)
    bare.ensemble = bare.net_ensemble = net
    html = "\n".join(page.net_parts([bare, var], {"skip": skip}))
    assert html.count("<tr><td>oct4</td>") == 1 and f"{bare.title}: {NET_OUTPUT}" not in html
    assert f"In the variant {bare.title} cable.B.Fz is 0 N in every member" in html
