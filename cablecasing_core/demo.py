"""The main job (``make demo``): build the FMU when its builder is present, and run the default
scenario, writing results and figures under ``results/``.

Writes: modes.json (Hz), trfam_xyz.png (Fig. 17-like, viscous and structural), trfam_<d>.csv,
simulation.csv (support forces), simulation.png (forces and the contact histogram, Fig. 22),
report.html.
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
    from cablecasing_core.plotting import plot_time_result, plot_trfam

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

    res = cc.simulate(model, duration=args.duration)
    res.save(out / "simulation.csv")
    plot_time_result(res, out / "simulation.png")
    rms = {n: float(np.sqrt(np.mean(res.support_force(n) ** 2))) for n in ("casing.B.Fx", "casing.B.Fy", "casing.B.Fz")}
    rows = "".join(f"<tr><td>{k}</td><td>{v:.4g}</td></tr>" for k, v in rms.items())
    (out / "report.html").write_text(f"""<!doctype html><html><head><meta charset="utf-8"><title>cablecasing demo</title></head>
<body><h1>Cable in casing: default specimen</h1>
<p>{fmu_note}</p>
<h2>Natural frequencies (Hz)</h2><pre>{json.dumps({k: [round(x, 2) for x in v] for k, v in modes.items()}, indent=1)}</pre>
<h2>TRFAM of the casing (Eq. 12), structural and viscous damping</h2><img src="trfam_xyz.png">
<h2>Default scenario ({args.duration} s): support forces and contact histogram (Fig. 22)</h2>
<img src="simulation.png"><table border=1><tr><th>output</th><th>RMS (N)</th></tr>{rows}</table>
</body></html>""")
    print(f"wrote {out}/ (modes.json, trfam_xyz.png, simulation.csv, simulation.png, report.html)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
