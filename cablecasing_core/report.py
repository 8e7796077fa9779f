"""The report of the built-in specimen (``cablecasing report``; ``examples/demo.py`` adds the FMU run):
natural frequencies, the casing's TRFAM, the default scenario in the time domain, its octave bands
and its wavelet scalogram, as CSV and PNG files and one ``report.html``.

Writes into ``out``: modes.json (Hz), trfam_xyz.png (Fig. 17-like, viscous and structural),
trfam_<d>.csv, trfam_z.png, simulation.csv and simulation.png (the core run: forces and the contact
histogram beside the curvature, Fig. 22), octave_bands.csv/.png (Table 3), scalogram.png (Fig. 21)
and report.html.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np


def write_report(
    out: str | Path, duration: float = 0.2, fmu_force: tuple | None = None, fmu_note: str = "The FMU was not run."
) -> Path:
    """Run the built-in specimen and write the report into the folder ``out``.

    duration: simulated time of the default scenario (s). fmu_force: ``(t, F)``, the time (s) and
    casing.B.Fz (N) of the same scenario through the FMU, when it was run; the octave bands and the
    scalogram are then those of the FMU's record, else of the core's. fmu_note: one sentence on the
    FMU for the report. Returns the path of report.html.
    """
    import matplotlib.pyplot as plt

    import cablecasing_core as cc

    from .identification.wavelet import cwt_morlet
    from .plotting import plot_octave_bands, plot_scalogram, plot_time_result, plot_trfam, save_figure
    from .studies import octave_rms

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    model = cc.load_model()
    modes = {b: cc.natural_frequencies(model, b, 10).tolist() for b in model.bodies}
    (out / "modes.json").write_text(json.dumps(modes, indent=1))
    f = np.arange(10.0, 1000.0, 0.5)
    fig, axes = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    for ax, d in zip(axes, "xyz"):
        for damping, style in (("structural", "-"), ("viscous", "--")):
            H = cc.trfam(model, f"casing.A.{d}", f"casing.B.{d}", f, damping)
            ax.semilogy(f, np.abs(H), style, label=damping)
            if damping == "viscous":
                np.savetxt(
                    out / f"trfam_{d}.csv",
                    np.column_stack([f, H.real, H.imag, np.abs(H)]),
                    delimiter=",",
                    header="frequency_hz,re_kg,im_kg,magnitude_kg",
                    comments="",
                )
        ax.set_ylabel(f"|TRFAM| {d} (kg)")
        ax.legend()
    axes[-1].set_xlabel("frequency (Hz)")
    save_figure(fig, out / "trfam_xyz.png")
    plot_trfam(f, {"viscous": cc.trfam(model, "casing.A.z", "casing.B.z", f)}, out / "trfam_z.png")

    res = cc.simulate(model, duration=duration)  # per-node contact data for Fig. 22
    res.save(out / "simulation.csv")
    plot_time_result(res, out / "simulation.png")
    tF, F = fmu_force if fmu_force is not None else (res.time, res.support_force("casing.B.Fz"))
    fs = 1.0 / (tF[1] - tF[0])
    keep = tF > 0.05
    bands = octave_rms(F[keep], fs, beyond_nyquist="drop")
    np.savetxt(
        out / "octave_bands.csv",
        np.column_stack([bands.lower, bands.upper, bands.rms]),
        delimiter=",",
        header="f_low_hz,f_high_hz,rms_N",
        comments="",
        fmt="%.6g",
    )
    plot_octave_bands(bands, out / "octave_bands.png", "RMS casing.B.Fz (N)")
    fr = np.geomspace(20.0, 2000.0, 80)
    W = np.abs(cwt_morlet(F, fs, fr))
    W = W if W.shape[0] == len(F) else W.T
    plot_scalogram(tF, fr, W, out / "scalogram.png", "|W| of casing.B.Fz (Fig. 21)")
    rms = {n: float(np.sqrt(np.mean(res.support_force(n) ** 2))) for n in ("casing.B.Fx", "casing.B.Fy", "casing.B.Fz")}
    rows = "".join(f"<tr><td>{k}</td><td>{v:.4g}</td></tr>" for k, v in rms.items())
    source = "through the FMU with fmpy (fmu_outputs.csv)" if fmu_force is not None else "with the core"
    html = out / "report.html"
    rounded = json.dumps({k: [round(x, 2) for x in v] for k, v in modes.items()}, indent=1)
    html.write_text(f"""<!doctype html><html><head><meta charset="utf-8"><title>cablecasing demo</title></head>
<body><h1>Cable in casing: default specimen</h1>
<p>{fmu_note} The default scenario (random 10-1000 Hz, 5 m/s2 RMS at casing end A in z, and the cable's
50 Hz axial excitation) was run {source}, and with the core for the per-node contact data (simulation.csv).</p>
<h2>Natural frequencies (Hz)</h2><pre>{rounded}</pre>
<h2>TRFAM of the casing (Eq. 12), structural and viscous damping (Fig. 17)</h2><img src="trfam_xyz.png">
<h2>Support forces and contact-time histogram beside the curvature (Fig. 22)</h2>
<img src="simulation.png"><table border=1><tr><th>output</th><th>RMS (N)</th></tr>{rows}</table>
<h2>Octave-band RMS of casing.B.Fz (Table 3)</h2><img src="octave_bands.png">
<h2>Wavelet scalogram of casing.B.Fz (Fig. 21)</h2><img src="scalogram.png">
</body></html>""")
    return html
