"""Figures of the NVH outputs (matplotlib, Agg): PSD, transfer functions with coherence, band levels."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..plotting import plain_log_ticks, save_figure  # (also selects the Agg backend)
from .spectra import level_db, level_unit, reference


def db_axis(ax, ref, unit, power):
    """A right-hand axis in dB of the left axis' values (amplitudes, or power quantities with ``power``)."""
    k = 10.0 if power else 20.0
    sq = ref**2 if power else ref
    sec = ax.secondary_yaxis(
        "right",
        functions=(lambda v: k * np.log10(np.maximum(v, 1e-300) / sq), lambda L: sq * 10 ** (L / k)),
    )
    sec.set_yscale("linear")  # (dB is linear in the log of the left axis; it would inherit "log")
    sec.set_ylabel(level_unit(ref, unit, power).replace("^2", "$^2$"))
    return sec


def plot_psd(psds, path, ref=None, log_frequency=True, f_range=None, title=None, dynamic_range_db=60.0):
    """PSDs (``spectra.PSD``; unit^2/Hz, log axis) with their level in dB re ref^2/Hz on the right;
    each line drawn over the part of ``f_range`` (Hz; default all) that its lines measure,
    :meth:`~cablecasing_core.nvh.spectra.PSD.covered`: from 2 df (below it they are no measurement,
    docs/nvh.md) to fs/2. The y axis spans ``dynamic_range_db`` (dB) below the highest line shown
    (or down to the lowest line, when that is less), so a record whose spectrum collapses above its
    band keeps its shape."""
    psds = list(psds)
    unit = psds[0].unit
    one_unit = all(p.unit == unit for p in psds)  # (lines of several units share no dB axis)
    r = reference(unit, ref) if one_unit and (unit or ref) else None
    fig, ax = plt.subplots(figsize=(7.5, 4 + 0.22 * len(psds)))  # (the legend below the axes: a line each)
    lo, hi = f_range or (0.0, np.inf)
    spans = [p.covered(lo, hi) for p in psds]
    shown = []
    for p, (a, b) in zip(psds, spans):
        sel = (p.f_hz >= a * (1 - 1e-12)) & (p.f_hz <= b)  # (2 df itself is a line: kept against round-off)
        shown.append(p.density[sel])
        ax.plot(
            p.f_hz[sel],
            p.density[sel],
            lw=0.8,
            label=f"{p.name}{'' if one_unit else f' ({p.unit}$^2$/Hz)'} (df {p.df:.3g} Hz, "
            f"{p.n_averages} averages; from 2 df)",
        )
    ax.set_yscale("log")
    if log_frequency:
        ax.set_xscale("log")
    lo = min(a for a, _ in spans)
    hi = max(min(hi, max(p.f_hz[-1] for p in psds)), 2 * lo)  # (a range wholly below 2 df: an empty axis)
    ax.set_xlim(lo, hi)
    if log_frequency:
        plain_log_ticks(ax, [lo, hi])
    shown = np.concatenate(shown)
    shown = shown[shown > 0]
    if shown.size:  # the visible range, at most dynamic_range_db below the peak
        ax.set_ylim(max(shown.min() / 2, shown.max() * 10 ** (-dynamic_range_db / 10)), shown.max() * 2)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel(f"PSD ({unit}$^2$/Hz)" if unit and one_unit else "PSD (unit$^2$/Hz: each line's in the legend)")
    if r is not None:
        db_axis(ax, r, unit, power=True)
    ax.grid(True, which="both", alpha=0.3)
    # (below the axes: inside, its long entries covered the spectra's peaks)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), frameon=False)
    ax.set_title(title or "power spectral density (Welch)", fontsize=10)
    save_figure(fig, path)


#: The styles of a transfer plot's reference curves, in the order given (a curve's own style, the
#: third item of its tuple, overrides it).
REFERENCE_STYLES = ({"color": "k", "ls": "--", "lw": 0.9}, {"color": "0.55", "ls": ":", "lw": 0.9})


def plot_transfer(
    tr, path, reference_curves=None, log_frequency=True, f_range=None, title=None, reference_coherence=None
):
    """A :class:`~cablecasing_core.nvh.transfer.Transfer`: magnitude (log), phase (deg) and coherence,
    with a band of +-2 random errors around |H1| and optional ``reference_curves`` {label: (f_hz, H)}
    or {label: (f_hz, H, style)} (e.g. the TRFAM of the frequency domain; styles
    :data:`REFERENCE_STYLES` in turn, or the matplotlib keywords of ``style``), and
    ``reference_coherence`` {label: (f_hz, coherence)} drawn dashed in the coherence panel (e.g. the
    coherence the window alone leaves of a noise-free linear system); every curve is named in a legend."""
    fig, (am, ap, ac) = plt.subplots(3, 1, figsize=(7.5, 7), sharex=True, gridspec_kw={"height_ratios": [3, 2, 1.2]})
    f = tr.f_hz
    sel = f > 0 if f_range is None else (f >= f_range[0]) & (f <= f_range[1])
    mag = np.abs(tr.H)
    am.fill_between(
        f[sel],
        (mag * np.clip(1 - 2 * tr.error, 0.1, None))[sel],
        (mag * (1 + 2 * tr.error))[sel],
        color="tab:blue",
        alpha=0.2,
        lw=0,
        label="±2 random errors (from the coherence)",
    )
    am.plot(f[sel], mag[sel], lw=0.9, label=f"{tr.estimator} estimate ({tr.n_averages} averages)")
    ap.plot(f[sel], np.degrees(np.angle(tr.H[sel])), lw=0.8)
    for k, (label, curve) in enumerate((reference_curves or {}).items()):
        fr, Hr = curve[:2]
        style = {**REFERENCE_STYLES[k % len(REFERENCE_STYLES)], **(curve[2] if len(curve) > 2 else {})}
        am.plot(fr, np.abs(Hr), label=label, **style)
        ap.plot(fr, np.degrees(np.angle(Hr)), **style)
    ac.plot(f[sel], tr.coherence[sel], lw=0.8, color="tab:green", label=f"coherence of the {tr.estimator} estimate")
    for label, (fr, g) in (reference_coherence or {}).items():
        ac.plot(fr, g, color="k", ls="--", lw=0.8, label=label)
    am.set_yscale("log")
    am.set_ylabel(f"|{tr.kind}| ({tr.unit})" if tr.unit != "1" else f"|{tr.kind}| (-)")
    ap.set_ylabel("phase (deg)")
    ap.set_yticks([-180, -90, 0, 90, 180])
    ac.set_ylabel("coherence (-)")
    ac.set_ylim(0, 1.05)
    ac.set_xlabel("frequency (Hz)")
    if log_frequency:
        ac.set_xscale("log")
        plain_log_ticks(ac, f[sel])
    for ax in (am, ap, ac):
        ax.grid(True, which="both", alpha=0.3)
    am.legend(fontsize=7 if reference_curves else 8)
    if reference_coherence:
        ac.legend(fontsize=7, loc="lower right")
    am.set_title(title or f"{tr.kind}: {tr.ratio}", fontsize=10)
    save_figure(fig, path)


def band_ticks(bands) -> list:
    """Tick labels of bands (``BandRMS``, ``Bands``, an ``Ensemble``: anything with ``labels``,
    ``lower`` and ``upper``) by their nominal mid-band frequency (Hz; IEC 61260-1 names, or the
    octave a Table 3 band stands in for under its own name, ``oct5`` over 250)."""
    from .bands import nominal_of

    centre = np.sqrt(np.asarray(bands.lower) * np.asarray(bands.upper))
    ticks = []
    for lab, c in zip(bands.labels, centre):
        f = nominal_of(lab, c)
        ticks.append(f"{f:g}" if lab == f"{f:g}Hz" else f"{lab}\n{f:g}")
    return ticks


def set_band_ticks(ax, x, bands):
    """Ticks at ``x`` labelled by :func:`band_ticks`; upright up to 16 bands, turned beyond (a
    third-octave set's four-digit names would run into each other)."""
    ax.set_xticks(x, band_ticks(bands), fontsize=7, rotation=0 if len(x) <= 16 else 90)


def plot_band_levels(bands, path, unit="N", ref=None, labels=None, title=None):
    """Band RMS (``nvh.bands.BandRMS``, one or several) as bars in ``unit`` (log axis) with the
    level in dB re ``ref`` (default the unit's reference) on the right."""
    bands = list(bands)
    r = reference(unit, ref)
    fig, ax = plt.subplots(figsize=(7.5, 3.8))
    n = len(bands)
    width = 0.8 / n
    x = np.arange(len(bands[0].rms))
    for i, b in enumerate(bands):
        ax.bar(x + (i - (n - 1) / 2) * width, b.rms, width, label=None if labels is None else labels[i])
    ax.set_yscale("log")
    set_band_ticks(ax, x, bands[0])
    ax.set_xlabel("band: nominal mid-band frequency (Hz)")
    ax.set_ylabel(f"band RMS ({unit})")
    db_axis(ax, r, unit, power=False)
    ax.grid(True, axis="y", which="both", alpha=0.3)
    if labels:
        ax.legend(fontsize=8)
    ax.set_title(title or f"band levels, dB re {r:g} {unit}", fontsize=10)
    save_figure(fig, path)


__all__ = ["band_ticks", "level_db", "plot_band_levels", "set_band_ticks", "plot_psd", "plot_transfer"]
