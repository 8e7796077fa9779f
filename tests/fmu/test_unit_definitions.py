"""build_fmu.py's table of units (``UNITS``: unit -> SI base-unit exponents, the modelDescription's
UnitDefinitions) holds every unit the model schema gives a key, an input or an output: a unit added
to the schema fails here, not first when an FMU is built (``SystemExit`` in
``complete_description``)."""

from cablecasing_core.model import schema


def test_every_unit_of_the_schema_has_a_unit_definition(build_fmu, clipped_specimen):
    units = {spec.unit for spec in schema.SCHEMA.values() if spec.unit}  # ("": a word or Boolean key)
    units |= {unit for _, _, unit in schema.INPUT_KINDS}
    units |= {schema.input_spec(name)[0] for name in schema.inputs_of(clipped_specimen)}
    units |= {schema.output_spec(name)[0] for name in schema.outputs_of(clipped_specimen)}
    assert {"Pa", "N.m.s/rad", "m/s2", "J"} <= units  # (keys, inputs, outputs and clip outputs all read)
    missing = sorted(units - set(build_fmu.UNITS))
    assert not missing, f"units of the schema without an entry in build_fmu.UNITS: {missing}"


def test_the_unit_definitions_are_the_si_base_units_of_each_unit(build_fmu):
    """Each entry's exponents, checked by dimensional analysis on a few derived units (N = kg m/s2,
    Pa = N/m2, J = N m, Hz = 1/s)."""
    n = build_fmu.UNITS["N"]
    assert n == {"kg": 1, "m": 1, "s": -2}
    assert build_fmu.UNITS["Pa"] == {**n, "m": n["m"] - 2}
    assert build_fmu.UNITS["J"] == build_fmu.UNITS["N.m"] == {**n, "m": n["m"] + 1}
    assert build_fmu.UNITS["Hz"] == build_fmu.UNITS["1/s"] == {"s": -1}
