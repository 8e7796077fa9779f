"""Command line ``cablecasing``: a thin shell over the core API.

Sub-commands: ``modes``, ``trfam``, ``keys`` (the model file's keys, from the schema), ``simulate``
(``simulate.py``), ``static`` (``static.py``), ``identify ...`` (``identify.py``), ``study``,
``ensemble``, ``pool``, ``bands``, ``report`` (``study.py``), each module registering its own with
``add_parser``. A model argument is a TOML file or the name of a built-in specimen (``default``,
``installed``).
Every error in the input prints one line naming the key, the value and what is allowed, and
exits with status 2.
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from ..errors import CableCasingError, ModelError
from ..model import load_model
from . import identify, simulate, static, study


def _model(path):
    return load_model(path)


def cmd_modes(args):
    from ..frequency.modal import natural_frequencies

    model = _model(args.model)
    res = {b: natural_frequencies(model, b, args.count).tolist() for b in model.bodies}
    if args.json:
        print(json.dumps(res))
    else:
        for b, f in res.items():
            print(f"{b}: natural frequencies (Hz)")
            for i, v in enumerate(f, 1):
                print(f"  {i:3d}  {v:12.4f}")
    return 0


def cmd_trfam(args):
    from ..frequency.trfam import trfam

    model = _model(args.model)
    if not (args.fmin > 0 and args.fmax > args.fmin and args.df > 0):
        raise ModelError("--fmin/--fmax/--df", (args.fmin, args.fmax, args.df), "need 0 < fmin < fmax and df > 0 (Hz)")
    f = np.arange(args.fmin, args.fmax + 0.5 * args.df, args.df)
    H = trfam(model, args.input, args.output, f, damping=args.damping)
    table = np.column_stack([f, H.real, H.imag, np.abs(H), np.degrees(np.angle(H))])
    header = "frequency_hz,re_kg,im_kg,magnitude_kg,phase_deg"
    if args.out:
        np.savetxt(args.out, table, delimiter=",", header=header, comments="", fmt="%.10g")
        print(f"wrote {args.out}")
    else:
        print(header)
        for row in table:
            print(",".join(f"{v:.10g}" for v in row))
    if args.plot:
        from ..plotting import plot_trfam

        plot_trfam(f, {f"{args.damping}": H}, args.plot, title=f"TRFAM {args.output} / {args.input}")
        print(f"wrote {args.plot}")
    return 0


def cmd_keys(args):
    """Print the model file's keys from the schema: key, type, default, unit, allowed, description."""
    from ..model.schema import SCHEMA

    rows = [s for k, s in SCHEMA.items() if k.startswith(args.prefix or "")]
    if not rows:
        raise ModelError("prefix", args.prefix, "matches no key of the model file; try 'casing' or 'scenario'")
    for s in rows:
        default = s.default_from or s.default
        print(f"{s.key}\t{s.type}\t{default}\t{s.unit or '-'}\t{s.allowed}\t{s.description}")
    return 0


def build_parser():
    p = argparse.ArgumentParser(prog="cablecasing", description="Cable-in-casing vibration model (SI units).")
    sub = p.add_subparsers(dest="command", required=True)

    m = sub.add_parser("modes", help="natural frequencies of each body (Hz)")
    m.add_argument("model", nargs="?", default=None, help="model TOML file (default: built-in specimen)")
    m.add_argument("--count", type=int, default=10, help="number of modes per body")
    m.add_argument("--json", action="store_true", help="print JSON {body: [Hz, ...]}")
    m.set_defaults(func=cmd_modes)

    t = sub.add_parser("trfam", help="apparent-mass transfer function (kg), Eq. (12)")
    t.add_argument("model", nargs="?", default=None)
    t.add_argument("--input", default="casing.A.x", help="driven support DOF, e.g. casing.A.x")
    t.add_argument("--output", default="casing.B.x", help="support DOF whose force is the output")
    t.add_argument("--fmin", type=float, default=10.0, help="Hz")
    t.add_argument("--fmax", type=float, default=1000.0, help="Hz")
    t.add_argument("--df", type=float, default=0.5, help="Hz")
    t.add_argument("--damping", choices=["viscous", "structural", "none"], default="viscous")
    t.add_argument("--out", help="CSV file to write")
    t.add_argument("--plot", help="PNG file to write")
    t.set_defaults(func=cmd_trfam)

    k = sub.add_parser("keys", help="the keys of the model file: type, default, unit, allowed values, meaning")
    k.add_argument("prefix", nargs="?", default=None, help="only keys that start with this, e.g. contact")
    k.set_defaults(func=cmd_keys)

    for module in (simulate, identify, study):
        module.add_parser(sub)
    static.add_parser(sub)
    return p


def main(argv=None):
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except CableCasingError as exc:
        print(f"cablecasing: error: {exc}", file=sys.stderr)
        return 2
