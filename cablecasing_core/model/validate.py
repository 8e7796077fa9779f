"""Validation of a model file's tables, built from the schema (:mod:`.schema`).

Each table is checked key by key with the schema's validators (unknown keys and missing required
keys first, then every value; defaults filled in), then against the other keys where the schema's
``note`` says so: the casing's inner diameter between the cable and the outer diameter, the
duration at least one step, a random band below the Nyquist frequency, a target on a clamped
support of a body that exists, a tension only with a cable and loads only on bodies that a clamped
support holds. Every mistake raises :class:`~cablecasing_core.errors.ModelError`
naming the dotted key, the value and what is allowed; nothing is half-built.
"""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np

from ..errors import ModelError
from .schema import BODY_NAMES, OPTIONAL, SECTIONS, SUPPORT_NAMES, lookup, table


def check_keys(prefix, data, allowed, required=()):
    """``data`` must be a table whose keys are among ``allowed`` and hold every one of ``required``."""
    if not isinstance(data, dict):
        raise ModelError(prefix, data, "must be a table (section)")
    for k in data:
        if k not in allowed:
            raise ModelError(f"{prefix}.{k}", data[k], "unknown key; allowed keys are " + ", ".join(sorted(allowed)))
    for k in required:
        if k not in data:
            raise ModelError(f"{prefix}.{k}", None, "is required")


def _table(prefix, data, specs, extra=()):
    """The keys ``specs`` of table ``data`` (dotted name ``prefix``) checked, defaults filled in, in
    schema order; ``extra``: names of sub-tables the caller checks."""
    check_keys(prefix, data, {s.name for s in specs} | set(extra), [s.name for s in specs if s.required])
    out = {}
    for s in specs:
        if s.name in data:
            out[s.name] = s.check(data[s.name], f"{prefix}.{s.name}")
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


# ---------------------------------------------------------------- issue 24: isolators, clips, routes
def _mounts(name, data, supports, geometry):
    """The isolators of ``name``'s isolator supports and the casing's clips, checked: a table
    [<body>.isolator.<A|B>] for each isolator support and none for another, each clip inside the
    route on a node of its own (the nearest node, not an end node), excitation names unique."""
    iso = data.get("isolator", {})
    check_keys(f"{name}.isolator", iso, set(SUPPORT_NAMES))
    out = {}
    for s in SUPPORT_NAMES:
        key = f"{name}.isolator.{s}"
        if supports[s] == "isolator":
            if s not in iso:
                raise ModelError(key, None, f"is required: {name}.supports.{s} is an isolator")
            out.setdefault("isolator", {})[s] = _table(key, iso[s], table(f"{name}.isolator.<support>"))
        elif s in iso:
            raise ModelError(key, iso[s], f"belongs to an isolator support, but {name}.supports.{s} = '{supports[s]}'")
    if name != "casing" or "clip" not in data:
        return out
    clips = data["clip"]
    if not isinstance(clips, list) or not all(isinstance(c, dict) for c in clips):
        raise ModelError("casing.clip", clips, "must be an array of tables [[casing.clip]], each with at and stiffness")
    s_nodes = _node_arc_lengths(geometry)
    length, taken, names = s_nodes[-1], {}, {}
    out["clip"] = []
    for i, c in enumerate(clips):
        key = f"casing.clip[{i}]"
        c = _table(key, c, table("casing.clip[]"))
        if c["at"] >= length:
            raise ModelError(f"{key}.at", c["at"], f"must be inside the route, below its length {length:.6g} m")
        node = int(np.argmin(np.abs(s_nodes - c["at"])))
        if node in (0, len(s_nodes) - 1):
            raise ModelError(
                f"{key}.at", c["at"], f"is nearest to an end node (s = {s_nodes[node]:.6g} m); clip the casing inside"
            )
        if node in taken:
            raise ModelError(
                f"{key}.at", c["at"], f"is nearest to node {node}, which casing.clip[{taken[node]}] holds already"
            )
        taken[node] = i
        if "excitation" in c:
            if c["excitation"] in names or c["excitation"] in BODY_NAMES:
                raise ModelError(f"{key}.excitation", c["excitation"], "must be unique among the clips and not a body")
            names[c["excitation"]] = i
        out["clip"].append(c)
    return out


def _node_arc_lengths(geometry):
    """Arc lengths (m) of the centerline's nodes (the route built as the structure builds it)."""
    from ..structure.geometry import build_centerline, centerline_from_route
    from ..structure.routing import SegmentRoute

    if "segments" in geometry:
        route = SegmentRoute(geometry["start"], geometry["direction"], geometry["segments"])
        return centerline_from_route(route, geometry["n_elements"]).s
    return build_centerline(geometry["points"], geometry["n_elements"], geometry["curve"]).s


def _geometry(data):
    """[geometry] checked: exactly one of points and segments; each bend's toward leaves the
    tangent where the bend starts."""
    out = _table("geometry", data, table("geometry"))
    given = [k for k in ("points", "segments") if k in out]
    if len(given) != 1:
        raise ModelError(
            "geometry", sorted(data), "needs exactly one of points (a curve through points) and segments (a route)"
        )
    if "segments" in out:
        t = np.asarray(out["direction"]) / np.linalg.norm(out["direction"])
        for i, seg in enumerate(out["segments"]):
            if "bend" in seg:
                b = seg["bend"]
                w = np.asarray(b["toward"]) / np.linalg.norm(b["toward"])
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


def _excitation(key, e, scenario, bodies, base_dir):
    if not isinstance(e, dict):
        raise ModelError(key, e, "must be a table with target and kind")
    kind = lookup(f"{key}.kind").check(e.get("kind"), f"{key}.kind")
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
                f"upper frequency must be below the Nyquist frequency {nyquist:.6g} Hz",
            )
    elif kind == "csv":
        path = Path(out["file"])
        if not path.is_absolute() and base_dir is not None:
            path = Path(base_dir) / path
        out["file"] = str(path)
    return out


def _scenario(data, bodies, base_dir):
    out = _table("scenario", data, table("scenario"), extra=("excitation",))
    if out["duration"] < out["dt"]:
        raise ModelError(
            "scenario.duration", out["duration"], f"must be at least one time step (scenario.dt = {out['dt']} s)"
        )
    exc = data.get("excitation", {})
    if not isinstance(exc, dict):
        raise ModelError("scenario.excitation", exc, "must be a table of named excitations")
    out["excitation"] = {
        name: _excitation(f"scenario.excitation.{name}", e, out, bodies, base_dir) for name, e in exc.items()
    }
    return out


def validate(data: dict, base_dir: str | None = None) -> dict:
    """Check a raw model dictionary (as read from TOML) and return a cleaned copy with every default
    filled in. ``base_dir``: the folder relative CSV paths are read from. Raises :class:`ModelError`
    at the first problem, naming the dotted key."""
    if not isinstance(data, dict):
        raise ModelError("<model>", data, "must be a TOML document with sections")
    check_keys("<model>", data, set(SECTIONS), required=("geometry",))
    out = {"geometry": _geometry(data["geometry"])}
    bodies = {n: _body(n, data[n], out["geometry"]) for n in BODY_NAMES if n in data}
    if not bodies:
        raise ModelError("<model>", sorted(data), "needs at least one body section, [casing] or [cable]")
    out.update(bodies)
    if "casing" in bodies and "cable" in bodies and bodies["casing"]["d_inner"] <= bodies["cable"]["d"]:
        raise ModelError(
            "casing.d_inner",
            bodies["casing"]["d_inner"],
            f"must be larger than cable.d = {bodies['cable']['d']} m (there must be a radial gap)",
        )
    out["contact"] = _table("contact", data.get("contact", {}), table("contact"))
    out["loads"] = _loads(data.get("loads", {}), bodies)
    out["scenario"] = _scenario(data.get("scenario", {}), bodies, base_dir)
    return out


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
        held = {"clamped", "isolator"} & set(b["supports"].values()) or b.get("clip")  # (issue 24: mounts hold)
        for key, value, on in mine:
            if on and not held:
                raise ModelError(
                    key,
                    value,
                    f"loads the {name}, which has no clamped or isolator support (nor a clip) to hold it "
                    "(a static state needs one)",
                )
    return out
