"""The model file: its schema (every key with type, default, unit, allowed range and description),
validation built from it, the validated :class:`Model`, and the built-in specimens.

* :mod:`.schema` - THE schema (:func:`~.schema.lookup`), the support channels and the outputs;
* :mod:`.validators` - the one set of validators (also used for function arguments);
* :mod:`.validate` - a model file's tables checked with the schema;
* :mod:`.model` - :class:`Model`, :class:`BodySpec`;
* :mod:`.load` - TOML files and the built-in specimens (``specimens/default.toml``, ``installed.toml``).
"""

from .load import default_model, load_model, model_from_dict, specimen_names
from .model import BodySpec, Model

__all__ = ["BodySpec", "Model", "default_model", "load_model", "model_from_dict", "specimen_names"]
