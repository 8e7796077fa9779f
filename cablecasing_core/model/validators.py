"""The one set of input validators of the package.

Each validator checks one value and returns it cleaned, or raises
:class:`~cablecasing_core.errors.ModelError` naming the key (a dotted model key such as
``casing.E``, or an argument such as ``dt``), the value and what is allowed. A validator is an
object: calling it checks a value (``Number(gt=0, unit="s")("dt", 1e-5)``), and its ``allowed``
text is what the schema's key table and the error messages say. The model schema
(:mod:`.schema`) is built from them, and so are the checks of function arguments elsewhere (time
steps, frequencies, counts, seeds), either directly or through the schema's key
(``lookup("scenario.dt").check(dt, "dt")``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from numbers import Integral, Real

import numpy as np

from ..errors import ModelError


def _unit_phrase(unit):
    if unit in (None, "", "1"):
        return ""
    return " of seconds" if unit == "s" else f" in {unit}"


def _fmt(x):
    return f"{x:g}" if isinstance(x, float) else str(x)


class Number:
    """A finite real number (or a whole number with ``integer=True``), within optional bounds:
    ``gt``/``ge`` below, ``lt``/``le`` above (exclusive/inclusive), in ``unit`` (FMI-style, "1" for
    dimensionless). Booleans are not numbers; numpy scalars are. Returns a float (an int)."""

    def __init__(self, *, gt=None, ge=None, lt=None, le=None, integer=False, unit=None):
        self.gt, self.ge, self.lt, self.le, self.integer, self.unit = gt, ge, lt, le, integer, unit
        kind = "whole number" if integer else "number"
        self.allowed = self._text(kind)
        # what a NaN or an infinity is told: the same range, the number said finite
        self.finite = self._text("finite number")

    def _text(self, kind):
        """What is allowed, in words, of a ``kind`` ("number", "whole number", "finite number")."""
        gt, ge, lt, le = self.gt, self.ge, self.lt, self.le
        lo = (">", gt) if gt is not None else (">=", ge) if ge is not None else None
        hi = ("<", lt) if lt is not None else ("<=", le) if le is not None else None
        if lo == (">", 0) and hi is None:
            text = f"a positive {kind}"
        elif lo == (">=", 0) and hi is None:
            text = f"zero or a positive {kind}"
        elif lo and hi:
            text = (
                f"a {kind} in {'(' if lo[0] == '>' else '['}{_fmt(lo[1])}, {_fmt(hi[1])}{')' if hi[0] == '<' else ']'}"
            )
        elif lo or hi:
            op, bound = lo or hi
            text = f"a {kind} {op} {_fmt(bound)}"
        else:
            text = f"a {kind}"
        return text + _unit_phrase(self.unit)

    def __call__(self, key, value):
        kind = type(value)
        if kind is not float and kind is not int:  # (the common cases first: this runs per FMU step)
            value = _scalar(value)
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, Real):
                raise ModelError(key, value, "must be " + self.allowed)
            if self.integer and not isinstance(value, Integral):
                raise ModelError(key, value, "must be " + self.allowed)
        elif self.integer and kind is float:
            raise ModelError(key, value, "must be " + self.allowed)
        if self.integer:
            # compared as an int: float() rounds the 512 largest seeds up to 2**63, above MAX_SEED
            v = int(value)
        else:
            try:
                v = float(value)
            except OverflowError:  # an integer beyond any float
                raise ModelError(key, value, "must be " + self.allowed) from None
            if not math.isfinite(v):
                raise ModelError(key, value, "must be " + self.finite)
        if (
            (self.gt is not None and not v > self.gt)
            or (self.ge is not None and not v >= self.ge)
            or (self.lt is not None and not v < self.lt)
            or (self.le is not None and not v <= self.le)
        ):
            raise ModelError(key, value, "must be " + self.allowed)
        return v


class NumberOrTable:
    """A :class:`Number`, or a table ``[[f_Hz, value], ...]`` of such values at frequencies >= 0 Hz,
    sorted by strictly increasing frequency (a frequency-dependent value, interpolated linearly)."""

    def __init__(self, number):
        self.number = number
        self.frequency = Number(ge=0, unit="Hz")
        self.allowed = number.allowed + ", or a table [[f_Hz, value], ...] by strictly increasing frequency"

    def __call__(self, key, value):
        if not isinstance(value, list):
            return self.number(key, value)
        if len(value) < 1:
            raise ModelError(key, value, "a table needs at least one row [f_Hz, value]")
        rows = []
        for i, row in enumerate(value):
            if not isinstance(row, list) or len(row) != 2:
                raise ModelError(f"{key}[{i}]", row, "each table row must be [f_Hz, value]")
            rows.append([self.frequency(f"{key}[{i}][0]", row[0]), self.number(f"{key}[{i}][1]", row[1])])
        freqs = [r[0] for r in rows]
        if any(b <= a for a, b in zip(freqs, freqs[1:])):
            raise ModelError(key, value, "table rows must be sorted by strictly increasing frequency")
        return rows


class Choice:
    """One of a fixed set of values (strings)."""

    def __init__(self, *choices):
        self.choices = choices
        self.allowed = "one of " + ", ".join(repr(c) for c in choices)

    def __call__(self, key, value):
        if value not in self.choices:
            raise ModelError(key, value, "must be " + self.allowed)
        return value


class Boolean:
    """true or false (a TOML boolean)."""

    allowed = "true or false"

    def __call__(self, key, value):
        if not isinstance(value, (bool, np.bool_)):
            raise ModelError(key, value, "must be " + self.allowed)
        return bool(value)


class Text:
    """A non-empty string (``what`` says what it names)."""

    def __init__(self, what):
        self.allowed = what

    def __call__(self, key, value):
        if not isinstance(value, str) or not value:
            raise ModelError(key, value, "must be " + self.allowed)
        return value


#: The least length of a route's part (m): a straight, a bend's radius, the step between two points.
#: A micrometre is below any cable's roughness; shorter parts are a slip of units (or 1e-300), and
#: their rounding (1e-16 of coordinates up to 1000 m) is no longer small beside them.
MIN_LENGTH = 1e-6


class Points:
    """At least two points [x, y, z] (m), each different from the one before; at most
    :attr:`MAX_POINTS` points, coordinates within +-1000 m."""

    MAX_POINTS = 10000  # (the spline's arc length is integrated on 200 samples per span)
    allowed = (
        f"2 to {MAX_POINTS} points [x, y, z] in m, coordinates within +-1000 m, consecutive points at least "
        f"{MIN_LENGTH:g} m apart"
    )
    coordinate = Number(ge=-1e3, le=1e3, unit="m")

    def __call__(self, key, value):
        if not isinstance(value, list) or len(value) < 2:
            raise ModelError(key, value, "needs at least two points [x, y, z] in m")
        if len(value) > self.MAX_POINTS:
            raise ModelError(key, f"{len(value)} points", f"must have at most {self.MAX_POINTS} points")
        clean = []
        for i, p in enumerate(value):
            if not isinstance(p, list) or len(p) != 3:
                raise ModelError(f"{key}[{i}]", p, "each point must be [x, y, z] in m")
            clean.append([self.coordinate(f"{key}[{i}][{j}]", c) for j, c in enumerate(p)])
        arr = np.array(clean)
        seg = np.linalg.norm(np.diff(arr, axis=0), axis=1)
        scale = max(np.ptp(arr, axis=0).max(), 1e-300)
        for i, s in enumerate(seg):
            if s <= 1e-9 * scale:
                raise ModelError(
                    f"{key}[{i + 1}]",
                    clean[i + 1],
                    f"repeats the previous point {clean[i]}; consecutive points must differ",
                )
            if s < MIN_LENGTH:
                raise ModelError(
                    f"{key}[{i + 1}]",
                    clean[i + 1],
                    f"is {s:.3g} m from the previous point {clean[i]}; consecutive points must be at least "
                    f"{MIN_LENGTH:g} m apart",
                )
        return clean


class Vector:
    """Three finite numbers [x, y, z] in ``unit``, global axes (a vector key such as
    ``loads.gravity``; with ``nonzero`` a direction, not all zero). Returns a list of three floats."""

    def __init__(self, unit=None, nonzero=False, bound=None):
        self.unit, self.nonzero = unit, nonzero
        self.component = Number(unit=unit) if bound is None else Number(ge=-bound, le=bound, unit=unit)
        within = "" if bound is None else f" within +-{_fmt(float(bound))}"
        self.allowed = (
            "three finite numbers [x, y, z]" + within + _unit_phrase(unit) + (", not all zero" if nonzero else "")
        )

    def __call__(self, key, value):
        if isinstance(value, np.ndarray):
            value = value.tolist()
        if not isinstance(value, (list, tuple)) or len(value) != 3:
            raise ModelError(key, value, "must be " + self.allowed)
        out = []
        for c in value:
            try:
                out.append(self.component(key, c))
            except ModelError:
                raise ModelError(key, value, "must be " + self.allowed) from None
        if self.nonzero and not any(out):
            raise ModelError(key, value, "must be a direction, " + self.allowed)
        return out


class Band:
    """A frequency band [f_low_Hz, f_high_Hz], 0 < f_low < f_high."""

    allowed = "[f_low_Hz, f_high_Hz] with 0 < f_low < f_high <= 1e5"
    edge = Number(gt=0, le=1e5, unit="Hz")

    def __call__(self, key, value):
        if not isinstance(value, list) or len(value) != 2:
            raise ModelError(key, value, "must be [f_low_Hz, f_high_Hz]")
        lo, hi = self.edge(f"{key}[0]", value[0]), self.edge(f"{key}[1]", value[1])
        if hi <= lo:
            raise ModelError(key, value, "upper frequency must exceed the lower one")
        return [lo, hi]


class Target:
    """A support channel ``<casing|cable>.<A|B>.<x|y|z|axial>``, or an excited clip's
    ``<excitation>.<x|y|z>``; which bodies, supports and clips exist is checked with the model (a
    cross-check of the loader)."""

    def __init__(self, bodies, supports, directions):
        self.parts = (bodies, supports, directions)
        self.allowed = (
            f"'<{'|'.join(bodies)}>.<{'|'.join(supports)}>.<{'|'.join(directions)}>' or a clip's "
            f"'<excitation>.<{'|'.join(d for d in directions if d != 'axial')}>'"
        )

    def __call__(self, key, value):
        parts = value.split(".") if isinstance(value, str) else []
        clip = len(parts) == 2 and parts[0] not in self.parts[0] and parts[1] in self.parts[2] and parts[1] != "axial"
        if not clip and (len(parts) != 3 or any(p not in allowed for p, allowed in zip(parts, self.parts))):
            raise ModelError(key, value, "must be " + self.allowed)
        return value


class Segments:
    """A route's segments: a list of ``{straight = L}`` (m) and ``{bend = {radius = R, angle_deg =
    phi, toward = [x, y, z]}}`` (m, degrees in (0, 360), the direction the bend turns to); whether
    ``toward`` leaves the tangent is checked by the loader, which knows the tangent."""

    allowed = (
        "a list of {straight = L_m} and {bend = {radius = R_m, angle_deg = phi, toward = [x, y, z]}}, "
        "1e-06 <= L <= 1000, 1e-06 <= R <= 1000, 0 < phi < 360, each bend's arc R phi at least 1e-06 m"
    )
    # (as the points' coordinates: within +-1000 m; and at least the points' least spacing)
    length = Number(ge=MIN_LENGTH, le=1e3, unit="m")
    angle = Number(gt=0, lt=360, unit="deg")
    toward = Vector(unit="", nonzero=True)
    #: What each of a segment's numbers is: {leaf: (unit, description)} (the report's parameter table)
    leaves = {
        "straight": ("m", "length of a straight segment"),
        "bend.radius": ("m", "radius of a circular bend"),
        "bend.angle_deg": ("deg", "angle a bend turns through"),
        "bend.toward": ("", "the direction a bend turns to (global axes)"),
    }

    def __call__(self, key, value):
        if not isinstance(value, list) or not value:
            raise ModelError(key, value, "must be " + self.allowed)
        out = []
        for i, seg in enumerate(value):
            k = f"{key}[{i}]"
            if not isinstance(seg, dict) or len(seg) != 1 or next(iter(seg)) not in ("straight", "bend"):
                raise ModelError(
                    k, seg, "each segment must be {straight = L_m} or {bend = {radius, angle_deg, toward}}"
                )
            if "straight" in seg:
                out.append({"straight": self.length(f"{k}.straight", seg["straight"])})
                continue
            b = seg["bend"]
            names = ("radius", "angle_deg", "toward")
            if not isinstance(b, dict) or set(b) != set(names):
                raise ModelError(f"{k}.bend", b, "must be {radius = R_m, angle_deg = phi, toward = [x, y, z]}")
            bend = {
                "radius": self.length(f"{k}.bend.radius", b["radius"]),
                "angle_deg": self.angle(f"{k}.bend.angle_deg", b["angle_deg"]),
                "toward": self.toward(f"{k}.bend.toward", b["toward"]),
            }
            arc = bend["radius"] * math.radians(bend["angle_deg"])
            if not arc >= MIN_LENGTH:  # (as short as a straight may be: a shorter one is no bend to mesh)
                raise ModelError(
                    f"{k}.bend.angle_deg",
                    bend["angle_deg"],
                    f"gives an arc of {arc:.3g} m with radius {bend['radius']:g} m: a bend's arc must be at least "
                    f"{MIN_LENGTH:g} m, as a straight's length",
                )
            out.append({"bend": bend})
        return out


class Triple:
    """A number, or three numbers [axial, lateral_1, lateral_2], each within ``number``'s bounds
    (a number stands for the same value in all three directions). Returns the list of three."""

    def __init__(self, number):
        self.number = self.component = number
        self.allowed = number.allowed + ", or three of them [axial, lateral_1, lateral_2]"

    def __call__(self, key, value):
        if isinstance(value, list):
            if len(value) != 3:
                raise ModelError(key, value, "must be " + self.allowed)
            return [self.number(f"{key}[{j}]", v) for j, v in enumerate(value)]
        v = self.number(key, value)
        return [v, v, v]


class StiffnessTable:
    """A table ``[[f_Hz, k_scale, loss_factor], ...]`` of a rubber mount's dynamic stiffness against
    frequency (the stiffness times k_scale > 0, loss factor >= 0), by strictly increasing f >= 0."""

    allowed = "a table [[f_Hz, k_scale, loss_factor], ...], f >= 0 strictly increasing, k_scale > 0, loss_factor >= 0"
    columns = (Number(ge=0, unit="Hz"), Number(gt=0), Number(ge=0))

    def __call__(self, key, value):
        if not isinstance(value, list) or not value:
            raise ModelError(key, value, "must be " + self.allowed)
        rows = []
        for i, row in enumerate(value):
            if not isinstance(row, list) or len(row) != 3:
                raise ModelError(f"{key}[{i}]", row, "each row must be [f_Hz, k_scale, loss_factor]")
            rows.append([c(f"{key}[{i}][{j}]", x) for j, (c, x) in enumerate(zip(self.columns, row))])
        if any(b[0] <= a[0] for a, b in zip(rows, rows[1:])):
            raise ModelError(key, value, "rows must be sorted by strictly increasing frequency")
        return rows


class ChannelName:
    """A name for a clip's own input channels: letters, digits and _, starting with a letter
    (``dash`` gives the channels ``dash.x``, ``dash.y``, ``dash.z``)."""

    allowed = "a name of letters, digits and _ starting with a letter (its channels are <name>.x, .y, .z)"

    def __call__(self, key, value):
        if not isinstance(value, str) or not value or not value[0].isalpha() or not value.replace("_", "a").isalnum():
            raise ModelError(key, value, "must be " + self.allowed)
        return value


#: A TOML bare key: what a table's name may be without quotes (``[scenario.excitation.NAME]``).
BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


class ExcitationName:
    """The name of an excitation, ``[scenario.excitation.<name>]``: a TOML bare key (ASCII letters,
    digits, _ and -), so that it is one part of the dotted keys ``scenario.excitation.<name>.rms``
    (``with_overrides``, ``--set``, the FMU's parameters) and a table name written without quotes."""

    allowed = "a name of ASCII letters, digits, _ and - (a TOML bare key, such as cable_axial)"

    def __call__(self, key, value):
        if not isinstance(value, str) or not BARE_KEY.fullmatch(value):
            raise ModelError(key, value, "must be " + self.allowed)
        return value


# ------------------------------------------------------------------------------ argument checks
def _kind(value) -> str:
    """``value``'s type in words for a message: ``a dict``, ``a str``, ``an int``."""
    if value is None:
        return "None"
    name = "dict" if isinstance(value, dict) else "list" if isinstance(value, list) else type(value).__name__
    return ("an " if name[:1].lower() in "aeiou" else "a ") + name


def check_model(value, key: str = "model"):
    """``value`` when it is a validated :class:`~cablecasing_core.model.model.Model`, else a
    :class:`ModelError` naming ``key``, the value (a short excerpt) and how to get a model: the
    check of every entry point that takes one (modes, TRFAM, the time domain, the statics)."""
    from .model import Model

    if isinstance(value, Model):
        return value
    how = "cc.load_model(path or specimen name) or cc.model_from_dict(a dict of the model file's tables)"
    if isinstance(value, str):
        how = f"load it first: cc.load_model({value!r}), or cc.model_from_dict(a dict of the model file's tables)"
    elif isinstance(value, Mapping):
        how = "validate the dict first: cc.model_from_dict(data), or cc.load_model(path or specimen name)"
    raise ModelError(key, value, f"must be a cablecasing_core.Model, not {_kind(value)}: {how}")


def check_contact(value):
    """The ``contact`` argument of the time domain and the statics (``simulate``, ``Engine``,
    ``static_state``): None (the model's ``contact.enabled``), True or False (a numpy bool too);
    anything else, ``"no"`` among them, a :class:`ModelError` naming ``contact``."""
    if value is not None and not isinstance(value, (bool, np.bool_)):
        raise ModelError("contact", value, "must be None (the model's contact.enabled), True or False")
    return value


def contact_in_force(model, contact=None) -> bool:
    """Whether a run or a static state of ``model`` has contact: ``contact`` (:func:`check_contact`:
    None takes the model's ``contact.enabled``) and both bodies (the contact is between them). One
    rule for ``simulate``, ``Engine``, ``static_state`` and ``cablecasing static``."""
    contact = model.contact["enabled"] if check_contact(contact) is None else bool(contact)
    return contact and "casing" in model.bodies and "cable" in model.bodies


def mapping(key: str, value, what: str) -> Mapping:
    """``value`` when it is a mapping (a ``dict``), else a :class:`ModelError` naming ``key``, the
    value and ``what`` it must hold."""
    if isinstance(value, Mapping):
        return value
    raise ModelError(key, value, f"must be a mapping (a dict) {what}, not {_kind(value)}")


def names_of(key: str, value, what: str) -> tuple[str, ...]:
    """``value`` as a tuple of names: one ``str`` is one name, else an iterable of ``str`` (a
    :class:`ModelError` naming ``key``, the value and ``what`` the names must be, otherwise)."""
    if isinstance(value, str):
        return (value,)
    try:
        names = tuple(value)
    except TypeError:
        names = None
    if names is None or isinstance(value, Mapping) or not all(isinstance(n, str) for n in names):
        raise ModelError(key, value, f"must be a name or a list of names ({what})")
    return names


def number(key, value, **bounds):
    """:class:`Number` ``(**bounds)`` applied to ``value`` (e.g. ``number("fs", fs, gt=0, unit="Hz")``)."""
    return Number(**bounds)(key, value)


def _scalar(value):
    """A 0-d array of a number as that number (numpy's reduction of an array subclass, such as
    fmpy's results, is a 0-d array of the subclass, not a numpy scalar); anything else as it is."""
    if isinstance(value, np.ndarray) and value.shape == () and value.dtype.kind in "fiu":
        return value.item()
    return value


def integer(key, value, minimum, maximum=None, why=""):
    """A whole number >= ``minimum`` (and <= ``maximum``, which ``why`` explains) (Python or numpy
    integer, or a 0-d array of one; not a bool); returns an int."""
    value = _scalar(value)
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, Integral) or value < minimum:
        raise ModelError(key, value, f"must be an integer >= {minimum}" + (f" and <= {maximum}" if maximum else ""))
    if maximum is not None and value > maximum:
        raise ModelError(key, value, f"must be an integer from {minimum} to {maximum}{why}")
    return int(value)


_SECONDS = {False: Number(gt=0, unit="s"), True: Number(ge=0, unit="s")}


def seconds(key, value, *, zero_ok=False, none_ok=False):
    """A time in s: positive (or, with ``zero_ok``, zero too); None passes with ``none_ok`` (the
    caller's default). The check of every time step, duration and skip of the package."""
    if value is None and none_ok:
        return None
    rule = _SECONDS[zero_ok]
    try:
        return rule(key, value)
    except ModelError:
        raise ModelError(
            key, value, "must be " + rule.allowed + (" (or left out: the default)" if none_ok else "")
        ) from None


def array_1d(key, x, min_len=2, complex_ok=False):
    """A finite 1-D float (or, with ``complex_ok``, complex) array of at least ``min_len`` samples."""
    try:
        a = np.asarray(x)
    except Exception:  # pragma: no cover - numpy accepts almost anything
        raise ModelError(key, type(x).__name__, "must be a 1-D array of numbers") from None
    if a.ndim != 1:
        raise ModelError(key, f"array of shape {a.shape}", "must be a 1-D array")
    if np.iscomplexobj(a):
        if not complex_ok:
            raise ModelError(key, "complex array", "must be real")
        a = a.astype(complex)
    else:
        try:
            a = a.astype(float)
        except (TypeError, ValueError):
            raise ModelError(key, "non-numeric array", "must be a 1-D array of numbers") from None
    if a.size < min_len:
        raise ModelError(key, f"{a.size} samples", f"needs at least {min_len} samples")
    if not np.all(np.isfinite(a)):
        raise ModelError(key, "array with nan/inf", "must contain finite numbers only")
    return a


def frequencies(key, freqs_hz, fs=None, at_most=None):
    """A non-empty 1-D array of positive finite frequencies (Hz), real numbers and not bools (True
    would read as 1 Hz; a complex number would lose its imaginary part); with the sampling rate
    ``fs`` (Hz) each must also lie below fs/2; at most ``at_most`` of them (model/limits.py), when
    given."""
    raw = freqs_hz if isinstance(freqs_hz, np.ndarray) else np.asarray(freqs_hz, dtype=object)
    if raw.dtype.kind == "c" or (
        raw.dtype == object and any(isinstance(v, (complex, np.complexfloating)) for v in np.ravel(raw).tolist())
    ):  # (float() would drop the imaginary part with numpy's ComplexWarning)
        raise ModelError(key, freqs_hz, "must be real frequencies in Hz (a complex number is none)")
    if raw.dtype.kind == "b" or (
        raw.dtype == object and any(isinstance(v, (bool, np.bool_)) for v in np.ravel(raw).tolist())
    ):
        raise ModelError(key, freqs_hz, "must be frequencies in Hz (numbers, not True or False)")
    try:
        f = np.atleast_1d(np.asarray(freqs_hz, dtype=float))
    except (TypeError, ValueError):
        raise ModelError(key, freqs_hz, "must be one or more frequencies in Hz (numbers)") from None
    if f.ndim != 1 or f.size == 0:
        raise ModelError(key, freqs_hz, "must be one or more frequencies in Hz")
    if at_most is not None and f.size > at_most:
        raise ModelError(key, f"{f.size} frequencies", f"must be at most {at_most} (model/limits.py)")
    bad = ~np.isfinite(f) | (f <= 0.0)
    if fs is not None:
        bad |= f >= fs / 2.0
    if np.any(bad):
        if fs is None:
            raise ModelError(key, freqs_hz, "must be a non-empty vector of positive finite frequencies in Hz")
        raise ModelError(
            key, float(f[bad][0]), f"every frequency must lie in the open interval (0, fs/2) = (0, {fs / 2.0:g}) Hz"
        )
    return f
