"""cablecasing_core: vibration model of a gear-shift cable inside a curved casing (Otrin and
Boltezar): two spatially curved 3D Euler-Bernoulli beams on one centerline, coupled by frictional
contact across the radial gap. SI units throughout (m, kg, s, N, Pa, rad; frequencies in Hz).

The package follows the paper: ``model`` (the model file, its schema and the built-in specimen),
``structure`` (centerline, sections, the beam element, assembly: Eqs. 1-9, 13, 32-34; Eq. 35 not
needed), ``frequency`` (modes and the apparent mass TRFAM: Eqs. 10-13), ``timedomain`` (the Newmark
engine with contact: Eqs. 14-24, 27-34, 36-39; 25-26 not implemented), ``identification`` (Section
3), ``studies`` (Section 4), ``nvh`` (PSD, levels, transfer functions of any record), ``records``
(record files by suffix), ``report``, ``cli``.

A tutorial (it runs as a doctest: ``python -m pytest --doctest-modules cablecasing_core/__init__.py``,
or ``python -c "import doctest, cablecasing_core as cc; doctest.testmod(cc)"``). Load the built-in
specimen; every key is in ``model.data``, checked against the schema (docs/model_file.md), and a
change is a validated copy:

>>> import numpy as np
>>> import cablecasing_core as cc
>>> model = cc.load_model()                       # or cc.load_model("my_model.toml")
>>> model.parameters()["casing.E"]                # Pa
5000000000.0
>>> stiffer = model.with_overrides({"casing.E": 6e9, "contact.friction": 0.1})
>>> stiffer.bodies["casing"].E
6000000000.0
>>> from cablecasing_core.model.schema import lookup
>>> lookup("contact.friction").unit, lookup("contact.friction").allowed
('1', 'a number in [0, 10]')

Natural frequencies of one body with its supports (Hz), and the apparent-mass transfer function
between its ends (kg, Eq. 12) with structural damping (Eq. 11):

>>> f = cc.natural_frequencies(model, "casing", count=3)
>>> bool(np.all(np.diff(f) > 0) and 5.0 < f[0] < 15.0)
True
>>> freqs = np.arange(10.0, 200.0, 0.5)
>>> H = cc.trfam(model, "casing.A.z", "casing.B.z", freqs, damping="structural")
>>> H.shape, H.dtype
((380,), dtype('complex128'))

The time domain: the model's scenario through the Newmark engine with contact (the force each
body exerts on its supports, N; the contact state per cable node; the energy ledger, J). The work
the supports did is what the bodies hold plus what damping took (to 1e-6, the trapezoidal rule):

>>> res = cc.simulate(model, duration=0.002)      # 200 steps of 1e-5 s
>>> res.support_forces.shape, res.contact_state.shape
((200, 24), (200, 36))
>>> e = res.energies
>>> bool(abs(e["kinetic"] + e["strain"] + e["rayleigh_dissipation"] - e["support_work"]) < 1e-6 * e["support_work"])
True

Invalid input raises :class:`ModelError` naming the key, the value and what is allowed:

>>> model.with_overrides({"casing.nu": 0.7})
Traceback (most recent call last):
...
cablecasing_core.errors.ModelError: casing.nu = 0.7: must be a number in [-0.999, 0.4999]

A model is read-only (``model.data["casing"]["E"] = 1e9`` raises ``TypeError``): a change is a
validated copy, as above. Warnings are :class:`ModelWarning` (``cc.ModelWarning``; a run's solver
warnings :class:`SolverWarning`, one of them), to filter as one. Also at this level:
:func:`static_state` (an installed model at rest) and :func:`body_buckling` (a body's buckling load,
:class:`Buckling`); the other public names are in their modules (``cablecasing_core.nvh``,
``.studies``, ``.records``, ``.identification``; docs/architecture.md lists them).

For a step-by-step engine (the FMU's), see :class:`~cablecasing_core.timedomain.engine.Engine`.
"""

from __future__ import annotations

from importlib import import_module as _import_module
from importlib import metadata as _metadata

from .errors import CableCasingError, ModelError, ModelWarning, PlausibilityWarning, SimulationError, SolverWarning
from .model import BodySpec, Model, default_model, load_model, model_from_dict

# The solvers are imported when first used (PEP 562): importing them pulls in scipy's solvers and
# the numba kernels (about 0.5 s), which a command such as ``cablecasing static`` or ``cablecasing
# keys`` does not need all of.
_LAZY = {
    "modes": ".frequency.modal",
    "natural_frequencies": ".frequency.modal",
    "trfam": ".frequency.trfam",
    "trfam_matrix": ".frequency.trfam",
    "SimulationResult": ".timedomain.simulation",
    "StaticState": ".timedomain.static_state",
    "static_state": ".timedomain.static_state",
    "body_buckling": ".timedomain.body_storage",
    "Buckling": ".structure.buckling",
    "contact_episodes": ".timedomain.simulation",
    "simulate": ".timedomain.simulation",
}


def __getattr__(name):
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(_import_module(_LAZY[name], __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))


try:
    __version__ = _metadata.version("cablecasing")
except _metadata.PackageNotFoundError:  # a copy that is not installed (e.g. bundled in the FMU)
    __version__ = "0.0.0+unknown"

__all__ = [
    "BodySpec",
    "Buckling",
    "CableCasingError",
    "Model",
    "ModelError",
    "ModelWarning",
    "PlausibilityWarning",
    "SimulationError",
    "SimulationResult",
    "SolverWarning",
    "StaticState",
    "__version__",
    "body_buckling",
    "contact_episodes",
    "default_model",
    "load_model",
    "model_from_dict",
    "modes",
    "natural_frequencies",
    "simulate",
    "static_state",
    "trfam",
    "trfam_matrix",
]
