"""Figures of the model (matplotlib, Agg backend): TRFAM (Fig. 17), geometry and contact (Fig. 22),
time histories, scalograms without and with the cable drive (Figs. 20-21). Units on every axis. The
figures of the studies, of the NVH outputs (band levels: ``plot_band_levels``) and of the
identification are in their packages (``studies/plots.py``, ``nvh/plots.py``,
``identification/plots.py``), written with :func:`save_figure`."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .files import atomic_path  # noqa: E402

#: Line styles of the damping models, as in Fig. 17 (structural solid, viscous dashed).
DAMPING_STYLES = {"structural": "-", "viscous": "--", "none": ":"}


def plot_trfam(freqs_hz, curves, path, title="TRFAM", log_frequency=False):
    """Magnitude (kg, log) and phase (deg) of one or more TRFAM curves ``{label: complex array}``;
    ``log_frequency``: logarithmic frequency axis."""
    fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    for label, H in curves.items():
        style = DAMPING_STYLES.get(label, "-")
        a1.semilogy(freqs_hz, np.abs(H), style, label=label)
        a2.plot(freqs_hz, np.degrees(np.angle(H)), style, label=label)
    a1.set_ylabel("|TRFAM| (kg)")
    a2.set_ylabel("phase (deg)")
    a2.set_yticks([-180, -90, 0, 90, 180])
    a2.set_xlabel("frequency (Hz)")
    if log_frequency:
        a2.set_xscale("log")
        plain_log_ticks(a2, freqs_hz)
    a1.set_title(title)
    a1.legend()
    a1.grid(True, which="both", alpha=0.3)
    a2.grid(True, which="both", alpha=0.3)
    save_figure(fig, path)


def plot_trfam_xyz(freqs_hz, curves, path, title="TRFAM", log_frequency=True, natural_hz=()):
    """Fig. 17: the TRFAM in x, y and z (rows), magnitude (kg, log) and phase (deg) side by side,
    one curve per damping model. ``curves`` = {direction: {damping: complex array}};
    ``natural_hz``: natural frequencies marked by thin vertical lines."""
    fig, axes = plt.subplots(3, 2, figsize=(10, 8), sharex=True, gridspec_kw={"width_ratios": [3, 2]})
    for row, (d, by_damping) in enumerate(curves.items()):
        am, ap = axes[row]
        for label, H in by_damping.items():
            style = DAMPING_STYLES.get(label, "-")
            am.semilogy(freqs_hz, np.abs(H), style, lw=1.0, label=label)
            ap.plot(freqs_hz, np.degrees(np.angle(H)), style, lw=0.8, label=label)
        for f in natural_hz:
            for ax in (am, ap):
                ax.axvline(f, color="tab:green", lw=0.6, alpha=0.5, zorder=0)
        am.set_ylabel(f"|TRFAM| {d} (kg)")
        ap.set_ylabel(f"phase {d} (deg)")
        ap.set_yticks([-180, -90, 0, 90, 180])
        am.set_title(f"({'abc'[row]}) direction {d}", loc="left", fontsize=9)
        for ax in (am, ap):
            ax.grid(True, which="both", alpha=0.3)
    axes[0, 0].legend(fontsize=8, title="damping", title_fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel("frequency (Hz)")
        if log_frequency:
            ax.set_xscale("log")
            plain_log_ticks(ax, freqs_hz)
    fig.suptitle(title, fontsize=10)
    save_figure(fig, path)


def plain_log_ticks(ax, freqs_hz, axis="x"):
    """Ticks 1-2-5 per decade, written as plain numbers, on a logarithmic frequency axis (Hz)."""
    from matplotlib.ticker import FixedLocator, NullFormatter, ScalarFormatter

    lo, hi = float(np.min(freqs_hz)), float(np.max(freqs_hz))
    ticks = [m * 10.0**e for e in range(-1, 6) for m in (1, 2, 5) if lo <= m * 10.0**e <= hi]
    a = ax.xaxis if axis == "x" else ax.yaxis
    a.set_major_locator(FixedLocator(ticks))
    a.set_major_formatter(ScalarFormatter())
    a.set_minor_formatter(NullFormatter())


def _route_axes(ax, P):
    """The 3D axes of a route's nodes ``P`` (m): equal scales, at most four ticks per axis, and an
    axis along which the route is flat (extent below 2 % of the largest: a route in a plane) drawn
    thin with a single tick at its value, so its ticks do not pile up over the labels."""
    from matplotlib.ticker import FixedLocator, MaxNLocator

    ext = np.ptp(P, axis=0)
    big = float(ext.max()) or 1.0
    ax.set_box_aspect(np.maximum(ext, 0.08 * big) + 0.05 * big)
    for k, axis in enumerate((ax.xaxis, ax.yaxis, ax.zaxis)):
        if ext[k] < 0.02 * big:
            mid = float(np.mean(P[:, k]))
            (ax.set_xlim, ax.set_ylim, ax.set_zlim)[k](mid - 0.06 * big, mid + 0.06 * big)
            axis.set_major_locator(FixedLocator([round(mid, 6) + 0.0]))
        else:
            axis.set_major_locator(MaxNLocator(4))
    ax.tick_params(labelsize=7)


def plot_geometry(centerline, path, values=None, label=None, title=None):
    """3D view of the centerline (m) with ends A and B; optional per-node ``values`` as colour
    (e.g. the contact time of Fig. 22a, with ``label`` for the colour bar)."""
    fig = plt.figure(figsize=(6.5, 5))
    ax = fig.add_subplot(projection="3d")
    P = centerline.nodes
    ax.plot(P[:, 0], P[:, 1], P[:, 2], "-", color="0.5")
    if values is None:
        ax.scatter(P[:, 0], P[:, 1], P[:, 2], color="k", s=14)
    else:
        sc = ax.scatter(P[:, 0], P[:, 1], P[:, 2], c=values, s=30, cmap="viridis")
        fig.colorbar(sc, ax=ax, shrink=0.6, pad=0.12, label=label or "")
    ax.text(*P[0], " A")
    ax.text(*P[-1], " B")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    _route_axes(ax, P)
    if title:
        ax.set_title(title, fontsize=10)
    save_figure(fig, path)


def plot_routing(model, path, summary=None):
    """The routing as ``cablecasing geometry --plot`` draws it (like Fig. 22a): a 3D view of the
    centerline (m) with its nodes, the supports of the casing (clamped, isolator, free) and its
    clips, and the curvature (1/m) along the arc length (m) with the bends shaded, the nodes marked
    and the smallest radius noted."""
    from .structure.geometry import centerline_of
    from .structure.mount_element import clip_node
    from .structure.route_summary import curvature_profile, geometry_summary

    g = summary or geometry_summary(model)
    cl = centerline_of(model)
    s, k = curvature_profile(model)
    P = cl.nodes
    fig = plt.figure(figsize=(11, 4.8))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    ax.plot(P[:, 0], P[:, 1], P[:, 2], "-", color="0.5", lw=1)
    ax.scatter(P[:, 0], P[:, 1], P[:, 2], color="k", s=6)
    body = "casing" if "casing" in model.bodies else next(iter(model.bodies))
    marks = {"clamped": ("s", "k"), "isolator": ("o", "tab:orange"), "free": ("^", "0.6")}
    for end, node in (("A", 0), ("B", -1)):
        kind = model.bodies[body].supports[end]
        m, c = marks[kind]
        ax.scatter(*P[node], marker=m, color=c, s=70, depthshade=False)
        ax.text(*P[node], f"  {end} ({kind})", fontsize=8)
    for i, clip in enumerate(model.data.get("casing", {}).get("clip", [])):
        node = clip_node(cl.s, clip["at"])
        ax.scatter(*P[node], marker="D", color="tab:blue", s=50, depthshade=False)
        name = clip.get("excitation", f"clip {i}")
        ax.text(*P[node], f"  {name} ({cl.s[node]:.3g} m)", fontsize=7, color="tab:blue")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    _route_axes(ax, P)
    ax.set_title(f"routing ({g['source']}): {g['length_m']:.4g} m, {g['n_elements']} elements", fontsize=9)
    a2 = fig.add_subplot(1, 2, 2)
    a2.plot(s, k, "r-", lw=1.2, label="curvature")
    for b in g["bends"]:
        arc = np.radians(b["angle_deg"]) * b["radius_m"]
        a2.axvspan(b["start_m"], b["start_m"] + max(arc, 1e-3 * g["length_m"]), color="tab:orange", alpha=0.15)
    a2.plot(cl.s, cl.curvature, "k.", ms=4, label="at the nodes")
    for clip in model.data.get("casing", {}).get("clip", []):
        a2.axvline(cl.s[clip_node(cl.s, clip["at"])], color="tab:blue", lw=0.8, ls="--")  # (where it acts)
    if g["min_radius_m"]:
        a2.set_title(
            f"min radius {g['min_radius_m']:.4g} m at s = {g['min_radius_at_m']:.4g} m, "
            f"total bend {g['total_bend_deg']:.4g} deg",
            fontsize=9,
        )
    a2.set_xlabel("arc length from end A (m)")
    a2.set_ylabel("curvature (1/m)")
    a2.grid(True, alpha=0.3)
    a2.legend(fontsize=8)
    save_figure(fig, path)


def plot_time_result(res, path, outputs=("casing.B.Fx", "casing.B.Fy", "casing.B.Fz")):
    """Support forces (N) over time and, when the run had contact, the contact-time histogram over
    the cable's nodes with the centerline's curvature beside it (Fig. 22b); without contact the
    second panel shows the curvature alone and says so."""
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 6))
    for name in outputs:
        a1.plot(res.time, res.support_force(name), lw=0.6, label=name)
    a1.set_xlabel("time (s)")
    a1.set_ylabel("support force (N)")
    a1.legend(fontsize=8)
    a1.grid(True, alpha=0.3)
    plot_contact_histogram(a2, res.arc_length, res.contact_time, res.curvature)
    save_figure(fig, path)


def plot_contact_histogram(ax, arc_length, contact_time, curvature, label="contact time (s)"):
    """On ``ax``: bars of ``contact_time`` per cable node over the arc length (m) and the curvature
    (1/m) on a second axis (Fig. 22b). No bars (and a note) when there was no contact."""
    if np.any(contact_time > 0):
        ax.bar(arc_length, contact_time, width=0.8 * (arc_length[1] - arc_length[0]), label=label)
        ax.set_ylabel(label)
        ax.set_ylim(bottom=0)
    else:
        ax.set_yticks([])
        ax.text(
            0.02,
            0.9,
            "no contact in this run (contact off, or the gap never closed)",
            transform=ax.transAxes,
            fontsize=9,
        )
    ax.set_xlabel("arc length from A (m)")
    c = ax.twinx()
    c.plot(arc_length, curvature, "r-", label="curvature")
    c.set_ylabel("curvature (1/m)", color="r")
    c.set_ylim(bottom=0)


def save_figure(fig, path):
    """Lay out ``fig``, write it to ``path`` (PNG at 110 dpi, or by suffix; atomically) and close it."""
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)


def plot_scalograms(
    panels,
    freqs_hz,
    path,
    unit="N",
    natural_hz=(),
    harmonics_hz=(),
    title=None,
    harmonics_on=None,
    skip_s=None,
    cone_gamma=None,
):
    """Scalograms side by side (Figs. 20-21): ``panels`` = [(t s, |W| (n_t x n_f) in ``unit``, title),
    ...], each with its own colour bar of |W| in ``unit`` (a harmonic of amplitude A shows as |W| = A
    on its ridge: the Morlet transform of ``identification.wavelet``), so that a weak panel stays
    readable beside a strong one; each panel's title states its scale when the scales differ.
    ``natural_hz`` are marked by dashed white lines labelled on the right of the last panel,
    ``harmonics_hz`` (a drive frequency and its multiples) by dotted red lines labelled inside the
    panels ``harmonics_on`` (indices; default every panel: a panel without the drive has none).
    ``skip_s``: a grey vertical line at that time (s; the start left out of the levels);
    ``cone_gamma``: the Morlet gamma of the transform, whose cone of influence is drawn in grey
    dash-dot: within sqrt(2) gamma / (2 pi f) s of either end of the record the transform feels the
    record's edges (the e-folding time of an edge's effect on the wavelet power, Torrence & Compo
    1998, with the envelope's standard deviation gamma / (2 pi f) of ``cwt_morlet``)."""
    fig, axes = plt.subplots(1, len(panels), figsize=(5.6 * len(panels), 4.4), sharey=True, squeeze=False)
    tops = [float(np.max(W)) or 1.0 for _, W, _ in panels]
    differ = max(tops) > 1.5 * min(tops)
    marked = range(len(panels)) if harmonics_on is None else harmonics_on
    for k, (ax, (t, W, sub)) in enumerate(zip(axes[0], panels)):
        W = np.asarray(W)
        mesh = ax.pcolormesh(t, freqs_hz, W.T, shading="auto", cmap="magma", vmin=0, vmax=tops[k])
        fig.colorbar(mesh, ax=ax, label=f"|W| ({unit})", pad=0.02 if k < len(panels) - 1 else 0.09)
        ax.set_yscale("log")
        ax.set_ylim(freqs_hz[0], freqs_hz[-1])
        plain_log_ticks(ax, freqs_hz, axis="y")
        ax.set_xlabel("time (s)")
        scale = f"\ncolour scale 0-{tops[k]:.3g} {unit}"
        if tops[k] < max(tops):
            scale += f" ({max(tops) / tops[k]:.2g} x finer than panel ({chr(97 + tops.index(max(tops)))}))"
        ax.set_title(f"({chr(97 + k)}) {sub}{scale if differ else ''}", fontsize=9, loc="left")
        for f in natural_hz:
            ax.axhline(f, color="w", ls="--", lw=0.6, alpha=0.7)
        if skip_s is not None:
            ax.axvline(skip_s, color="0.75", ls="-", lw=1.0)
        if cone_gamma is not None and len(t):
            f = np.asarray(freqs_hz, dtype=float)
            tau = np.sqrt(2.0) * cone_gamma / (2.0 * np.pi * f)
            for edge in (t[0] + tau, t[-1] - tau):
                inside = (edge >= t[0]) & (edge <= t[-1])
                ax.plot(edge[inside], f[inside], color="0.75", ls="-.", lw=0.9)
            ax.set_xlim(t[0], t[-1])
        if k in marked:
            for f in harmonics_hz:
                ax.axhline(f, color="tab:red", ls=":", lw=1.0)
            _labels(ax, harmonics_hz, 0.01, 0, "left", "tab:red", "{:g} Hz", inside=True)
        if k == len(panels) - 1:
            _labels(ax, natural_hz, 1.0, 2, "left", "0.3", "{:.0f}")
    axes[0, 0].set_ylabel("frequency (Hz)")
    if title:
        fig.suptitle(title, fontsize=10)
    save_figure(fig, path)


def _labels(ax, freqs, x, dx, ha, color, fmt, inside=False):
    """Labels of marked frequencies at the left or right edge of ``ax``, skipping any that would
    overlap the one below (closer than 1.3 font heights on the axis as drawn); ``inside``: on a
    dark box, for labels drawn over the image."""
    size = 7 if inside else 6
    fig = ax.figure
    height_pt = ax.get_position().height * fig.get_figheight() * 72
    lo, hi = (np.log(v) for v in ax.get_ylim())
    last = -np.inf
    for f in sorted(freqs):
        y_pt = (np.log(f) - lo) / (hi - lo) * height_pt
        if not lo <= np.log(f) <= hi or y_pt - last < 1.3 * size:
            continue
        last = y_pt
        ax.annotate(
            fmt.format(f),
            (x, f),
            xycoords=("axes fraction", "data"),
            xytext=(dx, 0),
            textcoords="offset points",
            fontsize=size,
            va="center",
            ha=ha,
            color=color,
            bbox=dict(boxstyle="square,pad=0.1", fc="black", ec="none", alpha=0.6) if inside else None,
        )
