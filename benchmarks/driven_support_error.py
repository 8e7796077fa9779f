"""The error of the force at a driven support when its motion comes as inputs sampled every
communication step h (the FMU's way: displacement, velocity and acceleration at each point,
reconstructed through the step, ``timedomain/support_motion.py``), against the engine driven by
the exact motion, for a harmonic motion of casing.A.y at one frequency (contact off, the default
specimen, ``solver.dt`` = 1e-5 s, the model's half-cosine fade-in over 0.01 s, 0.1 s).

The force contains the inertia of the support's own node times the support's acceleration, whose
reconstruction is second order in x = ωh (docs/fmu.md, "Motion inside a communication step"), so
the error relative to the force's RMS grows about as (ωh)². Prints ``name: value`` lines:
``rel_err_<f>Hz_h<h>`` (the RMS of the difference over the force's RMS, on the h grid) and
``coefficient_<f>Hz_h<h>`` (that error over (ωh)²). The FMU gives the core's reconstruction bit for
bit (tests/fmu), so these are the FMU's figures; they do not depend on the machine's speed.

    .venv/bin/python benchmarks/driven_support_error.py [--frequencies 100 300 600 1000] [--steps 1e-4 5e-5 2e-5]
"""

import numpy as np
from _options import checked, parser

import cablecasing_core as cc
from cablecasing_core.errors import renamed
from cablecasing_core.model.schema import CHANNELS
from cablecasing_core.model.validators import number
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion
from cablecasing_core.timedomain.support_motion import SupportReconstruction

AMPLITUDE, DURATION = 1e-5, 0.1  # m, s


def force(model, h, exact):
    """casing.A.Fy (N) at t = h, 2h, ..., DURATION: driven by the exact motion, or by its samples."""
    motion = scenario_motion(model)
    eng = Engine(model, dt=1e-5, ledger=False)
    out, rows, rec = np.zeros(len(eng.output_names)), [], SupportReconstruction(12)
    for k in range(int(round(DURATION / h))):
        if exact:
            eng.advance(h, motion)
        else:
            u, v, a = (np.ascontiguousarray(q[0]) for q in motion(k * h))
            eng.advance_reconstructed(h, rec, u, v, a, out)
        eng.output_values(out)
        rows.append(out.copy())
    return np.array(rows)[:, eng.output_names.index("casing.A.Fy")]


def main():
    p = parser(__doc__)
    p.add_argument("--frequencies", type=float, nargs="+", default=[100.0, 300.0, 600.0, 1000.0], help="Hz")
    p.add_argument("--steps", type=float, nargs="+", default=[1e-4, 5e-5, 2e-5], help="communication steps h, s")
    args = p.parse_args()
    assert "casing.A.y" in CHANNELS
    base = (
        cc.load_model().without_excitations(["casing_random", "cable_axial"]).with_overrides({"contact.enabled": False})
    )
    models = {}
    with checked(p):
        for h in args.steps:
            number("--steps", h, gt=0, le=DURATION / 2, unit="s")  # (two steps of the run at least)
        with renamed({"scenario.excitation.tone.frequency": "--frequencies"}):
            for f in args.frequencies:
                models[f] = base.with_overrides(
                    {
                        "scenario.excitation.tone.kind": "harmonic",
                        "scenario.excitation.tone.target": "casing.A.y",
                        "scenario.excitation.tone.frequency": f,
                        "scenario.excitation.tone.amplitude": AMPLITUDE,
                    }
                )
    for f, model in models.items():
        for h in args.steps:
            ref, got = force(model, h, True), force(model, h, False)
            err = float(np.sqrt(np.mean((got - ref) ** 2) / np.mean(ref**2)))
            print(f"rel_err_{f:g}Hz_h{h:g}: {err:.4g}")
            print(f"coefficient_{f:g}Hz_h{h:g}: {err / (2 * np.pi * f * h) ** 2:.3g}")


if __name__ == "__main__":
    main()
