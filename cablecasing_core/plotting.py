"""Figures (matplotlib, Agg backend): TRFAM, geometry, time histories, octave bands, scalograms.
Units on every axis. The figures of the studies and of the identification are in their packages
(``studies/plots.py``, ``identification/plots.py``), written with :func:`save_figure`."""

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
    save_figure(fig, path)


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
    save_figure(fig, path)


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
    save_figure(fig, path)


def save_figure(fig, path):
    """Lay out ``fig``, write it to ``path`` (PNG, 110 dpi) and close it."""
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_octave_bands(bands, path, ylabel="RMS"):
    """Bar chart of octave-band RMS values (``studies.octave_rms`` result), Table 3."""
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.bar(range(1, len(bands.rms) + 1), bands.rms)
    ax.set_xticks(
        range(1, len(bands.rms) + 1),
        [f"{lo:g}-{hi:g}" for lo, hi in zip(bands.lower, bands.upper)],
        rotation=45,
        fontsize=7,
    )
    ax.set_xlabel("octave band (Hz)")
    ax.set_ylabel(ylabel)
    save_figure(fig, path)


def plot_scalogram(t, freqs_hz, W, path, title="|W|"):
    """Wavelet scalogram |W| (time s x frequency Hz), Figs. 20-21."""
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.pcolormesh(t, freqs_hz, np.asarray(W).T, shading="auto")
    ax.set_yscale("log")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title(title)
    save_figure(fig, path)
