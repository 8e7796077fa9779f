"""The figures and tables of the report, each from the runs of :mod:`.runs` (the reference records
read back from their files, the ensembles, the study), written into the report's folder."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import ModelError
from ..files import atomic_path, write_text
from ..nvh.bands import NO_RESPONSE_DB, no_response
from ..records import after_skip
from .runs import NET_OUTPUT, OUTPUT

#: Frequencies of the TRFAM (Hz): Fig. 17's range on a 0.25 Hz grid, to which :func:`trfam_grid` adds
#: points around each resonance that the grid alone would not resolve.
TRFAM_HZ = np.arange(5.0, 1000.25, 0.25)
#: Harmonics of the drive drawn in the scalograms (more lines would hide the transform).
HARMONICS_DRAWN = 8


def trfam_grid(model, body, dampings=("structural", "viscous")):
    """:data:`TRFAM_HZ` (Hz) with points added around the natural frequencies f_n of ``body`` in its
    range: where the grid's step is wider than half a mode's half-power bandwidth b (the narrower
    of ``dampings``'), f_n + k b / 4 for k = -4..4 (within f_n +- b, where the peak lies). A grid
    lands at worst df/2 from a peak, where |TRFAM| is 1/sqrt(1 + (df/b)^2) of its height: with
    these points within b/8 of it, 97 % or more (the 0.25 Hz grid alone: 11 % or less where b >=
    0.5 Hz). A mode without damping (b = 0, an infinite peak) gets none."""
    from ..frequency.trfam import half_power_bandwidths

    step = TRFAM_HZ[1] - TRFAM_HZ[0]
    lo, hi = TRFAM_HZ[0], TRFAM_HZ[-1]
    widths = [half_power_bandwidths(model, body, d, lo, hi) for d in dampings]
    fn = widths[0][0]
    bw = np.min([b for _, b in widths], axis=0) if len(fn) else np.zeros(0)
    extra = [f + b * np.arange(-4, 5) / 4.0 for f, b in zip(fn, bw) if 0.0 < b < 2.0 * step]
    grid = np.unique(np.concatenate([TRFAM_HZ, *extra]))
    return grid[(grid >= lo) & (grid <= hi)]


#: Scalogram frequencies (Hz), log-spaced over the octaves of Table 3 that the excitation reaches.
SCALOGRAM_HZ = np.geomspace(20.0, 2000.0, 90)


def trfam_figure(model, body, out):
    """Fig. 17: TRFAM of ``body`` from end A to end B in x, y, z, structural and viscous damping,
    log frequency axis with phase; trfam_<d>.csv (both dampings) and trfam.uff (UFF 58, six FRFs).
    Returns {direction: {damping: H}}."""
    import cablecasing_core as cc

    from ..frequency.modal import mode_count
    from ..plotting import plot_trfam_xyz
    from ..records import uff_dof
    from ..uff import Record, frf_fields, write_uff

    freqs = trfam_grid(model, body)
    curves = {}
    recs = []
    for d in "xyz":
        curves[d] = {}
        for damping in ("structural", "viscous"):
            H = cc.trfam(model, f"{body}.A.{d}", f"{body}.B.{d}", freqs, damping)
            curves[d][damping] = H
            node, k, *_ = uff_dof(f"{body}.B.{d}")
            ref, kr, *_ = uff_dof(f"{body}.A.{d}")
            recs.append(
                Record(
                    "frf",
                    freqs,
                    H,
                    f"TRFAM {body}.B.{d}/{body}.A.{d} {damping}",
                    node,
                    k,
                    ref,
                    kr,
                    **frf_fields("apparent_mass"),
                )
            )
        s, v = curves[d]["structural"], curves[d]["viscous"]
        table = np.column_stack([freqs, s.real, s.imag, v.real, v.imag])
        header = "frequency [Hz],re structural [kg],im structural [kg],re viscous [kg],im viscous [kg]"
        with atomic_path(out / f"trfam_{d}.csv") as tmp:
            np.savetxt(tmp, table, delimiter=",", header=header, comments="", fmt="%.10g")
    write_uff(out / "trfam.uff", recs)
    natural = cc.natural_frequencies(model, body, min(12, mode_count(model, body)))
    plot_trfam_xyz(
        freqs,
        curves,
        out / "trfam_xyz.png",
        title=f"TRFAM of the {body} from end A to end B, Eq. 12 (Fig. 17); green: its first {len(natural)} "
        f"natural frequencies (to {natural[-1]:.0f} Hz)",
        natural_hz=[f for f in natural if f <= freqs[-1]],
    )
    return curves


def run_label(info, seed=True) -> str:
    """The settings of the report's runs for a figure's title: ``seed 1, 1 s at dt = 1e-05 s,
    levels after 0.32 s`` (``info``: :func:`~cablecasing_core.report.write_report`'s; without the
    seed for a figure of every seed)."""
    if not info:
        return ""
    head = f"seed {info['seeds'][0]}, " if seed else ""
    return f"{head}{info['duration']:g} s at dt = {info['dt']:g} s, levels after {info['skip']:g} s"


def time_figure(variants, path, info=None):
    """The support forces at B of every variant's reference record over time (N), one panel per
    variant, the start the levels leave out (``info["skip"]``) shaded."""
    import matplotlib.pyplot as plt

    from ..plotting import save_figure

    fig, axes = plt.subplots(len(variants), 1, figsize=(8, 2.6 * len(variants) + 0.7), sharex=True, squeeze=False)
    for ax, v in zip(axes[:, 0], variants):
        r = v.result
        for name in ("casing.B.Fx", "casing.B.Fy", "casing.B.Fz"):
            ax.plot(r.time, r.support_force(name), lw=0.5, label=name)
        if info:
            ax.axvspan(0.0, info["skip"], color="0.85", zorder=0, label=f"left out of the levels ({info['skip']:g} s)")
        ax.set_ylabel("force (N)")
        ax.set_title(f"{v.title}: reference record ({v.record.name})", fontsize=9, loc="left")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, ncol=4, loc="upper right")
    axes[-1, 0].set_xlabel("time (s)")
    if info:
        fig.suptitle(f"Support forces at B of the reference records: {run_label(info)}", fontsize=9)
    save_figure(fig, path)


def scalogram_figure(variants, path, natural, harmonics, skip, info=None):
    """Figs. 20-21: Morlet scalograms |W| (N) of casing.B.Fz of the reference records, side by side,
    each on its own colour scale (stated when they differ), natural frequencies (dashed) marked on
    both and the drive's harmonics (dotted; the first :data:`HARMONICS_DRAWN` of ``harmonics``) on the
    records with the drive only; the skip (s) and the cone of influence (``plot_scalograms``) marked,
    the wavelet's gamma and the seed in the title."""
    from ..identification.wavelet import DEFAULT_GAMMA, cwt_morlet
    from ..plotting import plot_scalograms

    panels, driven = [], []
    for k, v in enumerate(variants):
        if v.key == "drive":
            driven.append(k)
        r = v.result
        fs = 1.0 / (r.time[1] - r.time[0])
        W = np.abs(cwt_morlet(r.support_force(OUTPUT), fs, SCALOGRAM_HZ))
        step = max(1, len(r.time) // 1500)  # (columns drawn: the transform itself is at the full rate)
        keep = slice(None, None, step)
        panels.append((r.time[keep], W[keep], f"{OUTPUT} {v.title}"))
    plot_scalograms(
        panels,
        SCALOGRAM_HZ,
        path,
        unit="N",
        natural_hz=natural,
        harmonics_hz=harmonics[:HARMONICS_DRAWN],
        harmonics_on=driven,
        skip_s=skip,
        cone_gamma=DEFAULT_GAMMA,
        title=f"Wavelet transform |W| of {OUTPUT} (Figs. 20-21), Morlet gamma = {DEFAULT_GAMMA:g}"
        + (f"; {run_label(info)}" if info else "")
        + "\ndashed: natural frequencies of the casing"
        + (
            ""
            if not (driven and len(harmonics))
            else ", dotted: the drive and its harmonics"
            if len(harmonics) <= HARMONICS_DRAWN
            else f", dotted: the drive and its first harmonics ({HARMONICS_DRAWN} of {len(harmonics)})"
        )
        + "; grey: the skip and the cone of influence",
    )


def contact_figures(model, var, out, info=None):
    """Fig. 22 from the ensemble with the cable drive (contact time pooled over its seeds; else the
    reference record): the routing in 3D coloured by the contact time, and the histogram beside the
    curvature. The contact time is counted over each whole run, from t = 0 (the skip included), as
    the labels say. Returns where the most contact is and where the curvature is highest
    (``{"what", "s_most", "kappa_most", "s_curviest", "kappa_max", "duration"}``, m and 1/m), or None
    for a model without a cable."""
    import matplotlib.pyplot as plt

    from ..plotting import plot_contact_histogram, plot_geometry, save_figure
    from ..structure.geometry import centerline_of

    if "cable" not in model.bodies:  # (a report's model has a casing: check_report_settings)
        return None
    r = var.result
    if var.ensemble is not None and var.ensemble.contact_time.size:
        ct = var.ensemble.contact_time.mean(axis=0)
        what = f"mean of seeds {var.ensemble.seeds[0]}..{var.ensemble.seeds[-1]}, {var.title}"
    else:
        ct, what = r.contact_time, f"reference record, {var.title}"
    duration = float(r.time[-1])
    label = f"contact time per run of {duration:g} s (s)"
    counted = f"counted from t = 0 over the whole run, the first {info['skip']:g} s included" if info else ""
    cl = centerline_of(model)
    plot_geometry(
        cl,
        out / "routing_contact.png",
        values=ct,
        label=label,
        title=f"(a) routing and contact time (Fig. 22a)\n{what}" + (f"\n{counted}" if counted else ""),
    )
    fig, ax = plt.subplots(figsize=(7, 3.6))
    plot_contact_histogram(ax, r.arc_length, ct, r.curvature, label=label)
    ax.set_title(
        f"(b) contact time per cable node and curvature (Fig. 22b): {what}" + (f"\n{counted}" if counted else ""),
        fontsize=8,
        loc="left",
    )
    save_figure(fig, out / "contact_histogram.png")
    ct = np.asarray(ct, dtype=float)
    kappa = np.asarray(r.curvature, dtype=float)
    most, curviest = int(np.argmax(ct)), int(np.argmax(kappa))
    return {
        "what": what,
        "duration": duration,
        "any": bool(np.any(ct > 0)),
        "s_most": float(r.arc_length[most]),
        "kappa_most": float(kappa[most]),
        "s_curviest": float(r.arc_length[curviest]),
        "kappa_max": float(kappa[curviest]),
    }


def band_figure(variants, path, confidence=0.95, info=None, bias=None):
    """Band levels of casing.B.Fz as ensemble means with their 95 % confidence intervals (N, log
    axis, and dB re 1 N), one series per variant. A band that holds no response
    (:func:`no_response`) is not drawn but named at the foot of the axis, so that the axis spans the
    bands that hold one (the no-drive variant's octaves 8-9, window artefacts near -180 dB re 1 N,
    stretched it over 10 decades). ``info``: the runs' settings, in the title; ``bias``: the known
    mesh bias per band of each variant (``{key: [%, ...]}``, :func:`.page.mesh_bias`), written above
    a level where it is larger than the level's interval (half-width, relative)."""
    import matplotlib.pyplot as plt

    from ..nvh.plots import db_axis, set_band_ticks
    from ..plotting import save_figure

    ens = [v for v in variants if v.ensemble is not None]
    if not ens:
        return
    e0 = ens[0].ensemble
    x = np.arange(1, len(e0.labels) + 1)
    fig, ax = plt.subplots(figsize=(7, 3.8))
    shown, gaps = [], []
    offsets = np.linspace(-0.12, 0.12, len(ens)) if len(ens) > 1 else [0.0]
    for v, dx in zip(ens, offsets):
        e = v.ensemble
        lo, hi = e.ci(confidence)
        off = no_response(e.mean)
        on = ~off
        bar = ax.errorbar(
            x[on] + dx,
            e.mean[on],
            yerr=[(e.mean - lo)[on], (hi - e.mean)[on]],
            fmt="o",
            capsize=3,
            label=f"{v.title}: mean of {e.n} seeds, {confidence:.0%} CI",
        )
        shown += [e.mean[on], lo[on], hi[on]]
        gaps += [(xi + dx, bar[0].get_color()) for xi in x[off]]
        for b, pct in enumerate((bias or {}).get(v.key) or ()):
            half = max(hi[b] - e.mean[b], e.mean[b] - lo[b]) / e.mean[b] if e.mean[b] > 0 else np.inf
            if on[b] and abs(pct) / 100.0 > half:
                ax.annotate(
                    f"mesh {pct:+.0f} %",
                    (x[b] + dx, hi[b]),
                    xytext=(0, 3),
                    textcoords="offset points",
                    fontsize=6,
                    color=bar[0].get_color(),
                    ha="center",
                    va="bottom",
                )
    ax.set_yscale("log")
    vals = np.concatenate(shown)
    vals = vals[vals > 0]
    if vals.size:
        ax.set_ylim(vals.min() / 3, vals.max() * 2)
    for xi, color in gaps:
        ax.text(
            xi,
            0.03,
            "no response",
            transform=ax.get_xaxis_transform(),
            rotation=90,
            fontsize=7,
            color=color,
            ha="center",
            va="bottom",
        )
    ax.set_ylabel(f"RMS {OUTPUT} (N)")
    db_axis(ax, 1.0, "N", power=False)
    title = f"Band levels of {OUTPUT} (Table 3): ensemble means over excitation seeds"
    if info:
        title += (
            f"\n{info['duration']:g} s runs at dt = {info['dt']:g} s, after {info['skip']:g} s, "
            f"Hann's window, seeds {info['seeds'][0]}..{info['seeds'][-1]}"
        )
    if bias:
        title += "\nmesh ±N %: the bias of 35 elements beyond the interval (docs/time_domain.md, 'The mesh')"
    if gaps:
        title += f"\n(not drawn: bands more than {NO_RESPONSE_DB:g} dB below the variant's strongest, no response)"
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    set_band_ticks(ax, x, e0)
    ax.set_xlabel("band: nominal mid-band frequency (Hz)")
    save_figure(fig, path)


def psd_figure(variants, path, skip, info=None):
    """PSD (Welch, Hann's window, segments of the power of two nearest fs / 4 samples or a quarter
    of the record, whichever is shorter: the resolution the legend states) of casing.B.Fz of the
    reference records, and beside it, for a model with a cable, of the force into B, net.B.Fz
    (casing.B.Fz + cable.B.Fz), N^2/Hz and dB re 1 N^2/Hz, over Table 3's bands (11-5680 Hz) from 2
    df on. A variant whose net.B.Fz is its casing.B.Fz (cable.B.Fz zero: no drive) draws one line,
    named as both. A series that does not vary (:func:`constant`: casing.B.Fz of a model whose
    excitation does not reach it) has no power to draw on the log axis: it is left out and named in
    the title (the page says so too, ``page.psd_note``); with none left the figure says so. Returns
    the lowest frequency drawn (Hz, 2 df; None when nothing is drawn), the variants whose net.B.Fz is
    their casing.B.Fz (their titles) and the series left out (their names)."""
    from ..nvh import psd
    from ..nvh.bands import octave_bands
    from ..nvh.plots import plot_psd

    ps = []
    net, same, flat = False, [], []
    for v in variants:
        r = v.result
        keep = after_skip(r.time, skip)
        fs = 1.0 / (r.time[1] - r.time[0])
        nper = min(2 ** int(np.round(np.log2(fs / 4.0))), 2 ** int(np.log2(keep.sum() // 4)))
        x = r.support_force(OUTPUT)[keep]
        name = f"{OUTPUT} {v.title}"
        if constant(x):
            flat.append(f"{OUTPUT} ({v.title})")
            x = None
        if v.net_bands is not None:  # (a model with a cable: the record's net.B.Fz, records.derived_terms)
            rec = r.records()
            y = rec.column(NET_OUTPUT)[after_skip(rec.time, skip, rec.time[0])]
            net = True
            if x is not None and np.array_equal(x, y):  # (no force of the cable at B: one curve, not two)
                same.append(v.title)
                name += f" (= {NET_OUTPUT}: cable.B.Fz is 0 N)"
            else:
                if x is not None:
                    ps.append(psd(x, fs, nperseg=nper, unit="N", name=name))
                if constant(y):
                    flat.append(f"{NET_OUTPUT} ({v.title})")
                else:
                    ps.append(psd(y, fs, nperseg=nper, unit="N", name=f"{NET_OUTPUT} {v.title}"))
                continue
        if x is not None:
            ps.append(psd(x, fs, nperseg=nper, unit="N", name=name))
    shown = f"{OUTPUT} and {NET_OUTPUT} = {OUTPUT} + cable.B.Fz" if net else OUTPUT
    t3 = octave_bands("table3")
    lo, hi = float(t3.lower[0]), float(t3.upper[-1])
    head = f"PSD of {shown}, reference records\n" + (run_label(info) if info else f"after {skip:g} s")
    left_out = f"\nnot drawn, constant (no power): {', '.join(flat)}" if flat else ""
    if not ps:
        _empty_figure(path, head + left_out, "every series is constant: no power spectral density to draw")
        return {"from_hz": None, "same": same, "constant": flat}
    first = max(lo, min(p.covered(lo, hi)[0] for p in ps))
    plot_psd(
        ps,
        path,
        f_range=(lo, hi),
        title=head
        + f"; Welch, Hann's window\nTable 3's bands {lo:g}-{hi:g} Hz"
        + (f" from 2 df = {first:.3g} Hz (below it Welch's lines do not measure)" if first > lo else "")
        + left_out,
    )
    return {"from_hz": first, "same": same, "constant": flat}


def constant(x) -> bool:
    """Whether the series ``x`` does not vary (every sample equal: zero power after its mean is removed,
    nothing to draw on a log axis of a PSD)."""
    x = np.asarray(x)
    return x.size == 0 or bool(np.all(x == x[0]))


def _empty_figure(path, title, text):
    """A figure without axes that says ``text`` under ``title``, written to ``path``."""
    import matplotlib.pyplot as plt

    from ..plotting import save_figure

    fig, ax = plt.subplots(figsize=(7.5, 2))
    ax.set_axis_off()
    ax.text(0.5, 0.5, text, ha="center", va="center", fontsize=10)
    ax.set_title(title, fontsize=10)
    save_figure(fig, path)


def net_table(variants, path):
    """The Table 3 band RMS (N) of casing.B.Fz, cable.B.Fz and net.B.Fz of the reference records
    (``Variant.net_bands``, :func:`.runs.net_bands`) written to ``path`` (bands_net_B.csv) at full
    precision, one row per variant and band; the variants that have them (a model with a cable), or
    none (no file)."""
    rows = [v for v in variants if v.net_bands is not None]
    if not rows:
        return []
    names = list(rows[0].net_bands)
    lines = ["variant,band,f_low [Hz],f_high [Hz]," + ",".join(f"{n} [N]" for n in names)]
    for v in rows:
        b0 = v.net_bands[names[0]]
        for i, lab in enumerate(b0.labels):
            values = ",".join(repr(float(v.net_bands[n].rms[i])) for n in names)
            lines.append(f"{v.key},{lab},{b0.lower[i]:g},{b0.upper[i]:g},{values}")
    write_text(path, "\n".join(lines) + "\n")
    return rows


def input_spectrum(model, target):
    """The PSD ((m/s2)^2/Hz) of the model's random excitations of the support channel ``target``
    (``casing.A.z``), a function of f (Hz): the sum of the records' own PSDs
    (:func:`~cablecasing_core.timedomain.random_record.random_psd`, rms^2 / (K df) over each one's
    K lines); None when it has none."""
    from ..timedomain.random_record import random_psd

    ex = [e for e in model.scenario["excitation"].values() if e["kind"] == "random" and e["target"] == target]
    if not ex:
        return None

    def psd(f):
        return sum(random_psd(e["rms"], e["band"], f) for e in ex)

    psd.bands = [tuple(e["band"]) for e in ex]
    return psd


#: The apparent mass's range in the report (Hz): the input's band on the built-in specimens.
AM_RANGE_HZ = (10.0, 1000.0)
#: The report's H1 resolution asked for (Hz): 6.1 Hz lines (16384 samples at 1e-5 s), 8 averages of
#: the 0.68 s after the skip of a 1 s run; of the 0.44 s of a 0.5 s run 5 (overlapping by 58 % so that
#: they span it), there the finest lines with at least 3 half-overlapping averages
#: (``nvh.transfer.MIN_AVERAGES``). The casing's modes
#: below 100 Hz are 1.9-3.9 Hz wide (half power, viscous), so the lines do not resolve them and the
#: coherence drops by the window's bias: on the built-in specimen's record without the drive (seed
#: 1, 0.5 s, no contact) its median is 0.60 over 10-100 Hz and 0.99 over 10-1000 Hz, the window
#: alone predicts 0.50 and 0.99, and at 24.4 Hz lines (21 averages) it falls to 0.81 over 10-1000 Hz
#: (40 lines; over 10-100 Hz they are 4, no meaningful median: MIN_MEDIAN_LINES)
#: (tests/nvh/test_report_apparent_mass.py). A shorter record takes the finest it allows
#: (``nvh.transfer.finest_resolution``).
AM_RESOLUTION_HZ = 8.0
#: The fewest lines over which the report gives the coherence's median (``apparent_mass_note``): the
#: median of 5 lines is the middle one of at least 2 below and 2 above it, so that neither a line on
#: a mode's peak nor one in a notch sets it alone; over fewer (a short --duration's 10-100 Hz: 4
#: lines at 24.4 Hz, 1 at 97.7 Hz) the page gives the count and says a median is not meaningful.
MIN_MEDIAN_LINES = 5


def apparent_mass_figure(model, var, path, skip):
    """H1 apparent mass of the reference record ``var`` from the driven support's acceleration to
    casing.B.Fz, with coherence, against what it estimates: the TRFAM (viscous) averaged over the
    estimator's window (:func:`~cablecasing_core.nvh.transfer.window_expectation`, under the
    scenario's input spectrum), and the TRFAM as computed for reference; in the coherence panel
    the coherence that window leaves of the noise-free TRFAM. Returns a summary dict (resolution,
    averages, the median coherence measured and expected from the window alone over 10-100 and
    10-1000 Hz and the number of lines each is taken over, the same at 4 times coarser lines, the
    casing's modes narrower than the lines), or None when the record has no such input."""
    import cablecasing_core as cc

    from ..frequency.trfam import half_power_bandwidths
    from ..nvh import apparent_mass
    from ..nvh.plots import plot_transfer
    from ..nvh.transfer import finest_resolution, window_expectation
    from ..records import read_records

    rec = read_records(var.record)
    d = OUTPUT[-1]
    inp = f"casing.A.a{d}"
    if inp not in rec.columns:
        return None
    lo, hi = AM_RANGE_HZ
    # (AM_RESOLUTION_HZ, or the finest a short record allows: a finer resolution_hz is refused)
    tr = apparent_mass(rec, inp, OUTPUT, skip=skip, resolution_hz=max(AM_RESOLUTION_HZ, finest_resolution(rec, skip)))
    nper = 2 * (len(tr.f_hz) - 1)  # (the one-sided lines of an even segment: nperseg / 2 + 1)
    df = float(tr.f_hz[1])

    def H_of(f):
        return cc.trfam(model, f"casing.A.{d}", f"casing.B.{d}", f, "viscous")

    scenario = (var.model or model).scenario  # (the record's: the variant's scenario; the structure is model's)
    G = input_spectrum(var.model or model, f"casing.A.{d}")
    fe, EH, coh = window_expectation(H_of, rec.fs, nper, lo, hi, G)
    fine = trfam_grid(model, "casing", ("viscous",))
    fine = fine[fine >= lo]
    H = H_of(fine)
    plot_transfer(
        tr,
        path,
        reference_curves={
            f"TRFAM averaged over the window of {df:.3g} Hz lines: what H1 estimates (frequency domain)": (fe, EH),
            "TRFAM, viscous, as computed (frequency domain; narrower than the lines at its peaks)": (fine, H),
        },
        reference_coherence={"coherence the window alone leaves of the noise-free TRFAM": (fe, coh)},
        f_range=AM_RANGE_HZ,
        title=f"Apparent mass {tr.ratio} from the record {var.title} (H1)",
    )

    ranges = [(a, b) for a, b in ((lo, 100.0), (lo, hi)) if b > a]

    def medians(f, g):
        return {f"{a:g}-{b:g}": float(np.median(g[(f >= a) & (f <= b)])) for a, b in ranges}

    def lines(f):  # (how many lines each median is taken over)
        return {f"{a:g}-{b:g}": int(np.count_nonzero((f >= a) & (f <= b))) for a, b in ranges}

    on_lines = np.abs(fe / df - np.round(fe / df)) < 1e-6  # (the grid's points on the estimate's lines)
    out = {
        "input": inp,
        "n_averages": tr.n_averages,
        "n_effective": tr.n_effective,
        "df": df,
        "median_coherence": medians(tr.f_hz, tr.coherence),
        "median_lines": lines(tr.f_hz),
        "expected_coherence": medians(fe[on_lines], coh[on_lines]),
        "input_bands": G.bands if G is not None else None,
        "other_inputs": sorted(  # (the casing's other driven channels: what the input does not explain)
            {t for t in (e["target"] for e in scenario["excitation"].values()) if t.startswith("casing.")}
            - {f"casing.A.{d}"}
        ),
        "contact": var.result is not None and float(np.sum(var.result.contact_time)) > 0.0,
    }
    fn, b = half_power_bandwidths(model, "casing", "viscous", lo, hi)
    out["narrow_modes"] = [(float(f), float(w)) for f, w in zip(fn, b) if 0.0 < w < df]
    from ..errors import ModelError

    try:  # 4 times coarser lines, 4 times as many averages or more
        coarse = apparent_mass(rec, inp, OUTPUT, skip=skip, nperseg=nper // 4)
        out["coarser"] = {
            "df": float(coarse.f_hz[1]),
            "n_averages": coarse.n_averages,
            "median_coherence": medians(coarse.f_hz, coarse.coherence),
            "median_lines": lines(coarse.f_hz),
        }
    except ModelError:
        out["coarser"] = None
    return out


def _rms(x):
    """(mean, RMS total, RMS dynamic) of ``x`` (N): the total includes the mean, the dynamic one
    (the standard deviation) is what vibrates, as in ``simulate``'s table and the band levels."""
    return float(np.mean(x)), float(np.sqrt(np.mean(x**2))), float(np.std(x))


#: The columns of rms.csv and of the report's RMS table (N).
RMS_COLUMNS = ("mean", "RMS total", "RMS dynamic")


def rms_table(variants, path, skip):
    """The mean, the RMS total (with the mean) and the RMS dynamic (the mean removed: what
    vibrates, what the band levels and the PSD hold) (N) of the casing's support forces at B of every
    reference record after ``skip`` s, from the saved records; written to rms.csv at full precision.
    Returns [(variant, {name: (mean, total, dynamic)})]."""
    rows = []
    for v in variants:
        r = v.result
        keep = after_skip(r.time, skip)
        rows.append((v, {n: _rms(r.support_force(n)[keep]) for n in ("casing.B.Fx", "casing.B.Fy", "casing.B.Fz")}))
    lines = ["variant,record,output," + ",".join(f"{c.lower()} [N]" for c in RMS_COLUMNS)]
    lines += [f"{v.key},{v.record.name},{n}," + ",".join(repr(x) for x in t) for v, d in rows for n, t in d.items()]
    write_text(path, "\n".join(lines) + "\n")
    return rows


#: The files of a report's study in its folder ``study/`` (:func:`study_figures`)
STUDY_FILES = ("study.csv", "study.csv.meta.json", "model.toml", "correlations.png", "sobol.png")


def clear_study(folder: Path):
    """Remove an earlier report's study files from ``folder`` (a report whose study shows fewer, or
    none, would otherwise leave them beside its page)."""
    for name in STUDY_FILES:
        (folder / name).unlink(missing_ok=True)


def study_figures(model, folder: Path, n_samples, duration, skip, progress, say=lambda runs: None, scheduler="serial"):
    """A small study (Fig. 23) over the paper's parameters that the model has (every run the model's
    scenario for ``duration`` s; ``n_samples`` rounded up to whole base points, whose number of runs
    is passed to ``say`` before they run): study.csv, correlations.png and, with enough complete
    groups, sobol.png, its runs on ``scheduler`` ("serial" or "threads"). Returns a summary dict, or None
    when the model has none of those parameters."""
    from ..studies import (
        DEFAULT_EVALUATE,
        PAPER_BOUNDS,
        correlations,
        plot_correlations,
        plot_sobol,
        run_study,
        size_warnings,
        sobol_indices,
    )
    from ..studies.sampling import base_points, check_bounds, group_size
    from ..studies.sensitivity import sobol_shown, widest_interval

    known = model.parameters()
    bounds = {k: b for k, b in PAPER_BOUNDS.items() if k in known}
    if "cable" not in model.bodies:  # (without a cable the contact's keys change nothing)
        bounds = {k: b for k, b in bounds.items() if not k.startswith(("contact.", "cable."))}
    if not bounds:
        return None
    bounds = check_bounds(bounds, model=model)
    folder.mkdir(parents=True, exist_ok=True)
    clear_study(folder)
    say(base_points(bounds, n_samples) * group_size(bounds))
    # the model the runs take (each run is it with its overrides), for the reader; the runs are given the
    # Model itself, so that study.csv.meta.json names it by its fingerprint, not by a path that the report's
    # staging folder (report.staged_report) would leave pointing nowhere
    write_text(folder / "model.toml", model.to_toml())
    kwargs = {"duration": duration, "skip": skip}
    res = run_study(
        folder / "study.csv",
        DEFAULT_EVALUATE,
        bounds=bounds,
        n_samples=n_samples,
        seed=0,
        scheduler=scheduler,
        evaluate_kwargs=kwargs,
        quantity={"name": OUTPUT, "unit": "N", "what": "RMS in the octave bands of Table 3"},
        model=model,
        progress=progress,
    )
    seeds = {f"scenario.excitation.{n}.seed": e["seed"] for n, e in model.scenario["excitation"].items() if "seed" in e}
    out = {
        "csv": "study/study.csv",
        "runs": len(res.status),
        "ok": int(res.ok.sum()),
        "bounds": bounds,
        "seeds": seeds,
        "res": res,
    }
    if out["ok"] >= 3:
        out["pearson"], out["spearman"] = correlations(res, "pearson"), correlations(res, "spearman")
        plot_correlations(res, folder / "correlations.png", cors=(out["pearson"], out["spearman"]))
    try:
        sob = sobol_indices(res)
    except ModelError as exc:  # too few complete groups: the page says so
        sob, out["sobol_note"] = None, f"No Sobol indices: {exc.allowed}."
    out["warnings"] = size_warnings(res, sob) if out["ok"] else ["every run failed"]
    if sob is not None and not sobol_shown(sob):
        worst = widest_interval(sob)
        sob = None
        out["sobol_note"] = (
            f"The Sobol indices of these {res.n_base} base points are not shown: their intervals reach "
            f"±{worst:.3g}. A larger study gives them: cablecasing study --samples N (docs/studies.md)."
        )
    out["sobol"] = sob
    if sob is not None:
        plot_sobol(res, folder / "sobol.png", sob=sob)
    return out
