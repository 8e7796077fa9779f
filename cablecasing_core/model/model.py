"""The validated model: :class:`Model` (the checked tables and typed views) and :class:`BodySpec`
(one body's material, section and supports). SI units throughout."""

from __future__ import annotations

import copy
import hashlib
import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ModelError
from .schema import BODY_NAMES, SCHEMA, lookup
from .validate import validate
from .validators import BARE_KEY, Choice


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
    rest_shape: str = "routing"

    @property
    def E_ref(self):
        """Reference modulus (Pa): the scalar, or the first table value."""
        return float(self.E[0][1]) if isinstance(self.E, list) else float(self.E)

    def modulus(self, f_hz: ArrayLike) -> np.ndarray:
        """Dynamic modulus E_d(f) in Pa at frequencies ``f_hz`` (Hz)."""
        return _interp_table(self.E, f_hz)

    def loss(self, f_hz: ArrayLike) -> np.ndarray:
        """Loss factor eta(f) (dimensionless) at frequencies ``f_hz`` (Hz)."""
        return _interp_table(self.loss_factor, f_hz)

    @property
    def frequency_dependent(self) -> bool:
        return isinstance(self.E, list)


@dataclass(frozen=True)
class Model:
    """A validated model (SI units). Build it with :func:`~cablecasing_core.load_model` or
    :func:`~cablecasing_core.model_from_dict`; ``data`` is the checked nested dictionary with every
    default filled in (docs/model_file.md), ``bodies`` its :class:`BodySpec` views."""

    data: dict
    source: str = "<built-in>"
    base_dir: str | None = None
    bodies: dict = field(default_factory=dict, compare=False)
    #: the keys whose value came from another key because the file left them out
    #: (``validate.derived_keys``: a random excitation's seed from scenario.seed)
    derived: frozenset = frozenset()

    def __post_init__(self):
        bodies = {}
        for n in BODY_NAMES:
            if n in self.data:
                b = self.data[n]
                bodies[n] = BodySpec(
                    name=n,
                    E=b["E"],
                    nu=b["nu"],
                    rho=b["rho"],
                    alpha=b["alpha"],
                    beta=b["beta"],
                    loss_factor=b["loss_factor"],
                    supports=dict(b["supports"]),
                    d_outer=b["d_outer"] if n == "casing" else b["d"],
                    d_inner=b["d_inner"] if n == "casing" else 0.0,
                    I_override=b.get("I"),
                    rest_shape=b.get("rest_shape", "routing"),
                )
        object.__setattr__(self, "bodies", bodies)

    @property
    def geometry(self) -> dict:
        return self.data["geometry"]

    @property
    def contact(self) -> dict:
        return self.data["contact"]

    @property
    def scenario(self) -> dict:
        return self.data["scenario"]

    @property
    def loads(self) -> dict:
        """The [loads] table: ``gravity`` (m/s2, global [x, y, z]) and ``cable_tension`` (N)."""
        return self.data["loads"]

    @property
    def installed(self) -> bool:
        """True when the bodies are loaded at rest (gravity, a cable tension or a straight cable):
        the time domain then starts from the static state (docs/installed.md)."""
        cable = self.bodies.get("cable")
        return bool(
            any(self.loads["gravity"]) or self.loads["cable_tension"] > 0.0 or (cable and cable.rest_shape != "routing")
        )

    @property
    def radial_gap(self) -> float:
        """Radial gap e = (casing.d_inner - cable.d) / 2 in m (Eqs. 30-31); needs both bodies."""
        return 0.5 * (self.data["casing"]["d_inner"] - self.data["cable"]["d"])

    def parameters(self) -> dict[str, float]:
        """Every numeric scalar of the model as ``{dotted.key: value}`` (SI units).

        Tables (frequency-dependent values), point lists and strings are not included; a vector key
        (``loads.gravity``) is given by its components (``loads.gravity.x``, ``.y``, ``.z``).
        """
        out = {}
        for key, v in dotted(self.data).items():
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                out[key] = v
            elif _vector(key) is not None:
                out.update({f"{key}.{c}": float(x) for c, x in zip(_vector(key).components, v)})
        return out

    def text_parameters(self) -> dict[str, str]:
        """Every key of the model outside [scenario] whose value is one of a fixed set of words
        (``geometry.curve``, ``contact.law``, ``cable.rest_shape``, the supports), as
        ``{dotted.key: value}``: the FMU's String parameters besides ``model_file``."""
        data = {k: v for k, v in self.data.items() if k != "scenario"}
        return {
            key: v
            for key, v in dotted(data).items()
            if isinstance(v, str) and key in SCHEMA and isinstance(SCHEMA[key].validator, Choice)
        }

    def with_overrides(self, overrides: Mapping[str, object]) -> Model:
        """A validated copy with ``{dotted.key: value}`` replaced (e.g. ``{"casing.E": 6e9}``).

        A key the file left out and the validation took from another (a random excitation's seed
        from ``scenario.seed``) follows an override of that other key. Keys must already exist in
        the model, or be a known optional key of an existing section;
        a vector key's component is set by its scalar key (``{"loads.gravity.z": -9.81}``); an
        unknown key raises :class:`ModelError`.
        """
        data = copy.deepcopy(self.data)
        derived = self.derived - set(overrides)
        for key in derived:  # taken again from their source, which an override may change
            parts = key.split(".")
            node = data
            for p in parts[:-1]:
                node = node[p]
            node.pop(parts[-1], None)
        for key, value in overrides.items():
            parts = key.split(".")
            vector = _vector(".".join(parts[:-1]))
            component = None
            if vector is not None and parts[-1] in vector.components:  # a vector's component
                component = vector.components.index(parts[-1])
                parts = parts[:-1]
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
            if component is None:
                node[parts[-1]] = value
            elif isinstance(node.get(parts[-1]), list) and len(node[parts[-1]]) == 3:
                node[parts[-1]][component] = value
            else:
                raise ModelError(key, value, "is not a key of this model")
        checked = validate(data, base_dir=self.base_dir)
        return Model(checked, source=self.source, base_dir=self.base_dir, derived=derived)

    def fingerprint(self) -> str:
        """A short hash (16 hex digits) of the model's data (SI values, defaults filled in): equal for
        equal models, whatever their source or folder (a tabulated excitation enters by its file's
        content, not its path, so that the same files in two folders give one fingerprint and an
        edited file another)."""
        data = dict(self.data)
        excitation = self.data.get("scenario", {}).get("excitation", {})
        if any(isinstance(e, dict) and "file" in e for e in excitation.values()):
            data["scenario"] = {**self.data["scenario"], "excitation": {}}
            for name, e in excitation.items():
                if isinstance(e, dict) and "file" in e:
                    try:
                        e = {**e, "file": "sha256:" + hashlib.sha256(Path(e["file"]).read_bytes()).hexdigest()}
                    except OSError:  # (a file gone since the model was loaded: its path stands for it)
                        pass
                data["scenario"]["excitation"][name] = e
        text = json.dumps(data, sort_keys=True, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o))
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    def to_toml(self) -> str:
        """The model as TOML text (round-trips through :func:`load_model`)."""
        return _to_toml(self.data)


def _vector(key):
    """The spec of ``key`` when it is a vector key (with components: ``loads.gravity``, a mount's
    ``stiffness``), else None."""
    try:
        spec = lookup(key) if key else None
    except ModelError:
        return None
    return spec if spec is not None and spec.components else None


def dotted(data: Mapping) -> dict:
    """Every leaf of a nested table as ``{dotted.key: value}``, in the table's order (a model's data,
    a TOML file of dotted keys)."""
    out = {}

    def walk(prefix, node):
        for k, v in node.items():
            key = f"{prefix}.{k}" if prefix else k
            if isinstance(v, dict):
                walk(key, v)
            else:
                out[key] = v

    walk("", data)
    return out


#: How a TOML basic string writes the characters it cannot hold as they are (TOML 1.0, "String").
_ESCAPES = {"\\": "\\\\", '"': '\\"', "\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f", "\r": "\\r"}


def _toml_string(s: str) -> str:
    """``s`` as a TOML basic string: quotes and backslashes escaped, and every control character
    (U+0000 to U+001F, U+007F), which a basic string may not hold, as its escape."""
    out = []
    for c in s:
        if c in _ESCAPES:
            out.append(_ESCAPES[c])
        elif c < " " or c == "\x7f":
            out.append(f"\\u{ord(c):04X}")
        else:
            out.append(c)
    return '"' + "".join(out) + '"'


def _toml_key(k) -> str:
    """A key of a TOML table: bare when it is a bare key (letters, digits, _ and -), else quoted
    (an empty name, one with a space or a dot, which bare would be a nested table)."""
    k = str(k)
    return k if BARE_KEY.fullmatch(k) else _toml_string(k)


def _to_toml(data):
    """The checked model ``data`` as TOML text: tables as [sections], the supports and the
    segments inline; every key that is not a bare key quoted, every string escaped, so that
    ``tomllib.loads(_to_toml(data)) == data`` for every valid model."""

    def fmt(v):
        if isinstance(v, (bool, np.bool_)):
            return "true" if v else "false"
        if isinstance(v, str):
            return _toml_string(v)
        if isinstance(v, (list, tuple)):
            return "[" + ", ".join(fmt(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{_toml_key(k)} = {fmt(x)}" for k, x in v.items()) + " }"
        if isinstance(v, (int, np.integer)):
            return str(int(v))
        return repr(float(v))

    lines = []

    def section(path, node):
        scalars = {k: v for k, v in node.items() if not (isinstance(v, dict) and k != "supports")}
        subs = {k: v for k, v in node.items() if isinstance(v, dict) and k != "supports"}
        lines.append("[" + ".".join(_toml_key(p) for p in path) + "]")
        lines.extend(f"{_toml_key(k)} = {fmt(v)}" for k, v in scalars.items())
        lines.append("")
        for k, v in subs.items():
            section((*path, k), v)

    for name, node in data.items():
        section((name,), node)
    return "\n".join(lines)
