"""The model file: loading and validation, the validated :class:`Model`, the built-in specimens."""
from .load import BodySpec, Model, default_model, load_model, model_from_dict

__all__ = ["BodySpec", "Model", "default_model", "load_model", "model_from_dict"]
