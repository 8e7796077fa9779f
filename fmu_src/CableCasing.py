"""FMI 2.0 co-simulation slave of the cable-in-casing model: an adapter over
``cablecasing_core.engine.Engine`` (no physics here).

Inputs at each communication point: displacement, velocity and acceleration of the 12 support
channels; inside a step the core's ``kinematics.QuinticStep`` reconstructs the motion. Outputs: the
force and moment each body exerts on each support, and a contact summary.

pythonfmu turns any Python exception into fmi2Fatal, so nothing here raises: setters only store
values, and every problem (a non-finite input, an invalid parameter, a blow-up) is logged with the
variable and the value and reported by ``do_step`` returning False (fmi2Discard).
"""
import os
import sys
import traceback

if "NUMBA_CACHE_DIR" not in os.environ:  # keep compiled kernels outside the unpacked FMU
    os.environ["NUMBA_CACHE_DIR"] = os.path.join(os.path.expanduser("~"), ".cache", "cablecasing", "numba")

_HERE = os.path.dirname(os.path.abspath(__file__))


def _stable_package_path():
    """numba keys its cache by the source file's path, and each unpacked FMU lands in a new folder:
    copy the bundled cablecasing_core once to a per-user folder named by its content hash and import
    it from there, so that later instantiations reuse the compiled kernels."""
    import hashlib
    import shutil

    src = os.path.join(_HERE, "cablecasing_core")
    if not os.path.isdir(src):
        return None
    h = hashlib.sha1()
    for dirpath, _, files in sorted(os.walk(src)):
        for f in sorted(files):
            if f.endswith((".py", ".toml", ".csv")):
                with open(os.path.join(dirpath, f), "rb") as fh:
                    h.update(f.encode() + fh.read())
    dest = os.path.join(os.path.dirname(os.environ["NUMBA_CACHE_DIR"]), "pkg-" + h.hexdigest()[:16])
    if not os.path.isdir(os.path.join(dest, "cablecasing_core")):
        tmp = dest + f".tmp{os.getpid()}"
        shutil.copytree(src, os.path.join(tmp, "cablecasing_core"))
        try:
            os.replace(tmp, dest)
        except OSError:  # another process won the race; its copy is identical
            shutil.rmtree(tmp, ignore_errors=True)
    return dest


try:
    _PKG = _stable_package_path() or _HERE
except OSError:  # read-only home: fall back to the unpacked resources (works, compiles each time)
    _PKG = _HERE
for _p in (_HERE, _PKG):
    if _p not in sys.path:
        sys.path.insert(0, _p)

import numpy as np  # noqa: E402
from pythonfmu import Boolean, DefaultExperiment, Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real, String  # noqa: E402
from pythonfmu.enums import Fmi2Status  # noqa: E402

import cablecasing_core as cc  # noqa: E402
from cablecasing_core.config import CHANNELS  # noqa: E402
from cablecasing_core.engine import OUTPUTS, Engine, state_from_bytes, state_to_bytes  # noqa: E402
from cablecasing_core.kinematics import QuinticStep, taylor_target  # noqa: E402

KINDS = (("", "displacement", "m"), ("v", "velocity", "m/s"), ("a", "acceleration", "m/s2"))


def input_name(channel, kind):
    """'casing.A.x' -> 'casing.A.x', 'casing.A.vx', 'casing.A.ax'."""
    body, support, d = channel.split(".")
    return f"{body}.{support}.{kind}{d}"


class CableCasing(Fmi2Slave):
    author = "cablecasing developers"
    description = "Gear-shift cable in a curved casing: 3D Euler-Bernoulli beams with frictional contact (SI units)"
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=1.0, step_size=1e-4)

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        base = cc.load_model()
        self._defaults = base.parameters()
        self._params = dict(self._defaults)
        self.model_file = ""
        self._contact_enabled = bool(base.contact["enabled"])
        self._dt = float(base.scenario["dt"])
        self._inputs = np.zeros((3, len(CHANNELS)))
        self._outputs = {n: 0.0 for n in OUTPUTS}
        self._engine = None
        self._support = tuple(np.zeros(len(CHANNELS)) for _ in range(3))
        self._error = None

        for key, value in self._defaults.items():
            self.register_variable(Real(key, causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed,
                                        description=f"model parameter {key} (see the model file)",
                                        getter=self._getter(key), setter=self._setter(key)), nested=False)
        self.register_variable(String("model_file", causality=Fmi2Causality.parameter,
                                      variability=Fmi2Variability.fixed,
                                      description="path of a model TOML file; empty = built-in specimen"), nested=False)
        self.register_variable(Real("solver.dt", causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed,
                                    description="internal Newmark time step (s)",
                                    getter=lambda: self._dt, setter=lambda v: setattr(self, "_dt", v)), nested=False)
        self.register_variable(Boolean("contact.enabled", causality=Fmi2Causality.parameter,
                                       variability=Fmi2Variability.fixed, description="contact between cable and casing",
                                       getter=lambda: self._contact_enabled,
                                       setter=lambda v: setattr(self, "_contact_enabled", bool(v))), nested=False)
        for k, (prefix, what, _) in enumerate(KINDS):
            for c, ch in enumerate(CHANNELS):
                self.register_variable(Real(input_name(ch, prefix), causality=Fmi2Causality.input,
                                            variability=Fmi2Variability.continuous, start=0.0,
                                            description=f"{what} of support {ch[:-2]} along global {ch[-1]}",
                                            getter=self._in_getter(k, c), setter=self._in_setter(k, c)), nested=False)
        for name in OUTPUTS:
            desc = _output_description(name)
            var, vb = (Integer, Fmi2Variability.discrete) if name == "contact.active" else (Real, Fmi2Variability.continuous)
            self.register_variable(var(name, causality=Fmi2Causality.output, variability=vb,
                                       description=desc, getter=self._out_getter(name)), nested=False)

    # ---------------------------------------------------------------- variable access (never raise)
    def _getter(self, key):
        return lambda: self._params[key]

    def _setter(self, key):
        def set_(v):
            self._params[key] = v
        return set_

    def _in_getter(self, k, c):
        return lambda: float(self._inputs[k, c])

    def _in_setter(self, k, c):
        def set_(v):
            self._inputs[k, c] = v
        return set_

    def _out_getter(self, name):
        return lambda: self._outputs[name]

    def _fail(self, msg, exc=None):
        text = msg if exc is None else f"{msg}\n{traceback.format_exc()}"
        self.log(text, Fmi2Status.error)
        self._error = msg
        return False

    # ---------------------------------------------------------------- life cycle
    def exit_initialization_mode(self):
        self._build()

    def _build(self):
        try:
            model = cc.load_model(self.model_file or None)
            # parameters changed from the built-in values override the model (file or built-in)
            over = {}
            for k, v in self._params.items():
                if v != self._defaults[k]:
                    if isinstance(self._defaults[k], int) and float(v).is_integer():
                        v = int(v)
                    over[k] = v
            over["contact.enabled"] = self._contact_enabled
            model = model.with_overrides(over)
            self._engine = Engine(model, dt=self._dt, ledger=False)
            self._error = None
        except Exception as exc:  # reported by do_step; raising here would be fmi2Fatal
            self._engine = None
            self._fail(f"invalid parameter: {exc}", exc if not isinstance(exc, cc.ModelError) else None)

    def do_step(self, current_time, step_size):
        if self._engine is None:
            return self._fail(self._error or "the model is not initialised")
        bad = ~np.isfinite(self._inputs)
        if bad.any():
            k, c = np.argwhere(bad)[0]
            return self._fail(f"input {input_name(CHANNELS[c], KINDS[k][0])} = {self._inputs[k, c]!r}: "
                              "inputs must be finite numbers")
        if not (np.isfinite(step_size) and step_size > 0):
            return self._fail(f"communication step = {step_size!r}: must be a positive number of seconds")
        try:
            u, v, a = self._inputs
            motion = QuinticStep(self._engine.time, step_size, self._support, taylor_target(u, v, a, step_size))
            state = self._engine.get_state()
            try:
                self._engine.advance(step_size, motion)
            except Exception:
                self._engine.set_state(state)  # nothing half-written: the step is discarded whole
                raise
            self._support = motion.end_state()
            self._outputs = self._engine.outputs()
            return True
        except cc.CableCasingError as exc:
            return self._fail(f"step from t = {current_time:.6g} s failed: {exc}")
        except Exception as exc:
            return self._fail(f"step from t = {current_time:.6g} s failed: {exc!r}", exc)

    # ---------------------------------------------------------------- FMU state (complete, no pickle)
    def _get_fmu_state(self):
        s = {} if self._engine is None else {f"engine/{k}": v for k, v in self._engine.get_state().items()}
        s["slave/inputs"] = self._inputs.copy()
        s["slave/support"] = np.array(self._support)
        s["slave/outputs"] = np.array([float(self._outputs[n]) for n in OUTPUTS])
        return s

    def _set_fmu_state(self, state):
        eng = {k[len("engine/"):]: v for k, v in state.items() if k.startswith("engine/")}
        if self._engine is None:
            self._build()
        if self._engine is not None and eng:
            self._engine.set_state(eng)
        self._inputs[:] = state["slave/inputs"]
        self._support = tuple(np.array(x) for x in state["slave/support"])
        vals = state["slave/outputs"]
        self._outputs = {n: (int(x) if n == "contact.active" else float(x)) for n, x in zip(OUTPUTS, vals)}

    @staticmethod
    def _fmu_state_to_bytes(state):
        return state_to_bytes(state)

    @staticmethod
    def _fmu_state_from_bytes(data):
        return state_from_bytes(data)


def _output_description(name):
    if name == "contact.active":
        return "number of cable nodes in contact with the casing"
    if name == "contact.max_penetration":
        return "largest penetration of the cable into the casing wall (m)"
    if name == "contact.dissipated_energy":
        return "energy dissipated by contact damping and friction since t = 0 (J)"
    body, support, comp = name.split(".")
    kind = "force" if comp.startswith("F") else "moment"
    return f"{kind} the {body} exerts on support {support}, global {comp[1].lower()} component"
