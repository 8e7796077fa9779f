"""What a cable engineer asks of a routing (``cablecasing geometry``): its length, its bends with
radius and angle, the total bend angle, the smallest radius and where, the radial gap and the
element length; and the plausibility warnings of a route (not errors).

For a route given by segments the bends are the model's own (exact radius and angle). For a route
through points the bends are the runs of the curve where the curvature exceeds
:data:`BEND_CURVATURE` (2 1/m: a radius below 0.5 m; a spline through the built-in specimen's
points ripples up to 1.3 1/m on its straights) and that turn by more than :data:`BEND_MIN_DEG`,
sampled on :data:`DENSE` points: each bend's angle is the integral of the curvature over its run,
its radius the run's arc length over that angle (the mean radius) and its smallest radius one over
the run's largest curvature. A polyline has no curvature but corners: each corner above
:data:`KINK_DEG` is a kink, a bend of radius 0 and the angle between its two chords; a corner
below it, as in a polyline through many points of an arc, turns by its angle over the mean of its
two chords, which is the radius of that arc (the total bend counts every corner).

The band advice (:func:`band_advice`) sets the mesh and the time step against the scenario's
excitation band: each body's bending wavelength at the band's top and the elements on it, and
Newmark's period error there with ``scenario.dt`` (:mod:`~cablecasing_core.timedomain.accuracy`).
"""

from __future__ import annotations

import numpy as np

from ..model.schema import MAX_ELEMENTS
from ..timedomain.accuracy import newmark_period_error, step_for_period_error
from .assembly import axial_prestress
from .geometry import build_centerline, centerline_of, clip_breaks, node_stations, route_of
from .sections import section_of

BEND_CURVATURE = 2.0  # 1/m, curvature above which a point-defined route counts as bent
BEND_MIN_DEG = 2.0  # degrees: a run above BEND_CURVATURE that turns less is ripple, not a bend
DENSE = 4000  # samples of a point-defined route for its curvature profile
KINK_DEG = 1.0  # degrees: a polyline's corner above this is a kink (warned)


def curvature_profile(model, n=DENSE):
    """(s, curvature): arc length (m) and curvature (1/m) of the routing on ``n`` + 1 points, exact
    for a route by segments, from the dense spline (or zero along a polyline) for points."""
    route = route_of(model)
    if route is not None:
        s = np.linspace(0.0, route.length, n + 1)
        return s, route.curvature(s)
    g = model.geometry
    cl = build_centerline(g["points"], n, g["curve"], frames=False)
    return cl.s, cl.curvature


def _corner_angles(points):
    """(arc length m, turning angle deg) of the polyline through ``points`` at each interior point
    (points[1] .. points[-2], in order)."""
    P = np.asarray(points, dtype=float)
    d = np.diff(P, axis=0)
    lengths = np.linalg.norm(d, axis=1)
    u = d / lengths[:, None]
    ang = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", u[:-1], u[1:]), -1.0, 1.0)))
    return np.cumsum(lengths)[:-1], ang


def _polyline_kinks(points):
    """(arc length m, angle deg) of each corner of the polyline through ``points``."""
    return [(float(a), float(b)) for a, b in zip(*_corner_angles(points)) if b > KINK_DEG]


def _polyline_corner_radius(points):
    """(arc length m, radius m) of the tightest corner of the polyline through ``points`` that is
    not a kink (at most :data:`KINK_DEG`, above zero): the mean of its two chords over its angle,
    the radius of an arc the polyline samples; (None, None) when there is no such corner."""
    s, ang = _corner_angles(points)
    lengths = np.linalg.norm(np.diff(np.asarray(points, dtype=float), axis=0), axis=1)
    mean_chord = 0.5 * (lengths[:-1] + lengths[1:])
    soft = (ang > 0.0) & (ang <= KINK_DEG)
    if not soft.any():
        return None, None
    r = np.where(soft, mean_chord / np.radians(np.where(soft, ang, 1.0)), np.inf)
    i = int(np.argmin(r))
    return float(s[i]), float(r[i])


#: The most samples of the route in the search for places where it meets itself (pairs: its square).
MEET_SAMPLES = 2000


def _sampled(model, n):
    """(s, points, unit tangents) of the routing at ``n`` + 1 points of equal arc length (m): exact
    for a route by segments, the spline's or polyline's otherwise."""
    route = route_of(model)
    if route is not None:
        s = np.linspace(0.0, route.length, n + 1)
        p, t, _, _ = route._evaluate(s)
        return s, p, t
    g = model.geometry
    cl = build_centerline(g["points"], n, g["curve"], frames=False)
    return cl.s, cl.nodes, cl.tangents


def self_approach(model, length=None):
    """Where the route meets or crosses itself: (s1, s2, distance, turn) in m, m, m, degrees, the
    closest pair of its points that are nearer than the bodies' outer diameter d (the casing's, or
    the cable's alone) and between which the route turns by 180 degrees or more, or None.

    Along a curve that turns by less than 180 degrees between two points their distance is at least
    their arc length times cos(turn / 2): only there are points nearer than d neighbours (a bend, however
    tight, above the radius d / 2 that validation asks); beyond, a pair nearer than d is the route
    coming back onto itself (a loop, a crossing, a bend of nearly 360 degrees). The route is sampled at
    spacing d / 2 (at most :data:`MEET_SAMPLES` points), so a crossing is always found and a near
    pass to within a sample spacing. ``length``: the route's (m), if known."""
    d = model.data["casing"]["d_outer"] if "casing" in model.data else model.data["cable"]["d"]
    length = centerline_of(model).length if length is None else length
    n = int(min(MEET_SAMPLES, max(16, np.ceil(2.0 * length / d))))
    s, p, t = _sampled(model, n)
    turn = np.concatenate([[0.0], np.cumsum(np.arccos(np.clip(np.einsum("ij,ij->i", t[:-1], t[1:]), -1.0, 1.0)))])
    best = None
    for i0 in range(0, len(s), 256):  # (blocks of rows: at most 256 x 2001 distances at a time)
        i = np.arange(i0, min(i0 + 256, len(s)))
        D = np.linalg.norm(p[i, None, :] - p[None, :, :], axis=2)
        close = (D < d) & (turn[None, :] - turn[i, None] >= np.pi - 1e-9)
        if close.any():
            a, b = np.nonzero(close)
            k = int(np.argmin(D[a, b]))
            if best is None or D[a[k], b[k]] < best[2]:
                best = (
                    float(s[i[a[k]]]),
                    float(s[b[k]]),
                    float(D[a[k], b[k]]),
                    float(np.degrees(turn[b[k]] - turn[i[a[k]]])),
                )
    return best


def geometry_summary(model) -> dict:
    """The routing's figures (SI units, arc lengths from end A): ``length_m``, ``min_radius_m``
    and ``min_radius_at_m`` (None on a straight route), ``total_bend_deg``, ``gap_m`` (None without
    both bodies), ``element_length_m`` (the mean, length / n_elements), ``element_length_min_m`` and
    ``element_length_max_m`` (the shortest and longest element's arc: they differ with
    ``geometry.nodes_at_clips``, whose spans share the elements), ``n_elements``, ``bends`` (a list of {"start_m",
    "radius_m" (the mean), "min_radius_m", "angle_deg"}) and ``source`` ("segments", "spline" or
    "polyline")."""
    g = model.geometry
    cl = centerline_of(model)
    route = route_of(model)
    if route is not None:
        bends = [{"start_m": s0, "radius_m": r, "min_radius_m": r, "angle_deg": a} for s0, r, a in route.bends]
        source = "segments"
        if bends:
            i = int(np.argmin([b["radius_m"] for b in bends]))
            rmin, at = bends[i]["radius_m"], bends[i]["start_m"]
        else:
            rmin = at = None
        total = float(sum(b["angle_deg"] for b in bends))
    elif g["curve"] == "polyline" and len(g["points"]) > 2:
        source = "polyline"
        kinks = _polyline_kinks(g["points"])
        bends = [{"start_m": s, "radius_m": 0.0, "min_radius_m": 0.0, "angle_deg": a} for s, a in kinks]
        total = float(np.sum(_corner_angles(g["points"])[1]))  # (every corner: an arc's points turn by < 1 deg)
        rmin, at = (0.0, bends[0]["start_m"]) if bends else (None, None)
        if not bends:
            at, rmin = _polyline_corner_radius(g["points"])
    else:
        source = "spline" if len(g["points"]) > 2 else "polyline"
        s, k = curvature_profile(model)
        ds = np.diff(s)
        kmid = 0.5 * (k[1:] + k[:-1])
        total = float(np.degrees(np.sum(kmid * ds)))
        bent = kmid > BEND_CURVATURE
        bends = []
        i = 0
        while i < len(bent):
            if bent[i]:
                j = i
                while j < len(bent) and bent[j]:
                    j += 1
                angle = float(np.sum(kmid[i:j] * ds[i:j]))
                if np.degrees(angle) > BEND_MIN_DEG:
                    bends.append(
                        {
                            "start_m": s[i],
                            "radius_m": (s[j] - s[i]) / angle,
                            "min_radius_m": 1.0 / float(np.max(k[i : j + 1])),
                            "angle_deg": np.degrees(angle),
                        }
                    )
                i = j
            else:
                i += 1
        if k.max() > 0:
            rmin, at = float(1.0 / k.max()), float(s[int(np.argmax(k))])
        else:
            rmin = at = None
    gap = model.radial_gap if {"casing", "cable"} <= set(model.bodies) else None
    return {
        "length_m": float(cl.length),
        "min_radius_m": rmin,
        "min_radius_at_m": at,
        "total_bend_deg": total,
        "gap_m": gap,
        "element_length_m": float(cl.length / cl.n_elements),
        "element_length_min_m": float(np.min(np.diff(cl.s))),
        "element_length_max_m": float(np.max(np.diff(cl.s))),
        "n_elements": int(cl.n_elements),
        "bends": [{k: float(v) for k, v in b.items()} for b in bends],
        "source": source,
    }


def route_numbers(geometry) -> str:
    """What gives the lengths of the route of ``geometry`` (a model's [geometry] table), for a
    warning that they may be in the wrong unit: its points, or its segments' lengths and radii."""
    return "the points" if geometry.get("points") else "the segments' lengths and radii"


def length_warning(length, long_only=False, given_by="the points"):
    """The warning of a route of ``length`` (m) that is likely in the wrong unit (longer than 10 m,
    or shorter than 1 cm unless ``long_only``), or None; ``given_by``: what gives its lengths
    (:func:`route_numbers`)."""
    if length > 10.0:
        return f"the route is {length:.4g} m long, more than 10 m: are {given_by} in mm?"
    if length < 0.01 and not long_only:
        return f"the route is {length:.3g} m long, less than 1 cm: are {given_by} in m?"
    return None


# The band advice's thresholds, from the built-in specimen's mesh study (docs/time_domain.md, "The mesh":
# the largest error of the modes in each Table 3 band at 35 elements, whose tops 1420, 2840 and 5680 Hz
# put 4.1, 2.9 and 2.0 elements on the casing's bending wavelength and 3.9, 2.7 and 1.9 on the cable's):
# the modes are at most 0.5-0.6 % high with 4 per wavelength at the band's top (710-1420 Hz), 1.7-2.5 %
# with 2.7-2.9 (1420-2840 Hz) and 9.5-10.3 % with 2 (2840-5680 Hz), so the bodies' own error grows about
# as the fourth power of the element length, and 6 per wavelength puts it near 0.1 %. The levels with
# contact converge more slowly than the modes (the same section); these bound the bodies' share only.
MIN_PER_WAVELENGTH = 4.0  # elements per bending wavelength at the band's top below which geometry warns
ADVISED_PER_WAVELENGTH = 6.0  # what the warning's n_elements gives
# Newmark's relative period error (2 pi f dt)^2 / 12 above which geometry warns, and the one its dt gives:
# 1 % is the error at the top of Table 3 (5680 Hz) at the specimens' 1e-5 s; their own band's top, 1 kHz,
# has 0.033 %, and the time step's tables (docs/time_domain.md) show their levels converged there.
MAX_PERIOD_ERROR = 0.01
ADVISED_PERIOD_ERROR = 0.005


def bending_wavelength(EI, rho_A, P, f_hz):
    """The bending wavelength (m) at ``f_hz`` (Hz) of an Euler-Bernoulli beam of bending stiffness
    ``EI`` (N m2) and mass per length ``rho_A`` (kg/m) under the axial force ``P`` (N, tension
    positive): 2 pi / k with EI k^4 + P k^2 = rho_A w^2, k^2 = (-P + sqrt(P^2 + 4 EI rho_A w^2)) / (2 EI).
    A tension lengthens the wave, a compression shortens it."""
    w = 2.0 * np.pi * f_hz
    k2 = (-P + np.sqrt(P * P + 4.0 * EI * rho_A * w * w)) / (2.0 * EI)
    return float(2.0 * np.pi / np.sqrt(k2))


def excitation_top(model):
    """The top of the scenario's excitation band: (f_top in Hz, which excitation sets it and how, in words),
    the highest of each random excitation's upper band edge, each harmonic's frequency and each
    impulse's 1 / width (Hz; a Hann bump of width w holds most of its spectrum below 1 / w), counting
    those that move (a non-zero RMS or amplitude); None when there is none. A CSV table's content is
    not known without reading the file and is not counted (:func:`band_advice` names them)."""
    top = None
    for name, e in model.scenario.get("excitation", {}).items():
        kind = e["kind"]
        key = f"scenario.excitation.{name}"
        if kind == "random" and e["rms"] > 0:
            f, what = float(e["band"][1]), f"the upper edge of {key}'s random band"
        elif kind == "harmonic" and e["amplitude"] != 0:
            f, what = float(e["frequency"]), f"the frequency of {key}, harmonic"
        elif kind == "impulse" and e["amplitude"] != 0:
            f, what = 1.0 / float(e["width"]), f"one over the width of {key}, an impulse of {e['width']:g} s"
        else:
            continue
        if top is None or f > top[0]:
            top = (f, what)
    return top


def _band_modulus(spec, f_hz):
    """The modulus (Pa) for the waves of body ``spec`` up to ``f_hz``: the scalar ``E``, or a table's
    smallest value over [0, f_hz] (the time domain takes the table at the first natural frequency,
    the frequency domain at each frequency: both are at least this, so the wavelength is not
    overstated)."""
    if not spec.frequency_dependent:
        return spec.E_ref
    f = np.array([0.0, f_hz] + [float(row[0]) for row in spec.E if float(row[0]) <= f_hz])
    return float(np.min(spec.modulus(f)))


def element_lengths_text(g):
    """The elements' length in a :func:`geometry_summary` ``g`` as text: "0.02428 m", or "0.0219 to
    0.0262 m" when they differ (clips on nodes)."""
    lo, hi = g["element_length_min_m"], g["element_length_max_m"]
    return f"{hi:.4g} m" if f"{lo:.4g}" == f"{hi:.4g}" else f"{lo:.4g} to {hi:.4g} m"


def _longest_element(length, n, breaks):
    """The arc length (m) of the longest of ``n`` elements on a route of ``length`` m with a node at
    each of ``breaks`` (m; None: equal elements, ``length / n``): structure/geometry.py's
    :func:`~.geometry.node_stations`, as the centerline is cut."""
    if not breaks:
        return length / n
    return float(np.max(np.diff(node_stations(length, n, breaks))))


def _fewest_elements(length, breaks, longest):
    """The fewest elements (at least one a span) on a route of ``length`` m with a node at each of
    ``breaks`` (m, or None) whose longest element is at most ``longest`` m (to 1e-12 relative);
    it may exceed :data:`MAX_ELEMENTS`, which the callers say."""
    n = int(np.ceil(length / longest * (1 - 1e-12)))
    if breaks:  # (at least one element a span)
        n = max(n, len(breaks) + 1)
    while breaks and n < MAX_ELEMENTS and _longest_element(length, n, breaks) > longest * (1 + 1e-12):
        n += 1  # (a span's elements are longer than the mean by less than twice: a few more at most)
    return n


def band_advice(model, summary=None):
    """The mesh and time step against the scenario's excitation band (SI units), or None when the
    scenario has no excitation :func:`excitation_top` counts: ``f_top_hz`` and ``set_by`` (which
    excitation sets it and how, in words), ``dt_s`` (``scenario.dt``), ``period_error`` (Newmark's relative period error
    at f_top, :func:`newmark_period_error`; 0.01 is 1 %), ``dt_for_advised_s`` (the step for
    :data:`ADVISED_PERIOD_ERROR`), ``n_elements``, ``bodies`` {name: {``wavelength_m`` (the bending
    wavelength at f_top, :func:`bending_wavelength`, with the body's EI (its I, or the effective
    ``I``; the modulus of :func:`_band_modulus`), rho A (the geometric area) and axial force, the
    cable's tension and the casing's equal compression, ``structure.assembly.axial_prestress``),
    ``axial_force_N``, ``elements_per_wavelength`` (the wavelength over the longest element at
    ``n_elements``: the route length over ``n_elements``, or, where ``geometry.nodes_at_clips`` cuts the
    route at the clips into spans of their own elements, the longest of those, :func:`_longest_element`)}},
    ``n_elements_for_advised`` (the fewest elements that put :data:`ADVISED_PER_WAVELENGTH` on every body's
    wavelength, so counted) and ``not_counted`` (the CSV excitations, whose content is not read)."""
    top = excitation_top(model)
    if top is None:
        return None
    f_top, what = top
    g = summary or geometry_summary(model)
    length, n = g["length_m"], g["n_elements"]
    breaks = clip_breaks(model.geometry, model.data.get("casing"))
    h = _longest_element(length, n, breaks)  # (m: length / n without clips)
    dt = float(model.scenario["dt"])
    bodies = {}
    for body, spec in model.bodies.items():
        sec = section_of(spec)
        P = float(axial_prestress(model, body)) + 0.0  # (+ 0.0: no -0.0 for the casing without a tension)
        lam = bending_wavelength(_band_modulus(spec, f_top) * sec.I, spec.rho * sec.A, P, f_top)
        bodies[body] = {
            "wavelength_m": lam,
            "axial_force_N": P,
            "elements_per_wavelength": lam / h if breaks else lam * n / length,
        }
    shortest = min(b["wavelength_m"] for b in bodies.values())
    advised = _fewest_elements(length, breaks, shortest / ADVISED_PER_WAVELENGTH)
    return {
        "f_top_hz": f_top,
        "set_by": what,
        "dt_s": dt,
        "period_error": float(newmark_period_error(f_top, dt)),
        "dt_for_advised_s": step_for_period_error(f_top, ADVISED_PERIOD_ERROR),
        "n_elements": n,
        "bodies": bodies,
        "n_elements_for_advised": advised,
        "not_counted": csv_excitations(model),
    }


def csv_excitations(model) -> list[str]:
    """The keys of the scenario's CSV excitations (``scenario.excitation.NAME``): their content is not
    read, so :func:`excitation_top` does not count them."""
    return [f"scenario.excitation.{k}" for k, e in model.scenario.get("excitation", {}).items() if e["kind"] == "csv"]


def no_band_advice_why(model=None) -> str:
    """Why :func:`band_advice` is None for ``model`` (``geometry``'s text and its JSON's
    ``band_advice_why``): its CSV excitations, named, when those are all it has, else no excitation
    with a known top frequency."""
    tables = csv_excitations(model) if model is not None else []
    if tables:
        return (
            f"{', '.join(tables)} (CSV tables) are the scenario's only excitations, and their content is not read; "
            'check the mesh and the step against the table\'s band by hand (docs/model_file.md, "Your own model")'
        )
    return "the scenario has no excitation with a known top frequency"


def band_advice_lines(advice, model=None) -> list[str]:
    """The text lines of a :func:`band_advice` as ``cablecasing geometry`` prints them (one that says
    there is none for None, and why: :func:`no_band_advice_why`)."""
    if advice is None:
        why, tables = no_band_advice_why(model), model is not None and csv_excitations(model)
        return [f"  band advice       none: {why}" if tables else f"  band advice       none ({why})"]
    f = advice["f_top_hz"]
    bodies = ", ".join(
        f"{k} {b['elements_per_wavelength']:.2g} (wavelength {b['wavelength_m']:.4g} m)"
        for k, b in advice["bodies"].items()
    )
    lines = [
        f"  band top          {f:.4g} Hz: {advice['set_by']}",
        f"  per wavelength    {bodies}: elements on the bending wavelength at {f:.4g} Hz; "
        f"{advice['n_elements_for_advised']} elements give {ADVISED_PER_WAVELENGTH:g} on each",
        f"  time step         {advice['dt_s']:g} s: Newmark's period error {100 * advice['period_error']:.2g} % at "
        f"{f:.4g} Hz ({100 * ADVISED_PERIOD_ERROR:g} % at {advice['dt_for_advised_s']:.2g} s)",
    ]
    if advice["not_counted"]:
        lines.append(f"  not counted       {', '.join(advice['not_counted'])} (CSV tables: their content is not read)")
    return lines


def band_advice_warnings(advice) -> list[str]:
    """The warnings of a :func:`band_advice` (None: none): fewer than :data:`MIN_PER_WAVELENGTH`
    elements on a body's bending wavelength at the band's top, naming the ``geometry.n_elements``
    that gives :data:`ADVISED_PER_WAVELENGTH`; Newmark's period error there above
    :data:`MAX_PERIOD_ERROR`, naming the ``scenario.dt`` that gives :data:`ADVISED_PERIOD_ERROR`."""
    if advice is None:
        return []
    out = []
    where = f"at the excitation's top, {advice['f_top_hz']:.4g} Hz ({advice['set_by']}),"
    coarse = {k: b for k, b in advice["bodies"].items() if b["elements_per_wavelength"] < MIN_PER_WAVELENGTH}
    if coarse:
        need = advice["n_elements_for_advised"]
        each = " and ".join(
            f"{b['elements_per_wavelength']:.2g} on the {k}'s bending wavelength ({b['wavelength_m']:.4g} m)"
            for k, b in coarse.items()
        )
        fix = (
            f"geometry.n_elements = {need} gives {ADVISED_PER_WAVELENGTH:g} on each"
            if need <= MAX_ELEMENTS
            else f"the {need} elements that give {ADVISED_PER_WAVELENGTH:g} on each are more than the "
            f"{MAX_ELEMENTS} allowed (lower the band or shorten the route)"
        )
        out.append(
            f"{where} the {advice['n_elements']} elements put {each}, fewer than {MIN_PER_WAVELENGTH:g} per "
            "wavelength (the built-in specimen's modes are 0.5 % high at 4, 2.5 % at 2.9 and 10 % at 2; band "
            f'levels with contact converge more slowly: docs/time_domain.md, "The mesh"): {fix}; check it with '
            f"`cablecasing ensemble MODEL --against geometry.n_elements={min(need, MAX_ELEMENTS)}`"
        )
    if advice["period_error"] > MAX_PERIOD_ERROR:
        out.append(
            f"{where} Newmark's period error (2 pi f dt)^2 / 12 at scenario.dt = {advice['dt_s']:g} s is "
            f"{100 * advice['period_error']:.2g} %, above {100 * MAX_PERIOD_ERROR:g} %: scenario.dt = "
            f"{advice['dt_for_advised_s']:.2g} s gives {100 * ADVISED_PERIOD_ERROR:g} %; check it with "
            f"`cablecasing ensemble MODEL --against scenario.dt={advice['dt_for_advised_s']:.2g}`"
        )
    return out


def plausibility_warnings(model, summary=None, advice=True) -> list[str]:
    """Plain-language warnings (not errors) about a routing that is likely a mistake, the one
    list of them: a route longer than 10 m or shorter than 1 cm (points given in mm, or in km?)
    or shorter than ten times the largest diameter (no slender beam), points at which the route
    doubles back (turns by more than 120 degrees), a kink in a polyline, a bend radius below ten
    casing diameters; and, with ``advice``, an element longer than a tenth of the shortest bend's
    arc (the built-in specimen has 6.5 elements per bend) and the band advice's
    (:func:`band_advice_warnings`: too few elements on a bending wavelength, or too long a step, for
    the scenario's excitation band). Loading a file warns without the advice, which is a matter of
    accuracy, not a likely mistake, and concerns the time domain's scenario alone (``modes``,
    ``trfam`` and ``static`` do not run it); ``cablecasing geometry`` gives it."""
    g = summary or geometry_summary(model)
    out = []
    length = g["length_m"]
    given_by = route_numbers(model.geometry)
    if length_warning(length, long_only=True, given_by=given_by):
        out.append(length_warning(length, long_only=True, given_by=given_by))
    diameters = [model.data[b][k] for b, k in (("casing", "d_outer"), ("cable", "d")) if b in model.data]
    short = []
    if diameters and length < 10 * max(diameters):
        short.append(
            f"less than ten times the diameter {max(diameters):g} m: a body this short is no slender beam, and the "
            "Euler-Bernoulli elements (which neglect shear) do not describe it"
        )
    if length < 0.01:
        short.append(f"less than 1 cm: are {given_by} in m?")  # (length_warning's)
    if short:
        out.append(f"the route is {length:.3g} m long, " + "; ".join(short))
    points = model.geometry.get("points") or []
    turns = _corner_angles(points)[1] if len(points) > 2 else np.zeros(0)
    back = np.flatnonzero(turns > 120.0)  # turns by more than 120 degrees at one point
    if back.size:
        out.append(
            f"geometry.points[{back[0] + 1}]: the route turns by {turns[back[0]]:.0f} degrees there: it doubles "
            "back on itself, and the centerline bends tighter than any cable or casing can"
        )
    meet = self_approach(model, length)
    if meet is not None:
        s1, s2, dist, turn = meet
        who = (
            f"casing.d_outer = {model.data['casing']['d_outer']:g} m"
            if "casing" in model.data
            else (f"cable.d = {model.data['cable']['d']:g} m")
        )
        out.append(
            f"the route meets itself: at s = {s1:.4g} m and s = {s2:.4g} m it is {dist:.3g} m from itself, less than "
            f"the outer diameter {who}, and turns by {turn:.0f} deg between "
            "them: the model has no contact of a body with itself, so it passes through"
        )
    if g["source"] == "polyline":
        kinks = g["bends"]
        smooth = '(curve = "spline" or segments give a smooth route)'
        if len(kinks) == 1:
            k = kinks[0]
            out.append(f"the polyline has a kink of {k['angle_deg']:.3g} deg at s = {k['start_m']:.4g} m {smooth}")
        elif kinks:  # (one line: a polyline through many points of an arc has a kink at each)
            worst = max(kinks, key=lambda b: b["angle_deg"])
            out.append(
                f"the polyline has {len(kinks)} kinks, of {min(b['angle_deg'] for b in kinks):.3g} to "
                f"{worst['angle_deg']:.3g} deg (the largest at s = {worst['start_m']:.4g} m) {smooth}"
            )
        d = model.data["casing"]["d_outer"] if "casing" in model.data else None
        at, r = _polyline_corner_radius(model.geometry["points"])
        if d is not None and r is not None and r < 10.0 * d:  # (the arc its dense points sample)
            out.append(
                f"the polyline turns with a radius of {r:.4g} m at s = {at:.4g} m (a corner's angle over its "
                f"chords), below ten casing diameters ({10.0 * d:.4g} m)"
            )
        return out + (band_advice_warnings(band_advice(model, g)) if advice else [])
    d = model.data["casing"]["d_outer"] if "casing" in model.data else None
    if d is not None:
        for b in g["bends"]:
            r = b.get("min_radius_m", b["radius_m"])
            if r < 10.0 * d:
                where = "a radius" if r == b["radius_m"] else f"a smallest radius (its mean {b['radius_m']:.4g} m)"
                out.append(
                    f"the bend at s = {b['start_m']:.4g} m has {where} of {r:.4g} m, below ten "
                    f"casing diameters ({10.0 * d:.4g} m)"
                )
    if g["bends"] and advice:
        arcs = [np.radians(b["angle_deg"]) * b["radius_m"] for b in g["bends"]]
        i = int(np.argmin(arcs))
        if g["element_length_max_m"] > 0.1 * arcs[i]:  # (the longest element: with clips on nodes they differ)
            need = _fewest_elements(g["length_m"], clip_breaks(model.geometry, model.data.get("casing")), 0.1 * arcs[i])
            fix = (
                f"about {need} elements (geometry.n_elements) resolve it"
                if need <= MAX_ELEMENTS
                else f"the {need} elements that would resolve it are more than the {MAX_ELEMENTS} allowed "
                f"(geometry.n_elements = {MAX_ELEMENTS} gives {MAX_ELEMENTS * arcs[i] / g['length_m']:.3g} per "
                "bend arc; "
                "or widen the bend, or shorten the route)"
            )
            out.append(
                f"the elements ({element_lengths_text(g)}) are longer than a tenth of the shortest bend's "
                f"arc ({arcs[i]:.4g} m at s = {g['bends'][i]['start_m']:.4g} m): {fix}"
            )
    return out + (band_advice_warnings(band_advice(model, g)) if advice else [])
