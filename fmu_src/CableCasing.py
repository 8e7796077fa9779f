"""FMI 2.0 co-simulation slave of the cable-in-casing model (pythonfmu).

Only an adapter over ``cablecasing_core.timedomain.engine.Engine``; there is no physics here:

* inputs: displacement (m), velocity (m/s) and acceleration (m/s2) of the 12 support channels at
  the start of each communication step; ``cablecasing_core.timedomain.support_motion`` reconstructs the motion
  inside the step (quintic Hermite from the supports' state to the Taylor extrapolation);
* outputs: ``engine.outputs()`` after the step (force and moment each body exerts on each support,
  contact summary);
* parameters: every numeric key of the built-in model under its dotted name, ``contact.enabled``,
  ``model_file`` and ``solver.dt``, applied with ``Model.with_overrides`` when initialisation ends.

pythonfmu turns a Python exception in any call into fmi2Fatal and discards the instance, and it
offers no way to return fmi2Error. So nothing here raises: setters only store values; a problem
(an invalid parameter, a non-finite input, a blow-up) is logged at the status it deserves, naming
the variable and the value, and ``do_step`` returns False, which pythonfmu reports as fmi2Discard.
A failed step is rolled back whole, so the master may retry it (for example with a smaller step).
"""

import os
import sys
import traceback

# The bundled package must win over any installed copy: resources first on sys.path.
_RESOURCES = os.path.dirname(os.path.abspath(__file__))
if not sys.path or sys.path[0] != _RESOURCES:
    sys.path.insert(0, _RESOURCES)

# The kernels' numba cache (a per-user folder keyed by the kernels' sources, so it outlives the
# unpacked FMU) is installed by the bundled package itself: cablecasing_core.timedomain.kernels.
import numpy as np  # noqa: E402
from pythonfmu import (
    Boolean,
    DefaultExperiment,
    Fmi2Causality,
    Fmi2Slave,
    Fmi2Variability,  # noqa: E402
    Integer,
    Real,
    String,
)
from pythonfmu.enums import Fmi2Status  # noqa: E402

import cablecasing_core as cc  # noqa: E402
from cablecasing_core.model.schema import CHANNELS, OUTPUTS, lookup, output_spec  # noqa: E402
from cablecasing_core.model.validators import seconds  # noqa: E402
from cablecasing_core.timedomain.engine import Engine, state_from_bytes, state_to_bytes  # noqa: E402
from cablecasing_core.timedomain.support_motion import SupportReconstruction  # noqa: E402

NCH = len(CHANNELS)
KINDS = (("", "displacement", "m"), ("v", "velocity", "m/s"), ("a", "acceleration", "m/s2"))
INTEGER_OUTPUTS = ("contact.active",)


def input_name(channel, kind):
    """Input variable of a channel: kind '' -> 'casing.A.x', 'v' -> 'casing.A.vx', 'a' -> 'casing.A.ax'."""
    body, support, d = channel.split(".")
    return f"{body}.{support}.{kind}{d}"


def parameter_info(key):
    """(unit, description) of a model key such as 'casing.E' or 'scenario.excitation.x.rms' (the
    model schema); the scenario's keys describe the model file's own run, which the FMU does not make."""
    spec = lookup(key)
    note = " (not used: the FMU's inputs drive the supports)" if key.startswith("scenario.") else ""
    return spec.unit, spec.description + note


class CableCasing(Fmi2Slave):
    """Gear-shift cable in a curved casing, driven at its four supports (see module docstring)."""

    author = "cablecasing developers"
    description = (
        "Gear-shift cable sliding in a curved casing: two spatially curved 3D Euler-Bernoulli "
        "beams with frictional penalty contact, driven by support motion (SI units)"
    )
    version = cc.__version__
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=1.0, step_size=1e-4)

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        base = cc.load_model()
        self.units = {}  # variable name -> unit (read by build_fmu.py)
        self._start = dict(base.parameters())
        self._start["contact.enabled"] = bool(base.contact["enabled"])
        self._start["model_file"] = ""
        self._start["solver.dt"] = float(base.scenario["dt"])
        self._values = dict(self._start)
        self._inputs = np.zeros(3 * NCH)  # u (m), v (m/s), a (m/s2) of CHANNELS
        self._out = np.zeros(len(OUTPUTS))
        self._out_dirty = False
        self._engine = None
        self._applied = None  # the configuration the engine was built with
        self._recon = SupportReconstruction(NCH)
        self._start_time = 0.0
        self._initialized = False
        self._error = None  # message of a problem that blocks stepping

        # inputs: u, v, a of every channel
        self._input_vr = {}
        for k, (prefix, what, unit) in enumerate(KINDS):
            for c, ch in enumerate(CHANNELS):
                body, support, d = ch.split(".")
                self._add(
                    Real(
                        input_name(ch, prefix),
                        causality=Fmi2Causality.input,
                        variability=Fmi2Variability.continuous,
                        start=0.0,
                        description=f"{what} of the {body}'s support {support} along global {d}",
                        getter=self._input_getter(k * NCH + c),
                        setter=self._input_setter(k * NCH + c),
                    ),
                    unit,
                )
                self._input_vr[len(self.vars) - 1] = k * NCH + c
        # outputs
        self._output_vr = {}  # value reference of a Real output -> index
        self._set_plans, self._get_plans = {}, {}  # tuple of value references -> index array
        for i, name in enumerate(OUTPUTS):
            unit, text = output_spec(name)
            if name in INTEGER_OUTPUTS:
                var = Integer(
                    name,
                    causality=Fmi2Causality.output,
                    variability=Fmi2Variability.discrete,
                    description=text,
                    getter=self._output_getter(i, int),
                )
            else:
                var = Real(
                    name,
                    causality=Fmi2Causality.output,
                    variability=Fmi2Variability.continuous,
                    description=text,
                    getter=self._output_getter(i, float),
                )
            self._add(var, unit)
            if name not in INTEGER_OUTPUTS:
                self._output_vr[var.value_reference] = i
        # parameters
        for key, value in self._start.items():
            if key in ("contact.enabled", "model_file", "solver.dt"):
                continue
            unit, text = parameter_info(key)
            kind = Integer if isinstance(value, int) else Real
            self._add(
                kind(
                    key,
                    causality=Fmi2Causality.parameter,
                    variability=Fmi2Variability.fixed,
                    description=text,
                    getter=self._param_getter(key),
                    setter=self._param_setter(key, kind),
                ),
                unit if kind is Real else "",
            )
        self._add(
            Boolean(
                "contact.enabled",
                causality=Fmi2Causality.parameter,
                variability=Fmi2Variability.fixed,
                description="contact between cable and casing on (true) or off (false: two independent linear bodies)",
                getter=self._param_getter("contact.enabled"),
                setter=self._param_setter("contact.enabled", Boolean),
            ),
            "",
        )
        self._add(
            String(
                "model_file",
                causality=Fmi2Causality.parameter,
                variability=Fmi2Variability.fixed,
                description="path of a model TOML file; empty = the built-in specimen",
                getter=self._param_getter("model_file"),
                setter=self._param_setter("model_file", String),
            ),
            "",
        )
        self._add(
            Real(
                "solver.dt",
                causality=Fmi2Causality.parameter,
                variability=Fmi2Variability.fixed,
                description="internal Newmark time step; a communication step is split into steps of this "
                "size and one shorter last step",
                getter=self._param_getter("solver.dt"),
                setter=self._param_setter("solver.dt", Real),
            ),
            "s",
        )
        self._check_import_origin()

    # ------------------------------------------------------------------ registration helpers
    def _add(self, var, unit):
        self.register_variable(var, nested=False)
        self.units[var.name] = unit

    def _input_getter(self, i):
        return lambda: float(self._inputs[i])

    def _input_setter(self, i):
        def set_input(value):
            self._inputs[i] = value

        return set_input

    def _output_getter(self, i, kind):
        def get_output():
            self._refresh_outputs()
            return kind(self._out[i])

        return get_output

    def _param_getter(self, key):
        return lambda: self._values[key]

    def _param_setter(self, key, kind):
        cast = {Real: float, Integer: int, Boolean: bool, String: str}[kind]

        def set_param(value):
            if self._initialized:
                self.log(
                    f"parameter {key} = {value!r} ignored: parameters are fixed after initialisation "
                    "(reset the FMU to change them)",
                    Fmi2Status.warning,
                )
                return
            self._values[key] = cast(value)

        return set_param

    def _check_import_origin(self):
        here = os.path.dirname(os.path.abspath(cc.__file__))
        if not here.startswith(_RESOURCES + os.sep) and not here.startswith(os.path.realpath(_RESOURCES) + os.sep):
            self.log(
                f"cablecasing_core was already imported from {here} before this FMU was loaded; that copy "
                f"is used, not the one in {_RESOURCES}",
                Fmi2Status.warning,
            )

    # ------------------------------------------------------------------ fast variable access
    def set_real(self, vrs, values):
        key = tuple(vrs)
        idx = self._set_plans.get(key)
        if idx is None:  # first time this list of references: plan it
            idx = self._set_plans[key] = self._plan(key, self._input_vr)
        if idx is not False:  # inputs only: one vectorised assignment
            self._inputs[idx] = values
            return
        for vr, value in zip(vrs, values):
            i = self._input_vr.get(vr)
            if i is not None:
                self._inputs[i] = value
            else:
                var = self.vars.get(vr)
                if isinstance(var, Real) and var.setter is not None:
                    var.setter(value)
                else:
                    self._refuse("set a Real", vr, value)

    def get_real(self, vrs):
        key = tuple(vrs)
        idx = self._get_plans.get(key)
        if idx is None:
            idx = self._get_plans[key] = self._plan(key, self._output_vr)
        if idx is not False:  # Real outputs only
            self._refresh_outputs()
            return self._out[idx].tolist()
        out = []
        for vr in vrs:
            i = self._output_vr.get(vr)
            if i is not None:
                self._refresh_outputs()
                out.append(float(self._out[i]))
            else:
                var = self.vars.get(vr)
                out.append(
                    float(var.getter()) if isinstance(var, Real) else float(self._refuse("get a Real", vr, None))
                )
        return out

    def _plan(self, key, table):
        """Index array of value references that are all in ``table`` (else False); the cache of
        plans is bounded, since a master normally repeats a few lists of references."""
        if len(self._set_plans) + len(self._get_plans) > 64:
            self._set_plans.clear()
            self._get_plans.clear()
        if key and all(vr in table for vr in key):
            return np.array([table[vr] for vr in key], dtype=np.intp)
        return False

    def get_integer(self, vrs):
        return [
            int(self.vars[vr].getter())
            if isinstance(self.vars.get(vr), Integer)
            else self._refuse("get an Integer", vr, None)
            for vr in vrs
        ]

    def get_boolean(self, vrs):
        return [
            bool(self.vars[vr].getter())
            if isinstance(self.vars.get(vr), Boolean)
            else self._refuse("get a Boolean", vr, None)
            for vr in vrs
        ]

    def get_string(self, vrs):
        return [
            str(self.vars[vr].getter())
            if isinstance(self.vars.get(vr), String)
            else str(self._refuse("get a String", vr, None))
            for vr in vrs
        ]

    def set_integer(self, vrs, values):
        self._set_typed(Integer, "set an Integer", vrs, values)

    def set_boolean(self, vrs, values):
        self._set_typed(Boolean, "set a Boolean", vrs, values)

    def set_string(self, vrs, values):
        self._set_typed(String, "set a String", vrs, values)

    def _set_typed(self, kind, what, vrs, values):
        """Set writable variables of type ``kind``; any other reference is refused (logged)."""
        for vr, value in zip(vrs, values):
            var = self.vars.get(vr)
            if isinstance(var, kind) and var.setter is not None:
                var.setter(value)
            else:
                self._refuse(what, vr, value)

    def _refuse(self, what, vr, value):
        """A call with a value reference of the wrong type (or a read-only one): log at fmi2Error
        and ignore it (pythonfmu cannot return fmi2Error, and raising would be fmi2Fatal)."""
        var = self.vars.get(vr)
        which = f"{var.name} ({type(var).__name__}, {var.causality.name})" if var is not None else "no variable"
        self.log(
            f"cannot {what} through value reference {vr}: {which}"
            + ("" if value is None else f"; value {value!r} ignored"),
            Fmi2Status.error,
        )
        return 0

    def _refresh_outputs(self):
        if self._out_dirty:
            self._engine.output_values(self._out)
            self._out_dirty = False

    # ------------------------------------------------------------------ life cycle
    def setup_experiment(self, start_time=0.0, *args, **kwargs):
        self._start_time = float(start_time or 0.0)

    def exit_initialization_mode(self):
        self._initialized = True
        self._build()

    def _config(self):
        """The configuration that decides the engine: the overrides of the model (parameters whose
        value differs from their start value), the model file and the internal step."""
        over = {k: v for k, v in self._values.items() if k not in ("model_file", "solver.dt") and v != self._start[k]}
        return self._values["model_file"], over, self._values["solver.dt"]

    def _build(self):
        """Build the engine from the parameters; on a problem log it (fmi2Error) and block stepping."""
        model_file, over, dt = self._config()
        try:
            seconds("solver.dt", dt)
            model = cc.load_model(model_file or None)
            if over:
                model = model.with_overrides(over)
            self._engine = Engine(model, dt=dt, ledger=False)
        except cc.ModelError as exc:
            self._engine = None
            return self._block(f"invalid parameter {exc}", Fmi2Status.error)
        except Exception as exc:  # noqa: BLE001  (never raise into pythonfmu: that is fmi2Fatal)
            self._engine = None
            return self._block(f"the model cannot be built: {exc!r}\n{traceback.format_exc()}", Fmi2Status.error)
        self._applied = (model_file, over, dt)
        self._error = None
        self._recon.reset()
        self._out[:] = 0.0
        self._out_dirty = True
        return True

    def _block(self, msg, status):
        self._error = msg
        self.log(msg, status)
        return False

    def do_step(self, current_time, step_size):
        if self._error is not None:
            self.log(f"step from t = {current_time:.9g} s refused: {self._error}", Fmi2Status.discard)
            return False
        eng = self._engine
        if eng is None:
            self.log("doStep before initialisation ended (call fmi2ExitInitializationMode first)", Fmi2Status.discard)
            return False
        x = self._inputs
        if not np.isfinite(x).all():
            i = int(np.flatnonzero(~np.isfinite(x))[0])
            k, c = divmod(i, NCH)
            self.log(
                f"input {input_name(CHANNELS[c], KINDS[k][0])} = {float(x[i])!r} at t = {current_time:.9g} s: "
                f"must be a finite number ({KINDS[k][2]}); step discarded",
                Fmi2Status.discard,
            )
            return False
        if not (np.isfinite(step_size) and step_size > 0):
            self.log(f"communication step = {step_size!r} s: must be a positive number of seconds", Fmi2Status.discard)
            return False
        here = self._start_time + eng.time
        if abs(current_time - here) > 1e-6 * step_size + 1e-12 * abs(here):
            self.log(
                f"doStep from t = {current_time!r} s, but the FMU is at t = {here!r} s: steps must follow "
                "each other (or restore an FMU state first)",
                Fmi2Status.discard,
            )
            return False
        motion = self._recon.motion(eng.time, step_size, x[:NCH], x[NCH : 2 * NCH], x[2 * NCH :])
        try:
            eng.advance(step_size, motion)  # on any error it leaves the engine as it was
        except Exception as exc:  # noqa: BLE001  (never raise into pythonfmu: that is fmi2Fatal)
            msg = f"step from t = {current_time:.9g} s over {step_size:.6g} s discarded (state rolled back): {exc}"
            if not isinstance(exc, cc.CableCasingError):
                msg += "\n" + traceback.format_exc()
            self.log(msg, Fmi2Status.discard)
            return False
        self._recon.accept(motion)
        self._out_dirty = True
        return True

    # ------------------------------------------------------------------ FMU state (complete, no pickle)
    def _get_fmu_state(self):
        """Everything that decides the continuation: the parameter values, the inputs, the support
        state of the reconstruction, the start time, and the engine's complete state."""
        s = {
            "fmu.inputs": self._inputs.copy(),
            "fmu.support": self._recon.state.copy(),
            "fmu.start_time": np.array(self._start_time),
            "fmu.initialized": np.array(self._initialized),
            "fmu.built": np.array(self._engine is not None),
            "fmu.error": np.array(self._error or ""),
            "fmu.model_file": np.array(self._values["model_file"]),
            "fmu.values": np.array([float(self._values[k]) for k in self._numeric_keys()]),
        }
        if self._engine is not None:
            s.update({f"engine.{k}": v for k, v in self._engine.get_state().items()})
        return s

    def _numeric_keys(self):
        return [k for k in self._start if k != "model_file"]

    def _set_fmu_state(self, state):
        """Restore a state from :meth:`_get_fmu_state`; on failure log it with the traceback at
        fmi2Error and refuse further steps (the instance may be half restored)."""
        try:
            self._restore(state)
        except Exception as exc:  # noqa: BLE001
            self._block(
                f"the FMU state cannot be restored ({exc}); steps are refused until a valid state is "
                f"set or the FMU is reset\n{traceback.format_exc()}",
                Fmi2Status.error,
            )

    def _restore(self, state):
        if "fmu.invalid" in state:
            raise ValueError(str(state["fmu.invalid"]))
        for k, v in zip(self._numeric_keys(), state["fmu.values"]):
            start = self._start[k]
            self._values[k] = bool(v) if isinstance(start, bool) else int(v) if isinstance(start, int) else float(v)
        self._values["model_file"] = str(state["fmu.model_file"])
        self._inputs[:] = state["fmu.inputs"]
        self._start_time = float(state["fmu.start_time"])
        self._initialized = bool(state["fmu.initialized"])
        if bool(state["fmu.built"]):
            if self._engine is None or self._applied != self._config():
                if not self._build():
                    return
            self._engine.set_state({k[len("engine.") :]: v for k, v in state.items() if k.startswith("engine.")})
        else:
            self._engine, self._applied = None, None
        self._recon.state = np.array(state["fmu.support"], dtype=float)
        self._error = str(state["fmu.error"]) or None
        self._out_dirty = self._engine is not None

    @staticmethod
    def _fmu_state_to_bytes(state):
        return state_to_bytes(state)

    @staticmethod
    def _fmu_state_from_bytes(data):
        # never raise (pythonfmu would answer fmi2Fatal): an unreadable state is reported when set
        try:
            return state_from_bytes(data)
        except Exception as exc:  # noqa: BLE001
            return {"fmu.invalid": np.array(f"{len(data)} bytes are not a serialised CableCasing FMU state: {exc!r}")}
