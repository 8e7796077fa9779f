"""cablecasing_core: vibration model of a gear-shift cable inside a curved casing.

Units are SI throughout (m, kg, s, N, Pa, rad; frequencies in Hz where named ``*_hz``).

>>> import cablecasing_core as cc
>>> model = cc.load_model()                  # the built-in specimen (None) or a TOML path
>>> f = cc.natural_frequencies(model, "casing", count=5)   # Hz
"""
from .model import Model, default_model, load_model, model_from_dict
from .errors import CableCasingError, ModelError, SimulationError
from .frequency.trfam import trfam, trfam_matrix
from .frequency.modal import modes, natural_frequencies
from .timedomain.simulation import SimulationResult, contact_episodes, simulate

__all__ = ["CableCasingError", "Model", "ModelError", "SimulationError", "contact_episodes", "default_model",
           "load_model", "model_from_dict", "modes", "natural_frequencies", "SimulationResult", "simulate", "trfam",
           "trfam_matrix"]
