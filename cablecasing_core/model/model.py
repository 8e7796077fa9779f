"""The validated model: :class:`Model` (the checked tables and typed views) and :class:`BodySpec`
(one body's material, section and supports). SI units throughout."""

from __future__ import annotations

import copy
import hashlib
import json
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ..errors import NOT_SHOWN, ModelError, plain
from .schema import BODY_NAMES, SCHEMA, SUPPORT_NAMES, KeySpec, lookup
from .validate import validate
from .validators import BARE_KEY, Choice, mapping, names_of

_READ_ONLY = (
    "a validated Model is read-only (its checks would not see the change): make a changed copy with "
    "model.with_overrides({'casing.E': 6e9}) or model.without_excitations([...]), or take a mutable deep copy "
    "with model.to_dict() (copy.deepcopy(model.data)) and validate it with cc.model_from_dict"
)


def _refuse(self, *args, **kwargs):
    raise TypeError(_READ_ONLY)


class _Frozen:
    """A validated :class:`Model`'s container, read-only (its type's mutators refuse, :func:`_refuse`):
    ``copy.copy`` gives a plain shallow copy (its ``_plain`` type), ``copy.deepcopy`` a plain, mutable
    deep one (:func:`thaw`: yours to change, as :meth:`Model.to_dict`), and pickling keeps it frozen."""

    __slots__ = ()

    def __reduce__(self):
        return (type(self), (self._plain(self),))

    def __copy__(self):
        return self._plain(self)

    def __deepcopy__(self, memo):
        return thaw(self)


class FrozenDict(_Frozen, dict):
    """A table of a validated :class:`Model` (``model.data`` and the tables in it, ``model.bodies``):
    a ``dict`` for reading (``isinstance(x, dict)``, ``json.dumps``, ``==`` with a dict), whose every
    change raises ``TypeError`` saying how to change a model; copied and pickled as :class:`_Frozen`."""

    __slots__ = ()
    _plain = dict
    __setitem__ = __delitem__ = __ior__ = _refuse
    clear = pop = popitem = setdefault = update = _refuse


class FrozenList(_Frozen, list):
    """A list of a validated :class:`Model` (a table of values ``[[f, E], ...]``, the route's
    points, the clips): a ``list`` for reading whose every change raises ``TypeError``; copied and
    pickled as :class:`_Frozen`."""

    __slots__ = ()
    _plain = list
    __setitem__ = __delitem__ = __iadd__ = __imul__ = _refuse
    append = clear = extend = insert = pop = remove = reverse = sort = _refuse


def freeze(value):
    """``value`` with every ``dict`` in it a :class:`FrozenDict` and every ``list`` a :class:`FrozenList`
    (a new structure: the value given is neither changed nor aliased)."""
    if isinstance(value, dict):
        return FrozenDict((k, freeze(v)) for k, v in value.items())
    if isinstance(value, list):
        return FrozenList(freeze(v) for v in value)
    if isinstance(value, tuple):
        return tuple(freeze(v) for v in value)
    return value


def thaw(value):
    """A plain, mutable deep copy of ``value`` (:class:`FrozenDict` -> ``dict``, :class:`FrozenList`
    -> ``list``, any other dict or list copied alike)."""
    if isinstance(value, dict):
        return {k: thaw(v) for k, v in value.items()}
    if isinstance(value, list):
        return [thaw(v) for v in value]
    return copy.deepcopy(value)


def at_frequency(value, f_hz: ArrayLike, column: int = 1) -> np.ndarray:
    """A frequency-dependent value of the model at the frequencies ``f_hz`` (Hz), in the value's
    unit, shaped as ``f_hz``. ``value`` is a scalar (the same at every frequency) or a table
    ``[[f_Hz, v1, v2, ...], ...]`` in ascending f (a modulus's ``E``, a loss factor, a mount's
    ``[f, k_scale, loss]`` rows), read in its column ``column``: linear in f between the rows, held at
    the first and last rows' values outside them. The one rule of the model's tables."""
    f = np.asarray(f_hz, dtype=float)
    if np.ndim(value) == 0:
        return np.full(f.shape, float(value))
    t = np.asarray(value, dtype=float)
    return np.interp(f, t[:, 0], t[:, column])


@dataclass(frozen=True)
class BodySpec:
    """Material, section and support data of one body (SI units): ``E`` Young's modulus (Pa),
    ``nu`` Poisson's ratio (-), ``rho`` density (kg/m3), ``alpha`` (1/s) and ``beta`` (s) Rayleigh's
    damping coefficients (Eq. 40), ``loss_factor`` eta (-), ``supports`` {"A", "B": support type},
    ``d_outer`` and ``d_inner`` the section's outer and bore diameters (m; the cable's d is
    ``d_outer``, its ``d_inner`` 0), ``I_override`` a given second moment of area (m4) or None,
    ``rest_shape`` the cable's shape at rest (a word of the schema). docs/model_file.md lists each key.

    ``E`` and ``loss_factor`` may be tables ``[[f_Hz, value], ...]`` (Hz; Pa, -); use :meth:`modulus`
    and :meth:`loss` to evaluate them at a frequency.
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
        return at_frequency(self.E, f_hz)

    def loss(self, f_hz: ArrayLike) -> np.ndarray:
        """Loss factor eta(f) (dimensionless) at frequencies ``f_hz`` (Hz)."""
        return at_frequency(self.loss_factor, f_hz)

    def __deepcopy__(self, memo):
        return self  # (read-only, as the model it belongs to)

    @property
    def frequency_dependent(self) -> bool:
        return isinstance(self.E, list)


def radial_gap(data: Mapping) -> float:
    """The radial gap e = (casing.d_inner - cable.d) / 2 (m) between the casing's bore and the cable
    (Eqs. 30-31) of a model's tables ``data`` (both bodies there, diameters in m): the one place it is
    computed (:attr:`Model.radial_gap`; the validation's warning of a gap below the roughness)."""
    return 0.5 * (data["casing"]["d_inner"] - data["cable"]["d"])


@dataclass(frozen=True)
class Model:
    """A validated model (SI units). Build it with :func:`~cablecasing_core.load_model` or
    :func:`~cablecasing_core.model_from_dict`; ``data`` is the checked nested dictionary with every
    default filled in (docs/model_file.md), ``bodies`` its :class:`BodySpec` views.

    A model is read-only, so that nothing changes behind its checks: ``data`` (every table and list
    in it) and ``bodies`` are :class:`FrozenDict` and :class:`FrozenList`, which read as ``dict`` and
    ``list`` and raise ``TypeError`` on any change. A changed model is a validated copy
    (:meth:`with_overrides`, :meth:`without_excitations`); :meth:`to_dict` (or
    ``copy.deepcopy(model.data)``) gives a plain mutable copy of the data to edit and validate again
    (:func:`~cablecasing_core.model_from_dict`). A model pickles, deep-copies and hashes (equal
    models, equal hashes), so it can key a cache. Two models are equal when their ``data``, the
    folder their relative files resolve against (``base_dir``) and their ``derived`` keys are: the
    same file loaded by a relative and by an absolute path is one model; where a model came from,
    its ``source`` (a label for messages), is not compared."""

    data: dict
    source: str = field(default="<built-in>", compare=False)
    base_dir: str | None = None
    bodies: dict = field(default_factory=dict, compare=False)
    #: the keys whose value came from another key because the file left them out
    #: (``validate.derived_keys``: a random excitation's seed from scenario.seed)
    derived: frozenset = frozenset()

    def __post_init__(self):
        if not isinstance(self.data, FrozenDict):  # (a copy: the caller's dict is neither frozen nor aliased)
            object.__setattr__(self, "data", freeze(self.data))
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
                    supports=b["supports"],
                    d_outer=b["d_outer"] if n == "casing" else b["d"],
                    d_inner=b["d_inner"] if n == "casing" else 0.0,
                    I_override=b.get("I"),
                    rest_shape=b.get("rest_shape", "routing"),
                )
        object.__setattr__(self, "bodies", FrozenDict(bodies))

    def __hash__(self):
        # (from the data alone, as equality: the fingerprint's text without the excitation files'
        # contents, which may change on disk while the model is a key)
        return hash(_data_text(self.data))

    def __deepcopy__(self, memo):
        return self  # (read-only: a copy would be equal in every way)

    def to_dict(self) -> dict:
        """A plain, mutable deep copy of :attr:`data` (``dict``s and ``list``s), to edit and validate
        again with :func:`~cablecasing_core.model_from_dict`."""
        return thaw(self.data)

    @property
    def geometry(self) -> dict:
        """The [geometry] table: the route (``points`` in m, or ``start`` (m), ``direction`` and
        ``segments``: lengths and radii in m, angles in degrees, ``angle_deg``), ``n_elements``;
        units per key in docs/model_file.md."""
        return self.data["geometry"]

    @property
    def contact(self) -> dict:
        """The [contact] table: ``enabled``, ``law``, ``stiffness`` (N/m), ``damping`` (kg/s),
        ``friction`` (-), ``stick_velocity`` (m/s), ...; units per key in docs/model_file.md."""
        return self.data["contact"]

    @property
    def scenario(self) -> dict:
        """The [scenario] table: ``duration`` and ``dt`` (s), ``ramp`` (s), ``seed``, the excitations
        (amplitudes in m, m/s or m/s2, frequencies in Hz); units per key in docs/model_file.md."""
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
        """Radial gap e = (casing.d_inner - cable.d) / 2 in m (Eqs. 30-31, :func:`radial_gap`); needs
        both bodies (a :class:`ModelError` names the one missing)."""
        for body in BODY_NAMES:
            if body not in self.data:
                raise ModelError(
                    "radial_gap",
                    plain(f"model {self.source}"),
                    f"needs a [{body}]: the radial gap lies between the "
                    "casing and the cable, and this model has only one body",
                )
        return radial_gap(self.data)

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

        Each key is a key of the schema, as a model file writes it: a value (``contact.friction``),
        a vector (``loads.gravity``) or a vector's component (``{"loads.gravity.z": -9.81}``,
        ``casing.isolator.A.stiffness.lateral_1``). A table (``contact``, ``loads``,
        ``scenario.excitation.casing_random``) is refused, naming it: its keys are set one by one,
        so that none the change leaves out is lost. A key the model does not give yet is added,
        with the tables it is in (``casing.isolator.A.stiffness`` with an isolator support A); a
        body the model does not have is not. An unknown key raises :class:`ModelError` listing the
        keys allowed where it is. A key the file left out and the validation took from another (a
        random excitation's seed from ``scenario.seed``) follows an override of that other key.
        A key of an excitation the model does not have raises :class:`ModelError` naming the
        model's excitations, unless the overrides make that excitation, its kind among them. A
        support set to ``clamped`` or ``free`` leaves its isolator's table (``casing.isolator.A``
        when ``casing.supports.A`` was an isolator) behind, unless a key of that table is set with
        it: the table belonged to the support the change replaced.
        """
        overrides = mapping("overrides", overrides, "{dotted.key: value}, e.g. {'casing.E': 6e9}")
        data = self.to_dict()
        replaced = _replaced_isolators(data, overrides)
        derived = frozenset(k for k in self.derived - set(overrides) if not k.startswith(replaced))
        for key in derived:  # taken again from their source, which an override may change
            parts = key.split(".")
            node = data
            for p in parts[:-1]:
                node = node[p]
            node.pop(parts[-1], None)
        for key, value in overrides.items():
            if isinstance(value, np.generic):
                value = value.item()
            if isinstance(value, np.ndarray):
                value = value.tolist()
            spec = override_spec(key)
            parts = key.split(".")
            _on_an_excitation_it_has(key, value, data, overrides)
            vector = _vector(".".join(parts[:-1]))
            component = None
            if vector is not None and parts[-1] in vector.components:  # a vector's component
                spec.check(value, key)  # (refused under the key given, not the vector's)
                component = vector.components.index(parts[-1])
                parts = parts[:-1]
            node = data  # (every table on the way is a table: override_spec refuses a clip's keys)
            for i, p in enumerate(parts[:-1]):
                if p not in node:
                    if i == 0:  # (a body the model does not have)
                        raise ModelError(key, value, f"belongs to the [{p}], which this model does not have")
                    node[p] = {}
                node = node[p]
            if component is None:
                node[parts[-1]] = value
            elif isinstance(node.get(parts[-1]), list) and len(node[parts[-1]]) == 3:
                node[parts[-1]][component] = value
            else:
                raise ModelError(
                    key, value, f"is a component of {'.'.join(parts)}, which the model does not give: set that first"
                )
            _one_route(key, value, data["geometry"])
        checked = validate(data, base_dir=self.base_dir)
        return Model(checked, source=self.source, base_dir=self.base_dir, derived=derived)

    def without_excitations(self, names, source: str | None = None) -> Model:
        """A validated copy without the scenario's excitations ``names`` (their keys, derived ones
        too, leave with them; every other key and what it was derived from stay), its source
        ``source`` or this one's. ``names`` is a list of names or one name (a ``str``). An unknown
        name raises :class:`ModelError` listing the model's."""
        have = self.data["scenario"]["excitation"]
        names = names_of("names", names, "excitations of the model: " + (", ".join(sorted(have)) or "none"))
        for name in names:
            if name not in have:
                raise ModelError(
                    "scenario.excitation", name, f"must name an excitation of the model: {sorted(have) or 'none'}"
                )
        data = self.to_dict()
        for name in names:
            del data["scenario"]["excitation"][name]
        prefixes = tuple(f"scenario.excitation.{name}." for name in names)
        derived = frozenset(k for k in self.derived if not k.startswith(prefixes))
        checked = validate(data, base_dir=self.base_dir)
        return Model(checked, source=self.source if source is None else source, base_dir=self.base_dir, derived=derived)

    def fingerprint(self, scenario: bool = True) -> str:
        """A short hash (16 hex digits) of the model's data (SI values, defaults filled in): equal for
        equal models, whatever their source or folder (a tabulated excitation enters by its file's
        content, not its path, so that the same files in two folders give one fingerprint and an
        edited file another). ``scenario=False``: of the structure alone (everything but
        ``[scenario]``: the bodies, their supports and mounts, the loads and the contact), what a
        state of :class:`~cablecasing_core.timedomain.engine.Engine` belongs to."""
        data = dict(self.data)
        if not scenario:
            data.pop("scenario", None)
        excitation = self.data.get("scenario", {}).get("excitation", {}) if scenario else {}
        if any(isinstance(e, dict) and "file" in e for e in excitation.values()):
            data["scenario"] = {**self.data["scenario"], "excitation": {}}
            for name, e in excitation.items():
                if isinstance(e, dict) and "file" in e:
                    try:
                        e = {**e, "file": "sha256:" + hashlib.sha256(Path(e["file"]).read_bytes()).hexdigest()}
                    except OSError:  # (a file gone since the model was loaded: its path stands for it)
                        pass
                data["scenario"]["excitation"][name] = e
        return hashlib.sha256(_data_text(data).encode()).hexdigest()[:16]

    def to_toml(self) -> str:
        """The model as TOML text (round-trips through :func:`load_model`: the model it loads is
        this one). The keys the validation derived from another because the file left them out
        (:attr:`derived`: a random excitation's seed from ``scenario.seed``) are left out again, so
        that a change of their source (``--set scenario.seed=2``) changes them in the written file
        as in this model."""
        return _to_toml(self.data, skip=self.derived)


def _data_text(data) -> str:
    """The model ``data`` as canonical JSON text (sorted keys), what :meth:`Model.fingerprint` hashes."""
    return json.dumps(data, sort_keys=True, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o))


#: Why a clip's key cannot be set by its dotted key.
_CLIP_KEYS = (
    "is a key of a clip (an array of tables [[casing.clip]]), which cannot be set by a dotted key: "
    "change the clip in the model file (to compare two clip layouts, run an ensemble of each file on the same "
    "seeds and settings and pair them: pool A.csv --against B.csv --other-model, docs/studies.md 'Two model files')"
)


def _on_an_excitation_it_has(key, value, data, overrides) -> None:
    """A :class:`ModelError` for ``key`` when it belongs to an excitation that neither the model
    data has nor ``overrides`` make (``scenario.excitation.NAME.rms`` without
    [scenario.excitation.NAME] and without ``scenario.excitation.NAME.kind``): a value alone
    cannot make one, which needs its kind and target."""
    parts = key.split(".")
    have = data.get("scenario", {}).get("excitation", {})
    if len(parts) > 3 and parts[:2] == ["scenario", "excitation"] and parts[2] not in have:
        if f"scenario.excitation.{parts[2]}.kind" in overrides:
            return  # (a new excitation, made key by key: validation checks it whole)
        raise ModelError(
            key,
            value,
            f"belongs to the excitation '{parts[2]}', which this model does not have (its excitations: "
            f"{', '.join(sorted(have)) or 'none'}): an excitation needs its kind and target (in the model file, "
            "docs/model_file.md, Excitations, or set with it)",
        )


def _replaced_isolators(data, overrides) -> tuple[str, ...]:
    """Removes from the model ``data`` each isolator table whose support ``overrides`` set to
    ``clamped`` or ``free`` without setting a key of the table itself (it belonged to the isolator
    the change replaced); returns the removed tables' key prefixes (``"casing.isolator.A."``)."""
    removed = []
    for body in BODY_NAMES:
        tables = data.get(body, {}).get("isolator", {})
        for s in SUPPORT_NAMES:
            prefix = f"{body}.isolator.{s}"
            key = f"{body}.supports.{s}"
            if s not in tables or key not in overrides:
                continue
            try:
                kind = lookup(key).check(overrides[key], key)
            except ModelError:
                continue  # (refused by with_overrides, naming it)
            if kind == "isolator":
                continue
            if any(k == prefix or k.startswith(prefix + ".") for k in overrides):
                continue  # (both set: validation names the contradiction)
            del tables[s]
            removed.append(prefix + ".")
        if body in data and "isolator" in data[body] and not tables:
            del data[body]["isolator"]
    return tuple(removed)


def override_spec(key) -> KeySpec:
    """The :class:`KeySpec` of ``key`` to set with :meth:`Model.with_overrides` (``--set``), or a
    :class:`ModelError` naming it: a table is refused with an example of its keys (a table given
    whole would replace the keys it leaves out by their defaults), an unknown key lists the keys
    allowed where it is (the wording of an unknown key of a model file)."""
    if not isinstance(key, str):
        raise ModelError(str(key), NOT_SHOWN, "must be a dotted model key, e.g. contact.friction")
    parts = key.split(".")
    if parts[0] == "casing" and len(parts) > 1 and parts[1].startswith("clip"):  # (casing.clip[0].at too)
        raise ModelError(key, NOT_SHOWN, _CLIP_KEYS)
    try:
        return lookup(key)
    except ModelError:
        pass
    below = [k[len(parts)] for k in _schema_keys_under(parts)]  # (in schema order)
    if below:
        example = ".".join(parts + [below[0] if below[0] != "<support>" else SUPPORT_NAMES[0]])
        example = next((f"{example}.{k}" for k in _schema_keys_under(example.split("."), full=True)), example)
        raise ModelError(
            key,
            NOT_SHOWN,
            f"is a table, not a key: set its keys one by one (e.g. {example}); a table given whole would "
            "replace every key it leaves out by its default",
        )
    for n in range(len(parts) - 1, -1, -1):  # the innermost table it is in: the keys allowed there
        names = {k[n] for k in _schema_keys_under(parts[:n])}
        if names:
            shown = {"<support>": SUPPORT_NAMES, "clip[]": ("clip",), "<name>": ("<name>",)}
            return _unknown(key, sorted({x for name in names for x in shown.get(name, (name,))}))
    return _unknown(key, [])  # pragma: no cover (the top level has keys)


def _unknown(key, names):
    raise ModelError(key, NOT_SHOWN, "unknown key; allowed keys are " + ", ".join(names))


def _schema_keys_under(parts, full=False):
    """The schema's keys in the table ``parts`` (a named table by any name, a support by A or B),
    each as its parts; with ``full`` the rest of the key after ``parts``, as text."""
    out = []
    for k in SCHEMA:
        ks = k.split(".")
        if len(ks) > len(parts) and all(_part_matches(a, b) for a, b in zip(ks, parts)):
            out.append(".".join(ks[len(parts) :]) if full else ks)
    return out


def _part_matches(pattern, part):
    if pattern == "<name>":
        return True
    if pattern == "<support>":
        return part in SUPPORT_NAMES
    if pattern == "clip[]":
        return part == "clip" or re.fullmatch(r"clip\[\d+\]", part) is not None
    return pattern == part


def _one_route(key, value, geometry):
    """A route is given by points or by segments: a change that gives the other refuses, naming it
    (a dotted key cannot remove the one the model gives)."""
    if key in ("geometry.points", "geometry.segments") and "points" in geometry and "segments" in geometry:
        other = "geometry.segments" if key == "geometry.points" else "geometry.points"
        raise ModelError(
            key,
            value,
            f"cannot be set on a model whose route is given by {other}: a route is given by points or by "
            f"segments, not both, and {other} must go (change the route in the model file)",
        )


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


# The package's one TOML writer (the model file of Model.to_toml, and identification.params_toml's
# lines): written here, not with tomli_w or tomlkit, so that writing needs no dependency beyond the
# reader (tomllib, tomli before Python 3.11). It writes only what a model holds (tables, inline
# tables, arrays, strings, booleans, integers, floats); the round trip tomllib.loads(_to_toml(data))
# == data is tested on awkward keys and strings and on every specimen
# (tests/model/test_model_file_checks.py).

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


def toml_text(v) -> str:
    """The TOML text of the value ``v`` (the counterpart of :func:`~.load.toml_value`): a boolean,
    an integer, a float (``repr``: every bit, and always with a point or an exponent, so that it reads
    back as a float), an escaped string, an array of lists and tuples, an inline table of dicts."""
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, str):
        return _toml_string(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_text(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_toml_key(k)} = {toml_text(x)}" for k, x in v.items()) + " }"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    return repr(float(v))


def _to_toml(data, skip=frozenset()):
    """The checked model ``data`` as TOML text: tables as [sections], the supports and the
    segments inline; every key that is not a bare key quoted, every string escaped, so that
    ``tomllib.loads(_to_toml(data)) == data`` for every valid model; the dotted keys ``skip`` (a
    model's derived keys) left out."""
    lines = []

    def section(path, node):
        scalars = {
            k: v
            for k, v in node.items()
            if not (isinstance(v, dict) and k != "supports") and ".".join((*path, k)) not in skip
        }
        subs = {k: v for k, v in node.items() if isinstance(v, dict) and k != "supports"}
        lines.append("[" + ".".join(_toml_key(p) for p in path) + "]")
        lines.extend(f"{_toml_key(k)} = {toml_text(v)}" for k, v in scalars.items())
        lines.append("")
        for k, v in subs.items():
            section((*path, k), v)

    for name, node in data.items():
        section((name,), node)
    return "\n".join(lines)
