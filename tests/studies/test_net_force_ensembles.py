"""A sum of support outputs (net.B.Fz, paths.Fz, a+b; docs/nvh.md "Net forces and paths") is an
output of a run, an ensemble and a study as any support output is: its band levels are those of
the summed samples, computed here independently from the two bodies' histories."""

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.errors import ModelError
from cablecasing_core.nvh.bands import octave_rms
from cablecasing_core.records import unit_of
from cablecasing_core.studies import seed_ensemble, seed_ensembles


def test_support_force_of_a_sum_is_the_sum_of_the_histories():
    res = cc.simulate(cc.default_model(), duration=0.02)
    both = res.support_force("casing.B.Fz") + res.support_force("cable.B.Fz")
    assert np.array_equal(res.support_force("net.B.Fz"), both)  # (the same additions in the same order)
    ends = sum(res.support_force(f"{b}.{e}.Fz") for b in ("casing", "cable") for e in ("A", "B"))
    np.testing.assert_allclose(res.support_force("paths.Fz"), ends, rtol=0, atol=1e-12 * np.abs(ends).max())
    with pytest.raises(ModelError, match="output"):
        res.support_force("net.C.Fz")
    with pytest.raises(ModelError, match="output"):
        res.support_force("casing.B.Fz+casing.B.Mx")  # (N and N.m do not add)


@pytest.mark.filterwarnings("ignore:.*fewer than 4 FFT lines")  # (0.15 s: the short record is the point, not oct1-2)
def test_an_ensemble_of_the_net_force_bands_the_summed_samples(tmp_path):
    """seed_ensembles gives casing.B.Fz and net.B.Fz from the same runs (as the report takes them):
    each member's levels are those of that seed's run, its forces added here independently."""
    from cablecasing_core.studies.ensemble_runs import seed_overrides

    model = cc.default_model()
    both = seed_ensembles(model, seeds=[1, 2], outputs=("casing.B.Fz", "net.B.Fz"), duration=0.2, skip=0.05)
    assert list(both) == ["casing.B.Fz", "net.B.Fz"] and both["net.B.Fz"].output == "net.B.Fz"
    assert unit_of("net.B.Fz") == "N" and unit_of("net.B.Mx") == "N.m" and unit_of("a+b") == ""
    for i, seed in enumerate((1, 2)):  # independently: the run of that seed, its two forces added
        res = cc.simulate(model.with_overrides(seed_overrides(model, seed)), duration=0.2)
        keep = res.time > 0.05 + 1e-9
        casing = res.support_force("casing.B.Fz")[keep]
        fs = 1.0 / (res.time[1] - res.time[0])
        for name, f in (("casing.B.Fz", casing), ("net.B.Fz", casing + res.support_force("cable.B.Fz")[keep])):
            expected = octave_rms(f, fs, "table3").rms
            # (the same samples through the same window: equal to rounding, 1e-12 of the largest band)
            np.testing.assert_allclose(both[name].levels[i], expected, rtol=0, atol=1e-12 * np.nanmax(expected))
        np.testing.assert_array_equal(both["net.B.Fz"].contact_time[i], res.contact_time)
    assert both["net.B.Fz"].settings == both["casing.B.Fz"].settings
    with pytest.raises(ModelError, match="output"):
        seed_ensemble(model, seeds=[1, 2], output="net.B.Fq", duration=0.2)
    for bad in ("net.B.Fz", (), ("net.B.Fz", "net.B.Fz")):
        with pytest.raises(ModelError, match="outputs"):
            seed_ensembles(model, seeds=[1, 2], outputs=bad, duration=0.2)


def test_the_study_command_takes_a_sum_as_its_output_and_names_a_wrong_one():
    from cablecasing_core.cli.study import study_output

    model = cc.default_model()
    assert study_output("net.B.Fz", model) == "net.B.Fz"
    assert study_output("casing.B.Fz+cable.B.Fz", model) == "casing.B.Fz+cable.B.Fz"
    with pytest.raises(ModelError, match="--output"):
        study_output("net.B.Fz+casing.B.Mx", model)  # (N and N.m)
    with pytest.raises(ModelError, match="did you mean"):
        study_output("casing.B.Fzz", model)  # (not a sum: the command's own message, with its guess)
