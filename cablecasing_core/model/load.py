"""Model files: parsing, validation and the built-in specimen.

A model is a TOML file with the sections ``[geometry]``, ``[casing]``, ``[cable]`` (either body may
be left out, at least one must be present), ``[contact]`` and ``[scenario]``. Every mistake raises
:class:`~cablecasing_core.errors.ModelError` naming the dotted key, the value and what is allowed;
nothing is half-built. All values are SI (m, kg, s, Pa, N/m, kg/s); frequencies are in Hz.

The validated model is an immutable :class:`Model` that keeps the checked nested dictionary
(``model.data``) and offers typed views (``model.bodies``, ``model.contact``, ``model.scenario``).
"""
from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

import numpy as np

from ..errors import ModelError

BODY_NAMES = ("casing", "cable")
SUPPORT_NAMES = ("A", "B")
SUPPORT_TYPES = ("clamped", "free")
DIRECTIONS = ("x", "y", "z")
CONTACT_LAWS = ("hertz", "linear")
EXCITATION_KINDS = ("random", "harmonic", "impulse", "csv")
# The 12 translational support channels, in the FMU's input order (m, global axes).
CHANNELS = tuple(f"{b}.{s}.{d}" for b in BODY_NAMES for s in SUPPORT_NAMES for d in DIRECTIONS)

# --------------------------------------------------------------------------------------------
# small checkers: each raises ModelError(key, value, allowed)


def _number(key, value, *, positive=False, nonneg=False, lo=None, hi=None, integer=False):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ModelError(key, value, "must be a number")
    v = float(value)
    if not math.isfinite(v):
        raise ModelError(key, value, "must be a finite number")
    if integer and (not isinstance(value, int) or isinstance(value, bool)):
        raise ModelError(key, value, "must be a whole number")
    if positive and v <= 0:
        raise ModelError(key, value, "must be positive")
    if nonneg and v < 0:
        raise ModelError(key, value, "must be zero or positive")
    if lo is not None and v < lo:
        raise ModelError(key, value, f"must be at least {lo}")
    if hi is not None and v > hi:
        raise ModelError(key, value, f"must be at most {hi}")
    return int(value) if integer else v


def _number_or_table(key, value, *, positive=False, nonneg=False):
    """A scalar, or a table ``[[f_Hz, value], ...]`` sorted by strictly increasing frequency."""
    if isinstance(value, list):
        if len(value) < 1:
            raise ModelError(key, value, "a table needs at least one row [f_Hz, value]")
        rows = []
        for i, row in enumerate(value):
            if not isinstance(row, list) or len(row) != 2:
                raise ModelError(f"{key}[{i}]", row, "each table row must be [f_Hz, value]")
            f = _number(f"{key}[{i}][0]", row[0], nonneg=True)
            v = _number(f"{key}[{i}][1]", row[1], positive=positive, nonneg=nonneg)
            rows.append((f, v))
        freqs = [r[0] for r in rows]
        if any(b <= a for a, b in zip(freqs, freqs[1:])):
            raise ModelError(key, value, "table rows must be sorted by strictly increasing frequency")
        return [list(r) for r in rows]
    return _number(key, value, positive=positive, nonneg=nonneg)


def _choice(key, value, choices):
    if value not in choices:
        raise ModelError(key, value, "must be one of " + ", ".join(repr(c) for c in choices))
    return value


def _check_keys(prefix, table, allowed, required=()):
    if not isinstance(table, dict):
        raise ModelError(prefix, table, "must be a table (section)")
    for k in table:
        if k not in allowed:
            raise ModelError(f"{prefix}.{k}", table[k],
                             "unknown key; allowed keys are " + ", ".join(sorted(allowed)))
    for k in required:
        if k not in table:
            raise ModelError(f"{prefix}.{k}", None, "is required")


# --------------------------------------------------------------------------------------------
# section validators (return a cleaned copy with defaults filled in)

_GEOMETRY_KEYS = {"points", "n_elements", "curve"}
_BODY_KEYS = {
    "casing": {"E", "nu", "rho", "d_outer", "d_inner", "I", "alpha", "beta", "loss_factor", "supports"},
    "cable": {"E", "nu", "rho", "d", "I", "alpha", "beta", "loss_factor", "supports"},
}
_BODY_REQUIRED = {"casing": ("E", "rho", "d_outer", "d_inner"), "cable": ("E", "rho", "d")}
_CONTACT_KEYS = {"law", "stiffness", "damping", "friction", "stick_velocity", "enabled"}
_SCENARIO_KEYS = {"duration", "dt", "seed", "excitation", "ramp"}
_EXCITATION_KEYS = {
    "random": {"target", "kind", "rms", "band", "seed"},
    "harmonic": {"target", "kind", "frequency", "amplitude", "phase"},
    "impulse": {"target", "kind", "amplitude", "width", "start"},
    "csv": {"target", "kind", "file"},
}


def _validate_geometry(g):
    _check_keys("geometry", g, _GEOMETRY_KEYS, required=("points",))
    out = {"curve": _choice("geometry.curve", g.get("curve", "spline"), ("spline", "polyline")),
           "n_elements": _number("geometry.n_elements", g.get("n_elements", 35), integer=True, lo=1)}
    pts = g["points"]
    if not isinstance(pts, list) or len(pts) < 2:
        raise ModelError("geometry.points", pts, "needs at least two points [x, y, z] in m")
    clean = []
    for i, p in enumerate(pts):
        if not isinstance(p, list) or len(p) != 3:
            raise ModelError(f"geometry.points[{i}]", p, "each point must be [x, y, z] in m")
        clean.append([_number(f"geometry.points[{i}][{j}]", c) for j, c in enumerate(p)])
    arr = np.array(clean)
    seg = np.linalg.norm(np.diff(arr, axis=0), axis=1)
    scale = max(np.ptp(arr, axis=0).max(), 1e-300)
    for i, s in enumerate(seg):
        if s <= 1e-9 * scale:
            raise ModelError(f"geometry.points[{i + 1}]", clean[i + 1],
                             f"repeats the previous point {clean[i]}; consecutive points must differ")
    out["points"] = clean
    return out


def _validate_body(name, b):
    _check_keys(name, b, _BODY_KEYS[name], required=_BODY_REQUIRED[name])
    out = {"E": _number_or_table(f"{name}.E", b["E"], positive=True),
           "nu": _number(f"{name}.nu", b.get("nu", 0.3), lo=-0.999, hi=0.4999),
           "rho": _number(f"{name}.rho", b["rho"], positive=True),
           "alpha": _number(f"{name}.alpha", b.get("alpha", 0.0), nonneg=True),
           "beta": _number(f"{name}.beta", b.get("beta", 0.0), nonneg=True),
           "loss_factor": _number_or_table(f"{name}.loss_factor", b.get("loss_factor", 0.0), nonneg=True)}
    if name == "casing":
        out["d_outer"] = _number("casing.d_outer", b["d_outer"], positive=True)
        out["d_inner"] = _number("casing.d_inner", b["d_inner"], positive=True)
        if out["d_inner"] >= out["d_outer"]:
            raise ModelError("casing.d_inner", out["d_inner"],
                             f"must be smaller than casing.d_outer = {out['d_outer']} m")
    else:
        out["d"] = _number("cable.d", b["d"], positive=True)
    if "I" in b:
        out["I"] = _number(f"{name}.I", b["I"], positive=True)
    sup = b.get("supports", {"A": "clamped", "B": "clamped"})
    _check_keys(f"{name}.supports", sup, set(SUPPORT_NAMES))
    out["supports"] = {s: _choice(f"{name}.supports.{s}", sup.get(s, "clamped"), SUPPORT_TYPES)
                       for s in SUPPORT_NAMES}
    return out


def _validate_contact(c):
    _check_keys("contact", c, _CONTACT_KEYS)
    return {"enabled": _bool("contact.enabled", c.get("enabled", True)),
            "law": _choice("contact.law", c.get("law", "hertz"), CONTACT_LAWS),
            "stiffness": _number("contact.stiffness", c.get("stiffness", 1.0e6), positive=True),
            "damping": _number("contact.damping", c.get("damping", 100.0), nonneg=True),
            "friction": _number("contact.friction", c.get("friction", 0.15), nonneg=True),
            "stick_velocity": _number("contact.stick_velocity", c.get("stick_velocity", 1.0e-4), nonneg=True)}


def _bool(key, value):
    if not isinstance(value, bool):
        raise ModelError(key, value, "must be true or false")
    return value


def _target(key, value, bodies):
    parts = value.split(".") if isinstance(value, str) else []
    if (len(parts) != 3 or parts[0] not in BODY_NAMES or parts[1] not in SUPPORT_NAMES
            or parts[2] not in DIRECTIONS + ("axial",)):
        raise ModelError(key, value, "must be '<casing|cable>.<A|B>.<x|y|z|axial>'")
    if parts[0] not in bodies:
        raise ModelError(key, value, f"names body '{parts[0]}', which this model does not have")
    if bodies[parts[0]]["supports"][parts[1]] != "clamped":
        raise ModelError(key, value, f"support {parts[0]}.{parts[1]} is free; only clamped supports can be driven")
    return value


def _validate_scenario(s, bodies, base_dir):
    _check_keys("scenario", s, _SCENARIO_KEYS)
    out = {"duration": _number("scenario.duration", s.get("duration", 1.0), positive=True),
           "dt": _number("scenario.dt", s.get("dt", 1.0e-5), positive=True),
           "seed": _number("scenario.seed", s.get("seed", 0), integer=True, nonneg=True),
           "ramp": _number("scenario.ramp", s.get("ramp", 0.01), nonneg=True)}
    if out["duration"] < out["dt"]:
        raise ModelError("scenario.duration", out["duration"],
                         f"must be at least one time step (scenario.dt = {out['dt']} s)")
    exc = s.get("excitation", {})
    if not isinstance(exc, dict):
        raise ModelError("scenario.excitation", exc, "must be a table of named excitations")
    out["excitation"] = {}
    for name, e in exc.items():
        key = f"scenario.excitation.{name}"
        if not isinstance(e, dict):
            raise ModelError(key, e, "must be a table with target and kind")
        kind = _choice(f"{key}.kind", e.get("kind"), EXCITATION_KINDS)
        _check_keys(key, e, _EXCITATION_KEYS[kind], required=("target",))
        ce = {"target": _target(f"{key}.target", e["target"], bodies), "kind": kind}
        if kind == "random":
            ce["rms"] = _number(f"{key}.rms", e.get("rms", 5.0), nonneg=True)
            band = e.get("band", [10.0, 1000.0])
            if not isinstance(band, list) or len(band) != 2:
                raise ModelError(f"{key}.band", band, "must be [f_low_Hz, f_high_Hz]")
            lo = _number(f"{key}.band[0]", band[0], positive=True)
            hi = _number(f"{key}.band[1]", band[1], positive=True)
            if hi <= lo:
                raise ModelError(f"{key}.band", band, "upper frequency must exceed the lower one")
            if hi >= 0.5 / out["dt"]:
                raise ModelError(f"{key}.band", band,
                                 f"upper frequency must be below the Nyquist frequency {0.5 / out['dt']:.6g} Hz")
            ce["band"] = [lo, hi]
            ce["seed"] = _number(f"{key}.seed", e.get("seed", out["seed"]), integer=True, nonneg=True)
        elif kind == "harmonic":
            ce["frequency"] = _number(f"{key}.frequency", e.get("frequency"), positive=True)
            ce["amplitude"] = _number(f"{key}.amplitude", e.get("amplitude"))
            ce["phase"] = _number(f"{key}.phase", e.get("phase", 0.0))
        elif kind == "impulse":
            ce["amplitude"] = _number(f"{key}.amplitude", e.get("amplitude"))
            ce["width"] = _number(f"{key}.width", e.get("width", 1.0e-3), positive=True)
            ce["start"] = _number(f"{key}.start", e.get("start", 0.0), nonneg=True)
        else:
            f = e.get("file")
            if not isinstance(f, str) or not f:
                raise ModelError(f"{key}.file", f, "must be the path of a CSV file with columns time_s, displacement_m")
            path = Path(f)
            if not path.is_absolute() and base_dir is not None:
                path = Path(base_dir) / path
            ce["file"] = str(path)
        out["excitation"][name] = ce
    return out


def validate(data, base_dir=None):
    """Check a raw model dictionary (as read from TOML) and return a cleaned copy.

    Raises :class:`ModelError` at the first problem, naming the dotted key.
    """
    if not isinstance(data, dict):
        raise ModelError("<model>", data, "must be a TOML document with sections")
    _check_keys("<model>", data, {"geometry", "casing", "cable", "contact", "scenario"}, required=("geometry",))
    out = {"geometry": _validate_geometry(data["geometry"])}
    bodies = {n: _validate_body(n, data[n]) for n in BODY_NAMES if n in data}
    if not bodies:
        raise ModelError("<model>", sorted(data), "needs at least one body section, [casing] or [cable]")
    out.update(bodies)
    if "casing" in bodies and "cable" in bodies and bodies["casing"]["d_inner"] <= bodies["cable"]["d"]:
        raise ModelError("casing.d_inner", bodies["casing"]["d_inner"],
                         f"must be larger than cable.d = {bodies['cable']['d']} m (there must be a radial gap)")
    out["contact"] = _validate_contact(data.get("contact", {}))
    out["scenario"] = _validate_scenario(data.get("scenario", {}), bodies, base_dir)
    return out


# --------------------------------------------------------------------------------------------
# typed views


def _interp_table(value, f_hz):
    """Evaluate a scalar-or-table value at frequencies ``f_hz`` (Hz); linear, held at the ends."""
    f = np.asarray(f_hz, dtype=float)
    if isinstance(value, list):
        t = np.asarray(value, dtype=float)
        return np.interp(f, t[:, 0], t[:, 1])
    return np.full(f.shape, float(value))


@dataclass(frozen=True)
class BodySpec:
    """Material, section and support data of one body (SI units).

    ``E`` and ``loss_factor`` may be tables ``[[f_Hz, value], ...]``; use :meth:`modulus` and
    :meth:`loss` to evaluate them at a frequency.
    """

    name: str
    E: object
    nu: float
    rho: float
    alpha: float
    beta: float
    loss_factor: object
    supports: dict
    d_outer: float
    d_inner: float = 0.0
    I_override: float | None = None

    @property
    def E_ref(self):
        """Reference modulus (Pa): the scalar, or the first table value."""
        return float(self.E[0][1]) if isinstance(self.E, list) else float(self.E)

    def modulus(self, f_hz):
        """Dynamic modulus E_d(f) in Pa at frequencies ``f_hz`` (Hz)."""
        return _interp_table(self.E, f_hz)

    def loss(self, f_hz):
        """Loss factor eta(f) (dimensionless) at frequencies ``f_hz`` (Hz)."""
        return _interp_table(self.loss_factor, f_hz)

    @property
    def frequency_dependent(self):
        return isinstance(self.E, list)


@dataclass(frozen=True)
class Model:
    """A validated model. Build it with :func:`load_model` or :func:`model_from_dict`."""

    data: dict
    source: str = "<built-in>"
    base_dir: str | None = None
    bodies: dict = field(default_factory=dict, compare=False)

    def __post_init__(self):
        bodies = {}
        for n in BODY_NAMES:
            if n in self.data:
                b = self.data[n]
                bodies[n] = BodySpec(
                    name=n, E=b["E"], nu=b["nu"], rho=b["rho"], alpha=b["alpha"], beta=b["beta"],
                    loss_factor=b["loss_factor"], supports=dict(b["supports"]),
                    d_outer=b["d_outer"] if n == "casing" else b["d"],
                    d_inner=b["d_inner"] if n == "casing" else 0.0,
                    I_override=b.get("I"))
        object.__setattr__(self, "bodies", bodies)

    @property
    def geometry(self):
        return self.data["geometry"]

    @property
    def contact(self):
        return self.data["contact"]

    @property
    def scenario(self):
        return self.data["scenario"]

    @property
    def radial_gap(self):
        """Radial gap e = (casing.d_inner - cable.d) / 2 in m (Eqs. 30-31); needs both bodies."""
        return 0.5 * (self.data["casing"]["d_inner"] - self.data["cable"]["d"])

    def parameters(self):
        """Every numeric scalar of the model as ``{dotted.key: value}`` (SI units).

        Tables (frequency-dependent values), point lists and strings are not included.
        """
        out = {}

        def walk(prefix, node):
            for k, v in node.items():
                key = f"{prefix}.{k}" if prefix else k
                if isinstance(v, dict):
                    walk(key, v)
                elif isinstance(v, (int, float)) and not isinstance(v, bool):
                    out[key] = v
        walk("", self.data)
        return out

    def with_overrides(self, overrides):
        """A validated copy with ``{dotted.key: value}`` replaced (e.g. ``{"casing.E": 6e9}``).

        Keys must already exist in the model, or be a known optional key of an existing section;
        an unknown key raises :class:`ModelError`.
        """
        data = copy.deepcopy(self.data)
        for key, value in overrides.items():
            parts = key.split(".")
            node = data
            for p in parts[:-1]:
                if not isinstance(node, dict) or p not in node:
                    raise ModelError(key, value, "is not a key of this model")
                node = node[p]
            if not isinstance(node, dict):
                raise ModelError(key, value, "is not a key of this model")
            if isinstance(value, np.generic):
                value = value.item()
            if isinstance(value, np.ndarray):
                value = value.tolist()
            node[parts[-1]] = value
        return model_from_dict(data, source=self.source, base_dir=self.base_dir)

    def to_toml(self):
        """The model as TOML text (round-trips through :func:`load_model`)."""
        return _to_toml(self.data)


def model_from_dict(data, source="<dict>", base_dir=None):
    """Validate a raw nested dictionary and return a :class:`Model`."""
    return Model(validate(data, base_dir=base_dir), source=source, base_dir=base_dir)


def load_model(path=None):
    """Load and validate a model file (TOML). ``None`` gives the built-in specimen.

    Raises :class:`ModelError` for a file that cannot be read or any invalid key.
    """
    if path is None:
        text = resources.files("cablecasing_core.model").joinpath("specimens/default.toml").read_text()
        return Model(validate(tomllib.loads(text)), source="<built-in>")
    p = Path(path)
    try:
        text = p.read_text()
    except OSError as exc:
        raise ModelError("model_file", str(path), f"must be a readable TOML file ({exc.strerror})") from None
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ModelError("model_file", str(path), f"must be valid TOML ({exc})") from None
    base = str(p.resolve().parent)
    return Model(validate(raw, base_dir=base), source=str(p), base_dir=base)


def default_model():
    """The built-in model of the paper's specimen (see ``data/default_model.toml``)."""
    return load_model(None)


def _to_toml(data):
    def fmt(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
        if isinstance(v, list):
            return "[" + ", ".join(fmt(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {fmt(x)}" for k, x in v.items()) + " }"
        return repr(float(v)) if isinstance(v, float) else repr(v)

    lines = []

    def section(prefix, node):
        scalars = {k: v for k, v in node.items() if not (isinstance(v, dict) and k != "supports")}
        subs = {k: v for k, v in node.items() if isinstance(v, dict) and k != "supports"}
        lines.append(f"[{prefix}]")
        lines.extend(f"{k} = {fmt(v)}" for k, v in scalars.items())
        lines.append("")
        for k, v in subs.items():
            section(f"{prefix}.{k}", v)

    for name, node in data.items():
        section(name, node)
    return "\n".join(lines)
