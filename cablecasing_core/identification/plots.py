"""Figures of the identification (matplotlib, Agg backend), in the layout of the paper's figures.

* :func:`plot_ridges` - Fig. 10 (impulse response and its scalogram) and Fig. 11 (ln|W| along the
  ridges with the fitted lines, the edges and the noise floor).
* :func:`plot_circles` - Fig. 13: (a-c) Nyquist plots with the fitted circles, (d-f) loss-factor
  planes, (g-i) the ridge on the main diagonal.
* :func:`plot_modulus` - Fig. 8 (the adaptive process) and Fig. 9 (E against f with the smooth fit).
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import MaxNLocator, ScalarFormatter  # noqa: E402

from ..plotting import save_figure  # noqa: E402
from .wavelet import cwt_morlet  # noqa: E402


def plot_ridges(results, path, x=None, fs=None):
    """ln|W| along each ridge (Fig. 11); with the record ``x`` (sampled at ``fs`` Hz) also the
    impulse response and its scalogram (Fig. 10). ``results`` from :func:`wavelet_damping`."""
    n = len(results)
    top = x is not None and fs is not None
    fig, axes = plt.subplots(n + (2 if top else 0), 1, figsize=(7, 2.3 * (n + (2 if top else 0))), squeeze=False)
    axes = axes[:, 0]
    if top:
        t = results[0].t if len(results[0].t) == len(x) else np.arange(len(x)) / fs  # (the record's time axis)
        axes[0].plot(t, x, "k-", lw=0.7)
        axes[0].set_xlabel("time (s)")
        axes[0].set_ylabel("response")
        axes[0].set_title("impulse response (Fig. 10)")
        f_lo = 0.5 * min(r.f_requested_hz for r in results)
        f_hi = min(1.5 * max(r.f_requested_hz for r in results), 0.49 * fs)
        fr = np.linspace(f_lo, f_hi, 120)
        W = cwt_morlet(x, fs, fr, results[0].gamma, magnitude=True)  # (|W| as float: half the memory)
        step = max(1, len(t) // 800)
        axes[1].pcolormesh(t[::step], fr, W[::step].T, shading="auto", cmap="viridis")
        for r in results:
            axes[1].plot(r.t[r.fit_mask], r.ridge_hz[r.fit_mask], "w-", lw=0.8)
        axes[1].set_xlabel("time (s)")
        axes[1].set_ylabel("frequency (Hz)")
        axes[1].set_title("|W| and ridges")
        axes = axes[2:]
    for ax, r in zip(axes, results):
        ax.plot(r.t, r.log_w, color="0.6", lw=0.8, label="ln|W| on the ridge")
        ax.plot(r.t[r.fit_mask], r.log_w[r.fit_mask], "b-", lw=1.2, label="fitted part")
        tf = np.array(r.t_fit)
        ax.plot(tf, r.intercept + r.slope * tf, "r--", lw=1.2, label=f"slope {r.slope:.4g} 1/s, zeta = {r.zeta:.4g}")
        ax.axvspan(r.t[0], r.valid_from_s, color="0.9")
        ax.axvspan(r.t[-1] - r.edge_s, r.t[-1], color="0.9")
        if r.noise_floor > 0:
            ax.axhline(np.log(r.noise_floor), color="0.4", ls=":", lw=0.8, label="noise floor")
        finite = r.log_w[np.isfinite(r.log_w)]
        if finite.size:
            ax.set_ylim(max(finite.min(), np.log(max(r.noise_floor, 1e-300)) - 2), finite.max() + 0.5)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("ln|W|")
        ax.set_title(f"f_r = {r.f_natural_hz:.2f} Hz (ridge {r.f_ridge_hz:.2f} Hz)")
        ax.legend(fontsize=7, loc="upper right")
    save_figure(fig, path)


def plot_circles(results, path):
    """Fig. 13 for each resonance: Nyquist plot with the fitted circle, the loss-factor plane and
    its diagonal ridge. ``results`` from :func:`loss_factor_circle`."""
    n = len(results)
    fig, axes = plt.subplots(3, n, figsize=(3.6 * n, 9.5), squeeze=False)
    for j, r in enumerate(results):
        a, b, c = axes[0, j], axes[1, j], axes[2, j]
        s = np.linspace(0, 2 * np.pi, 361)
        a.plot(r.points.real, r.points.imag, "ko", ms=3, label="FRF (corrected)")
        a.plot(
            (r.centre + r.radius * np.exp(1j * s)).real,
            (r.centre + r.radius * np.exp(1j * s)).imag,
            "r-",
            lw=1,
            label="fitted circle",
        )
        zr = r.centre + r.radius * np.exp(1j * r.phi_r)
        a.plot([r.centre.real, zr.real], [r.centre.imag, zr.imag], "b-", lw=1)
        a.plot(zr.real, zr.imag, "bs", ms=5, label="resonance")
        a.set_aspect("equal", adjustable="datalim")
        a.set_xlabel("Re")
        a.set_ylabel("Im")
        a.set_title(f"f_r = {r.f_r_hz:.1f} Hz")
        a.legend(fontsize=6)
        # colour range at least +-1 % of eta, so that a flat plane looks flat (no rounding-noise stripes)
        lo = min(np.percentile(r.plane, 5), 0.99 * r.eta)
        hi = max(np.percentile(r.plane, 95), 1.01 * r.eta)
        im = b.pcolormesh(r.f_above_hz, r.f_below_hz, r.plane, shading="auto", cmap="viridis", vmin=lo, vmax=hi)
        cb = fig.colorbar(im, ax=b, label="eta")
        cb.formatter = ScalarFormatter(useOffset=False)
        cb.update_ticks()
        b.set_xlabel("f above (Hz)")
        b.set_ylabel("f below (Hz)")
        b.set_title("loss-factor plane")
        k = np.arange(1, r.diagonal.size + 1)
        c.plot(k, r.diagonal, "ko-", ms=3)
        c.axhline(r.eta, color="r", ls="--", label=f"eta = {r.eta:.4g}")
        c.set_ylim(min(r.diagonal.min(), 0.99 * r.eta), max(r.diagonal.max(), 1.01 * r.eta))
        c.yaxis.set_major_formatter(ScalarFormatter(useOffset=False))
        c.set_xlabel("pair index from the resonance")
        c.set_ylabel("eta on the diagonal")
        c.legend(fontsize=7)
    save_figure(fig, path)


def plot_modulus(result, path):
    """Fig. 8 (adaptive steps of E per mode) and Fig. 9 (identified E against f, smooth fit, table)."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    for f_m, m, steps in zip(result.f_measured_hz, result.modes, result.history):
        E = [s[0] for s in steps]
        a.plot(range(len(E)), E, "o--", label=f"mode {m} ({f_m:.1f} Hz)")
    a.xaxis.set_major_locator(MaxNLocator(integer=True))
    a.set_xlabel("adaptive step")
    a.set_ylabel("E (Pa)")
    a.set_title("adaptive process (Fig. 8)")
    a.legend(fontsize=7)
    tab = np.asarray(result.table)
    if result.f_measured_hz.min() < result.f_measured_hz.max():
        ff = np.geomspace(result.f_measured_hz.min(), result.f_measured_hz.max(), 200)
        b.plot(ff, result.E_fit(ff), "k-", label="smooth fit")
    b.plot(tab[:, 0], tab[:, 1], "k+", label="table rows")
    b.plot(result.f_measured_hz, result.E_mode, "o", mfc="none", label="per measured mode")
    b.set_xlabel("frequency (Hz)")
    b.set_ylabel("E (Pa)")
    b.set_title("dynamic modulus (Fig. 9)")
    b.legend(fontsize=7)
    save_figure(fig, path)
