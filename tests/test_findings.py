"""The paper's findings (Sections 4.2-4.4, 5) in the default scenario, from short runs.

Model result (0.2 s, built-in specimen): RMS of casing.B.Fz after the fade-in is 1.29, 0.96, 0.90 N
for friction 0.05, 0.1, 0.2; contact occurs only in the two bends. The contact time peaks in the
second bend (R = 0.2 m, out of plane) rather than in the tightest one (about 0.14 m): the cable's
axial excitation at end A is turned by the first bend into lateral motion that loads the second.
"""
import numpy as np
import pytest

import cablecasing_core as cc

T = 0.2


def rms_fz(over):
    r = cc.simulate(cc.load_model().with_overrides(over), duration=T)
    F = r.support_force("casing.B.Fz")[r.time > 0.02]     # after the 0.01 s fade-in
    return float(np.sqrt(np.mean(F**2))), r


@pytest.fixture(scope="module")
def base():
    return rms_fz({})


def test_friction_lowers_transmission(base):
    lo, _ = rms_fz({"contact.friction": 0.05})
    hi, _ = rms_fz({"contact.friction": 0.2})
    assert hi < base[0] < lo          # 0.2 < 0.15 (default) < 0.05


def test_longitudinal_cable_excitation_raises_transmission(base):
    small, _ = rms_fz({"scenario.excitation.cable_axial.amplitude": 2.5e-4})
    assert small < base[0]


def test_contact_concentrates_in_the_bends(base):
    r = base[1]
    ct, k = r.contact_time, r.curvature
    assert ct.sum() > 0
    curved = k > 0.3 * k.max()                  # the two bends (curvature above 2 1/m)
    assert ct[curved].sum() > 0.9 * ct.sum()    # nearly all contact time is in the bends
    assert k[np.argmax(ct)] > 0.5 * k.max()     # and the peak sits in a strongly curved part


# ------------------------------------------------------------------------------------------------
# Per octave band (Table 3), one-at-a-time sweeps over the paper's bounds (Section 4.4), 0.2 s runs.
# Model results (ratio of band levels high/low setting, bands 1..9), measured:
#   friction 0.2 / 0.05:       0.44 0.40 0.65 1.34 0.66 0.63 0.76 0.92 0.97  -> lower in 8 of 9 bands
#   cable E 8.5e10 / 3e10:     1.36 2.74 2.15 2.14 2.19 2.44 3.82 3.16 1.76
#   casing E 1e10 / 2e9:       0.90 1.25 1.39 0.72 0.59 1.47 6.59 5.09 4.90
#   axial amplitude 1e-3 / 2.5e-4 m: larger in every band
# So: friction lowers transmission in all bands but the 4th (88-177 Hz), where the stiffer stick
# phase passes more force; the casing modulus dominates the 7th-9th octaves and raises them, as in
# the paper; over octaves 1-6 the cable modulus matters more than the casing's here (the paper
# found it weaker), because in this model the cable's axial excitation is the main source and a
# stiffer cable drives the bends harder (see docs/studies.md).

from cablecasing_core.studies.montecarlo import default_evaluate  # noqa: E402


def bands(over):
    return np.array(list(default_evaluate(over, duration=0.2, skip=0.05).values()))


@pytest.fixture(scope="module")
def sweeps():
    return {k: bands(v) for k, v in {
        "mu_lo": {"contact.friction": 0.05}, "mu_hi": {"contact.friction": 0.2},
        "cab_lo": {"cable.E": 3e10}, "cab_hi": {"cable.E": 8.5e10},
        "cas_lo": {"casing.E": 2e9}, "cas_hi": {"casing.E": 1e10},
        "amp_lo": {"scenario.excitation.cable_axial.amplitude": 2.5e-4},
        "amp_hi": {"scenario.excitation.cable_axial.amplitude": 1e-3}}.items()}


def test_friction_lowers_most_bands(sweeps):
    lower = sweeps["mu_hi"] < sweeps["mu_lo"]
    assert lower.sum() >= 8


def test_axial_excitation_raises_every_band(sweeps):
    assert np.all(sweeps["amp_hi"] > sweeps["amp_lo"])


def test_casing_modulus_dominates_and_raises_the_high_octaves(sweeps):
    hi = slice(6, 9)                                        # octaves 7, 8, 9 (710-5680 Hz)
    cas = np.log(sweeps["cas_hi"][hi] / sweeps["cas_lo"][hi])
    cab = np.log(sweeps["cab_hi"][hi] / sweeps["cab_lo"][hi])
    assert np.all(cas > 0)                                  # a stiffer casing transmits more up there
    assert np.mean(np.abs(cas)) > np.mean(np.abs(cab))      # and matters more than the cable's modulus
