"""Changes of a model's keys, and whose fault a refusal is: the one rule the command line's
``--set`` (:mod:`..cli.assignments`) and the FMU's parameters (``fmu_src/CableCasing.py``) share.

:func:`with_changes` applies ``{key: (flag, value[, as typed])}`` through
:meth:`~.model.Model.with_overrides` and, when the model refuses, names the change to blame: the key
refused when it is one of the changes (``--set casing.E = -1: ...``; with an empty flag, as the FMU
gives them, the key alone: ``casing.E = -1.0: ...``), else the change(s) that make the model fail
alone, with the model's value it conflicts with (``casing.d_outer = 0.0035: conflicts with
casing.d_inner = 0.004 of the model <built-in>: must be smaller than ...``), so that a message
never names a key that nobody set (a model file's random band, which is no FMU parameter) as the
one that is invalid.
"""

from __future__ import annotations

from ..errors import NOT_SHOWN, ModelError, excerpt


def with_changes(model, changes, check=None):
    """``model`` with ``changes`` ({key: (flag, value)} or (flag, value, the value as typed)) applied
    and validated. A refused value is named by the flag that gave it (``--set casing.E = -1: ...``;
    an empty flag names the key alone), as typed when it is the value of the key refused; a key the
    model gives that the changes make invalid (its random band above the Nyquist frequency of a
    changed ``scenario.dt``) is named as the change that did it, with the model's value it
    conflicts with. ``check(model)``, if given, is a check of the changed model beyond its keys'
    (``ensemble``'s :func:`~cablecasing_core.studies.evaluators.check_model_runs`: a tension above
    the casing's buckling load): what it refuses is named the same way (the model without changes
    is checked too, its error as it is)."""
    if not changes:
        if check is not None:
            check(model)
        return model
    checked = False  # (whether the keys passed and the check refused)
    try:
        changed = model.with_overrides({key: change[1] for key, change in changes.items()})
        if check is not None:
            checked = True
            check(changed)
        return changed
    except ModelError as exc:
        given = next((k for k in changes if _same_key(str(exc.key), k)), None)
        if given is not None:
            value = exc.value
            if exc.key == given and exc.value is not NOT_SHOWN:
                value = _shown(changes[given])
            raise ModelError(_named(changes[given][0], exc.key), value, exc.allowed) from None
        raise _conflict(model, changes, exc, check, checked) from None


def _named(flag, key):
    """How a change is named: ``--set casing.E``, or ``casing.E`` without a flag."""
    return f"{flag} {key}" if flag else str(key)


def _shown(change):
    """The value of a change (flag, value[, typed]) as it is echoed: as typed when known."""
    return change[2] if len(change) > 2 else change[1]


def _same_key(refused, key):
    """Whether the refused key is the changed ``key``, a component of it (``band[1]``) or the vector
    it is a component of (``loads.gravity`` of ``loads.gravity.z``)."""
    return refused == key or refused.startswith((key + ".", key + "[")) or key.startswith(refused + ".")


def _conflict(model, changes, exc, check=None, checked=False):
    """The error ``exc`` of a key of the model that ``changes`` did not set, named as the change(s)
    that make that key fail alone (else those that fail alone for other keys; all of them if none
    does; the model's own error, as it is, when it fails ``check`` without them, ``checked``: ``exc``
    is the check's): the value of the model it conflicts with and what is allowed; for a time step,
    the largest that the model's excitations allow."""
    if checked:
        try:
            check(model)
        except ModelError as own:  # (the model fails without the changes: none of them is to blame)
            return own

    def refused(key):  # (the error of the change alone, or None)
        try:
            changed = model.with_overrides({key: changes[key][1]})
            if checked:
                check(changed)
        except ModelError as alone:
            return alone
        return None

    alone = {k: refused(k) for k in changes}
    failing = [k for k in changes if alone[k] is not None]
    # the changes that fail alone on the key refused, not those failing for a reason of their own (a
    # cable.d beyond the bore and a scenario.dt beyond the band's Nyquist: the bore's error is
    # cable.d's alone; the step's is said once cable.d is mended), else all that fail, else all
    culprits = [k for k in failing if str(alone[k].key) == str(exc.key)] or failing or list(changes)
    allowed = exc.allowed
    if culprits == ["scenario.dt"]:
        allowed = _step_rule(model, changes["scenario.dt"][1]) or allowed
    shown = "" if exc.value is NOT_SHOWN else f" = {excerpt(exc.value)}"
    what = f"conflicts with {exc.key}{shown} of the model {model.source}: {allowed}"
    if len(culprits) == 1:
        return ModelError(_named(changes[culprits[0]][0], culprits[0]), _shown(changes[culprits[0]]), what)
    named = ", ".join(f"{_named(changes[k][0], k)}={excerpt(_shown(changes[k]))}" for k in culprits)
    return ModelError(named, NOT_SHOWN, what)


def _step_rule(model, dt):
    """What the excitations of ``model`` allow of a time step ``dt`` (s) that they refuse (the
    message ``--dt`` gives: the largest step allowed), or None."""
    from ..timedomain.scenario import ScenarioMotion

    try:
        ScenarioMotion(model, dt)
    except ModelError as exc:
        return exc.allowed if exc.key == "dt" else None
    return None
