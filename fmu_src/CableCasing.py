"""FMI 2.0 co-simulation slave of the cable-in-casing model.

Only an adapter over ``cablecasing_core``'s time-domain ``Engine``; there is no physics here:

* the base model: the built-in specimen, or the model file the FMU was built for
  (``build_fmu.py --model FILE``: shipped as ``resources/model/<FILE>``, :func:`base_model_file`);
  the FMU's inputs and outputs are that model's (``model.schema.inputs_of``, ``outputs_of``);
* inputs: displacement (m), velocity (m/s) and acceleration (m/s2) of the base model's support
  channels (the 12 of the four supports, then ``<excitation>.x/.y/.z`` of each excited clip) at
  the start of each communication step; the core's support-motion reconstruction fills the
  motion inside the step (quintic Hermite from the supports' state to the inputs' Taylor
  extrapolation to third order, the jerk from the last two acceleration inputs);
* outputs: the engine's outputs after the step (force and moment each body exerts on each
  support, contact summary, then the force and moment through each clip of the base model);
* parameters: every numeric key of the base model under its dotted name (a vector key by its
  components, ``loads.gravity.x``, ``.y``, ``.z``), its word keys as Strings (``cable.rest_shape``,
  ``contact.law``, ... : ``Model.text_parameters``), ``contact.enabled``, ``model_file`` (a TOML
  path or a built-in specimen's name, e.g. ``installed``) and ``solver.dt``; those the master sets
  override the model (the base model or ``model_file``) through ``Model.with_overrides`` when
  initialisation ends. A ``model_file`` whose channels or outputs are not the FMU's (other excited
  clips, another number of clips) is refused at initialisation, naming them; the FMU built
  without a model file keeps its 12 channels and accepts clip models too (their excited clips at
  rest, their clip forces not outputs, with a warning).

The slave is driven by the FMU's own binary (``native/cablecasing_fmi2.c`` through
``cablecasing_fmi2_bridge.py``, Linux) with the ``fmi2_*`` methods, which return the FMI status
of the call; the inputs and outputs are two arrays that the binary reads and writes directly.
pythonfmu's binary (Windows) drives the same slave through pythonfmu's methods at the end of the
class, which map those statuses to what pythonfmu can express. Nothing here raises into a host:
every problem is logged, naming the variable and the value, at the status it deserves.

This module is over 400 lines because it is the FMU's whole adapter in one file, the one the
modelDescription is built from: variables, parameters in force, life cycle and statuses, the FMU
state and pythonfmu's methods; the bridge loads it as one file.
"""

import math
import os
import re
import threading
import warnings

import numpy as np
from pythonfmu import Boolean, DefaultExperiment, Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real, String
from pythonfmu.enums import Fmi2Status

# The kernels' numba cache (a per-user folder keyed by the kernels' sources, so it outlives the
# unpacked FMU) is installed by the bundled package itself: cablecasing_core.timedomain.kernels.
import cablecasing_core as cc
from cablecasing_core.errors import NOT_SHOWN, internal_error_text, renamed
from cablecasing_core.model import specimen_names
from cablecasing_core.model.changes import with_changes
from cablecasing_core.model.limits import check_time_domain
from cablecasing_core.model.schema import (
    BODY_NAMES,
    CHANNELS,
    DIRECTIONS,
    INTEGER_OUTPUTS,
    OUTPUTS,
    SUPPORT_NAMES,
    input_spec,
    inputs_of,
    lookup,
    output_spec,
    outputs_of,
    value_range,
)
from cablecasing_core.timedomain.engine import (
    ROUNDING_OF_TIME,
    SHORTEST_LONE_STEP,
    Engine,
    state_from_bytes,
    state_to_bytes,
    whole_steps,
)
from cablecasing_core.timedomain.scenario import scenario_motion
from cablecasing_core.timedomain.support_motion import GridMotion, SupportReconstruction

#: the folder (in resources/) of the model file an FMU was built for (build_fmu.py --model)
MODEL_FOLDER = "model"


def base_model_file(resources):
    """The model file this FMU was built for, or None (the built-in specimen): the one ``.toml``
    in ``model/`` beside this module (the bridge's lasting copy of resources/) or in
    ``resources`` (pythonfmu's binary, and build_fmu.py before the archive exists)."""
    for folder in (os.path.dirname(os.path.abspath(__file__)), resources or ""):
        folder = os.path.join(folder, MODEL_FOLDER)
        if os.path.isdir(folder):
            files = sorted(f for f in os.listdir(folder) if f.endswith(".toml"))
            if len(files) == 1:
                return os.path.join(folder, files[0])
    return None


def parameter_info(key):
    """(unit, description) of a model key such as 'casing.E' or 'scenario.excitation.x.rms' (the
    model schema); the scenario's keys describe the model file's own run, which the FMU makes only
    with scenario.drive."""
    spec = lookup(key)
    note = ""
    if key == "scenario.dt":
        note = " (the FMU's internal step when solver.dt is not set)"
    elif key == "scenario.duration":
        note = (
            " (in the FMU the master's stop time ends the run; this is how far the scenario's random "
            "record is computed ahead when the master sets no stop time, with scenario.drive = true)"
        )
    elif key.startswith("scenario."):
        note = " (used with scenario.drive = true, which drives the supports with the model's scenario)"
    return spec.unit, spec.description + note


#: The communication step (s) the modelDescription's DefaultExperiment suggests (``stepSize``), also
#: the warm-up's: ten steps of the default ``scenario.dt`` = 1e-5 s per doStep. The FMU's own choice of
#: how often a master exchanges the inputs, not a fact of the model (the model's step is
#: ``scenario.dt``, or ``solver.dt``); the DefaultExperiment's stop time is the model's
#: ``scenario.duration`` (``CableCasing.__init__``).
COMMUNICATION_STEP = 1e-4

#: FMI 2.0's Integer: a 32-bit signed int (the model schema's seeds go further)
FMI_INTEGER = (-(2**31), 2**31 - 1)


def fmi_integer(key, value):
    """``value`` of the Integer parameter ``key``, or a ModelError when FMI 2.0's Integer cannot hold
    it (a master would read another number)."""
    if not FMI_INTEGER[0] <= value <= FMI_INTEGER[1]:
        raise cc.ModelError(
            key, value, f"must be within FMI 2.0's Integer range {FMI_INTEGER[0]}..{FMI_INTEGER[1]} in an FMU"
        )
    return value


OK, WARNING, DISCARD, ERROR = (
    int(s) for s in (Fmi2Status.ok, Fmi2Status.warning, Fmi2Status.discard, Fmi2Status.error)
)
# The longest communication step one fmi2DoStep may take, in internal steps of solver.dt (10 s at
# the default 1e-5 s, some 10-20 s of wall time): a longer step is refused with fmi2Discard
# instead of running for hours (a master that asks for 1e12 s by mistake).
MAX_STEPS_PER_DOSTEP = 10**6
# The FMI 2.0 life-cycle phases, numbered as the binary's (native/cablecasing_fmi2.c, enum S_*): a
# restored FMU state puts the instance back in the phase it was saved in (FMI 2.0, 2.1.8).
INSTANTIATED, INITIALIZATION, STEPPING, TERMINATED = range(4)
# warnings.catch_warnings swaps the process's warning filters and display function and restores them
# on exit: two instances doing so at once on threads could restore each other's (the host's own
# warnings then vanish for good). Every such block of this module holds this lock (reentrant: a
# block may call another). It is kept on the warnings module, the one thing every FMU of a process
# shares: each FMU (each GUID) imports this file as a module of its own.
_WARNINGS_LOCK = warnings.__dict__.setdefault("_cablecasing_fmu_lock", threading.RLock())
SPECIAL = ("contact.enabled", "model_file", "solver.dt", "scenario.drive")


def _not_a_state(data, exc):
    """Why the bytes ``data`` are not a serialised FMU state (``exc``: what reading them raised).
    numpy's own words for bytes that are no npz archive advise loading them with allow_pickle, which
    the FMU never does: that reason is named without them."""
    why = repr(exc) if bytes(data[:2]) == b"PK" and "pickle" not in str(exc) else "not an npz archive"
    return f"{len(data)} bytes are not a serialised CableCasing FMU state: {why}"


def _phase_of(state):
    """The life-cycle phase an FMU state was saved in (``fmu.phase``, which every state of this FMU
    holds: one without it is of another version, whose support state does not fit either)."""
    if "fmu.phase" not in state:
        raise ValueError("it holds no life-cycle phase (a state of another version of this FMU)")
    phase = int(state["fmu.phase"])
    if phase not in (INSTANTIATED, INITIALIZATION, STEPPING, TERMINATED):
        raise ValueError(f"its life-cycle phase {phase} is not one of FMI's")
    return phase


#: The longest ``model_file`` path a message shows whole; a longer one (no file system takes a name of
#: 5000 characters) is shown by its start and end, so that what is allowed, after it, still fits the
#: host's buffer for a log message (fmpy's holds 2047 characters).
LONGEST_PATH_SHOWN = 600


def _path_text(path):
    """``path`` as a message shows it: repr, whole up to LONGEST_PATH_SHOWN characters."""
    if len(path) <= LONGEST_PATH_SHOWN:
        return repr(path)
    return f"{path[:400]!r}...{path[-150:]!r} ({len(path)} characters)"


class ModelFileError(cc.ModelError):
    """A ``model_file`` that gives no model: its message names model_file and the whole path (the
    core's ModelError cuts a long value short), up to LONGEST_PATH_SHOWN characters."""

    def __init__(self, path, allowed):
        super().__init__("model_file", path, allowed)
        self.args = (f"model_file = {_path_text(path)}: {allowed}",)


def _file_signature(path):
    """(modification time in ns, size in bytes) of the model file ``path``, None where it is no file
    (a built-in specimen's name, a path that cannot be read): what keys the slave's copies of a model
    file's values, so that a file rewritten under its name is read again."""
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return None
    return (st.st_mtime_ns, st.st_size)


class CableCasing(Fmi2Slave):
    """Gear-shift cable in a curved casing, driven at its four supports (see module docstring)."""

    author = "cablecasing developers"
    description = (
        "Gear-shift cable sliding in a curved casing: two spatially curved 3D Euler-Bernoulli "
        "beams with frictional penalty contact, driven by support motion (SI units)"
    )
    version = cc.__version__
    # (no class-level default_experiment: pythonfmu would prefer it to the instance's, which takes its
    # stop time from the base model, __init__)
    # The modelDescription's <LogCategories>, as the binary switches them (fmi2SetDebugLogging in
    # fmu_src/native/cablecasing_fmi2.c; docs/fmu.md, "Messages you may see"): pythonfmu's names, with
    # what each does here (its "Log all messages." for logAll is not what logAll switches)
    log_categories = {
        "logStatusWarning": "Warnings (fmi2Warning): shown whatever loggingOn; fmi2SetDebugLogging with this "
        "category switches them off and on",
        "logStatusDiscard": "Why a step or a status was discarded (fmi2Discard): shown whatever loggingOn; "
        "fmi2SetDebugLogging with this category switches them off and on",
        "logStatusError": "Errors (fmi2Error): always shown, cannot be switched off",
        "logStatusFatal": "Fatal errors (fmi2Fatal, which this FMU never returns): always shown",
        "logAll": "Informational messages (fmi2OK): shown with loggingOn = fmi2True; fmi2SetDebugLogging with "
        "this category, or with none, switches them off and on",
    }

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.base_file = base_model_file(kwargs.get("resources"))
        with _WARNINGS_LOCK, warnings.catch_warnings(record=True) as said:  # (logged when the engine is built: _build)
            warnings.simplefilter("always")
            self._base = cc.load_model(self.base_file) if self.base_file else cc.load_model()
        self._base_warnings = [str(w.message) for w in said]
        self.input_names, self.output_names = inputs_of(self._base), outputs_of(self._base)
        self._base_fingerprint = self._base.fingerprint()  # (a state names the model its FMU was built for)
        # the modelDescription's DefaultExperiment: 0 s to the base model's own scenario.duration (s),
        # in communication steps of COMMUNICATION_STEP
        self.default_experiment = DefaultExperiment(
            start_time=0.0, stop_time=float(self._base.scenario["duration"]), step_size=COMMUNICATION_STEP
        )
        self.nch = len(self.input_names) // 3  # support channels: 12, and 3 per excited clip
        self.units = {}  # variable name -> unit (read by build_fmu.py)
        self.ranges = {}  # parameter name -> (min, max), None for a side without a bound (build_fmu.py)
        self._start = dict(self._base.parameters())
        self._text_keys = tuple(self._base.text_parameters())  # the String parameters besides model_file
        self._start.update(self._base.text_parameters())
        self._start["contact.enabled"] = bool(self._base.contact["enabled"])
        self._start["model_file"] = ""
        self._start["solver.dt"] = float(self._base.scenario["dt"])
        self._start["scenario.drive"] = False
        # The parameters whose value the base model takes from another parameter, {key: source}: a
        # random excitation's seed that the model leaves to scenario.seed (Model.derived) and
        # solver.dt (the model's scenario.dt). Written with exactly its start value (what its
        # source's start derives) such a parameter is not an override: it follows its source, so a
        # master that writes every start value and changes the source gets the run of that change
        # alone, as the command line's --set (docs/fmu.md, "Parameters in force").
        self._derived = {k: lookup(k).default_from for k in sorted(self._base.derived) if k in self._start}
        self._derived["solver.dt"] = "scenario.dt"
        self._derived_cache = {}  # (model file, key, source value) -> the derived value in force
        self._log_sink = None
        self._tolerance_said = False  # fmi2SetupExperiment's tolerance is said unused once per instance
        self._end_offset_said = False  # the bodies' end supports set apart across the gap: warned once per instance
        # the two arrays the FMU's binary reads and writes directly
        self.inputs_buffer = np.zeros(3 * self.nch)  # u (m), v (m/s), a (m/s2) of the channels
        self._finite_inputs = np.zeros(3 * self.nch, dtype=bool)
        self.outputs_buffer = np.zeros(len(self.output_names))  # the outputs after the last step
        n = self.nch
        self._u, self._v, self._a = (self.inputs_buffer[k * n : (k + 1) * n] for k in range(3))  # views
        self._set = {}  # parameters the master set: key -> value
        self._file_cache = (None, None, None)  # ((path, _file_signature), its values or None, its Model or None)
        self._set_plans, self._get_plans = {}, {}  # pythonfmu's path: references -> index arrays
        self._input_vr, self._output_vr, self._param = {}, {}, {}  # value reference -> index, (key, type)
        self._register_variables()
        self._recon = SupportReconstruction(self.nch)
        # doStep calls that only moved the clock (a step within its rounding: no step taken), for the binary's
        # timing report, which counts the steps taken; never reset (the binary counts its changes)
        self.clock_only_calls = 0
        self._clear()

    def _clear(self):
        """The state of a newly instantiated slave (also after fmi2Reset)."""
        self._set = {}  # parameters the master set: key -> value
        self.inputs_buffer[:] = 0.0
        self.outputs_buffer[:] = 0.0
        self._engine = None
        self._drive = None  # the scenario's motion when scenario.drive is on
        self._applied = None  # the configuration the engine was built with
        self._recon.reset()
        self._start_time = 0.0
        self._stop_time = None  # (s) the master's stopTime, when it gives one
        self._initialized = False
        self.phase = INSTANTIATED  # the FMI life-cycle phase (a restored state brings its own)
        self._error = None  # why stepping is refused (an initialisation that failed)
        self._discarded = None  # (t, h, inputs) of the step last discarded, until a step is taken
        self._wants_to_end = False  # fmi2Terminated: that step was asked for again, and discarded again
        self._start_said = False  # whether the first step's position inputs were checked (_say_start_offset)

    # ------------------------------------------------------------------ variables
    def _register_variables(self):
        # inputs first, then outputs, each with consecutive value references (the binary reads and
        # writes the two buffers by value reference minus input_vr0 / output_vr0)
        for i, name in enumerate(self.input_names):
            unit, text = input_spec(name)
            var = self._add(
                Real(
                    name,
                    causality=Fmi2Causality.input,
                    variability=Fmi2Variability.continuous,
                    start=0.0,
                    description=text,
                    getter=lambda i=i: float(self.inputs_buffer[i]),
                    setter=lambda v, i=i: self.inputs_buffer.__setitem__(i, v),
                ),
                unit,
            )
            self._input_vr[var.value_reference] = i
        self.input_vr0 = min(self._input_vr)
        for i, name in enumerate(self.output_names):
            unit, text = output_spec(name)
            if name in INTEGER_OUTPUTS:
                var = Integer(
                    name,
                    causality=Fmi2Causality.output,
                    variability=Fmi2Variability.discrete,
                    description=text,
                    getter=lambda i=i: int(self.outputs_buffer[i]),
                )
            else:
                var = Real(
                    name,
                    causality=Fmi2Causality.output,
                    variability=Fmi2Variability.continuous,
                    description=text,
                    getter=lambda i=i: float(self.outputs_buffer[i]),
                )
            self._add(var, unit)
            self._output_vr[var.value_reference] = i
        self.output_vr0 = min(self._output_vr)
        self.integer_output_vrs = [vr for vr, i in self._output_vr.items() if self.output_names[i] in INTEGER_OUTPUTS]
        for key in self._text_keys:
            self._add_parameter(
                String(
                    key, causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed,
                    description=f"{parameter_info(key)[1]} ({lookup(key).allowed})",
                ),
                "",
            )  # fmt: skip
        for key, value in self._start.items():
            if key in SPECIAL or key in self._text_keys:
                continue
            unit, text = parameter_info(key)
            kind = Integer if isinstance(value, int) else Real
            if kind is Integer:
                fmi_integer(key, value)
            self._add_parameter(
                kind(key, causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed, description=text),
                unit if kind is Real else "",
            )
        self._add_parameter(
            Boolean(
                "contact.enabled",
                causality=Fmi2Causality.parameter,
                variability=Fmi2Variability.fixed,
                description=parameter_info("contact.enabled")[1],
            ),
            "",
        )
        self._add_parameter(
            String(
                "model_file",
                causality=Fmi2Causality.parameter,
                variability=Fmi2Variability.fixed,
                description="path of a model TOML file (a relative path is taken from the "
                "host's working folder when it is set), or the name of a built-in specimen ("
                + ", ".join(f"'{n}'" for n in specimen_names())
                + "); empty = "
                + (
                    f"the model file this FMU was built for, {os.path.basename(self.base_file)} (another file "
                    "must have the same excited clips and number of clips)"
                    if self.base_file
                    else "the built-in specimen"
                ),
            ),
            "",
        )
        step = lookup("scenario.dt")  # (solver.dt is the model's step as the FMU's parameter)
        self._add_parameter(
            Real(
                "solver.dt",
                causality=Fmi2Causality.parameter,
                variability=Fmi2Variability.fixed,
                description=f"{step.description} inside the FMU (unset: the model's scenario.dt); a communication "
                "step is split into steps of this size and one shorter last step",
            ),
            step.unit,
        )
        self._add_parameter(
            Boolean(
                "scenario.drive",
                causality=Fmi2Causality.parameter,
                variability=Fmi2Variability.fixed,
                description="the supports also follow the model's own [scenario] excitations (added to the "
                "inputs, evaluated at the steps of solver.dt; with zero inputs the FMU then runs the core's "
                "scenario run); false: the inputs alone move the supports",
            ),
            "",
        )

    def _add(self, var, unit):
        self.register_variable(var, nested=False)
        self.units[var.name] = unit
        return var

    def _add_parameter(self, var, unit):
        key = var.name
        var.getter = lambda: self._value(key)
        var.setter = lambda v: self._set_parameter(key, type(var).__name__, v)
        self._add(var, unit)
        self._param[var.value_reference] = (key, type(var).__name__)
        if isinstance(var, (Real, Integer)):  # the schema's allowed values (solver.dt: scenario.dt's)
            lo, hi = value_range("scenario.dt" if key == "solver.dt" else key)
            if isinstance(var, Integer):  # (and what FMI 2.0's Integer holds)
                lo, hi = max(lo, FMI_INTEGER[0]) if lo is not None else FMI_INTEGER[0], min(hi, FMI_INTEGER[1])
            self.ranges[key] = (lo, hi)

    def _value(self, key):
        """The value in force: the master's, else the model file's (when one is set), else the
        base model's (the built-in specimen, or the model file the FMU was built for); for
        ``solver.dt`` unset, the model's ``scenario.dt``, the master's if it set that; for a seed
        the model derives from ``scenario.seed``, unset, the seed derived from the master's
        ``scenario.seed`` if it set that."""
        if key in self._set:
            return self._set[key]
        if key == "solver.dt" and "scenario.dt" in self._set:  # (the model's step, as the master set it)
            return self._set["scenario.dt"]
        if key == "model_file":
            return ""
        if key in self._derived and self._derived[key] in self._set:
            value = self._derived_value(key)
            if value is not None:
                return value
        path = self._set.get("model_file")
        if path:
            values = self._file_values(path)
            if values is not None and key in values:
                return values[key]
        return self._start[key]

    def _derived_value(self, key):
        """The value of the derived parameter ``key`` (a random excitation's seed) that the model in
        force (``model_file``'s, else the base model) derives from the master's value of its source
        (``scenario.seed``), as ``Model.with_overrides`` derives it; None when that model gives the
        key itself (its value is then the model's) or the source's value makes no model (refused
        when initialisation ends)."""
        source = self._derived[key]
        path = self._set.get("model_file")
        model = self._file_model(path) if path else self._base
        cache = (self._file_cache[0] if path else None, key, self._set[source])  # (the file's (path, signature))
        if cache not in self._derived_cache:
            value = None
            if model is not None and key in model.derived:
                try:
                    with _WARNINGS_LOCK, warnings.catch_warnings():  # (the model's warnings are logged when built)
                        warnings.simplefilter("ignore")
                        value = model.with_overrides({source: self._set[source]}).parameters().get(key)
                except cc.CableCasingError:
                    value = None
            if len(self._derived_cache) > 64:
                self._derived_cache.clear()
            self._derived_cache[cache] = value
        return self._derived_cache[cache]

    def _file_model(self, path):
        """The Model of a model file (None if it cannot be read), read once per path and content."""
        self._file_values(path)
        return self._file_cache[2]

    def _follows(self, key, value):
        """Whether ``value`` of the parameter ``key`` leaves it to follow its source: a derived
        parameter (``self._derived``) written with exactly its start value, of its type."""
        start = self._start.get(key)
        return key in self._derived and type(value) is type(start) and value == start

    def _file_values(self, path):
        """The parameter values of a model file (None if it cannot be read: the error is reported
        when initialisation ends), read once per path and content: a file rewritten under the same
        name (a study that writes its next model file between runs, fmi2Reset) is read again, as the
        engine reads it (review BA2)."""
        read = (path, _file_signature(path))
        if self._file_cache[0] != read:
            model = None
            try:
                with _WARNINGS_LOCK, warnings.catch_warnings():  # (the model's warnings are logged when built: _build)
                    warnings.simplefilter("ignore")
                    model = cc.load_model(path)
                values = dict(model.parameters())
                values.update(model.text_parameters())
                values["contact.enabled"] = bool(model.contact["enabled"])
                values["solver.dt"] = float(model.scenario["dt"])
            except Exception:  # noqa: BLE001  (any failure, named with the path when initialisation ends: _load_file)
                values, model = None, None
            self._file_cache = (read, values, model)
        return self._file_cache[1]

    def _set_parameter(self, key, kind, value):
        """Store a parameter the master set; returns the status (an int)."""
        if kind == "String":
            path = key == "model_file"
            if value is None:
                self.log(
                    f"{key} = NULL: a string parameter needs a value ("
                    + ("an empty string selects the built-in specimen)" if path else f"{lookup(key).allowed})"),
                    Fmi2Status.error,
                )
                return ERROR
            if isinstance(value, bytes):
                self.log(
                    f"{key} = {value[:200]!r}: not valid UTF-8; FMI strings are UTF-8 ("
                    + ("give the path in UTF-8)" if path else f"{lookup(key).allowed})"),
                    Fmi2Status.error,
                )
                return ERROR
            if key != "model_file":  # a word key of the model: checked by the schema
                try:
                    value = lookup(key).check(value, key)
                except cc.ModelError as exc:
                    self.log(f"parameter {exc}", Fmi2Status.error)
                    return ERROR
            else:  # a path (from the host's working folder), or the name of a built-in specimen
                value = os.path.abspath(value) if value and value not in specimen_names() else value
        elif kind == "Boolean" and value not in (0, 1):  # (False == 0, True == 1)
            self.log(
                f"parameter {key} = {value!r} refused: an fmi2Boolean must be fmi2True (1) or fmi2False (0)",
                Fmi2Status.error,
            )
            return ERROR
        else:
            value = {"Real": float, "Integer": int, "Boolean": bool}[kind](value)
        follows = self._follows(key, value)  # (its start value: it follows its source, no override)
        if self._initialized:
            if (follows and key not in self._set) or (not follows and value == self._value(key)):
                return OK
            self.log(
                f"parameter {key} = {value!r} refused: parameters are fixed after initialisation (it is "
                f"{self._value(key)!r}; reset the FMU to change it)",
                Fmi2Status.error,
            )
            return ERROR
        if follows:
            self._set.pop(key, None)
            return OK
        self._set[key] = value
        if key == "model_file" and value:
            self.log(f"model_file: {value}", Fmi2Status.ok)
        return OK

    def _refuse(self, what, vr, value=None):
        var = self.vars.get(vr)
        which = f"{var.name} ({type(var).__name__}, {var.causality.name})" if var is not None else "no variable"
        self.log(
            f"cannot {what} through value reference {vr}: {which}"
            + ("" if value is None else f"; value {value!r} ignored"),
            Fmi2Status.error,
        )
        return ERROR

    def fmi2_get(self, kind, vrs, out):
        """fmi2Get<kind> of any variables into ``out`` (a sequence as long as ``vrs``); status."""
        status = OK
        if self.phase == INITIALIZATION and any(vr in self._output_vr for vr in vrs):
            status = self._initial_outputs()
            if status > WARNING:
                return status
        for k, vr in enumerate(vrs):
            i = self._output_vr.get(vr)
            integer = self.output_names[i] in INTEGER_OUTPUTS if i is not None else False
            if i is not None and integer == (kind == "Integer") and kind in ("Real", "Integer"):
                out[k] = self.outputs_buffer[i] if kind == "Real" else int(self.outputs_buffer[i])
                continue
            i = self._input_vr.get(vr)
            if i is not None and kind == "Real":
                out[k] = self.inputs_buffer[i]
                continue
            key_kind = self._param.get(vr)
            if key_kind is not None and key_kind[1] == kind:
                out[k] = self._value(key_kind[0])
                continue
            status = max(status, self._refuse(f"get {'an' if kind == 'Integer' else 'a'} {kind}", vr))
        return status

    def fmi2_set(self, kind, vrs, values):
        """fmi2Set<kind> of any variables; status."""
        status = OK
        for vr, value in zip(vrs, values):
            i = self._input_vr.get(vr)
            if i is not None and kind == "Real":
                self.inputs_buffer[i] = value
                continue
            key_kind = self._param.get(vr)
            if key_kind is not None and key_kind[1] == kind:
                status = max(status, self._set_parameter(key_kind[0], kind, value))
                continue
            status = max(status, self._refuse(f"set {'an' if kind == 'Integer' else 'a'} {kind}", vr, value))
        return status

    # ------------------------------------------------------------------ logging
    def attach_log_sink(self, sink):
        """Send every message at once to ``sink(status: int, message: str)`` (the FMU's binary)
        instead of pythonfmu's queue."""
        self._log_sink = sink

    def log(self, msg, status=Fmi2Status.ok, category=None, debug=None):
        if self._log_sink is not None:
            self._log_sink(int(status), msg)
        else:
            super().log(msg, status, category)

    # ------------------------------------------------------------------ life cycle
    def fmi2_setup_experiment(self, start_time, stop_time=None, tolerance=None):
        """fmi2SetupExperiment: ``stop_time`` and ``tolerance`` None when not defined. The tolerance is
        checked, and said once (logging on) not to be used: the FMU steps with the fixed solver.dt."""
        if not math.isfinite(start_time):
            self.log(
                f"fmi2SetupExperiment: startTime = {start_time!r}: must be a finite number of seconds", Fmi2Status.error
            )
            return ERROR
        if stop_time is not None and not (math.isfinite(stop_time) and stop_time >= start_time):
            self.log(
                f"fmi2SetupExperiment: stopTime = {stop_time!r}: must be a finite number of seconds not "
                f"before startTime = {start_time!r}",
                Fmi2Status.error,
            )
            return ERROR
        if tolerance is not None and not (math.isfinite(tolerance) and tolerance > 0):
            self.log(
                f"fmi2SetupExperiment: tolerance = {tolerance!r} (toleranceDefined): must be a finite number > 0, "
                "or not defined (the FMU does not use it)",
                Fmi2Status.error,
            )
            return ERROR
        if tolerance is not None and not self._tolerance_said:
            self._tolerance_said = True
            self.log(
                f"fmi2SetupExperiment: tolerance = {tolerance!r} is not used: the FMU steps with the fixed "
                "internal step solver.dt (s), the parameter that sets its accuracy; the contact's tolerance on a "
                "step's local error is the parameter contact.event_tolerance (m)"
            )
        self._start_time = float(start_time)
        self._stop_time = None if stop_time is None else float(stop_time)
        return OK

    def fmi2_enter_initialization_mode(self):
        self.phase = INITIALIZATION
        return OK

    def _initial_outputs(self):
        """The outputs read in Initialization Mode are initial unknowns (FMI 2.0, 2.2.8 and 4.2.4):
        those of the parameters set so far, so the engine is built for them (again when one has
        changed since; fmi2ExitInitializationMode builds it afresh in any case). OK, or ERROR when
        the parameters make no model (logged, as at fmi2ExitInitializationMode)."""
        if self._engine is not None and self._applied == self._config():
            return OK
        return OK if self._build() else ERROR

    def fmi2_exit_initialization_mode(self):
        self._initialized = True
        self.phase = STEPPING
        if self._engine is not None and self._applied == self._config():
            # built for these parameters when the master read outputs in Initialization Mode
            # (:meth:`_initial_outputs`): not built again, so the model's warnings are logged once
            return OK
        return OK if self._build() else ERROR

    def _config(self):
        """The configuration that decides the engine: the model file, the overrides (the
        parameters the master set), the internal step and scenario.drive (which decides whether
        the model's excitations must fit its supports: :meth:`_undriven`)."""
        over = {k: v for k, v in self._set.items() if k not in ("model_file", "solver.dt", "scenario.drive")}
        return self._set.get("model_file", ""), over, self._value("solver.dt"), bool(self._value("scenario.drive"))

    def _drive_motion(self, engine):
        """The model's scenario motion on the engine's grid when ``scenario.drive`` is on, else None."""
        if not self._value("scenario.drive"):
            return None
        model = engine.model
        with renamed({"dt": "solver.dt"}):  # (a random band above the Nyquist frequency of the FMU's step)
            return GridMotion(scenario_motion(model, dt=engine.dt), engine.dt)

    def _make_engine(self, config):
        """A new Engine for ``config``; raises ModelError naming the parameter."""
        model_file, over, dt, drive = config
        model = self._load_file(model_file) if model_file else self._base
        model, over = self._undriven(model, over, drive, model_file)
        if over:
            try:
                model = model.with_overrides(over)
            except cc.ModelError as exc:
                raise self._attributed(model, over, exc) from None
        values = model.parameters()
        for key, start in self._start.items():  # (a model file's seeds, read back through fmi2GetInteger)
            if isinstance(start, int) and not isinstance(start, bool) and key in values:
                fmi_integer(key, values[key])
        dt = lookup("scenario.dt").check(dt, "solver.dt")  # (the modelDescription's range of solver.dt, by name)
        self._check_memory(model, dt)
        with renamed({"dt": "solver.dt"}):  # (the engine's range of dt, named as the FMU's parameter)
            return Engine(model, dt=dt, ledger=False)

    @staticmethod
    def _load_file(path):
        """The model of ``model_file`` = ``path``; any failure (a file that is no model, a path
        the file system cannot take) is a ModelError that names model_file and the whole path."""
        try:
            return cc.load_model(path)
        except cc.ModelError as exc:
            if exc.key == "model_file":
                raise ModelFileError(path, str(exc.allowed)) from None
            if str(exc.allowed).startswith("is required") and "." not in str(exc.key):
                raise ModelFileError(path, f"its [{exc.key}] table is required; the file has none") from None
            raise ModelFileError(path, f"the file's model is invalid: {exc}") from None
        except Exception as exc:  # noqa: BLE001  (an OSError, UnicodeError, ...: no internal error)
            raise ModelFileError(path, f"cannot be read: {type(exc).__name__}: {' '.join(str(exc).split())}") from None

    @staticmethod
    def _check_memory(model, dt):
        """The core's check that the engine's matrices fit the memory available (model/limits.py,
        as ``simulate`` and the command line do; the FMU keeps no record, so only the matrices
        count): a model too large is a ModelError naming geometry.n_elements, before any is built."""
        try:
            check_time_domain(model, 0.0, dt)
        except cc.ModelError as exc:
            raise cc.ModelError(
                "geometry.n_elements",
                model.geometry["n_elements"],
                f"is too many for this machine: {exc.allowed}",
            ) from None

    def _undriven(self, model, over, drive, model_file):
        """(model, overrides) without what the run does not use. Without scenario.drive the
        scenario does not run, so the excitations of the bodies' supports (and the master's values
        of their keys, each checked against the schema alone, and of keys of excitations the model
        does not have) are left out of the model: the Engine does not use them, and the core's
        validation would otherwise hold them against the rest (a random band above the Nyquist
        frequency of a ``scenario.dt`` the master set; a support set ``free`` that an excitation's
        ``target``, no FMU variable, drives; a master writing every start value for a model_file
        without the built-in specimen's excitations). An excited clip's excitation stays: its
        support is an input of the FMU. With scenario.drive a support set ``free`` that an
        excitation of the model's [scenario] drives (the built-in specimen's drive casing.A.z and
        cable.A.axial) cannot be driven: a ModelError names the support's variable and the
        scenario's excitation that drives it."""
        excitations = model.scenario.get("excitation", {})
        unused = []
        for name, e in excitations.items():
            parts = str(e.get("target", "")).split(".")
            if len(parts) != 3 or parts[0] not in model.data:  # (a clip's excitation: no support of a body)
                continue
            if not drive:
                unused.append(name)
                continue
            key = f"{parts[0]}.supports.{parts[1]}"
            if over.get(key, model.data[parts[0]]["supports"][parts[1]]) == "free":
                raise cc.ModelError(
                    key,
                    "free",
                    f"is not allowed with scenario.drive = true: {self._whose(model_file)} drives support "
                    f"{parts[0]}.{parts[1]} (its excitation {name} targets '{e['target']}'), and only a clamped or "
                    "isolator support can be driven; set scenario.drive = false (the inputs alone then move the "
                    "supports), or give a model_file whose [scenario] drives no free support",
                )
        if drive:
            return model, over
        kept = tuple(f"scenario.excitation.{name}." for name in excitations if name not in unused)
        left_out = {k for k in over if k.startswith("scenario.excitation.") and not k.startswith(kept)}
        for k in left_out:
            lookup(k).check(over[k], k)  # (a value no model could take is still refused)
        if unused:
            model = model.without_excitations(unused)
        return model, {k: v for k, v in over.items() if k not in left_out}

    def _attributed(self, model, over, exc):
        """The error ``exc`` of ``model.with_overrides(over)`` named as the core names a refused
        change (``model.changes.with_changes``, the command line's rule too): the parameter the
        master set, and the model's key it conflicts with when the refused key is not one the master
        set (``casing.d_outer = 0.0035: conflicts with casing.d_inner = 0.004 of the model ...``;
        ``scenario.dt = 0.001: conflicts with scenario.excitation.casing_random.band = ...``: a key
        that is no parameter is never called the invalid one). An isolator support without its
        table stays as it is (:meth:`_fmu_message` words it)."""
        if self._isolator_without_table(exc):
            return exc
        try:
            with_changes(model, {key: ("", value) for key, value in over.items()})
        except cc.ModelError as named:
            return named
        return exc  # (not reached: the same overrides fail the same way)

    def _isolator_without_table(self, exc):
        """(body, support) when ``exc`` says the isolator table of a support the master set
        ``isolator`` is missing (no FMU parameter gives it), else None."""
        m = re.fullmatch(r"(casing|cable)\.isolator\.([AB])", str(exc.key))
        if m and "required" in str(exc.allowed) and self._set.get(f"{m[1]}.supports.{m[2]}") == "isolator":
            return m.groups()
        return None

    def _whose(self, model_file):
        """Whose [scenario] the model runs, in words: "the built-in specimen's scenario", ..."""
        if model_file in specimen_names():
            return f"the scenario of the built-in specimen '{model_file}'"
        if model_file:
            return f"the scenario of model_file {os.path.basename(model_file)}"
        if self.base_file is None:
            return "the built-in specimen's scenario"
        return f"the scenario of {os.path.basename(self.base_file)} (the model file this FMU was built for)"

    def _fmu_message(self, exc):
        """The core's ModelError as a C host's user can act on it (who sees only the
        modelDescription's variables): an isolator support's stiffness table, which is no FMU
        parameter, and the range of an Integer the master set as the modelDescription declares it (a
        model file's value keeps the core's range, or fmi_integer's message)."""
        isolator = self._isolator_without_table(exc)
        if isolator:  # (the whole table is missing, not one of its keys, for a support the master set isolator)
            body, s = isolator
            return (
                f"{body}.supports.{s} = 'isolator': an isolator support needs the isolator's table "
                f"[{body}.isolator.{s}] (its stiffness), which is not a parameter of this FMU: it comes from a model "
                f"file; set model_file to a model TOML file with a [{body}.isolator.{s}] table (docs/model_file.md, "
                f"Isolators and clips), or set {body}.supports.{s} to 'clamped' or 'free'"
            )
        if (exc.key, "Integer") in self._param.values() and exc.key in self._set:  # (the master's value)
            lo, hi = self.ranges[exc.key]
            if value_range(exc.key) != (lo, hi) and isinstance(exc.value, int) and not lo <= exc.value <= hi:
                return f"{exc.key} = {exc.value}: must be a whole number in [{lo}, {hi}] (the modelDescription's range)"
        return str(exc)

    def _build(self):
        """Build the engine from the parameters; on a problem log it (fmi2Error) and refuse steps."""
        config = self._config()
        try:
            with _WARNINGS_LOCK, warnings.catch_warnings(record=True) as said:
                warnings.simplefilter("always")
                self._engine = self._make_engine(config)
                drive = self._drive_motion(self._engine)
        except cc.ModelError as exc:
            self._engine = None
            several = exc.value is NOT_SHOWN and "=" in str(exc.key)  # (changes that conflict only together)
            return self._block(f"invalid parameter{'s' if several else ''} {self._fmu_message(exc)}")
        except cc.CableCasingError as exc:  # (the model's own failure, a static state that does not converge)
            self._engine = None
            return self._block(f"the model cannot be built: {' '.join(str(exc).split())}{self._set_text()}")
        except Exception as exc:  # noqa: BLE001  (never raise into the host)
            self._engine = None
            return self._block(f"the model cannot be built: {internal_error_text(exc, note=self._set_text())}")
        finally:
            self._log_warnings(said)
        problem = self._variables_problem(self._engine)
        if problem:
            self._engine = None
            return self._block(problem)
        self._applied = config
        self._drive = drive
        self._error = None
        self._start_said = False
        self._warm_up()
        self._recon.reset()
        self._engine.output_values(self.outputs_buffer)
        self._prepare_drive(say=True)
        return True

    def _set_text(self):
        """The parameters the master set, for a message of a model that cannot be built without one
        key to blame (``; parameters set: casing.I = 5e-324, loads.gravity.y = 10000.0``), else ''."""
        if not self._set:
            return ""
        shown = [f"{k} = {v!r}" for k, v in self._set.items()]
        if len(shown) > 12:
            shown = shown[:12] + [f"and {len(shown) - 12} more"]
        return "; parameters set: " + ", ".join(shown)

    def _prepare_drive(self, say=False):
        """With scenario.drive, the costly part of the scenario's motion now, not inside the steps
        (GridMotion.prepare): up to the master's stopTime, else over the scenario's own duration
        (fmusim, for one, gives no stopTime); ``say``: log how far."""
        if self._drive is None:
            return
        if self._stop_time is not None:
            until, why = self._stop_time - self._start_time, f"stopTime = {self._stop_time:.6g} s"
        else:
            until = self._engine.model.scenario["duration"]
            why = f"no stopTime: scenario.duration = {until:.6g} s"
        try:
            ahead = self._drive.prepare(until)
        except MemoryError:  # (the steps then compute the blocks as they go)
            ahead = 0.0
        if say and math.isfinite(ahead):  # (inf: the scenario has no random record)
            self.log(
                f"scenario.drive: the random excitation is computed ahead up to t = "
                f"{self._start_time + ahead:.6g} s ({why}), later within the steps"
            )

    # The communication step of the warm-up (s): the default experiment's; another h later costs
    # only its quintic matrix (the kernels are the same).
    WARM_UP_STEP = COMMUNICATION_STEP

    def _warm_up(self):
        """Load the step kernels now, in initialisation, not in the first two doSteps: the first
        takes the general path (the step loop, ~0.15 s to load) and the second the one-call step
        (~0.1 s), which a real-time master would see as two missed deadlines and which added ~25 us
        to every call of a 1 s run's average. Two throwaway steps from rest on the FMU's own buffers
        (zero inputs, the scenario's drive if on), then the engine back to its start (``reset``:
        t = 0, the state it was built with) and the reconstruction to rest; an error here is left
        for the first doStep to report."""
        eng, saved = self._engine, self.inputs_buffer.copy()
        h = max(self.WARM_UP_STEP, eng.dt)
        try:
            self.inputs_buffer[:] = 0.0
            for _ in range(2):
                eng.advance_reconstructed(h, self._recon, self._u, self._v, self._a, self.outputs_buffer, self._drive)
        except Exception:  # noqa: BLE001, S110  (the first doStep meets it again and reports it)
            pass
        finally:
            self.inputs_buffer[:] = saved
            eng.reset()
            self._recon.reset()

    def _log_warnings(self, said):
        """Python warnings of building the model (a ModelWarning: an absurd but valid value, the
        route's plausibility) as log messages with fmi2Warning, each once, the base model's with the
        first build: never as text on the host's stderr."""
        texts, self._base_warnings = self._base_warnings + [str(w.message) for w in said], []
        for text in dict.fromkeys(texts):
            self.log(text, Fmi2Status.warning)

    def _variables_problem(self, engine):
        """Why the engine's model does not fit this FMU's variables (None if it does). An FMU built
        for a model file has that model's channels and outputs, and refuses a ``model_file`` with
        others; the FMU of the built-in specimen accepts clip models too: their
        excited clips' supports stay at rest (or follow scenario.drive), their forces are no
        outputs, and it warns."""
        channels, outputs = engine.channels, engine.output_names
        if self.base_file is None:
            extra = channels[len(CHANNELS) :]
            clips = (len(outputs) - len(OUTPUTS)) // 6
            if extra:
                self.log(
                    f"the model's excited clips have the channels {', '.join(extra)}, which are not inputs of "
                    "this FMU (its inputs are the 12 support channels): they follow the model's own scenario "
                    "with scenario.drive, else stay at rest; the clips' forces are not outputs (build an FMU "
                    "for the model file, build_fmu.py --model, to have them: docs/fmu.md)",
                    Fmi2Status.warning,
                )
            elif clips:
                self.log(
                    f"the model's {clips} clips hold the casing as in the core, but their forces are not outputs "
                    "of this FMU (its outputs are the built-in specimen's); build an FMU for the model file, "
                    "build_fmu.py --model, to have them (docs/fmu.md)",
                    Fmi2Status.warning,
                )
            return None
        built = self.input_names[: self.nch]
        if channels == built and outputs == self.output_names:
            return None
        name = os.path.basename(self.base_file)

        def clips(chs):
            extra = chs[len(CHANNELS) :]
            return f"the excited clips' channels {', '.join(extra)}" if extra else "no excited clip"

        if channels != built:
            return (
                f"model_file {self._set.get('model_file')!r} has {clips(channels)}, but this FMU was built for "
                f"{name}, which has {clips(built)}: its inputs cannot drive that model; use a model file with the "
                "same excited clips, or build an FMU for it (build_fmu.py --model)"
            )
        return (
            f"model_file {self._set.get('model_file')!r} has {(len(outputs) - len(OUTPUTS)) // 6} clips, but this "
            f"FMU was built for {name} with {(len(self.output_names) - len(OUTPUTS)) // 6}: its outputs "
            "cannot hold that model's clip forces; use a model file with the same clips, or build an FMU for "
            "it (build_fmu.py --model)"
        )

    def _block(self, msg):
        self._error = msg
        self.log(msg, Fmi2Status.error)
        return False

    def fmi2_terminate(self):
        self.phase = TERMINATED
        eng = self._engine
        if eng is not None and eng.contact and eng.time > 0:
            steps = round(eng.time / eng.dt)
            if eng.vreg > 0.0:
                msg = (
                    f"contact events: none, {steps} steps of solver.dt = {eng.dt!r} s with friction regularised over "
                    f"contact.stick_velocity = {eng.vreg!r} m/s (contact.friction_law; docs/time_domain.md, "
                    "A friction law whose limit exists)"
                )
            else:
                msg = (
                    f"contact events: {eng.event_steps} of {steps} steps of solver.dt = {eng.dt!r} s recomputed in "
                    f"{eng.event_substeps} sub-steps (contact.event_substeps; "
                    "docs/time_domain.md, Events inside the step)"
                )
            if eng.event_tolerance > 0.0:
                msg += (
                    f"; {eng.tolerance_steps} steps recomputed in {eng.event_substeps} sub-steps for their estimated "
                    f"local error (contact.event_tolerance = {eng.event_tolerance!r} m); the largest estimated local "
                    f"displacement error of a step or sub-step kept: {eng.max_local_error:.3g} m"
                )
            self.log(msg, Fmi2Status.ok)
            for said in eng.solver_warnings():  # (the run itself is whole: fmi2Terminate still returns fmi2OK)
                self.log(said, Fmi2Status.warning)
        return OK

    def fmi2_reset(self):
        self._clear()
        return OK

    def fmi2_free_instance(self):
        """fmi2FreeInstance: drop what the instance holds (the engine, the scenario's motion, the
        log sink) and the variables' getters and setters, closures that refer back to the slave: the
        slave and its engine are then freed at once by reference counting, not when Python's cyclic
        garbage collector next runs (a C host that makes an instance per run grew by ~1.75 MB per
        instance, 60 MB at 140 elements)."""
        self._engine = self._drive = self._applied = None
        self._log_sink = None
        for var in self.vars.values():
            var.getter = var.setter = None
        self.vars.clear()
        self._param.clear()
        self._set_plans.clear()
        self._get_plans.clear()
        return OK

    def last_successful_time(self):
        return self._start_time + (self._engine.time if self._engine is not None else 0.0)

    def fmi2_do_step(self, current_time, step_size):
        eng = self._engine
        if eng is None:
            self.log(
                f"doStep refused: the FMU did not initialise ({self._error}); fix the parameter and reset the FMU",
                Fmi2Status.error,
            )
            return ERROR
        if not (math.isfinite(current_time) and math.isfinite(step_size) and step_size > 0):
            self.log(
                f"doStep(currentCommunicationPoint = {current_time!r} s, communicationStepSize = "
                f"{step_size!r} s): both must be finite numbers, the step positive",
                Fmi2Status.error,
            )
            return ERROR
        end = current_time + step_size
        if self._stop_time is not None and end - self._stop_time > self._clock_rounding(self._stop_time, step_size):
            self.log(
                f"doStep from t = {current_time!r} s over {step_size!r} s would end at t = {end!r} s, past "
                f"stopTime = {self._stop_time!r} s that the master set in fmi2SetupExperiment (stopTimeDefined): "
                "FMI 2.0 (2.1.6) does not allow computing past stopTime; end the simulation at stopTime, or reset "
                "the FMU and set up the experiment with a later stopTime",
                Fmi2Status.error,
            )
            return ERROR
        if step_size > MAX_STEPS_PER_DOSTEP * eng.dt:
            self.log(
                f"doStep over {step_size!r} s refused: at most {MAX_STEPS_PER_DOSTEP} internal steps of "
                f"solver.dt = {eng.dt!r} s ({MAX_STEPS_PER_DOSTEP * eng.dt:.6g} s) per call; take shorter "
                "communication steps",
                Fmi2Status.discard,
            )
            return self._discard(current_time, step_size)
        here = self._start_time + eng.time
        if abs(current_time - here) > self._clock_rounding(here, step_size):
            self.log(
                f"doStep from t = {current_time!r} s, but the FMU is at t = {here!r} s: steps must follow "
                "each other (or restore an FMU state first)",
                Fmi2Status.discard,
            )
            return self._discard(current_time, step_size)
        n, rest = whole_steps(step_size, eng.dt)
        if (n, rest) == (0, 0.0):
            # within the rounding of a clock (Engine.advance integrates no such rest): the FMU's clock
            # moves with the master's and the state stays, within 1e-6 solver.dt; a step taken
            self._start_time += step_size
            self._discarded, self._wants_to_end = None, False
            self.clock_only_calls += 1
            return OK
        if n == 0 and rest < SHORTEST_LONE_STEP * eng.dt:
            self.log(self._too_short(current_time, step_size, eng.dt, self._dt_source()), Fmi2Status.discard)
            return self._discard(current_time, step_size)
        x = self.inputs_buffer
        if not np.isfinite(x, out=self._finite_inputs).all():  # (not x @ x: it overflows, with a warning, past 1e154)
            i = int(np.flatnonzero(~self._finite_inputs)[0])
            self.log(
                f"input {self.input_names[i]} = {float(x[i])!r} at t = {current_time:.9g} s: "
                f"must be a finite number ({input_spec(self.input_names[i])[0]}); step discarded",
                Fmi2Status.discard,
            )
            return self._discard(current_time, step_size)
        if not self._start_said and math.isnan(self._recon.state[4, 0]):  # (the first step from rest)
            self._say_start_offset(current_time, step_size)
        try:  # on any error the engine and the reconstruction are left as they were
            eng.advance_reconstructed(
                step_size, self._recon, self._u, self._v, self._a, self.outputs_buffer, self._drive
            )
        except Exception as exc:  # noqa: BLE001  (never raise into the host)
            msg = self._input_overflow(exc, current_time, step_size)
            if msg is None:
                msg = f"step from t = {current_time:.9g} s over {step_size:.6g} s discarded (state rolled back): "
                msg += str(exc) if isinstance(exc, cc.CableCasingError) else internal_error_text(exc)
            self.log(msg, Fmi2Status.discard)
            return self._discard(current_time, step_size)
        # the FMU's clock is the master's: the engine's time (a sum of its steps, which leaves a rest
        # within the rounding of a clock untaken) is offset so that the next step is expected at
        # current_time + step_size as the master computed it, whatever its clock's rounding
        self._start_time = (current_time + step_size) - eng.time
        if self._discarded is not None:
            self._discarded, self._wants_to_end = None, False
        if not self._end_offset_said:  # (of a step taken: a discarded one has its own message)
            ends = eng.end_offset_excess(self._u)
            if ends is not None and (ends.across > ends.gap).any():
                self._say_end_offset(ends, current_time)
        return OK

    def _say_start_offset(self, current_time, step_size):
        """Warn (once per initialisation) when the first step starts with position inputs that are not
        zero: the model starts from rest at its reference position, and the reconstruction moves the
        supports from there to the inputs within the step. Starting it from the inputs instead would
        be right only for a rigid shift of every support alike; unequal offsets would need the bodies'
        static state under them, which the FMU does not compute (docs/fmu.md, Variables)."""
        self._start_said = True
        moved = [(name, float(x)) for name, x in zip(self.input_names[: self.nch], self._u) if x != 0.0]
        if not moved:
            return
        listed = ", ".join(f"{name} = {x!r} m" for name, x in moved[:6])
        if len(moved) > 6:
            listed += f" and {len(moved) - 6} more"
        self.log(
            f"position inputs not zero at the start time t = {current_time:.9g} s: {listed}; the model starts "
            "from rest at its reference position (the supports at 0), so these supports move from 0 to those "
            f"positions within the first step (h = {step_size:.6g} s), a jump the bodies feel as a transient force "
            "(an equal offset of every support too: it is no rigid shift here); give the inputs relative to their "
            "values at the start time, i.e. the motion about the installed position (docs/fmu.md, Variables)",
            Fmi2Status.warning,
        )

    def _say_end_offset(self, ends, current_time):
        """Warn (once per instance) that the position inputs set the two bodies' supports at an end
        apart across the route by more than the radial gap (``ends``: :meth:`Engine.end_offset_excess`
        of the inputs): the bodies share their end position, so the cable is pressed into the casing's
        wall there by the excess; said after the step, which was taken as given."""
        self._end_offset_said = True
        for k, end in enumerate(SUPPORT_NAMES):
            across, t = float(ends.across[k]), ends.tangent[k]
            if not across > ends.gap:
                continue
            given = []
            for d in DIRECTIONS:
                a, b = (float(self._u[CHANNELS.index(f"{body}.{end}.{d}")]) for body in BODY_NAMES)
                if a != b:
                    given.append(f"casing.{end}.{d} = {a!r} m, cable.{end}.{d} = {b!r} m")
            self.log(
                f"position inputs at t = {current_time:.9g} s set the casing's and the cable's supports at end {end} "
                f"{across * 1e3:.4g} mm apart across the route ({'; '.join(given)}: their difference normal to the "
                f"route's tangent [{t[0]:.4g}, {t[1]:.4g}, {t[2]:.4g}] there), more than the radial gap "
                f"{ends.gap * 1e3:.4g} mm between cable and casing (contact.enabled, casing.d_inner, cable.d): the two "
                f"bodies share their end position, so the cable is pressed into the casing's wall there by the excess, "
                f"{(across - ends.gap) * 1e3:.3g} mm, with a contact force that grows steeply with it; give both "
                "bodies' supports at an end the same motion across the route (along it the cable slides in the "
                "casing), or check how these inputs are connected (said once per instance; this step was taken with "
                "them)",
                Fmi2Status.warning,
            )
            return

    def _dt_source(self):
        """Where solver.dt's value comes from, for a message that names it: '' when the master set it,
        else the model's scenario.dt (the master's, when it set that)."""
        if "solver.dt" in self._set:
            return ""
        return f" (the model's scenario.dt{', as set' if 'scenario.dt' in self._set else ''}: solver.dt is not set)"

    @staticmethod
    def _too_short(current_time, step_size, dt, source=""):
        """The message of a step too short for a Newmark step of its own (between 1e-6 and 1e-3
        solver.dt, Engine.advance): nothing is computed; it names solver.dt (and ``source``, where its
        value comes from) and the largest value, three digits rounded down, with which the step would
        be taken."""
        need = step_size / SHORTEST_LONE_STEP
        digits = 10.0 ** (math.floor(math.log10(need)) - 2)
        fit = math.floor(need / digits) * digits
        while fit > digits and whole_steps(step_size, fit)[1] < SHORTEST_LONE_STEP * fit:  # (n = 0 here)
            fit -= digits  # (the rounding of the division put it just past the limit)
        lo = value_range("scenario.dt")[0]
        fix = (
            f"set solver.dt to at most {fit:.3g} s (h / {SHORTEST_LONE_STEP:g}) before fmi2ExitInitializationMode "
            "(reset the FMU to change it; a master whose every step is this short does best with solver.dt = h)"
            if lo is None or fit >= lo
            else f"solver.dt cannot be that small (at least {lo:g} s)"
        )
        return (
            f"doStep from t = {current_time!r} s over h = {step_size!r} s refused, nothing computed (the FMU stays "
            f"at t = {current_time!r} s): the step is {step_size / dt:.3g} of solver.dt = {dt!r} s{source}, too short "
            f"for a Newmark step of its own, which must be at least {SHORTEST_LONE_STEP:g} solver.dt "
            f"({SHORTEST_LONE_STEP * dt:.6g} s; a step of at most {ROUNDING_OF_TIME:g} solver.dt is a clock's "
            "rounding: no time): its accelerations lose their digits; "
            f"{fix}, or take a longer step (a master that shortens its last step to land on stopTime can add "
            "that rest to the step before it)"
        )

    @staticmethod
    def _clock_rounding(t, step_size):
        """How far (s) two times near ``t`` may differ and still be one instant of a master's clock
        that steps by ``step_size``: the tolerance of both the check that a step starts where the
        last ended and of stopTime. A clock t_k = t_0 + k h (fmpy, fmusim) is within a few ulp of
        its exact value; a sum t += h (fmuCheck) drifts by up to k / 2 ulp after k steps: 1e-12 |t|
        (~4500 ulp) holds thousands of steps' drift, and 1e-6 h the rest (10 s of steps of 1e-4 s
        drift by at most 9e-11 s < 1e-10 s). A last step that lands on stopTime by such sums (ten
        steps of 1e-4 s end at 0.0010000000000000002 s) is taken; one that ends later than this
        (a step past stopTime by any length a master means) is refused."""
        return 1e-6 * step_size + 1e-12 * abs(t)

    # The weighted size of an input (|u| / h**2, |v| / h, |a|: m/s2) past which a step whose solution
    # is no longer finite is blamed on it: no physical support motion comes near, and the squares
    # the engine forms of the forces and energies overflow double precision from ~1e154.
    OVERFLOWING_INPUT = 1e100

    def _input_overflow(self, exc, current_time, step_size):
        """When the step's error ``exc`` is the engine's refusal of a non-finite support motion
        (``<channel> <displacement|velocity|acceleration> = nan``) of a channel that is an input,
        or a solution that is no longer finite (``SimulationError.non_finite``) while an input
        weighs at least :data:`OVERFLOWING_INPUT` (every input being finite): the message naming
        the inputs the host gave for that channel (a huge value whose reconstruction over the step,
        or the forces from it, overflow), else None."""
        channels, n = self.input_names[: self.nch], self.nch
        # each input's weight in the quintic's acceleration (m/s2): u / h**2, v / h, a
        weight = [abs(float(x)) * step_size ** (j // n - 2) for j, x in enumerate(self.inputs_buffer)]
        if isinstance(exc, cc.SimulationError) and getattr(exc, "non_finite", False):
            j = max(range(len(weight)), key=weight.__getitem__)
            if not weight[j] >= self.OVERFLOWING_INPUT:  # (an unstable step, not an input)
                return None
            channel, what = channels[j % n], "the solution driven by the support motion reconstructed from it"
        elif isinstance(exc, cc.ModelError):
            channel, _, what = str(exc.key).rpartition(" ")
            if what not in ("displacement", "velocity", "acceleration") or channel not in channels:
                return None
            what = "the support motion reconstructed from it"
        else:
            return None
        c = channels.index(channel)
        given = [(self.input_names[c + k * n], float(self.inputs_buffer[c + k * n])) for k in range(3)]
        k = max(range(3), key=lambda k: weight[c + k * n])  # (the channel's input that weighs most)
        if given[k][1] == 0.0:  # (the supports' own state, not an input, is what overflows)
            return None
        others = ", ".join(f"{nm} = {x!r} {input_spec(nm)[0]}" for j, (nm, x) in enumerate(given) if j != k)
        name, value = given[k]
        return (
            f"input {name} = {value!r} {input_spec(name)[0]} at t = {current_time:.9g} s (with {others}): finite, but "
            f"{what} over the step of {step_size:.6g} s is not ({exc}); give "
            "inputs whose motion over a step fits in double precision; step discarded (state rolled back)"
        )

    def _discard(self, current_time, step_size):
        """fmi2Discard for the step (t, h) just refused, whose reason is logged. The FMU is as before
        it, so a master may retry with other inputs, a shorter step or a restored state; the same step
        with the same inputs would be discarded again (the FMU is deterministic), so when it is asked
        for again, fmi2Terminated reports true from then on (until a step is taken): a master that
        repeats a discarded step from fmi2LastSuccessfulTime until the slave asks to end (fmusim does)
        ends there instead of looping for ever."""
        key = (current_time, step_size, self.inputs_buffer.tobytes())
        if key == self._discarded and not self._wants_to_end:
            self._wants_to_end = True
            self.log(
                f"the step from t = {current_time:.9g} s over {step_size:.6g} s was asked for again with the same "
                "inputs and discarded again: it cannot be taken, so the FMU asks to end the simulation here "
                "(fmi2Terminated = true); change the inputs or the step, or restore an FMU state, to go on",
                Fmi2Status.error,
            )
        self._discarded = key
        return DISCARD

    def terminated(self):
        """fmi2Terminated: whether the FMU asks the master to end the simulation (:meth:`_discard`)."""
        return self._wants_to_end

    # ------------------------------------------------------------------ FMU state (complete, no pickle)
    def fmi2_get_state(self):
        """Everything that decides the continuation: the parameters the master set, the inputs,
        the support state of the reconstruction, the start time, and the engine's complete state."""
        numeric = [k for k in self._start if k != "model_file" and k not in self._text_keys]
        s = {
            "fmu.base_model": np.array(self._base_fingerprint),
            "fmu.inputs": self.inputs_buffer.copy(),
            "fmu.support": self._recon.state.copy(),
            "fmu.start_time": np.array(self._start_time),
            "fmu.initialized": np.array(self._initialized),
            "fmu.phase": np.array(self.phase),
            "fmu.built": np.array(self._engine is not None),
            "fmu.error": np.array(self._error or ""),
            "fmu.model_file": np.array(self._set.get("model_file", "")),
            "fmu.set_keys": np.array([k for k in numeric if k in self._set] or [""]),
            "fmu.set_values": np.array([float(self._set[k]) for k in numeric if k in self._set]),
            "fmu.set_text": np.array([f"{k}={self._set[k]}" for k in self._text_keys if k in self._set] or [""]),
        }
        if self._engine is not None:
            s.update({f"engine.{k}": v for k, v in self._engine.get_state().items()})
        return s

    def fmi2_set_state(self, state):
        """Restore a state from :meth:`fmi2_get_state` as a whole, or not at all: everything is
        checked (and a new engine built, if the state's parameters differ) before anything changes."""
        try:
            new = self._prepare_restore(state)
        except Exception as exc:  # noqa: BLE001
            self.log(f"the FMU state cannot be restored ({exc}); the instance is unchanged", Fmi2Status.error)
            return ERROR
        kept = new[1] is not None and new[1] is self._engine
        (
            self._set,
            self._engine,
            self._applied,
            inputs,
            support,
            self._start_time,
            self._initialized,
            self._error,
            self.phase,
        ) = new
        self.inputs_buffer[:] = inputs
        self._recon.state[...] = support
        self._discarded, self._wants_to_end = None, False  # (another state: a discarded step may now be taken)
        if self._engine is None:
            self._drive = None
        else:
            if not (kept and self._drive is not None):
                # another configuration (or none before): its scenario's motion, computed ahead as
                # at initialisation; the same engine keeps its motion, whose values depend on the
                # time alone, with the random blocks already computed
                self._drive = self._drive_motion(self._engine)
                self._prepare_drive()
            self._engine.output_values(self.outputs_buffer)
        return OK

    def _prepare_restore(self, state):
        if "fmu.invalid" in state:
            raise ValueError(str(state["fmu.invalid"]))
        if "fmu.base_model" in state and str(state["fmu.base_model"]) != self._base_fingerprint:
            raise ValueError("it is a state of an FMU built for another model (its parameters and outputs differ)")
        if str(state.get("fmu.error", "")):  # (FMI 2.0 allows only reset or free after that fmi2Error)
            raise ValueError(
                f"it was taken from an instance that did not initialise ({state['fmu.error']}), whose steps are "
                "all refused"
            )
        keys = [str(k) for k in np.asarray(state["fmu.set_keys"]).reshape(-1) if str(k)]
        values = np.asarray(state["fmu.set_values"], dtype=float).reshape(-1)
        if len(keys) != len(values) or any(k not in self._start for k in keys):
            raise ValueError("its parameter list does not fit this FMU")
        new_set = {}
        for k, v in zip(keys, values):
            start = self._start[k]
            new_set[k] = bool(v) if isinstance(start, bool) else int(v) if isinstance(start, int) else float(v)
        for item in (str(x) for x in np.asarray(state.get("fmu.set_text", [""])).reshape(-1) if str(x)):
            k, _, v = item.partition("=")
            if k not in self._text_keys:
                raise ValueError("its parameter list does not fit this FMU")
            new_set[k] = lookup(k).check(v, k)
        model_file = str(state["fmu.model_file"])
        if model_file:
            new_set["model_file"] = model_file
        inputs = np.array(state["fmu.inputs"], dtype=float).reshape(-1)
        support = np.array(state["fmu.support"], dtype=float)
        if inputs.shape != self.inputs_buffer.shape or support.shape != self._recon.state.shape:
            raise ValueError("its inputs or support state do not fit this FMU")
        start_time = float(state["fmu.start_time"])
        if not math.isfinite(start_time):  # (the clock every later step is checked against)
            raise ValueError(f"its start time {start_time!r} s is not a finite number")
        engine, applied = None, None
        if bool(state["fmu.built"]):
            saved, self._set = self._set, new_set
            try:
                config = self._config()
            finally:
                self._set = saved
            engine = (
                self._engine if (self._engine is not None and self._applied == config) else self._make_engine(config)
            )
            problem = self._variables_problem(engine) if engine is not self._engine else None
            if problem:  # (a state of an FMU built for another model file)
                raise ValueError(problem)
            engine_state = {k[len("engine.") :]: v for k, v in state.items() if k.startswith("engine.")}
            if engine is self._engine:  # Engine.set_state checks all before it writes any
                backup = engine.get_state()
                try:
                    engine.set_state(engine_state)
                except Exception:
                    engine.set_state(backup)
                    raise
            else:
                engine.set_state(engine_state)
            applied = config
        return (
            new_set,
            engine,
            applied,
            inputs,
            support,
            start_time,
            bool(state["fmu.initialized"]),
            str(state["fmu.error"]) or None,
            _phase_of(state),
        )

    @staticmethod
    def serialize_state(state):
        return state_to_bytes(state)

    def deserialize_state(self, data):
        """The state in serialised bytes, or None (logged at fmi2Error) if they are not one."""
        try:
            state = state_from_bytes(data)
            if "fmu.inputs" not in state:
                raise ValueError("no FMU inputs in it")
            return state
        except Exception as exc:  # noqa: BLE001
            self.log(f"the FMU state cannot be deserialised ({_not_a_state(data, exc)})", Fmi2Status.error)
            return None

    # ------------------------------------------------------------------ pythonfmu's binary (Windows)
    # pythonfmu calls these; a Python exception there is fmi2Fatal, and it can report fmi2Discard
    # (do_step returning False) but no fmi2Error, so errors are logged and steps refused.
    def setup_experiment(self, start_time=0.0, stop_time=None, tolerance=None):
        self.fmi2_setup_experiment(float(start_time or 0.0), stop_time, None if tolerance is None else float(tolerance))

    def exit_initialization_mode(self):
        self.fmi2_exit_initialization_mode()

    def do_step(self, current_time, step_size):
        return self.fmi2_do_step(current_time, step_size) <= WARNING

    def terminate(self):
        self.fmi2_terminate()

    def set_real(self, vrs, values):
        key = tuple(vrs)
        idx = self._set_plans.get(key)
        if idx is None:
            idx = self._set_plans[key] = self._plan(key, self._input_vr)
        if idx is not False:  # inputs only: one vectorised assignment
            self.inputs_buffer[idx] = values
            return
        self.fmi2_set("Real", vrs, values)

    def get_real(self, vrs):
        key = tuple(vrs)
        idx = self._get_plans.get(key)
        if idx is None:
            idx = self._get_plans[key] = self._plan(key, self._output_vr)
        if idx is not False and self.phase != INITIALIZATION:  # outputs only (fmi2_get: in initialisation)
            return self.outputs_buffer[idx].tolist()
        out = [0.0] * len(vrs)
        self.fmi2_get("Real", vrs, out)
        return out

    def _plan(self, key, table):
        """Index array of value references that are all in ``table`` (else False); bounded cache."""
        if len(self._set_plans) + len(self._get_plans) > 64:
            self._set_plans.clear()
            self._get_plans.clear()
        if key and all(vr in table for vr in key):
            return np.array([table[vr] for vr in key], dtype=np.intp)
        return False

    def _typed_get(self, kind, vrs, default):
        out = [default] * len(vrs)
        self.fmi2_get(kind, vrs, out)
        return out

    def get_integer(self, vrs):
        return self._typed_get("Integer", vrs, 0)

    def get_boolean(self, vrs):
        return self._typed_get("Boolean", vrs, False)

    def get_string(self, vrs):
        return self._typed_get("String", vrs, "")

    def set_integer(self, vrs, values):
        self.fmi2_set("Integer", vrs, values)

    def set_boolean(self, vrs, values):
        self.fmi2_set("Boolean", vrs, values)

    def set_string(self, vrs, values):
        self.fmi2_set("String", vrs, values)

    def _get_fmu_state(self):
        return self.fmi2_get_state()

    def _set_fmu_state(self, state):
        self.fmi2_set_state(state)

    @staticmethod
    def _fmu_state_to_bytes(state):
        return state_to_bytes(state)

    @staticmethod
    def _fmu_state_from_bytes(data):
        try:
            return state_from_bytes(data)
        except Exception as exc:  # noqa: BLE001
            return {"fmu.invalid": np.array(_not_a_state(data, exc))}
