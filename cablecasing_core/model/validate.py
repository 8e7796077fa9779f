"""Validation of a model file's tables, built from the schema (:mod:`.schema`).

Each table is checked key by key with the schema's validators (unknown keys and missing required
keys first, then every value; defaults filled in), then against the other keys where the schema's
``note`` says so: the casing's inner diameter between the cable and the outer diameter, the
duration at least one step, a random band and a harmonic's frequency below the Nyquist frequency,
excitations named by TOML bare keys, a target on a clamped or isolator support of a body that exists
(or an excited clip) whose mount passes the driven direction, a tension only with a cable, a stick
velocity above 0 with the regularized friction law, isolators and clips with some stiffness, every
part of the route and every element at least a micrometre long, and loads only on bodies that can
carry them as built (a tension with both ends of both bodies held, every loaded body held against
every rigid motion: structure/support_check.py). Every mistake raises
:class:`~cablecasing_core.errors.ModelError` naming the dotted key, the value and what is allowed;
nothing is half-built.

A valid model can still be physically absurd: a value outside its key's plausible range (the
schema's ``plausible``), a second moment of area I outside its diameters' bounds, an impulse after
the run's end or a ramp longer than the run, a radial gap far below a wire's roughness, a contact
stiffness whose time scale the step does not resolve, an impulse resolved by a few steps, a contact
sought on fewer than four elements, a gravity above 3 g. Each gives a
:class:`~cablecasing_core.errors.ModelWarning` that says why the
result may be meaningless (:func:`plausibility`, :func:`step_checks`); the model is used as given.
The route's own warnings (too long, too short, doubling back, kinked, bent too tightly) are in one
list, ``structure.route_summary.plausibility_warnings``, issued when a model file or dictionary is
loaded (``model.load``).
"""

from __future__ import annotations

import copy
import hashlib
import math
from pathlib import Path

import numpy as np

from ..errors import NOT_SHOWN, ModelError, ModelPropertyWarning, excerpt, warn_once_per_process
from .schema import BODY_NAMES, MAX_ELEMENTS, OPTIONAL, SECTIONS, SUPPORT_NAMES, lookup, table
from .validators import MIN_LENGTH, ExcitationName


def check_keys(prefix, data, allowed, required=()):
    """``data`` must be a table whose keys are among ``allowed`` and hold every one of ``required``."""
    if not isinstance(data, dict):
        raise ModelError(prefix, data, "must be a table (section)")
    name = (lambda k: k) if prefix == "<model>" else (lambda k: f"{prefix}.{k}")  # (a section by its name)
    for k in data:
        if k not in allowed:
            # (an unknown key's value is not shown: the file may be no model file at all, e.g. one of secrets)
            raise ModelError(name(k), NOT_SHOWN, "unknown key; allowed keys are " + ", ".join(sorted(allowed)))
    for k in required:
        if k not in data:
            raise ModelError(name(k), NOT_SHOWN, "is required")


def _table(prefix, data, specs, extra=()):
    """The keys ``specs`` of table ``data`` (dotted name ``prefix``) checked, defaults filled in, in
    schema order; ``extra``: names of sub-tables the caller checks."""
    check_keys(prefix, data, {s.name for s in specs} | set(extra), [s.name for s in specs if s.required])
    out = {}
    for s in specs:
        if s.name in data:
            out[s.name] = s.check(data[s.name], f"{prefix}.{s.name}")
            why = s.implausible(out[s.name])
            if why:
                _warn(f"{prefix}.{s.name} = {excerpt(out[s.name])} is {why}")
        elif s.default is not OPTIONAL:
            out[s.name] = s.check(copy.deepcopy(s.default), f"{prefix}.{s.name}")
    return out


def _body(name, data, geometry):
    if not isinstance(data, dict):
        raise ModelError(name, data, "must be a table (section)")
    if name == "cable" and "clip" in data:
        raise ModelError("cable.clip", data["clip"], "the cable is never clipped (it slides inside the casing)")
    out = _table(name, data, table(name), extra=("supports", "isolator", "clip"))
    if name == "casing" and out["d_inner"] >= out["d_outer"]:
        raise ModelError("casing.d_inner", out["d_inner"], f"must be smaller than casing.d_outer = {out['d_outer']} m")
    out["supports"] = _table(f"{name}.supports", data.get("supports", {}), table(f"{name}.supports"))
    out.update(_mounts(name, data, out["supports"], geometry))
    return out


# ---------------------------------------------------------------- isolators, clips, routes
def _mounts(name, data, supports, geometry):
    """The isolators of ``name``'s isolator supports and the casing's clips, checked: a table
    [<body>.isolator.<A|B>] for each isolator support and none for another, each clip inside the
    route on a node of its own (with ``geometry.nodes_at_clips``, the default, a node at its ``at``:
    :func:`_nodes_at_clips`; without, the nearest node of equal elements, not an end node),
    excitation names unique."""
    iso = data.get("isolator", {})
    check_keys(f"{name}.isolator", iso, set(SUPPORT_NAMES))
    out = {}
    for s in SUPPORT_NAMES:
        key = f"{name}.isolator.{s}"
        if supports[s] == "isolator":
            if s not in iso:
                raise ModelError(
                    key,
                    NOT_SHOWN,
                    f"the table [{key}] with its stiffness ({key}.stiffness, N/m) is required when "
                    f"{name}.supports.{s} = 'isolator'",
                )
            out.setdefault("isolator", {})[s] = _table(key, iso[s], table(f"{name}.isolator.<support>"))
            _holds(key, iso[s], out["isolator"][s], f"make {name}.supports.{s} free instead")
        elif s in iso:
            raise ModelError(
                key,
                iso[s],
                f"belongs to an isolator support, but {name}.supports.{s} = '{supports[s]}': leave the table out, "
                f"or make {name}.supports.{s} = 'isolator'",
            )
    if name != "casing" or "clip" not in data:
        return out
    clips = data["clip"]
    if not isinstance(clips, list) or not all(isinstance(c, dict) for c in clips):
        raise ModelError("casing.clip", clips, "must be an array of tables [[casing.clip]], each with at and stiffness")
    from ..structure.mount_element import clip_node

    s_nodes = _node_arc_lengths(geometry)
    length, taken, names = s_nodes[-1], {}, {}
    out["clip"] = []
    for i, c in enumerate(clips):
        key = f"casing.clip[{i}]"
        raw, c = c, _table(key, c, table("casing.clip[]"))
        _holds(key, raw, c, "leave the clip out")
        if c["at"] >= length:
            raise ModelError(f"{key}.at", c["at"], f"must be inside the route, below its length {length:.6g} m")
        if "excitation" in c:
            if c["excitation"] in names or c["excitation"] in BODY_NAMES:
                raise ModelError(f"{key}.excitation", c["excitation"], "must be unique among the clips and not a body")
            names[c["excitation"]] = i
        out["clip"].append(c)
    if geometry["nodes_at_clips"]:
        s_nodes = _nodes_at_clips(geometry, out["clip"], length)
    n = len(s_nodes) - 1
    for i, c in enumerate(out["clip"]):
        key = f"casing.clip[{i}]"
        node = clip_node(s_nodes, c["at"])
        if node in (0, n):
            raise ModelError(
                f"{key}.at", c["at"], f"is nearest to an end node (s = {s_nodes[node]:.6g} m); clip the casing inside"
            )
        if node in taken:
            raise ModelError(
                f"{key}.at", c["at"], f"is nearest to node {node}, which casing.clip[{taken[node]}] holds already"
            )
        taken[node] = i
        off = s_nodes[node] - c["at"]
        if abs(off) > CLIP_OFF_NODE * length / n:
            _warn(
                f"{key}.at = {c['at']:g} m: a clip acts at a node, the nearest, at s = {s_nodes[node]:.4g} m, "
                f"{1e3 * off:+.3g} mm from its at ({n} elements of {1e3 * length / n:.3g} mm; more than "
                f"{CLIP_OFF_NODE:.0%} of an element off): a refinement (more geometry.n_elements) moves the clip too, "
                "so a mesh study would mix the two; geometry.nodes_at_clips = true puts a node at each clip's at"
            )
    return out


def _nodes_at_clips(geometry, clips, length):
    """The nodes' arc lengths (m) of ``geometry.nodes_at_clips = true``: a node at each of the checked
    ``clips``' at (structure/geometry.py, ``node_stations``), on a route of ``length`` m. Refused: a
    span between two clips, or a clip and an end, shorter than half the mean element (an element
    far shorter than the rest; two clips at one place), and fewer elements than spans."""
    n = geometry["n_elements"]
    half = 0.5 * length / n
    at = [c["at"] for c in clips]
    order = sorted(range(len(at)), key=lambda i: at[i])
    edges = [(0.0, None), *((at[i], i) for i in order), (length, None)]
    for (a, ia), (b, ib) in zip(edges[:-1], edges[1:]):
        if b - a < half:
            # (the clip named: the span's far one, else its only one; the other end said with its place)
            i, (s_other, i_other) = (ib, (a, ia)) if ib is not None else (ia, (b, ib))
            if i_other is not None:
                other = f"casing.clip[{i_other}].at = {s_other:g} m"
            else:
                other = "end A (s = 0)" if s_other == 0.0 else f"end B (s = {length:.6g} m)"
            need = math.ceil(length / (2.0 * (b - a))) if b > a else None
            raise ModelError(
                f"casing.clip[{i}].at",
                at[i],
                f"is {1e3 * (b - a):.3g} mm from {other}, less than half the mean element (route length / "
                f"geometry.n_elements / 2 = {1e3 * half:.3g} mm): geometry.nodes_at_clips = true puts a node at each "
                "clip, and that span would hold an element far shorter than the rest; "
                + (
                    "two clips at one place hold one node: give one clip"
                    if not need
                    else f"move the clip, or give geometry.n_elements at least {need}, or set "
                    "geometry.nodes_at_clips = false"
                    if need <= MAX_ELEMENTS
                    else "move the clip, or set geometry.nodes_at_clips = false (geometry.n_elements would need at "
                    f"least {need}, above its largest, {MAX_ELEMENTS})"
                ),
            )
    if n < len(edges) - 1:
        raise ModelError(
            "geometry.n_elements",
            n,
            f"must be at least {len(edges) - 1} with geometry.nodes_at_clips = true: the {len(clips)} clips cut "
            f"the route into {len(edges) - 1} spans, each of at least one element",
        )
    from ..structure.geometry import node_stations

    return node_stations(length, n, sorted(at))  # (the centerline's s, without building it again)


def _holds(key, raw, mount, instead):
    """A mount (an isolator or a clip, ``key``) has a stiffness in some direction, translational or
    rotational: one with none holds nothing (a body on it alone has modes of 0 Hz; damping alone has
    no static stiffness either)."""
    if any(mount["stiffness"]) or any(mount["rotational_stiffness"]):
        return
    raise ModelError(
        f"{key}.stiffness",
        raw.get("stiffness"),
        f"must be above 0 in some direction, or else {key}.rotational_stiffness: a mount with no stiffness in "
        f"any direction, translational or rotational, holds nothing (a body held by it alone has modes of 0 Hz, "
        f"with damping or without); {instead}",
    )


def _node_arc_lengths(geometry):
    """Arc lengths (m) of the centerline's nodes of equal elements (the route built as the structure
    builds it)."""
    from ..structure.geometry import build_centerline, centerline_from_route
    from ..structure.routing import SegmentRoute

    if "segments" in geometry:
        route = SegmentRoute(geometry["start"], geometry["direction"], geometry["segments"])
        return centerline_from_route(route, geometry["n_elements"]).s
    return build_centerline(geometry["points"], geometry["n_elements"], geometry["curve"], frames=False).s


def _geometry(data):
    """[geometry] checked: exactly one of points and segments; each bend's toward leaves the
    tangent where the bend starts."""
    out = _table("geometry", data, table("geometry"))
    given = [k for k in ("points", "segments") if k in out]
    if not given:
        raise ModelError(
            "geometry", NOT_SHOWN, "needs geometry.points (a curve through points) or geometry.segments (a route)"
        )
    if len(given) == 2:
        raise ModelError(
            "geometry.segments",
            data["segments"],
            "cannot be given together with geometry.points: a route is given by points or by segments, not both; "
            "leave one of them out",
        )
    if "segments" in out:
        if "curve" in data:
            raise ModelError("geometry.curve", data["curve"], "belongs to a route given by points, not by segments")
        del out["curve"]  # (its default belongs to points only)
        t = _unit(out["direction"], "geometry.direction")
        for i, seg in enumerate(out["segments"]):
            if "bend" in seg:
                b = seg["bend"]
                w = _unit(b["toward"], f"geometry.segments[{i}].bend.toward")
                n = w - (w @ t) * t
                if np.linalg.norm(n) < 1e-6:
                    raise ModelError(
                        f"geometry.segments[{i}].bend.toward",
                        b["toward"],
                        f"must leave the tangent {np.round(t, 6).tolist()} where the bend starts (it is along it)",
                    )
                phi = np.radians(b["angle_deg"])
                n /= np.linalg.norm(n)
                t = np.cos(phi) * t + np.sin(phi) * n
    else:
        for k in ("start", "direction"):
            if k in data:
                raise ModelError(f"geometry.{k}", data[k], "belongs to a route given by segments, not by points")
            del out[k]  # (their defaults belong to segments only)
    return out


def _element_length(geometry):
    """The route's elements at least :data:`~.validators.MIN_LENGTH` long, as every part of the
    route (its length over geometry.n_elements; a route of points by its polyline, the spline's is a
    little longer): shorter elements' bending stiffness EI / h^3 outgrows their mass's h by more than
    double precision keeps (modes of 0.0000 Hz)."""
    length, n = _route_length(geometry), geometry["n_elements"]
    if length / n < MIN_LENGTH:
        raise ModelError(
            "geometry.n_elements",
            n,
            f"cuts the {length:.4g} m route into elements of {length / n:.3g} m, shorter than the least "
            f"{MIN_LENGTH:g} m; at most {max(int(length // MIN_LENGTH), 1)} elements (are the lengths in m?)",
        )


def _unit(v, key):
    """v (three finite numbers, not all zero) over its length, or a ModelError naming ``key`` when
    the length is not a positive finite number in double precision (components near 1e-160 or 1e160)."""
    length = float(np.linalg.norm(v))
    if not (0.0 < length < np.inf):
        raise ModelError(key, v, f"must be a direction whose length is a positive finite number (it is {length:g})")
    return np.asarray(v, dtype=float) / length


def _bends_wider_than_the_bodies(geometry, bodies):
    """Each bend of a route of segments wider than the bodies: a centerline radius at or below a
    body's outer radius folds the body onto itself (no beam can follow it)."""
    for i, seg in enumerate(geometry.get("segments") or []):
        if "bend" not in seg:
            continue
        R = seg["bend"]["radius"]
        for name, key in (("casing", "d_outer"), ("cable", "d")):
            if name in bodies and R <= 0.5 * bodies[name][key]:
                raise ModelError(
                    f"geometry.segments[{i}].bend.radius",
                    R,
                    f"must exceed the {name}'s outer radius {name}.{key} / 2 = {0.5 * bodies[name][key]:g} m: a "
                    f"tighter bend folds the {name} onto itself",
                )


def _on_a_clamped_support(key, target, bodies):
    """The target (format checked by the schema) names a body of the model and a clamped or
    isolator support, or a clip with that excitation."""
    if target.count(".") == 1:
        names = [c["excitation"] for c in bodies.get("casing", {}).get("clip", []) if "excitation" in c]
        if target.split(".")[0] not in names:
            raise ModelError(
                key,
                target,
                "names no clip excitation of this model (clips' excitations: " + (", ".join(names) or "none") + ")",
            )
        return
    body, support, _ = target.split(".")
    if body not in bodies:
        raise ModelError(key, target, f"names body '{body}', which this model does not have")
    if bodies[body]["supports"][support] == "free":
        raise ModelError(
            key, target, f"support {body}.{support} is free; only clamped and isolator supports can be driven"
        )


def derived_keys(raw: dict) -> frozenset:
    """The dotted keys of a (valid) raw model dictionary whose value the validation takes from
    another key because the file leaves them out (a random excitation's ``seed`` from
    ``scenario.seed``): :meth:`Model.with_overrides` derives them again from an overridden source."""
    out = set()
    excitations = raw.get("scenario", {}).get("excitation", {})
    for name, e in excitations.items():
        if not isinstance(e, dict):
            continue
        for s in table("scenario.excitation.<name>"):
            if s.default_from and s.name not in e and (not s.kinds or e.get("kind") in s.kinds):
                out.add(f"scenario.excitation.{name}.{s.name}")
    return frozenset(out)


def _random_seeds(raw: dict, excitations: dict, seed: int) -> None:
    """The seed of each random excitation that gives none of its own (``derived_keys``): the first
    random excitation in file order keeps ``scenario.seed`` itself (a model with one random
    excitation, as the built-in specimens, keeps its record bit for bit); every later one takes
    :func:`derived_seed` of ``scenario.seed`` and its name, so that two excitations are two
    independent records, not one record twice. By file order, not by the count: a random excitation
    added after the others leaves the records of those before it as they were."""
    first = True
    for name, e in excitations.items():
        if e["kind"] != "random":
            continue
        if not first and "seed" not in raw[name]:
            e["seed"] = derived_seed(seed, name)
        first = False


def derived_seed(seed: int, name: str) -> int:
    """The seed (0 to 2**31 - 1) of the random excitation ``name`` that gives none of its own and is
    not the model's first random excitation: the first 4 bytes of the SHA-256 digest of
    ``"<seed>/<name>"`` (``seed``: ``scenario.seed``), big-endian, shifted right by one bit. A
    function of the two alone, the same on every machine and in every version of Python and numpy;
    31 bits so that it is an FMI 2.0 Integer (an FMU exposes every seed as a parameter)."""
    digest = hashlib.sha256(f"{int(seed)}/{name}".encode()).digest()
    return int.from_bytes(digest[:4], "big") >> 1


def _excitation(key, e, scenario, bodies, base_dir):
    if not isinstance(e, dict):
        raise ModelError(key, e, "must be a table with target and kind")
    if "kind" not in e:
        raise ModelError(f"{key}.kind", NOT_SHOWN, "is required: " + lookup(f"{key}.kind").validator.allowed)
    kind = lookup(f"{key}.kind").check(e["kind"], f"{key}.kind")
    specs = [s for s in table("scenario.excitation.<name>") if not s.kinds or kind in s.kinds]
    out = _table(key, e, specs)
    _on_a_clamped_support(f"{key}.target", out["target"], bodies)
    for s in specs:
        if s.default_from and s.name not in out:
            out[s.name] = s.check(scenario[s.default_from.split(".")[1]], f"{key}.{s.name}")
    if kind == "random":
        nyquist = 0.5 / scenario["dt"]
        if out["band"][1] >= nyquist:
            raise ModelError(
                f"{key}.band",
                e.get("band", out["band"]),
                f"upper frequency must be below the Nyquist frequency 1 / (2 scenario.dt) = {nyquist:.6g} Hz "
                f"(scenario.dt = {scenario['dt']:g} s): take a shorter scenario.dt or a lower band",
            )
    elif kind == "harmonic":
        f, dt = out["frequency"], scenario["dt"]
        if f >= 0.5 / dt:
            raise ModelError(
                f"{key}.frequency",
                f,
                f"must be below the Nyquist frequency 1 / (2 scenario.dt) = {0.5 / dt:.6g} Hz "
                f"(scenario.dt = {dt:g} s): the steps would sample it as its alias at {alias(f, dt):.6g} Hz",
            )
    elif kind == "csv":
        path = Path(out["file"])
        if not path.is_absolute() and base_dir is not None:
            path = Path(base_dir) / path
        out["file"] = str(path)  # (read and checked by load_model: model.load.check_excitation_files)
    return out


def alias(f: float, dt: float) -> float:
    """The frequency (Hz, 0 to 1 / (2 dt)) that samples at the step ``dt`` (s) show of a harmonic of
    ``f`` Hz: f folded about the nearest multiple of the sampling rate 1 / dt."""
    fs = 1.0 / dt
    return abs(f - fs * round(f / fs))


def _scenario(data, bodies, base_dir):
    out = _table("scenario", data, table("scenario"), extra=("excitation",))
    if out["duration"] < out["dt"]:
        raise ModelError(
            "scenario.duration", out["duration"], f"must be at least one time step (scenario.dt = {out['dt']} s)"
        )
    exc = data.get("excitation", {})
    if not isinstance(exc, dict):
        raise ModelError("scenario.excitation", exc, "must be a table of named excitations")
    for name in exc:
        ExcitationName()("scenario.excitation.<name>", name)
    out["excitation"] = {
        name: _excitation(f"scenario.excitation.{name}", e, out, bodies, base_dir) for name, e in exc.items()
    }
    _random_seeds(exc, out["excitation"], out["seed"])
    T = out["duration"]
    for name, e in out["excitation"].items():
        if e.get("start", 0.0) >= T:
            _warn(
                f"scenario.excitation.{name}.start = {e['start']:g} s is at or after the end of the run, "
                f"scenario.duration = {T:g} s: the excitation moves nothing during it"
            )
    if out["ramp"] > T and out["excitation"]:
        _warn(
            f"scenario.ramp = {out['ramp']:g} s is longer than scenario.duration = {T:g} s: the support motion "
            f"never reaches its full amplitude (at the end {_ramp_share(T / out['ramp']):.3g} of it)"
        )
    return out


def _ramp_share(x):
    """The half-cosine fade-in's factor at the fraction ``x`` (0 to 1) of the ramp."""
    return 0.5 * (1.0 - math.cos(math.pi * min(x, 1.0)))


def validate(data: dict, base_dir: str | None = None) -> dict:
    """Check a raw model dictionary (as read from TOML) and return a cleaned copy with every default
    filled in. ``base_dir``: the folder relative CSV paths are read from. Raises :class:`ModelError`
    at the first problem, naming the dotted key."""
    if not isinstance(data, dict):
        raise ModelError("<model>", data, "must be a TOML document with sections")
    check_keys("<model>", data, set(SECTIONS), required=("geometry",))
    out = {"geometry": _geometry(data["geometry"])}
    _element_length(out["geometry"])
    try:
        bodies = {n: _body(n, data[n], out["geometry"]) for n in BODY_NAMES if n in data}
    except ModelError as exc:  # a clip placed on a route whose length is likely in the wrong unit: say so
        from ..structure.route_summary import length_warning, route_numbers

        hint = length_warning(_route_length(out["geometry"]), given_by=route_numbers(out["geometry"]))
        if hint and str(exc.key).startswith("casing.clip"):
            raise ModelError(exc.key, exc.value, f"{hint} ({exc.allowed})") from None
        raise
    if not bodies:
        raise ModelError("<model>", sorted(data), "needs at least one body section, [casing] or [cable]")
    out.update(bodies)
    _bends_wider_than_the_bodies(out["geometry"], bodies)
    if "casing" in bodies and "cable" in bodies and bodies["casing"]["d_inner"] <= bodies["cable"]["d"]:
        raise ModelError(
            "casing.d_inner",
            bodies["casing"]["d_inner"],
            f"must be larger than cable.d = {bodies['cable']['d']} m (there must be a radial gap)",
        )
    n = out["geometry"]["n_elements"]
    for name, b in bodies.items():
        if n < 2 and set(b["supports"].values()) == {"clamped"}:
            raise ModelError(
                "geometry.n_elements",
                n,
                f"must be at least 2 when both supports of the {name} are clamped (one element between two clamped "
                "ends has no free node: nothing moves but the supports)",
            )
    out["contact"] = _table("contact", data.get("contact", {}), table("contact"))
    check_tolerance_substeps(out["contact"]["event_tolerance"], out["contact"]["event_substeps"])
    check_regularized(out["contact"])
    out["loads"] = _loads(data.get("loads", {}), bodies)
    _installed_friction_law(out)
    out["scenario"] = _scenario(data.get("scenario", {}), bodies, base_dir)
    _carried(out)
    _driven_through_mounts(out)
    plausibility(out)
    step_checks(out, out["scenario"]["dt"], "scenario.dt")
    return out


def check_tolerance_substeps(tolerance, substeps):
    """contact.event_tolerance (m) > 0 recomputes a step in contact.event_substeps sub-steps: with
    one there is nothing to recompute in, and the tolerance would silently do nothing."""
    if tolerance > 0.0 and substeps < 2:
        raise ModelError(
            "contact.event_tolerance",
            tolerance,
            f"must be 0 with contact.event_substeps = {substeps}: a step above the tolerance is recomputed in "
            "contact.event_substeps sub-steps, so set that to 2-64 (8 is the default) or the tolerance to 0",
        )


def check_regularized(contact):
    """The regularized friction law's force, friction x N v / sqrt(v^2 + stick_velocity^2), needs a
    contact.stick_velocity > 0 (with 0 it is the switch law's discontinuous force, which the
    implicit solve of the regularized law cannot take)."""
    if contact["friction_law"] == "regularized" and contact["stick_velocity"] <= 0.0:
        raise ModelError(
            "contact.stick_velocity",
            contact["stick_velocity"],
            'must be > 0 m/s with contact.friction_law = "regularized": it is the slip speed over which '
            "Coulomb's force is regularised (1e-4 m/s is the default)",
        )


def _installed_friction_law(out):
    """Warn of a cable under a tension (loads.cable_tension > 0: it lies on the casing's wall in the
    bends) with the paper's switch friction law: there its stick-slip switches multiply as the time
    step shrinks and the band levels do not converge (10.7 % off a 128 times finer step), and a run
    recomputes most of its steps (81 % on a user's installed model, 3 times the regularised law's
    cost); the built-in installed specimen and the docs' installed models take the regularised law
    (docs/time_domain.md, "A friction law whose limit exists")."""
    c = out["contact"]
    if (
        out["loads"]["cable_tension"] > 0.0
        and "casing" in out
        and c["enabled"]
        and c["friction"] > 0.0
        and c["friction_law"] == "switch"
    ):
        _warn(
            f"loads.cable_tension = {out['loads']['cable_tension']:g} N lays the cable on the wall, where "
            'contact.friction_law = "switch" (the paper\'s law) does not converge with the time step (its stick-slip '
            "switches multiply as it shrinks) and recomputes most steps: set contact.friction_law = "
            '"regularized", as the built-in installed specimen does (docs/time_domain.md)'
        )


def _loads(data, bodies):
    """The [loads] table; a tension needs the cable, and a loaded body a clamped or isolator support
    (or a clip) to hold it
    (the casing's buckling load is checked where it is assembled, structure/buckling.py)."""
    out = _table("loads", data, table("loads"))
    if out["cable_tension"] > 0.0 and "cable" not in bodies:
        raise ModelError("loads.cable_tension", out["cable_tension"], "needs a [cable] (the tension is the cable's)")
    causes = [("loads.gravity", out["gravity"], any(out["gravity"]))]
    causes.append(("loads.cable_tension", out["cable_tension"], out["cable_tension"] > 0.0))
    for name, b in bodies.items():
        mine = list(causes)
        if name == "cable":
            mine.append(("cable.rest_shape", b["rest_shape"], b["rest_shape"] != "routing"))
        held = {"clamped", "isolator"} & set(b["supports"].values()) or b.get("clip")  # (mounts hold it too)
        for key, value, on in mine:
            if on and not held:
                raise ModelError(
                    key,
                    value,
                    f"loads the {name}, which has no clamped or isolator support (nor a clip) to hold it "
                    "(a static state needs one)",
                )
    return out


def _carried(out):
    """Each body can carry its loads as built: structure/support_check.py (a free end under a
    tension, a loaded body its supports and mounts leave free to move, mounts too soft to hold it)."""
    from ..structure.support_check import check_supported
    from .model import Model

    check_supported(Model(out))


def _driven_through_mounts(out):
    """Each excitation on an isolator support or an excited clip drives the mount in a direction in
    which it has stiffness or damping: a mount with neither along the driven direction (global x, y,
    z, or the tangent for axial) transmits nothing, and the excitation would move nothing (every
    output it causes zero)."""
    from ..structure.geometry import centerline_of
    from ..structure.mount_element import mounts_of
    from .model import Model

    excitations = out["scenario"]["excitation"]
    mounted = {}  # target channel prefix -> (body, mount label)
    for body in BODY_NAMES:
        if body in out:
            for s in SUPPORT_NAMES:
                if out[body]["supports"][s] == "isolator":
                    mounted[f"{body}.{s}"] = (body, s)
    for i, c in enumerate(out.get("casing", {}).get("clip", [])):
        if "excitation" in c:
            mounted[c["excitation"]] = ("casing", f"clip{i}")
    hits = [(n, e["target"]) for n, e in excitations.items() if e["target"].rsplit(".", 1)[0] in mounted]
    if not hits:
        return
    model = Model(out)
    centerline = centerline_of(model)
    mounts = {(b, m.label): m for b in {b for b, _ in mounted.values()} for m in mounts_of(model, b, centerline)}
    for name, target in hits:
        where, direction = target.rsplit(".", 1)
        body, label = mounted[where]
        m = mounts[(body, label)]
        d = m.axes[0] if direction == "axial" else np.eye(3)["xyz".index(direction)]
        keys = out[body]["isolator"][label] if label in SUPPORT_NAMES else out["casing"]["clip"][int(label[4:])]
        if not _carries(m.axes, keys, d):
            mount = f"{body}.isolator.{label}" if label in SUPPORT_NAMES else f"casing.clip[{label[4:]}]"
            raise ModelError(
                f"scenario.excitation.{name}.target",
                target,
                f"drives {mount} along {'its axis' if direction == 'axial' else direction}, in which it has "
                "neither stiffness nor damping: it transmits nothing, and the excitation would move nothing; "
                "drive another direction or give the mount stiffness in this one",
            )


#: The least share of a driven direction along a mount's axes with stiffness or damping that counts
#: as a drive through it: below it the direction lies along the mount's free axes to within 1e-6 rad
#: (a route's round-off out of its plane, ~1e-7, is no drive).
LEAST_DRIVE = 1e-6


def _carries(axes, keys, d):
    """Whether a mount (local ``axes``, rows axial, lateral_1, lateral_2; its checked ``keys``)
    passes a support motion along the unit ``d`` (global) through its stiffness or damping: the
    share of ``d`` along its axes with either above :data:`LEAST_DRIVE`."""
    held = (np.asarray(keys["stiffness"]) > 0) | (np.asarray(keys["damping"]) > 0)
    return float(np.linalg.norm((axes @ d)[held])) > LEAST_DRIVE


#: The largest distance (a share of an element's length) between a clip's ``at`` and the node it acts
#: at that is taken without a warning: 10 % (2.4 mm of the 0.85 m specimens' 24 mm elements). A clip
#: a few mm off its place changes the band levels below ~100 Hz by factors (docs/model_file.md,
#: Clips), and a refinement moves it; ``geometry.nodes_at_clips = true`` puts it on a node.
CLIP_OFF_NODE = 0.10


def _warn(text):
    """Warn of what the model's values mean: a property of the model, said once per process for the
    same words (every command that loads or overrides the same model builds it anew)."""
    warn_once_per_process(text, ModelPropertyWarning, stacklevel=4)


#: Standard gravity (m/s2), and the largest magnitude of loads.gravity that does not warn (3 g: a
#: static load; a vehicle's shocks and vibration are the scenario's).
EARTH = 9.81
MAX_GRAVITY = 3 * EARTH

#: The radial gap below which the contact law's smooth surfaces do not describe a wire in a casing:
#: the surface roughness of a drawn steel wire and a casing's liner (Ra 0.1-1.6 um).
ROUGHNESS = 1e-6  # m


#: The least share of its diameters' section (the tube's, the solid wire's) a body's I may be without
#: a warning: a stranded wire's effective I is a few per cent of its solid circle's, a lined casing's
#: (I_op of Table 2) most of its tube's.
I_LEAST = 1e-3


def plausibility(out: dict) -> list[str]:
    """The warnings (also issued as :class:`ModelWarning`) of a checked model whose values are
    valid but whose result may be meaningless: the gap, the bodies' I, the gravity, the elements (docs/model_file.md,
    "Warnings"; the route's are ``structure.route_summary.plausibility_warnings``, which loading a
    model file or dictionary issues). Returns their texts."""
    said = []

    def warn(text):
        said.append(text)
        _warn(text)

    bodies = [b for b in BODY_NAMES if b in out]
    both = len(bodies) == 2
    if both:
        from .model import radial_gap  # (model.py imports this module)

        gap = radial_gap(out)
        if gap < ROUGHNESS:
            warn(
                f"the radial gap (casing.d_inner - cable.d) / 2 = {gap:.3g} m is below the {ROUGHNESS:g} m "
                "roughness of a drawn wire and a casing's liner: the smooth contact law does not describe such a "
                "fit, and the cable starts pressed against the wall wherever the route bends (the energy it "
                "then takes is no vibration)"
            )
    for name in bodies:
        b = out[name]
        if "I" not in b:
            continue
        d_o, d_i = (b["d_outer"], b["d_inner"]) if name == "casing" else (b["d"], 0.0)
        solid, tube = math.pi * d_o**4 / 64, math.pi * (d_o**4 - d_i**4) / 64
        size = "casing.d_outer" if name == "casing" else "cable.d"
        if b["I"] > solid * (1 + 1e-9):
            warn(
                f"{name}.I = {b['I']:g} m4 is {b['I'] / solid:.3g} times the solid circle's pi d^4 / 64 = "
                f"{solid:.4g} m4 of {size} = {d_o:g} m: no homogeneous section inside that diameter is so stiff "
                "(an effective I_op may exceed it a little; is the unit m4?)"
            )
        elif b["I"] < I_LEAST * tube:
            section = "tube pi (d_outer^4 - d_inner^4) / 64" if name == "casing" else "section pi d^4 / 64"
            warn(
                f"{name}.I = {b['I']:g} m4 is below {I_LEAST:g} of its {section} = {tube:.4g} m4: the "
                f"{name} bends as a string, its bending modes near 0 Hz (is the unit m4?)"
            )
    g = float(np.linalg.norm(out["loads"]["gravity"]))
    if g > MAX_GRAVITY:
        warn(
            f"loads.gravity = {excerpt(out['loads']['gravity'])} is {g:.4g} m/s2, {g / EARTH:.3g} g: the static "
            f"load of an installed cable is the Earth's {EARTH} m/s2 (above {MAX_GRAVITY / EARTH:g} g it is no "
            "installation; shocks and vibration belong in the scenario)"
        )
    n = out["geometry"]["n_elements"]
    if both and out["contact"]["enabled"] and n < 4:
        warn(
            f"geometry.n_elements = {n}: the contact is sought at the cable's {n + 1} nodes, of which {max(n - 1, 0)} "
            "are free: the contact forces do not converge on so coarse a mesh (use 10 or more elements)"
        )
    return said


def _route_length(geometry) -> float:
    """The route's length (m): the polyline through its points, or the sum of its segments."""
    if geometry.get("points"):
        pts = geometry["points"]
        return sum(math.dist(a, b) for a, b in zip(pts, pts[1:]))
    total = 0.0
    for s in geometry.get("segments") or []:
        if "straight" in s:
            total += float(s["straight"])
        elif "bend" in s:
            total += float(s["bend"]["radius"]) * math.radians(float(s["bend"]["angle_deg"]))
    return total


def step_checks(out: dict, dt: float, key: str) -> list[str]:
    """The checks of a checked model against the time step ``dt`` (s; ``key`` names it): an impulse
    of fewer than two steps is refused; one of fewer than ten steps, and a linear contact stiffness
    whose period the step does not resolve (on a node carrying its share of the law per unit length,
    ``contact.law_length``), warn. Returns the warnings' texts."""
    said = []
    for name, e in out["scenario"]["excitation"].items():
        if e["kind"] == "impulse":
            k = f"scenario.excitation.{name}.width"
            if e["width"] < 2 * dt:
                raise ModelError(
                    k,
                    e["width"],
                    f"must be at least two time steps ({key} = {dt:g} s): a narrower bump falls between the samples "
                    "and moves nothing",
                )
            if e["width"] < 10 * dt:
                said.append(
                    f"{k} = {e['width']:g} s is resolved by {e['width'] / dt:.3g} steps of {dt:g} s: the bump's "
                    "spectrum is distorted above about 1 / (4 dt)"
                )
    if "cable" in out and "casing" in out and out["contact"]["enabled"] and out["contact"]["law"] == "linear":
        c = out["cable"]
        n = out["geometry"]["n_elements"]
        length = _route_length(out["geometry"])
        node_mass = c["rho"] * math.pi * c["d"] ** 2 / 4 * length / n
        L_c = out["contact"]["law_length"]
        share = length / n / L_c if L_c > 0 else 1.0  # (an interior node's, engine.contact_shares)
        w = math.sqrt(share * out["contact"]["stiffness"] / node_mass)
        if w * dt > 0.5:
            per = f" ({share:.3g} times on each node: contact.law_length = {L_c:g} m)" if L_c > 0 else ""
            said.append(
                f"contact.stiffness = {out['contact']['stiffness']:g} N/m{per} on a cable node of {node_mass:.3g} kg "
                f"oscillates with a period of {2 * math.pi / w:.3g} s, which the step {key} = {dt:g} s does not "
                "resolve (12 or more steps per period): the contact forces and their energy are meaningless"
            )
    for text in said:
        _warn(text)
    return said
