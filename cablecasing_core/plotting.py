"""Figures (matplotlib, Agg backend): TRFAM, geometry. Units on every axis."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def plot_trfam(freqs_hz, curves, path, title="TRFAM"):
    """Magnitude (kg, log) and phase (deg) of one or more TRFAM curves ``{label: complex array}``."""
    fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    for label, H in curves.items():
        a1.semilogy(freqs_hz, np.abs(H), label=label)
        a2.plot(freqs_hz, np.degrees(np.angle(H)), label=label)
    a1.set_ylabel("|TRFAM| (kg)")
    a2.set_ylabel("phase (deg)")
    a2.set_xlabel("frequency (Hz)")
    a1.set_title(title)
    a1.legend()
    a1.grid(True, which="both", alpha=0.3)
    a2.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_geometry(centerline, path, values=None, label=None):
    """3D view of the centerline (m); optional per-node ``values`` shown as colour."""
    fig = plt.figure(figsize=(6, 5))
    ax = fig.add_subplot(projection="3d")
    P = centerline.nodes
    ax.plot(P[:, 0], P[:, 1], P[:, 2], "-", color="0.5")
    if values is None:
        ax.scatter(P[:, 0], P[:, 1], P[:, 2], color="k", s=14)
    else:
        sc = ax.scatter(P[:, 0], P[:, 1], P[:, 2], c=values, s=14, cmap="viridis")
        fig.colorbar(sc, ax=ax, shrink=0.6, label=label or "")
    ax.text(*P[0], " A")
    ax.text(*P[-1], " B")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_time_result(res, path):
    """Support force at casing B (N) over time and the contact-time histogram over the cable's
    nodes with the centerline curvature beside it (Fig. 22)."""
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 6))
    for d in "xyz":
        a1.plot(res.time, res.support_force(f"casing.B.F{d}"), lw=0.6, label=f"casing.B.F{d}")
    a1.set_xlabel("time (s)")
    a1.set_ylabel("support force (N)")
    a1.legend()
    a2.bar(res.arc_length, res.contact_time, width=0.8 * (res.arc_length[1] - res.arc_length[0]), label="contact time")
    a2.set_xlabel("arc length from A (m)")
    a2.set_ylabel("contact time (s)")
    ax = a2.twinx()
    ax.plot(res.arc_length, res.curvature, "r-", label="curvature")
    ax.set_ylabel("curvature (1/m)", color="r")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_octave_bands(bands, path, ylabel="RMS"):
    """Bar chart of octave-band RMS values (``studies.octave_rms`` result), Table 3."""
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.bar(range(1, len(bands.rms) + 1), bands.rms)
    ax.set_xticks(range(1, len(bands.rms) + 1), [f"{lo:g}-{hi:g}" for lo, hi in zip(bands.lower, bands.upper)],
                  rotation=45, fontsize=7)
    ax.set_xlabel("octave band (Hz)")
    ax.set_ylabel(ylabel)
    _save(fig, path)


def plot_ensemble(ens, path, other=None, diff=None, confidence=0.95, labels=("base", "against")):
    """Band levels over excitation seeds (``studies.seed_ensemble``): the ensemble mean per band with
    its Student-t confidence interval (N, or N.m for a moment output; log axis), a second ensemble
    beside it, and, with ``diff`` (``studies.paired_difference(other, ens)``), the relative change
    r (%) per band with its interval."""
    unit = "N" if ".F" in ens.output else "N.m"
    x = np.arange(1, len(ens.labels) + 1)
    rows = 2 if diff is not None else 1
    fig, axes = plt.subplots(rows, 1, figsize=(7, 3.2 * rows + 0.6), sharex=True, squeeze=False)
    ax = axes[0, 0]
    sets = [(ens, labels[0], -0.12)] + ([(other, labels[1], 0.12)] if other is not None else [])
    for e, lab, dx in sets:
        lo, hi = e.ci(confidence)
        ax.errorbar(x + dx, e.mean, yerr=[e.mean - lo, hi - e.mean], fmt="o", capsize=3,
                    label=f"{lab} (mean of {e.n} seeds, {confidence:.0%} CI)")
    ax.set_yscale("log")
    ax.set_ylabel(f"RMS {ens.output} ({unit})")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    if diff is not None:
        a2 = axes[1, 0]
        lo, hi = diff.ci(confidence)
        a2.errorbar(x, 100 * diff.r, yerr=[100 * (diff.r - lo), 100 * (hi - diff.r)], fmt="s", capsize=3)
        a2.axhline(0.0, color="k", lw=0.8)
        a2.set_ylabel(f"{labels[1]} vs {labels[0]} (%)")
        a2.grid(True, alpha=0.3)
    last = axes[-1, 0]
    last.set_xticks(x, [f"{lo:g}-{hi:g}" for lo, hi in zip(ens.lower, ens.upper)], rotation=45, fontsize=7)
    last.set_xlabel("band (Hz)")
    _save(fig, path)


def plot_scalogram(t, freqs_hz, W, path, title="|W|"):
    """Wavelet scalogram |W| (time s x frequency Hz), Figs. 20-21."""
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.pcolormesh(t, freqs_hz, np.asarray(W).T, shading="auto")
    ax.set_yscale("log")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title(title)
    _save(fig, path)
