"""``cablecasing geometry``: the routing of a model in figures (length, bends, smallest radius,
gap, element length), as JSON, as a figure, and its plausibility warnings."""

from __future__ import annotations

import json
import warnings

import numpy as np

from ..errors import ModelWarning
from ..model.schema import BODY_NAMES
from .assignments import add_model_argument, model_argument


def cmd_geometry(args):
    from ..structure.buckling import buckling
    from ..structure.route_summary import (
        band_advice,
        band_advice_lines,
        element_lengths_text,
        geometry_summary,
        no_band_advice_why,
        plausibility_warnings,
    )
    from .paths import PLOT_SUFFIXES, check_output_path

    check_output_path("--plot", args.plot, PLOT_SUFFIXES)
    with warnings.catch_warnings(record=True) as said:  # (the route's are printed below with the figures, not twice)
        warnings.simplefilter("always")
        model = model_argument(args.model, args.set)
    g = geometry_summary(model)
    route = plausibility_warnings(model, g)
    for w in said:  # (the others: absurd values, the gravity, the gap)
        if str(w.message) not in {f"{model.source}: {t}" for t in route}:
            warnings.warn(w.message, w.category, stacklevel=1)
    keys = ("length_m", "min_radius_m", "min_radius_at_m", "total_bend_deg", "gap_m", "element_length_m",
            "element_length_min_m", "element_length_max_m", "bends")  # fmt: skip
    casing = _compressed_casing(model)
    buckled = [] if casing is None else [buckling(casing)]
    clips = _clips(model, casing)
    band = band_advice(model, g)
    if args.json:
        loads = {b.body: b.as_dict() for b in buckled}
        why = None if band is not None else no_band_advice_why(model)  # (the text's reason, when there is none)
        said = {"band_advice": band, "band_advice_why": why}
        print(json.dumps({**{k: g[k] for k in keys}, "clips": clips, "buckling": loads, **said}))
    else:
        print(f"routing ({g['source']}) of {model.source}")
        print(f"  length            {g['length_m']:.6g} m")
        print(f"  elements          {g['n_elements']} of {element_lengths_text(g)}")
        if g["min_radius_m"] is None:
            print("  straight (no bend)")
        else:
            print(f"  min radius        {g['min_radius_m']:.4g} m at s = {g['min_radius_at_m']:.4g} m")
            print(f"  total bend        {g['total_bend_deg']:.4g} deg")
        if g["gap_m"] is not None:
            print(f"  radial gap        {g['gap_m']:.4g} m")
        for i, b in enumerate(g["bends"]):
            smallest = f" (smallest {b['min_radius_m']:.4g} m)" if b["min_radius_m"] != b["radius_m"] else ""
            print(
                f"  bend {i}: from s = {b['start_m']:.4g} m, radius {b['radius_m']:.4g} m{smallest}, "
                f"{b['angle_deg']:.4g} deg"
            )
        for i, c in enumerate(clips):
            print(
                f"  clip {i}: at {c['at_m']:.4g} m, acts at the node at s = {c['node_s_m']:.4g} m "
                f"({1e3 * (c['node_s_m'] - c['at_m']):+.3g} mm)"
            )
        for b in buckled:
            print(f"  buckling          {b.text()}")
        print("\n".join(band_advice_lines(band, model)))
    for w in route:
        warnings.warn(w, stacklevel=1)
    for w in _buckling_warnings(model, buckled):
        warnings.warn(w, ModelWarning, stacklevel=1)
    if args.plot:
        from ..plotting import plot_routing

        plot_routing(model, args.plot, g)
        if not args.json:
            print(f"wrote {args.plot}")
    return 0


def _compressed_casing(model):
    """The casing as built (structure/assembly.py; its reference modulus) when it carries the
    cable's tension as compression (both bodies), for its buckling load (structure/buckling.py);
    else None."""
    if not set(BODY_NAMES) <= set(model.bodies):
        return None
    from ..structure.assembly import assemble_body

    return assemble_body(model, "casing", check_buckling=False)


def _buckling_warnings(model, buckled):
    """The warnings of a tension (N) at or above a body's buckling load (N) as built: what
    ``static`` and the time domain refuse (structure/buckling.py ``check_compression``)."""
    T = model.loads["cable_tension"]
    return [
        f"loads.cable_tension = {T}: at or above the {b.body}'s buckling load {b.load:.4g} N (the compression it "
        "carries, equal to the cable's tension), so `cablecasing static` and the time domain refuse the model; "
        f"lower the tension below {b.load:.4g} N or hold the {b.body} more stiffly"
        for b in buckled
        if T > 0.0 and np.isfinite(b.load) and T >= b.load
    ]


def add_parser(sub):
    p = sub.add_parser(
        "geometry", help="the routing: length, bends, min radius, gap, element length, buckling load; warnings"
    )
    add_model_argument(p, settable=True)
    p.add_argument(
        "--json",
        action="store_true",
        help="print JSON {length_m, min_radius_m, min_radius_at_m, total_bend_deg, gap_m, element_length_m, "
        "element_length_min_m, element_length_max_m, "
        "bends: [{start_m, radius_m, min_radius_m, angle_deg}], "
        "buckling: {casing: {load_N, at_m, supports, mechanism}}, band_advice: {f_top_hz, set_by, dt_s, "
        "period_error, dt_for_advised_s, n_elements, bodies: {casing: {wavelength_m, axial_force_N, "
        "elements_per_wavelength}}, n_elements_for_advised, not_counted} or null, band_advice_why: why it is null, "
        "or null} (arc "
        "lengths from end A; the buckling load of the casing as built, the most compression, i.e. cable tension, it "
        "carries; the bending wavelength at the excitation's top, Newmark's period error there, 0.01 is 1 %%)",
    )
    p.add_argument("--plot", help="figure to write (.png): 3D routing with supports and clips, curvature along it")
    p.set_defaults(func=cmd_geometry)


def _clips(model, casing=None):
    """The casing's clips in file order: ``at_m`` (the arc length asked for, m) and ``node_s_m``
    (the arc length of the node it acts at, m: structure/mount_element.py, ``clip_node``): those of
    the clips' mounts of ``casing`` (the casing as built, :func:`_compressed_casing`) when given, so
    that the centerline is not built again for them; else ``clip_positions``'s."""
    from ..structure.mount_element import clip_positions

    asked = model.data.get("casing", {}).get("clip", [])
    if casing is None:
        at_nodes = clip_positions(model)
    else:  # (a mount without a support is a clip, in file order)
        at_nodes = [m.at for m in casing.mounts if m.support is None]
    return [{"at_m": float(c["at"]), "node_s_m": s} for c, s in zip(asked, at_nodes)]
