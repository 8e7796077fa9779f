"""The worked example of docs/mounted_example.md: a gear-shift cable as installed
(examples/installation.toml: segment routing, isolated ends, two clips), its routing, its TRFAM with and
without the isolators and clips, and what the isolators do to the force transmitted to the gearbox
bracket (a time-domain ensemble with the cable inside and contact on).

    .venv/bin/python examples/installation.py [--seeds 6] [--duration 1.0] [--out results/installation]

Prints ``name: value`` lines (the figures quoted in docs/mounted_example.md) and writes
installation_routing.png, installation_trfam.png and installation_force.png into --out (default
results/installation; ``--out docs/img`` remakes the committed figures that docs/mounted_example.md shows).
"""

from __future__ import annotations

import argparse
import copy
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import cablecasing_core as cc
from cablecasing_core.frequency.trfam import trfam_band_rms
from cablecasing_core.plotting import plot_routing, save_figure
from cablecasing_core.studies import Bands, octave_rms

HERE = Path(__file__).resolve().parent


def variants(model):
    """The installation and three reference variants of it (Model each)."""
    d = model.data
    clamped = copy.deepcopy(d)
    clamped["casing"]["supports"] = {"A": "clamped", "B": "clamped"}
    del clamped["casing"]["isolator"]
    bare = copy.deepcopy(clamped)
    del bare["casing"]["clip"]
    no_table = copy.deepcopy(d)
    for s in "AB":
        del no_table["casing"]["isolator"][s]["table"]
    mk = lambda x: cc.model_from_dict(x, source=model.source)  # noqa: E731
    return {
        "clamped ends, no clips": mk(bare),
        "clamped ends, two clips": mk(clamped),
        "isolators + clips (viscous c)": mk(no_table),
        "isolators + clips (rubber table)": model,
    }


def main(argv=None):
    p = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.ArgumentDefaultsHelpFormatter
    )
    p.add_argument("--seeds", type=int, default=6, help="ensemble members per variant")
    p.add_argument("--duration", type=float, default=1.0, help="s per member (0.1 s skipped)")
    p.add_argument(
        "--out",
        default=str(HERE.parent / "results" / "installation"),
        help="folder of the figures (docs/img remakes the committed docs/img/installation_*.png)",
    )
    args = p.parse_args(argv)
    if args.seeds < 2:
        p.error(f"--seeds {args.seeds}: the ensembles need at least 2 members (their scatter is a standard deviation)")
    need = 0.1 + 1.0 / 11.0  # the skipped 0.1 s and one FFT line in octave 1 (11-22 Hz)
    if not args.duration >= need:
        p.error(f"--duration {args.duration:g}: the band levels need at least {need:.4g} s (0.1 s is skipped)")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    model = cc.load_model(HERE / "installation.toml")
    plot_routing(model, out / "installation_routing.png")

    f = np.arange(5.0, 1000.0 + 0.125, 0.25)  # Hz, to 1000 Hz: the last band's upper edge
    curves = {}
    for label, m in variants(model).items():
        # one damping model of the casing for all (its loss factor 0.05, Eq. 11), so that the curves
        # differ by the supports alone; the isolators' own damping (c or the table) acts in each
        curves[label] = cc.trfam(m, "casing.A.z", "casing.B.z", f, damping="structural")
        print(f"first_casing_frequency_hz[{label}]: {cc.natural_frequencies(m, 'casing', 1)[0]:.4g}")
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for label, H in curves.items():
        ax.loglog(f, np.abs(H), lw=1, label=label)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("|TRFAM| casing.B.z / casing.A.z (kg)")
    ax.set_title(
        "force at the gearbox bracket (B) per acceleration of the shifter end (A); casing loss factor 0.05", fontsize=9
    )
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    save_figure(fig, out / "installation_trfam.png")
    # the RMS of |TRFAM| over each band (trfam_band_rms: sqrt of the integral of |TRFAM|^2 over the band
    # / its width), relative to the clamped casing with its clips: docs/mounted_example.md's bands, then
    # Table 3's octaves (`cablecasing trfam --bands table3`, the report's bands) within the grid
    edges = ((10, 50), (50, 100), (100, 200), (200, 500), (500, 1000))
    own = Bands([lo for lo, _ in edges], [hi for _, hi in edges], [f"{lo}-{hi} Hz" for lo, hi in edges])
    ref = curves["clamped ends, two clips"]
    for bands, key in ((own, "trfam_rms_ratio"), ("table3", "trfam_table3_rms_ratio")):
        base = trfam_band_rms(f, ref, bands)
        for label in ("isolators + clips (viscous c)", "isolators + clips (rubber table)"):
            mine = trfam_band_rms(f, curves[label], bands)
            for lab, lo, hi, r in zip(mine.labels, mine.lower, mine.upper, mine.rms / base.rms):
                where = lab if bands is own else f"{lab} {lo:g}-{hi:g} Hz"
                print(f"{key}[{label}, {where}]: {r:.3g}")

    # the transmitted force in the time domain, cable inside and contact on: band levels over seeds
    runs = {}
    for label in ("clamped ends, two clips", "isolators + clips (viscous c)"):
        m = variants(model)[label]
        power = []
        for seed in range(1, args.seeds + 1):
            res = cc.simulate(m.with_overrides({"scenario.excitation.shaker.seed": seed}), duration=args.duration)
            x = res.support_force("casing.B.Fz")[res.time > 0.1]
            power.append(octave_rms(x, 1.0 / m.scenario["dt"], window="hann").rms ** 2)
        power = np.array(power)
        bands = octave_rms(x, 1.0 / m.scenario["dt"], window="hann")
        runs[label] = (power.mean(axis=0), power.std(axis=0, ddof=1) / np.sqrt(args.seeds))
    keep = bands.upper <= 1420.0
    centres = np.sqrt(bands.lower * bands.upper)[keep]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for k, (label, (mean, se)) in enumerate(runs.items()):
        db = 10 * np.log10(mean[keep])
        err = 10 / np.log(10) * se[keep] / mean[keep]
        ax.errorbar(centres * (0.96 + 0.08 * k), db, yerr=err, fmt="o-", capsize=3, label=label)
    for lo, hi, mc, mi in zip(bands.lower[keep], bands.upper[keep], runs["clamped ends, two clips"][0][keep],
                              runs["isolators + clips (viscous c)"][0][keep]):  # fmt: skip
        print(f"force_band_db_change[{lo:g}-{hi:g} Hz]: {10 * np.log10(mi / mc):+.1f}")
    ax.set_xscale("log")
    ax.set_xlabel("Table 3 band centre (Hz)")
    ax.set_ylabel("casing.B.Fz band level (dB re 1 N)")
    ax.set_title(
        f"force at B over {args.seeds} seeds ({args.duration:g} s, Hann), cable inside, contact on: mean +- 1 SE",
        fontsize=9,
    )
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    save_figure(fig, out / "installation_force.png")


if __name__ == "__main__":
    main()
