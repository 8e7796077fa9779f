"""The main job (``make demo``): build the FMU when its builder is present, and run the default
scenario, writing results and figures under ``results/``.

Writes: modes.json (Hz), trfam_xyz.png (Fig. 17-like, viscous and structural), trfam_<d>.csv,
fmu_outputs.csv (the default scenario through the FMU with fmpy), simulation.csv and
simulation.png (the core run: forces and the contact histogram beside the curvature, Fig. 22),
octave_bands.csv/.png (Table 3), scalogram.png (Fig. 21) and report.html.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

import numpy as np


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--out", default="results")
    p.add_argument("--duration", type=float, default=0.2, help="simulated time of the default scenario (s)")
    args = p.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    import cablecasing_core as cc
    from cablecasing_core.plotting import plot_octave_bands, plot_scalogram, plot_time_result, plot_trfam

    root = Path(__file__).resolve().parent.parent
    builder = root / "build_fmu.py"
    fmu_note = "FMU builder not present in this checkout."
    if builder.exists():
        r = subprocess.run([sys.executable, str(builder)], cwd=root)
        fmu_note = "FMU built: dist/CableCasing.fmu" if r.returncode == 0 else f"FMU build failed ({r.returncode})"
    print(fmu_note)

    model = cc.load_model()
    modes = {b: cc.natural_frequencies(model, b, 10).tolist() for b in model.bodies}
    (out / "modes.json").write_text(json.dumps(modes, indent=1))
    f = np.arange(10.0, 1000.0, 0.5)
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    for ax, d in zip(axes, "xyz"):
        for damping, style in (("structural", "-"), ("viscous", "--")):
            H = cc.trfam(model, f"casing.A.{d}", f"casing.B.{d}", f, damping)
            ax.semilogy(f, np.abs(H), style, label=damping)
            if damping == "viscous":
                np.savetxt(out / f"trfam_{d}.csv", np.column_stack([f, H.real, H.imag, np.abs(H)]), delimiter=",",
                           header="frequency_hz,re_kg,im_kg,magnitude_kg", comments="")
        ax.set_ylabel(f"|TRFAM| {d} (kg)")
        ax.legend()
    axes[-1].set_xlabel("frequency (Hz)")
    fig.tight_layout()
    fig.savefig(out / "trfam_xyz.png", dpi=110)
    plt.close(fig)
    plot_trfam(f, {"viscous": cc.trfam(model, "casing.A.z", "casing.B.z", f)}, out / "trfam_z.png")

    # the default scenario through the FMU (fmpy), the product's own path
    from .config import CHANNELS
    from .engine import SUPPORT_OUTPUTS
    from .scenario import scenario_motion
    h = 1e-4
    t = np.arange(0.0, args.duration + 0.5 * h, h)
    u, v, a = scenario_motion(model)(t)
    fmu_path = root / "dist" / "CableCasing.fmu"
    F = None
    if fmu_path.exists():
        from fmpy import simulate_fmu
        names = [f"{c[:-1]}{p}{c[-1]}" for p in ("", "v", "a") for c in CHANNELS]
        sig = np.zeros(len(t), dtype=[("time", float)] + [(n, float) for n in names])
        sig["time"] = t
        for k, arr in enumerate((u, v, a)):
            for c in range(len(CHANNELS)):
                sig[names[k * len(CHANNELS) + c]] = arr[:, c]
        r = simulate_fmu(str(fmu_path), stop_time=args.duration, step_size=h, output_interval=h, input=sig,
                         output=list(SUPPORT_OUTPUTS) + ["contact.active"])
        cols = list(r.dtype.names)
        np.savetxt(out / "fmu_outputs.csv", np.column_stack([r[c] for c in cols]), delimiter=",",
                   header=",".join(cols), comments="", fmt="%.9g")
        F, tF = r["casing.B.Fz"], r["time"]
        print(f"wrote {out / 'fmu_outputs.csv'} (default scenario through the FMU)")

    res = cc.simulate(model, duration=args.duration)          # per-node contact data for Fig. 22
    res.save(out / "simulation.csv")
    plot_time_result(res, out / "simulation.png")
    if F is None:
        F, tF = res.support_force("casing.B.Fz"), res.time
    from .studies import octave_rms
    keep = tF > 0.05
    bands = octave_rms(F[keep], 1.0 / (tF[1] - tF[0]), beyond_nyquist="drop")
    np.savetxt(out / "octave_bands.csv", np.column_stack([bands.lower, bands.upper, bands.rms]), delimiter=",",
               header="f_low_hz,f_high_hz,rms_N", comments="", fmt="%.6g")
    plot_octave_bands(bands, out / "octave_bands.png", "RMS casing.B.Fz (N)")
    scalogram = ""
    try:
        from .identification.wavelet import cwt_morlet
        fs = 1.0 / (tF[1] - tF[0])
        fr = np.geomspace(20.0, 2000.0, 80)
        W = np.abs(cwt_morlet(F, fs, fr))
        W = W if W.shape[0] == len(F) else W.T
        plot_scalogram(tF, fr, W, out / "scalogram.png", "|W| of casing.B.Fz (Fig. 21)")
        scalogram = '<h2>Wavelet scalogram of casing.B.Fz (Fig. 21)</h2><img src="scalogram.png">'
    except ImportError:
        print("scalogram skipped: the identification package is not available")
    rms = {n: float(np.sqrt(np.mean(res.support_force(n) ** 2))) for n in ("casing.B.Fx", "casing.B.Fy", "casing.B.Fz")}
    rows = "".join(f"<tr><td>{k}</td><td>{v:.4g}</td></tr>" for k, v in rms.items())
    (out / "report.html").write_text(f"""<!doctype html><html><head><meta charset="utf-8"><title>cablecasing demo</title></head>
<body><h1>Cable in casing: default specimen</h1>
<p>{fmu_note}. The default scenario (random 10-1000 Hz, 5 m/s2 RMS at casing end A in z, and the cable's
50 Hz axial excitation) was run through the FMU with fmpy (fmu_outputs.csv) and with the core for the
per-node contact data (simulation.csv).</p>
<h2>Natural frequencies (Hz)</h2><pre>{json.dumps({k: [round(x, 2) for x in v] for k, v in modes.items()}, indent=1)}</pre>
<h2>TRFAM of the casing (Eq. 12), structural and viscous damping (Fig. 17)</h2><img src="trfam_xyz.png">
<h2>Support forces and contact-time histogram beside the curvature (Fig. 22)</h2>
<img src="simulation.png"><table border=1><tr><th>output</th><th>RMS (N)</th></tr>{rows}</table>
<h2>Octave-band RMS of casing.B.Fz (Table 3)</h2><img src="octave_bands.png">
{scalogram}
</body></html>""")
    print(f"wrote {out}/ (see report.html)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
