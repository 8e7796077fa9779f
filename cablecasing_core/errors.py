"""Exceptions raised by cablecasing_core.

Every input error names the offending field (a dotted key path such as ``casing.E``), the value
that was given, and what is allowed, so that a user can fix a model file without reading code.
"""


class CableCasingError(Exception):
    """Base class of all errors raised by this package."""


class ModelError(CableCasingError, ValueError):
    """A model file, parameter or scenario that cannot work.

    Parameters
    ----------
    key : str
        Dotted path of the offending field, e.g. ``"casing.d_inner"``.
    value : object
        The value that was given.
    allowed : str
        Plain-language statement of what is allowed.
    """

    def __init__(self, key, value, allowed):
        self.key = key
        self.value = value
        self.allowed = allowed
        super().__init__(f"{key} = {value!r}: {allowed}")


class SimulationError(CableCasingError, RuntimeError):
    """A time-domain run that cannot continue (blow-up, excessive penetration).

    The message says when (time in s), where (body and node) and what happened.
    """


class PlausibilityWarning(UserWarning):
    """A model that is valid but likely a mistake (a route of 850 m: points in mm?, a bend tighter
    than ten casing diameters, ...; ``structure.route_summary.plausibility_warnings``)."""
