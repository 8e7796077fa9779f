"""THE schema of the model file: every key with its type, default, unit, allowed range and a
one-line description, in one place; the one list of the support channels and of the outputs; the
paper's study output (:data:`STUDY_OUTPUT`) and the model keys that run settings stand for
(:data:`SETTING_KEYS`).

The loader (:mod:`.load`) validates a model file with the schema's validators, the FMU takes its
parameters' units and descriptions from :func:`lookup`, the CLI its help texts, and the key table
of the documentation (docs/model_file.md) is generated from it (``python docs/make_key_table.py``; a
test checks that the committed table is the generated one).

>>> from cablecasing_core.model.schema import lookup, output_spec
>>> spec = lookup("scenario.excitation.casing_random.rms")
>>> spec.unit, spec.default, spec.allowed
('m/s2', 5.0, 'a number in [0, 1e+06] in m/s2')
>>> output_spec("casing.B.Fz")
('N', 'force the casing exerts on its support B, component along global z')

Keys under named tables are written with ``<name>`` (``scenario.excitation.<name>.rms``);
:func:`lookup` accepts them under any name. Units are FMI-style strings ("1": dimensionless,
"m/s2", "N.m", "kg/m3", ...; "" for text and booleans).

This module is over 400 lines because the schema is one table of all the model file's keys, kept
in one place on purpose; the validators are in ``validators.py``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from ..errors import ModelError
from .validators import (
    Band,
    Boolean,
    ChannelName,
    Choice,
    Number,
    NumberOrTable,
    Points,
    Segments,
    StiffnessTable,
    Target,
    Text,
    Triple,
    Vector,
)

BODY_NAMES = ("casing", "cable")
SUPPORT_NAMES = ("A", "B")
SUPPORT_TYPES = ("clamped", "isolator", "free")
DIRECTIONS = ("x", "y", "z")
#: The components of a mount's stiffness and damping: its support's local axes (mount_element.py)
MOUNT_AXES = ("axial", "lateral_1", "lateral_2")
#: the contact laws; a law's index here is its code in the kernels (ContactLaw.law)
CONTACT_LAWS = ("hertz", "linear", "hunt_crossley")
FRICTION_LAWS = ("switch", "regularized")
EXCITATION_KINDS = ("random", "harmonic", "impulse", "csv")
CSV_QUANTITIES = ("displacement", "velocity", "acceleration")
SECTIONS = ("geometry", "casing", "cable", "contact", "loads", "scenario")
REST_SHAPES = ("routing", "straight")
#: The most elements a body may have (the time domain's dense compliance of 6 (n + 1) DOFs and the
#: frequency domain's dense eigenproblem grow as n^2 in memory, n^3 in time; docs/model_file.md, Limits).
MAX_ELEMENTS = 2000
#: The largest seed: what a signed 64-bit integer holds (the ensembles' CSV files, numpy).
MAX_SEED = 2**63 - 1

#: The 12 translational support channels, in the FMU's input order (m, m/s, m/s2, global axes).
CHANNELS = tuple(f"{b}.{s}.{d}" for b in BODY_NAMES for s in SUPPORT_NAMES for d in DIRECTIONS)
FORCE_NAMES = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
#: Force (N) and moment (N.m) each body exerts on each support, in global axes.
SUPPORT_OUTPUTS = tuple(f"{b}.{s}.{c}" for b in BODY_NAMES for s in SUPPORT_NAMES for c in FORCE_NAMES)
CONTACT_OUTPUTS = ("contact.active", "contact.max_penetration", "contact.dissipated_energy")
#: The outputs whose values are whole numbers (``contact.active``, a count of nodes): an FMU declares
#: them Integer; every other output is a real number (:func:`output_spec`).
INTEGER_OUTPUTS = ("contact.active",)
#: Every output of the time domain (``Engine.output_values``, the FMU's outputs), in this order.
OUTPUTS = SUPPORT_OUTPUTS + CONTACT_OUTPUTS
#: The paper's study output (Section 4, Figs. 20-23): the force (N) the casing exerts on its
#: support B along global z, where the support force was measured; the default output of the
#: studies, the ensembles, the transfer functions, the report, and the column `bands` and `spectrum` read.
STUDY_OUTPUT = "casing.B.Fz"
#: The support inputs (the FMU's inputs; the columns of a run's record for its driven channels):
#: displacement ``casing.A.x`` (m), velocity ``casing.A.vx`` (m/s), acceleration ``casing.A.ax``
#: (m/s2) of every channel, in this order (kind-major).
INPUT_KINDS = (("", "displacement", "m"), ("v", "velocity", "m/s"), ("a", "acceleration", "m/s2"))
INPUTS = tuple(f"{c[:-1]}{k}{c[-1]}" for k, _, _ in INPUT_KINDS for c in CHANNELS)


def channels_of(data) -> tuple:
    """The support channels of a model (its checked data, or a :class:`Model`): the 12 of
    :data:`CHANNELS`, then ``<excitation>.x, .y, .z`` of each clip with an excitation, in file
    order (m, global axes). The engine's motion has one column per channel."""
    data = getattr(data, "data", data)
    clips = data.get("casing", {}).get("clip", [])
    return CHANNELS + tuple(f"{c['excitation']}.{d}" for c in clips if "excitation" in c for d in DIRECTIONS)


def clip_outputs(data) -> tuple:
    """The outputs of a model's clips: ``casing.clip<i>.Fx`` .. ``casing.clip<i>.Mz`` (N, N.m, the
    force and moment the casing exerts through clip i on its support, global axes), in file order."""
    data = getattr(data, "data", data)
    n = len(data.get("casing", {}).get("clip", []))
    return tuple(f"casing.clip{i}.{c}" for i in range(n) for c in FORCE_NAMES)


def outputs_of(data) -> tuple:
    """Every time-domain output of a model: :data:`OUTPUTS`, then :func:`clip_outputs`."""
    return OUTPUTS + clip_outputs(data)


def inputs_of(data) -> tuple:
    """The inputs of a model's channels (:func:`channels_of`), kind-major as :data:`INPUTS`."""
    return tuple(f"{c[:-1]}{k}{c[-1]}" for k, _, _ in INPUT_KINDS for c in channels_of(data))


class _Marker:
    def __init__(self, name):
        self.name = name

    def __repr__(self):
        return self.name


REQUIRED = _Marker("REQUIRED")  #: the key must be given
OPTIONAL = _Marker("OPTIONAL")  #: the key may be left out; there is no default


@dataclass(frozen=True)
class KeySpec:
    """One key of the model file.

    key: dotted key (``<name>`` for a named table); type: "float", "int", "bool", "str",
    "float or table" (a number or a table ``[[f_Hz, value], ...]``), "points" or "band"; default: the
    value taken when the key is left out, or :data:`REQUIRED`, :data:`OPTIONAL`; unit: FMI-style;
    description: one line; validator: the :mod:`.validators` object that checks a value; note:
    what the loader checks against other keys; kinds: the excitation kinds that take the key;
    default_from: the key whose value is the default; components: the names of a vector key's
    components, whose scalar keys ``<key>.<component>`` are parameters (the FMU's, ``with_overrides``);
    plausible: ``(low, high, why)``, the range of physically meaningful values inside the allowed one:
    a value outside it is taken, with a :class:`~cablecasing_core.errors.ModelWarning` that says
    ``why`` the result may be meaningless.

    The allowed ranges are what the numerics can take: within them no combination of values
    overflows, and a run either gives finite results or stops with a message (docs/model_file.md,
    Limits); they are far wider than any cable.
    """

    key: str
    type: str
    default: object
    unit: str
    description: str
    validator: object
    note: str = ""
    kinds: tuple = ()
    default_from: str | None = None
    components: tuple = ()
    plausible: tuple | None = None

    @property
    def allowed(self) -> str:
        """A short human text of the allowed values."""
        return self.validator.allowed + (f"; {self.note}" if self.note else "")

    @property
    def allowed_text(self) -> str:
        """:attr:`allowed` with the plausible range (``a warning outside ...``), as the key table and
        ``cablecasing keys`` show it."""
        return self.allowed + (f"; a warning outside {self.plausible_text}" if self.plausible else "")

    @property
    def default_text(self) -> str:
        """The default as the key table shows it: a value (TOML), ``required``, ``(none)`` or the key
        it is taken from."""
        if self.default_from:
            return self.default_from
        if self.default is REQUIRED:
            return "required"
        if self.default is OPTIONAL:
            return "(none)"
        value = self.default
        return ("true" if value else "false") if isinstance(value, bool) else repr(value).replace("'", '"')

    @property
    def plausible_text(self) -> str:
        """The plausible range as text (empty when the key has none)."""
        if not self.plausible:
            return ""
        lo, hi, _ = self.plausible
        return f"{lo:g} to {hi:g}" + (f" {self.unit}" if self.unit not in ("", "1") else "")

    def implausible(self, value) -> str | None:
        """Why ``value`` (checked; a number or a table's values) may give a meaningless result, or None."""
        if not self.plausible:
            return None
        lo, hi, why = self.plausible
        values = [row[1] for row in value] if isinstance(value, list) else [value]
        bad = [v for v in values if not (lo <= abs(v) <= hi or v == 0)]
        if not bad:
            return None
        size = " in magnitude" if any(v < 0 for v in bad) else ""  # (the range holds |value|)
        return f"outside the plausible {self.plausible_text}{size}: {why}"

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    @property
    def name(self) -> str:
        """The last part of the key (the name in its table)."""
        return self.key.rsplit(".", 1)[1]

    def check(self, value, key=None):
        """``value`` checked and cleaned; a :class:`ModelError` names ``key`` (default: this key)."""
        return self.validator(self.key if key is None else key, value)


_DIAMETER = (1e-4, 0.05, "the cables and casings this model describes are 0.1 to 50 mm thick")


def _diameter(key, description, note=""):
    """A diameter key (m): required, 1e-5 to 1 m, plausible 0.1 to 50 mm."""
    return KeySpec(
        key, "float", REQUIRED, "m", description, Number(ge=1e-5, le=1.0, unit="m"), note, plausible=_DIAMETER
    )


def _body(body):
    the = f"the {body}"
    keys = [
        KeySpec(
            f"{body}.E",
            "float or table",
            REQUIRED,
            "Pa",
            f"Young's (dynamic) modulus of {the}; a table makes it frequency-dependent (Section 3.1)",
            NumberOrTable(Number(gt=0, le=1e16, unit="Pa")),
            plausible=(1e5, 1.2e12, "solids lie between a soft rubber (1e5 Pa) and diamond (1.2e12 Pa)"),
        ),
        KeySpec(
            f"{body}.nu",
            "float",
            0.3,
            "1",
            f"Poisson ratio of {the} (G = E / (2 (1 + nu)))",
            Number(ge=-0.999, le=0.4999),
        ),
        KeySpec(
            f"{body}.rho",
            "float",
            REQUIRED,
            "kg/m3",
            f"density of {the}, averaged over its cross-section",
            Number(ge=0.01, le=1e5, unit="kg/m3"),
            plausible=(100.0, 25000.0, "solids lie between a foam (100 kg/m3) and osmium (22600 kg/m3)"),
        ),
        KeySpec(
            f"{body}.alpha",
            "float",
            0.0,
            "1/s",
            f"Rayleigh mass-proportional damping of {the}, C = alpha M + beta K (Eq. 40)",
            Number(ge=0, le=1e9, unit="1/s"),
            plausible=(0.0, 1e4, "the damping ratio alpha / (2 omega) exceeds 1 (overdamped) up to alpha / (4 pi) Hz"),
        ),
        KeySpec(
            f"{body}.beta",
            "float",
            0.0,
            "s",
            f"Rayleigh stiffness-proportional damping of {the}, C = alpha M + beta K (Eq. 40)",
            Number(ge=0, le=1.0, unit="s"),
            plausible=(0.0, 1e-3, "the damping ratio beta omega / 2 exceeds 1 (overdamped) from 1 / (pi beta) Hz"),
        ),
        KeySpec(
            f"{body}.loss_factor",
            "float or table",
            0.0,
            "1",
            f"structural loss factor of {the} (Eq. 11; frequency domain only, the time domain uses alpha, beta)",
            NumberOrTable(Number(ge=0, le=100.0)),
            plausible=(0.0, 2.0, "loss factors of solids lie below 2 (rubbers near their glass transition)"),
        ),
    ]
    if body == "casing":
        keys += [
            _diameter("casing.d_outer", "outer diameter of the casing (d_2 of Table 2)"),
            _diameter(
                "casing.d_inner",
                "inner diameter of the casing, in which the cable runs (d_5 of Table 2)",
                "below casing.d_outer and above cable.d",
            ),
        ]
    else:
        keys += [_diameter("cable.d", "diameter of the cable (D_z0)")]
    keys.append(
        KeySpec(
            f"{body}.I",
            "float",
            OPTIONAL,
            "m4",
            f"effective second moment of area of {the}'s section, instead of the one of its diameters "
            "(I_op of Table 2)",
            Number(gt=0, le=1.0, unit="m4"),
            note="a warning above the solid circle's pi d^4 / 64 of "
            + ("casing.d_outer" if body == "casing" else "cable.d")
            + " or below 1e-3 of the section of the diameters"
            + (", pi (d_outer^4 - d_inner^4) / 64" if body == "casing" else ""),
        )
    )
    keys += [
        KeySpec(
            f"{body}.supports.{s}",
            "str",
            "clamped",
            "",
            f"support {s} of {the}: clamped (its translations follow the support motion, rotations held), "
            f"isolator (a 6-DOF spring-damper to the moving support, [{body}.isolator.{s}]) or free",
            Choice(*SUPPORT_TYPES),
            note=f"isolator needs the table [{body}.isolator.{s}]",
        )
        for s in SUPPORT_NAMES
    ]
    keys += _mount_keys(f"{body}.isolator.<support>", "the isolator")
    if body == "casing":
        keys += [
            KeySpec(
                "casing.clip[].at",
                "float",
                REQUIRED,
                "m",
                "arc length from end A of a clip holding the casing (a node there by default; with "
                "geometry.nodes_at_clips = false the nearest node is clipped)",
                Number(gt=0, unit="m"),
                note="inside the route, at least half a mean element from an end and from another clip (with "
                "geometry.nodes_at_clips = false: its nearest node not an end node and not another clip's)",
            ),
            *_mount_keys("casing.clip[]", "the clip"),
            KeySpec(
                "casing.clip[].excitation",
                "str",
                OPTIONAL,
                "",
                "a name for the clip's own support channels <name>.x, .y, .z (m, global axes; FMU inputs "
                "and excitation targets); without it the clip's support is fixed",
                ChannelName(),
                note="unique among the model's clips",
            ),
        ]
    return keys


def _mount_keys(prefix, what):
    """The spring-damper keys of an isolator or a clip (local axes: axial along the tangent, the
    element frame's lateral y and z), each a number or three, by component a parameter."""
    # Upper bounds: a stiffer mount is a clamp to round-off, and beyond them the system turns
    # singular in double precision (a stiffness of 1e30 N/m gave zero natural frequencies); the
    # tests' stiffest mounts (clamp-like: 1e13 N/m, 1e11 N.m/rad) lie below them.
    triples = [
        (
            "stiffness",
            REQUIRED,
            "N/m",
            "translational stiffness",
            "[axial, lateral_1, lateral_2] in the support's local axes",
            1e14,
        ),
        (
            "rotational_stiffness",
            0.0,
            "N.m/rad",
            "rotational stiffness",
            "[about axial (torsion), lateral_1, lateral_2]",
            1e12,
        ),
        ("damping", 0.0, "N.s/m", "translational viscous damping", "[axial, lateral_1, lateral_2]", 1e10),
        (
            "rotational_damping",
            0.0,
            "N.m.s/rad",
            "rotational viscous damping",
            "[about axial, lateral_1, lateral_2]",
            1e8,
        ),
    ]
    keys = [
        KeySpec(
            f"{prefix}.{name}",
            "float or 3 floats",
            default,
            unit,
            f"{kind} of {what} {axes}",
            Triple(Number(ge=0, le=top, unit=unit)),
            note="with rotational_stiffness, above 0 in some direction" if name == "stiffness" else "",
            components=MOUNT_AXES,
        )
        for name, default, unit, kind, axes, top in triples
    ]
    keys.append(
        KeySpec(
            f"{prefix}.table",
            "table",
            OPTIONAL,
            "",
            f"dynamic stiffness of {what} against frequency, k(f) = k k_scale (1 + i loss_factor): in the "
            "frequency domain it replaces stiffness and damping (the time domain uses those); linear, held at the ends",
            StiffnessTable(),
        )
    )
    return keys


_EXC = "scenario.excitation.<name>"
_KEYS = [
    KeySpec(
        "geometry.curve",
        "str",
        "spline",
        "",
        "the centerline through the points: a cubic spline by arc length, or the polyline (Eqs. 32-34)",
        Choice("spline", "polyline"),
        note="only with geometry.points",
    ),
    KeySpec(
        "geometry.n_elements",
        "int",
        35,
        "1",
        "number of beam elements of each body along the centerline",
        Number(ge=1, le=MAX_ELEMENTS, integer=True),
        note="a run checks the memory it needs first (docs/model_file.md, Limits)",
    ),
    KeySpec(
        "geometry.nodes_at_clips",
        "bool",
        True,
        "",
        "a node at each casing clip's at: the elements are equal within each span between the ends and the clips, "
        "the spans sharing geometry.n_elements in proportion to their lengths (false: n_elements equal elements, "
        "each clip at its nearest node, which a change of n_elements moves)",
        Boolean(),
        note="each span at least half the mean element (route length / geometry.n_elements / 2); geometry.n_elements "
        "at least the number of spans",
    ),
    KeySpec(
        "geometry.points",
        "points",
        OPTIONAL,
        "m",
        "points on the centerline at rest, end A first",
        Points(),
        note="exactly one of geometry.points and geometry.segments",
    ),
    KeySpec(
        "geometry.start",
        "3 floats",
        [0.0, 0.0, 0.0],
        "m",
        "end A of a route given by segments",
        Vector(unit="m", bound=1e3),
    ),
    KeySpec(
        "geometry.direction",
        "3 floats",
        [1.0, 0.0, 0.0],
        "1",
        "unit tangent at end A of a route given by segments (normalised)",
        Vector(unit="", nonzero=True),
    ),
    KeySpec(
        "geometry.segments",
        "segments",
        OPTIONAL,
        "m",
        "the route as straights and circular bends from geometry.start along geometry.direction (exact arcs)",
        Segments(),
        note="each bend's toward not along the tangent where the bend starts",
    ),
    *_body("casing"),
    *_body("cable"),
    KeySpec(
        "contact.enabled",
        "bool",
        True,
        "",
        "contact between cable and casing (false: two independent linear bodies)",
        Boolean(),
    ),
    KeySpec(
        "contact.law",
        "str",
        "hertz",
        "",
        "normal contact law: Hertz (Eq. 29, from both bodies' moduli and radii) or linear (Eq. 24), each with "
        "contact.damping while compressing (Eq. 16); or hunt_crossley: Hertz's force times (1 + 3/2 alpha g_dot), "
        "alpha = contact.hunt_crossley_alpha, continuous at first touch (docs/time_domain.md)",
        Choice(*CONTACT_LAWS),
    ),
    KeySpec(
        "contact.stiffness",
        "float",
        1.0e6,
        "N/m",
        "penalty stiffness of the linear contact law (Eq. 24)",
        Number(gt=0, le=1e30, unit="N/m"),
    ),
    KeySpec(
        "contact.damping",
        "float",
        100.0,
        "kg/s",
        "contact damping, acting while the penetration grows (Eq. 16)",
        Number(ge=0, le=1e12, unit="kg/s"),
    ),
    KeySpec(
        "contact.hunt_crossley_alpha",
        "float",
        10.0,
        "s/m",
        "damping factor alpha of the Hunt-Crossley law (contact.law = hunt_crossley): N = k g^1.5 (1 + 3/2 alpha "
        "g_dot); an impact at v_in rebounds with restitution e, the root of -e x - ln(1 - e x) = x - ln(1 + x), x = "
        "3/2 alpha v_in (timedomain.engine.hunt_crossley_restitution): 1 - alpha v_in for alpha v_in << 1, 0.663 "
        "at 10 s/m and 0.05 m/s",
        Number(ge=0, le=1e6, unit="s/m"),
    ),
    KeySpec(
        "contact.law_length",
        "float",
        0.0,
        "m",
        "the length of cable the contact law stands for: 0 applies the law (its stiffness, Eqs. 24/29, and "
        "damping, Eq. 16) whole at every cable node, as the paper; > 0 gives each node the share l_i / "
        "law_length of it, l_i the node's tributary length, a law per unit length whose wall does not change "
        "with the mesh (the paper's wall at its 35 elements: the cable's length / 35; docs/time_domain.md, "
        "A contact law per unit length)",
        Number(ge=0, le=100.0, unit="m"),
    ),
    KeySpec(
        "contact.friction",
        "float",
        0.15,
        "1",
        "Coulomb friction coefficient between cable and casing (eta)",
        Number(ge=0, le=10.0),
        plausible=(0.0, 2.0, "dry friction coefficients of solids lie below 2"),
    ),
    KeySpec(
        "contact.stick_velocity",
        "float",
        1.0e-4,
        "m/s",
        "tangential relative speed below which a contact sticks (Section 2.1); with contact.friction_law = "
        "regularized, the slip speed over which Coulomb's force is regularised",
        Number(ge=0, le=1e3, unit="m/s"),
        note='> 0 with contact.friction_law = "regularized"',
        plausible=(0.0, 0.1, "a contact that sticks up to this speed hardly ever slips"),
    ),
    KeySpec(
        "contact.friction_law",
        "str",
        "switch",
        "",
        "friction law: switch (Section 2.1: a contact sticks while its tangential relative speed is below "
        "contact.stick_velocity and its stick force below friction x N, else slips with friction x N), or "
        "regularized: Coulomb's force continuous in the slip velocity, friction x N v / sqrt(v^2 + "
        "stick_velocity^2), solved implicitly; it has no stick-slip events and its band levels converge with "
        "the time step (docs/time_domain.md, A friction law whose limit exists)",
        Choice(*FRICTION_LAWS),
    ),
    KeySpec(
        "contact.event_substeps",
        "int",
        8,
        "1",
        "a Newmark step in which a contact switches between stick and slip, or slips so slowly that its "
        "friction could reverse the slip within the step, is recomputed in this many equal sub-steps "
        "(1: never; docs/time_domain.md, Events inside the step)",
        Number(ge=1, le=64, integer=True),
    ),
    KeySpec(
        "contact.event_tolerance",
        "float",
        0.0,
        "m",
        "a Newmark step whose estimated local error in displacement, dt^2/12 max |a(t+dt) - a(t)| over "
        "both bodies' translations (Zienkiewicz and Xie), exceeds this is recomputed in "
        "contact.event_substeps sub-steps, with either friction law (0: off; > 0 needs "
        "contact.event_substeps >= 2; docs/time_domain.md, A tolerance instead of a bare step)",
        Number(ge=0, le=1.0, unit="m"),
    ),
    KeySpec(
        "scenario.duration",
        "float",
        1.0,
        "s",
        "duration of the scenario's run",
        Number(gt=0, le=1e6, unit="s"),
        note="at least scenario.dt",
    ),
    KeySpec(
        "scenario.dt",
        "float",
        1.0e-5,
        "s",
        "time step of the Newmark integration",
        Number(ge=1e-10, le=1.0, unit="s"),
        plausible=(1e-8, 1e-3, "a step longer than 1 ms does not resolve the cable's contacts and modes"),
    ),
    KeySpec(
        "scenario.seed",
        "int",
        0,
        "1",
        "seed of the random excitations that give none of their own: the first random excitation in file order "
        "takes it, each later one a seed derived from it and the excitation's name (independent records)",
        Number(ge=0, le=MAX_SEED, integer=True),
    ),
    KeySpec(
        "scenario.ramp",
        "float",
        0.01,
        "s",
        "half-cosine fade-in of the support motion (0: none)",
        Number(ge=0, le=1e6, unit="s"),
        note="a warning above scenario.duration (with an excitation)",
    ),
    KeySpec(
        f"{_EXC}.target",
        "str",
        REQUIRED,
        "",
        "the driven support channel; axial acts along the body's tangent at that end, from A to B",
        Target(BODY_NAMES, SUPPORT_NAMES, DIRECTIONS + ("axial",)),
        note="a clamped or isolator support of a body of the model, or a clip's excitation; an isolator or clip "
        "with stiffness or damping along the driven direction",
    ),
    KeySpec(
        f"{_EXC}.kind",
        "str",
        REQUIRED,
        "",
        "the signal: band-limited random, harmonic, impulse or a CSV table",
        Choice(*EXCITATION_KINDS),
    ),
    KeySpec(
        f"{_EXC}.rms",
        "float",
        5.0,
        "m/s2",
        "RMS acceleration of the random excitation",
        Number(ge=0, le=1e6, unit="m/s2"),
        plausible=(0.0, 1e3, "a vehicle's vibration stays below 100 g"),
        kinds=("random",),
    ),
    KeySpec(
        f"{_EXC}.band",
        "band",
        [10.0, 1000.0],
        "Hz",
        "frequency band of the random excitation (flat spectrum)",
        Band(),
        note="f_high below the Nyquist frequency 1 / (2 scenario.dt)",
        kinds=("random",),
    ),
    KeySpec(
        f"{_EXC}.seed",
        "int",
        OPTIONAL,
        "1",
        "seed of the random excitation's phases; left out: scenario.seed for the model's first random excitation, "
        "for each later one a seed derived from scenario.seed and its name",
        Number(ge=0, le=MAX_SEED, integer=True),
        kinds=("random",),
        default_from="scenario.seed",
    ),
    KeySpec(
        f"{_EXC}.frequency",
        "float",
        REQUIRED,
        "Hz",
        "frequency of the harmonic excitation",
        Number(gt=0, le=1e6, unit="Hz"),
        note="below the Nyquist frequency 1 / (2 scenario.dt)",
        kinds=("harmonic",),
    ),
    KeySpec(
        f"{_EXC}.amplitude",
        "float",
        REQUIRED,
        "m",
        "displacement amplitude of the harmonic excitation, or height of the impulse's bump",
        Number(ge=-1.0, le=1.0, unit="m"),
        plausible=(0.0, 0.05, "a support that moves by more than 50 mm is not vibrating"),
        kinds=("harmonic", "impulse"),
    ),
    KeySpec(
        f"{_EXC}.phase",
        "float",
        0.0,
        "rad",
        "phase of the harmonic excitation, u = amplitude sin(2 pi f t + phase)",
        Number(unit="rad"),
        kinds=("harmonic",),
    ),
    KeySpec(
        f"{_EXC}.width",
        "float",
        1.0e-3,
        "s",
        "duration of the impulse's Hann-shaped displacement bump",
        Number(gt=0, le=1e6, unit="s"),
        note="at least 2 scenario.dt",
        kinds=("impulse",),
    ),
    KeySpec(
        f"{_EXC}.start",
        "float",
        0.0,
        "s",
        "start time of the impulse",
        Number(ge=0, le=1e6, unit="s"),
        note="a warning at or after scenario.duration",
        kinds=("impulse",),
    ),
    KeySpec(
        f"{_EXC}.file",
        "str",
        REQUIRED,
        "",
        "CSV table time_s,<value> of the quantity; a relative path is read from the model file's folder",
        Text("the path of a CSV file with a header line and columns time_s, <value>"),
        kinds=("csv",),
    ),
    # a CSV excitation as users have them: displacement, or accelerometer and velocity records
    KeySpec(
        f"{_EXC}.quantity",
        "str",
        "displacement",
        "",
        "what the CSV table's values are: displacement (m), velocity (m/s) or acceleration (m/s2); "
        "velocity and acceleration are integrated with drift removal (docs/model_file.md)",
        Choice(*CSV_QUANTITIES),
        kinds=("csv",),
    ),
]

# ------------------------------------------------------------------ the installed cable
# Loads and the cable's rest shape: gravity on both bodies (Eq. 7), the cable's static tension with
# the casing's equal compression (beam-column geometric stiffness and the prestress's own load in
# the routing), and a cable that is stress-free straight (docs/installed.md).
_KEYS += [
    KeySpec(
        "cable.rest_shape",
        "str",
        "routing",
        "",
        "stress-free shape of the cable: 'routing' (stress-free in the routing, the paper's) or 'straight' "
        "(straight off the reel and bent into the casing, so it carries the moment EI kappa of the routing)",
        Choice(*REST_SHAPES),
    ),
    KeySpec(
        "loads.gravity",
        "vector",
        [0.0, 0.0, 0.0],
        "m/s2",
        "gravitational acceleration in global axes, on both bodies (Eq. 7); zero = no gravity; "
        "FMU parameters loads.gravity.x, .y, .z",
        Vector(unit="m/s2", bound=1e4),
        components=DIRECTIONS,
    ),
    KeySpec(
        "loads.cable_tension",
        "float",
        0.0,
        "N",
        "static axial tension of the cable; the casing carries the equal compression between clamped ends, on "
        "isolators part of it (their axial springs relax it; docs/installed.md) (geometric stiffness of both "
        "bodies, and the tension's pull towards the inside of every bend)",
        Number(ge=0, le=1e7, unit="N"),
        plausible=(0.0, 1e4, "a steel wire of a few mm yields below 10 kN"),
        note="needs the cable, and below the casing's buckling load (checked when the casing is assembled)",
    ),
]

#: Every key of the model file, in the order of the validated model's tables.
SCHEMA = {spec.key: spec for spec in _KEYS}
#: The model key whose value a run setting takes the place of when it is given (not None): the
#: ``duration`` and ``dt`` (s) of ``studies.default_evaluate``, ``studies.seed_ensemble`` and
#: ``simulate``, and simulate's ``contact``. A change of that key beside the setting would do nothing
#: (``studies.evaluators.check_not_overridden`` refuses it).
SETTING_KEYS = {"duration": "scenario.duration", "dt": "scenario.dt", "contact": "contact.enabled"}


def lookup(key: str) -> KeySpec:
    """The :class:`KeySpec` of a dotted model key, e.g. ``"casing.E"``, ``"casing.supports.A"`` or
    ``"scenario.excitation.casing_random.rms"`` (a named table under any name; the spec's ``key`` is
    then the key asked for). Raises :class:`ModelError` for a key the model file does not have."""
    spec = SCHEMA.get(key)
    if spec is None and isinstance(key, str):
        parts = key.split(".")
        generic = None
        if len(parts) == 4 and parts[:2] == ["scenario", "excitation"]:
            generic = f"{_EXC}.{parts[3]}"
        elif len(parts) == 4 and parts[0] in BODY_NAMES and parts[1] == "isolator" and parts[2] in SUPPORT_NAMES:
            generic = f"{parts[0]}.isolator.<support>.{parts[3]}"
        elif len(parts) == 3 and parts[0] == "casing" and parts[1].startswith("clip["):
            generic = f"casing.clip[].{parts[2]}"
        if generic in SCHEMA:
            spec = replace(SCHEMA[generic], key=key)
        vector = None
        if spec is None and len(parts) > 1:  # a vector's component (loads.gravity.z, casing.isolator.A.stiffness.axial)
            try:
                vector = lookup(key.rsplit(".", 1)[0])
            except ModelError:
                pass
        if vector is not None and parts[-1] in vector.components:
            spec = component_spec(vector, parts[-1])
    if spec is None:
        raise ModelError(key, None, "is not a key of the model file (see docs/model_file.md)")
    return spec


def value_range(key: str) -> tuple:
    """``(min, max)``, the closed interval of the values a number key allows (an FMU parameter's
    min and max attributes): an exclusive bound is the nearest value inside it (the next double, or
    whole number); None for a side without a bound and for a key that is not a number. What the
    loader checks against other keys (``KeySpec.note``) is not in it."""
    v = lookup(key).validator
    v = getattr(v, "number", v)  # (a number or a table of them: the number's range)
    if not isinstance(v, Number):
        return None, None
    inward = (lambda b, d: b + d) if v.integer else (lambda b, d: math.nextafter(b, d * math.inf))
    lo = v.ge if v.ge is not None else None if v.gt is None else inward(v.gt, 1)
    hi = v.le if v.le is not None else None if v.lt is None else inward(v.lt, -1)
    return lo, hi


def component_spec(vector: KeySpec, component: str) -> KeySpec:
    """The scalar key ``<vector key>.<component>`` of a vector key (e.g. ``loads.gravity.z``): a
    float in the vector's unit; the FMU's parameter and ``Model.with_overrides`` use it."""
    i = vector.components.index(component)
    default = vector.default[i] if isinstance(vector.default, list) else vector.default
    axes = "global" if vector.components == DIRECTIONS else "local"
    return KeySpec(
        f"{vector.key}.{component}",
        "float",
        default,
        vector.unit,
        f"component {component} ({axes} axes) of {vector.key}: {vector.description}",
        vector.validator.component,
    )


def table(prefix: str) -> list:
    """The specs of the keys directly in the table ``prefix`` (e.g. ``"casing"``,
    ``"casing.supports"``, ``"scenario.excitation.<name>"``, ``"casing.isolator.<support>"``,
    ``"casing.clip[]"``), in schema order."""
    return [s for s in _KEYS if s.key.rsplit(".", 1)[0] == prefix]


def output_spec(name: str) -> tuple:
    """(unit, description) of a time-domain output of :data:`OUTPUTS` (or a clip's); its type is an
    integer for those of :data:`INTEGER_OUTPUTS`, else a real number."""
    if name == "contact.active":
        return "1", "number of cable nodes in contact with the casing (stick or slip)"
    if name == "contact.max_penetration":
        return "m", "largest penetration of a cable node into the casing wall (0 without contact)"
    if name == "contact.dissipated_energy":
        return "J", (
            "energy dissipated in the contacts since t = 0: the contact forces' work less the energy they store "
            "(damping and friction, and on a curved casing's mesh the normal forces' own work: docs/time_domain.md, "
            "Energy ledger)"
        )
    parts = name.split(".") if isinstance(name, str) else []
    if len(parts) == 3 and parts[0] == "casing" and parts[1][:4] == "clip" and parts[1][4:].isdigit():
        if parts[2] in FORCE_NAMES:
            kind, unit = ("force", "N") if parts[2][0] == "F" else ("moment", "N.m")
            axis = parts[2][1].lower()
            return unit, f"{kind} the casing exerts through clip {parts[1][4:]} on its support, along global {axis}"
    if name not in SUPPORT_OUTPUTS:
        raise ModelError("output", name, "must be one of " + ", ".join(OUTPUTS) + " or casing.clip<i>.Fx .. Mz")
    body, support, comp = name.split(".")
    kind, unit = ("force", "N") if comp[0] == "F" else ("moment", "N.m")
    return unit, f"{kind} the {body} exerts on its support {support}, component along global {comp[1].lower()}"


def is_output(name) -> bool:
    """Whether ``name`` is a time-domain output of some model: one of :data:`OUTPUTS` or a clip's
    ``casing.clip<i>.Fx`` .. ``Mz`` (what :func:`output_spec` describes)."""
    try:
        output_spec(name)
    except ModelError:
        return False
    return True


def input_spec(name: str) -> tuple:
    """(unit, description) of a support input of :data:`INPUTS`, e.g. ``"casing.A.az"``."""
    parts = name.split(".") if isinstance(name, str) else []
    if (
        name not in INPUTS
        and len(parts) == 2
        and parts[1] in [f"{k}{d}" for k, _, _ in INPUT_KINDS for d in DIRECTIONS]
    ):
        _, what, unit = next(q for q in INPUT_KINDS if q[0] == parts[1][:-1])
        return unit, f"{what} of the support of the clip with excitation {parts[0]} along global {parts[1][-1]}"
    if name not in INPUTS:
        raise ModelError("input", name, "must be a support input such as casing.A.z, casing.A.vz or casing.A.az")
    k = INPUTS.index(name) // len(CHANNELS)
    body, support, d = CHANNELS[INPUTS.index(name) % len(CHANNELS)].split(".")
    _, what, unit = INPUT_KINDS[k]
    return unit, f"{what} of the {body}'s support {support} along global {d}"


def markdown_table() -> str:
    """The key table of docs/model_file.md (Markdown), generated from the schema."""

    def default(spec):
        text = spec.default_text
        return text if spec.default_from is None and spec.default in (REQUIRED, OPTIONAL) else f"`{text}`"

    lines = ["| key | type | default | unit | allowed | description |", "|---|---|---|---|---|---|"]
    for spec in _KEYS:
        kinds = f" (kind {' or '.join(spec.kinds)})" if spec.kinds else ""
        allowed = spec.allowed_text.replace("|", "\\|")  # a | inside a Markdown table cell
        lines.append(
            f"| `{spec.key}` | {spec.type} | {default(spec)} | {spec.unit or '-'} | "
            f"{allowed} | {spec.description}{kinds} |"
        )
    return "\n".join(lines) + "\n"
