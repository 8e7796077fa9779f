"""The paper's findings (Sections 4.2-4.4, 5) in the default scenario, from ensembles of short runs.

With contact the response is chaotic (docs/time_domain.md): a single 0.2 s record is one draw, and
the band levels of two draws of the same setting scatter by 10-30 % (bands 1, 8, 9 the most). A
claim checked on one record can flip when any bit of the computation changes (a kernel edit, another
CPU): the earlier single-record version of these tests did once (friction lower in 7 of 9 bands
instead of >= 8). So every claim here is about **ensemble means over the seeds of the casing's
random excitation** (``scenario.excitation.casing_random.seed`` = 1..8; 1..16 for the contact
test), 0.2 s each, **paired**: every setting runs the same seeds, and a claim is tested on the N
per-seed differences.

Threshold, the same for every claim: the ensemble-mean difference must exceed K = 2 of its standard
errors (SE = sd of the paired differences / sqrt(N)), i.e. be significant, not merely of the right
sign. Every asserted claim has a measured margin of at least 4.77 SE on the test's seeds 1..8 (the
casing modulus in octave 9) and at least 6.36 SE on an independent set, seeds 9..16 (the axial
excitation in octave 1). The chance that a fresh draw of 8 seeds (which is what any change of the
computation's bits amounts to) lands below 2 SE when the true margin is 4.77 is P(t_7 < 2 |
noncentrality 4.77) = 6e-3 (noncentral t, 7 degrees of freedom); for 6.36 it is 6e-5. (The margins
quoted with each test were re-measured on 2026-12-08 at 097c9fc, after the default specimen's records
had moved with the route's own spline, the events inside the step and the kernels without fastmath;
the paragraph "What changed" below is from before those.) A claim that does
not reach this on both sets is stated as measured but not asserted. The
margins (effect in SE, 0.2 s runs) are given with each test as "seeds 1..8 (seeds 9..16)";
``python tests/studies/test_findings.py`` prints them.

What changed against the single-record version, measured on 16 seeds (0.2 s; 8 seeds of 1 s for
friction):
* friction 0.05 -> 0.2 does *not* lower the overall RMS of casing.B.Fz significantly: -0.015 N of
  0.94 N, 0.4 SE (0.2 s); -0.12 N of 1.0 N, 1.9 SE (1 s records). The single record's 1.29 -> 0.90 N
  was one draw. What is robust is the low-frequency part: octaves 1-3 (11-88 Hz) drop to 0.41, 0.46,
  0.60 of their level (7.5, 15.7, 12.8 SE over 16 seeds), octave 5 to 0.84 (5.8 SE over 16 seeds,
  3.2 on seeds 9..16: not asserted); octave 4 is unchanged (-0.3 SE) and octaves 6-9 change by
  +3..+14 % at 0.2 s (0.2-1.5 SE) and by -6..0 % at 1 s (under 0.8 SE): within the scatter. The paper's
  "lower in all bands" holds here only below 88 Hz (and 177-355 Hz) - fewer than the single record's
  "8 of 9".
* octave 1 alone (11-22 Hz, 1-2 FFT lines of a 0.15 s record, the widest scatter) is not asserted
  for friction: 4.2 SE on seeds 1..8 then, 4.89 now.
* contact concentrates in the bends in most draws (>= 0.9 of the contact time in 14 of 16), but in
  about 1 draw in 8 the straight run between the bends touches the wall too (from about 0.08 s on),
  and there the bends hold only 0.63 of the contact time and the peak is on the straight run. The
  assertion is on the pooled ensemble with thresholds that also hold for such draws.
"""

import functools

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.nvh.bands import window_options
from cablecasing_core.studies import octave_rms

pytestmark = pytest.mark.slow  # ensembles of 1 s records

T = 0.2  # s per run
SEEDS = tuple(range(1, 9))  # seeds of the sweeps
SEEDS_CONTACT = tuple(range(1, 17))
K = 2.0  # a claim holds when its ensemble-mean effect exceeds K standard errors
SEED_KEY = "scenario.excitation.casing_random.seed"
AMP_KEY = "scenario.excitation.cable_axial.amplitude"
SETTINGS = {
    "base": {},
    "mu_lo": {"contact.friction": 0.05},
    "mu_hi": {"contact.friction": 0.2},
    "amp_lo": {AMP_KEY: 2.5e-4},
    "amp_hi": {AMP_KEY: 1e-3},
    "cab_lo": {"cable.E": 3e10},
    "cab_hi": {"cable.E": 8.5e10},
    "cas_lo": {"casing.E": 2e9},
    "cas_hi": {"casing.E": 1e10},
}


@functools.cache
def run(setting, seed):
    """RMS of casing.B.Fz after the 0.01 s fade-in (0.02 s on), its nine Table 3 band levels after
    0.05 s through the rectangular window (the skip and window of docs/studies.md's findings table,
    computed before ``default_evaluate``'s whole periods and Hann's window), the contact time per
    cable node, curvature."""
    r = cc.simulate(cc.load_model().with_overrides({**SETTINGS[setting], SEED_KEY: seed}), duration=T)
    F = r.support_force("casing.B.Fz")
    total = float(np.sqrt(np.mean(F[r.time > 0.02] ** 2)))
    bands = octave_rms(F[r.time > 0.05], 1.0 / (r.time[1] - r.time[0]), **window_options("boxcar")).rms
    return total, bands, r.contact_time.copy(), r.curvature.copy()


def ensemble(setting, seeds=SEEDS):
    """Per-seed totals (N,) and band levels (N, 9) of a setting."""
    runs = [run(setting, s) for s in seeds]
    return np.array([x[0] for x in runs]), np.array([x[1] for x in runs])


def margin(a, b):
    """Paired difference of the ensemble means, mean(a - b), in standard errors (per column)."""
    d = np.asarray(a, float) - np.asarray(b, float)
    return d.mean(axis=0) / (d.std(axis=0, ddof=1) / np.sqrt(len(d)))


@pytest.fixture(scope="module")
def ens():
    return {name: ensemble(name) for name in SETTINGS}


def low_octaves(bands):
    """Combined RMS of octaves 1-3 (11-88 Hz), per seed."""
    return np.sqrt(np.sum(bands[:, :3] ** 2, axis=1))


# ------------------------------------------------------------------------------------------------
# Friction (Section 4.4, Fig. 23(e)): measured ratio of ensemble means mu 0.2 / 0.05 per band,
#   seeds 1..8:  0.37 0.52 0.63 1.07 0.80 1.04 0.97 1.11 1.08
#   seeds 9..16: 0.35 0.49 0.56 0.95 0.82 1.20 1.19 1.28 0.89
# margins (SE) 5.0 9.0 5.8 -1.3 5.3 -0.4 0.3 -1.0 -0.4 (3.3 13.7 15.5 1.5 4.5 -2.2 -1.4 -2.3 0.5);
# overall RMS 0.977 -> 0.936 N, 0.8 SE (0.892 -> 0.916 N, -0.5 SE): not a claim that holds.


def test_friction_lowers_transmission(ens):
    # 11-88 Hz together: 0.59 (0.54) of the level at mu = 0.05; margin 6.9 SE (17.0)
    assert margin(low_octaves(ens["mu_lo"][1]), low_octaves(ens["mu_hi"][1])) > K


def test_friction_lowers_the_low_octaves(ens):
    # octaves 2, 3 (22-88 Hz): margins 9.0, 5.8 SE (13.7, 15.5); octave 1 (5.0 SE (3.3)) and octave 5
    # (5.3 (4.5)) are lower too, but not by a margin that cannot flip (P(t_7 < 2) = 0.11 and 0.012
    # at the lesser margin of each)
    z = margin(ens["mu_lo"][1], ens["mu_hi"][1])
    assert np.all(z[1:3] > K), z


# ------------------------------------------------------------------------------------------------
# Axial (longitudinal) excitation of the cable, Fig. 23(d).


def test_longitudinal_cable_excitation_raises_transmission(ens):
    # overall RMS, 2.5e-4 -> 5e-4 m: 0.127 -> 0.891 N, margin 30.0 SE (20.3)
    assert margin(ens["base"][0], ens["amp_lo"][0]) > K


def test_axial_excitation_raises_every_band(ens):
    # 2.5e-4 -> 1e-3 m: every band up by 7-47x; smallest margin 12.9 SE, octave 1 (6.4, octave 1)
    z = margin(ens["amp_hi"][1], ens["amp_lo"][1])
    assert np.all(z > K), z


# ------------------------------------------------------------------------------------------------
# Moduli (Fig. 23(a), (b)): ratio of ensemble means of the band levels, high / low bound, seeds 1..8:
#   casing E 1e10 / 2e9:    0.95 1.43 1.51 0.81 0.53 1.44 6.38 3.75 2.53
#   cable E 8.5e10 / 3e10:  1.36 1.96 2.07 0.99 1.35 1.06 1.24 1.21 1.12
# (seeds 9..16: 1.03 1.54 1.44 0.66 0.49 1.27 5.29 4.22 3.14 and 1.54 1.98 1.85 1.00 1.43 1.05 1.27
# 1.36 1.38)
# The casing modulus dominates the 7th-9th octaves and raises them, as in the paper; over octaves
# 1-6 the cable modulus matters about as much as the casing's here (the paper found it weaker),
# because in this model the cable's axial excitation is the main source (see docs/studies.md).


def test_casing_modulus_dominates_and_raises_the_high_octaves(ens):
    hi = slice(6, 9)  # octaves 7, 8, 9 (710-5680 Hz)
    # a stiffer casing transmits more up there: margins 9.9, 13.6, 4.8 SE (13.0, 14.0, 10.8)
    z = margin(ens["cas_hi"][1][:, hi], ens["cas_lo"][1][:, hi])
    assert np.all(z > K), z
    # and matters more than the cable's modulus: per seed, mean |log ratio| over octaves 7-9 of the
    # casing minus that of the cable: 1.44 against 0.35 (1.46 against 0.38); margin 5.7 SE (6.9)
    cas = np.abs(np.log(ens["cas_hi"][1][:, hi] / ens["cas_lo"][1][:, hi])).mean(axis=1)
    cab = np.abs(np.log(ens["cab_hi"][1][:, hi] / ens["cab_lo"][1][:, hi])).mean(axis=1)
    assert margin(cas, cab) > K


# ------------------------------------------------------------------------------------------------
# Where the contact is (Fig. 22): the contact time per cable node, pooled over 16 seeds.


def bend_runs(curvature):
    """Node indices of the bends: the runs of nodes whose curvature exceeds 0.3 of the maximum
    (above 2 1/m; the two bends, 16 of 36 nodes)."""
    curved = np.flatnonzero(curvature > 0.3 * curvature.max())
    return np.split(curved, np.flatnonzero(np.diff(curved) > 1) + 1)


def test_contact_concentrates_in_the_bends():
    runs = [run("base", s) for s in SEEDS_CONTACT]
    ct = np.array([r[2] for r in runs])
    k = runs[0][3]
    first, second = bend_runs(k)
    assert len(first) + len(second) < 0.5 * len(k)
    assert np.all(ct.sum(axis=1) > 0)  # every draw touches
    pooled = ct.sum(axis=0)
    # the bends (under half of the nodes) hold most of the contact time: 0.92 pooled, 0.90-0.94 per
    # seed (2026-12-08); in earlier records two draws of 16 (seeds 6, 16) had the straight run between
    # the bends touch too, the bends' share 0.63 and 0.64 there, so 0.6 holds even if every draw were
    # of that kind
    assert pooled[np.concatenate([first, second])].sum() > 0.6 * pooled.sum()
    # more of it in the second bend (R = 0.2 m, out of plane) than in the tightest, first one (about
    # 0.14 m): the cable's axial excitation at end A is turned by the first bend into lateral motion
    # that loads the second. Pooled 0.64 against 0.28 of the contact time; second > first in every
    # one of the 16 draws (and in the earlier records' straight-run ones)
    assert pooled[second].sum() > pooled[first].sum()


if __name__ == "__main__":  # the measured margins quoted above
    np.set_printoptions(precision=2, suppress=True, linewidth=150)
    for seeds in (SEEDS, tuple(range(9, 17))):
        e = {name: ensemble(name, seeds) for name in SETTINGS}
        b = {name: v[1] for name, v in e.items()}
        print(f"seeds {seeds[0]}..{seeds[-1]}")
        print("  friction, ratio of means per band:", b["mu_hi"].mean(0) / b["mu_lo"].mean(0))
        print("  friction, margin per band (SE):  ", margin(b["mu_lo"], b["mu_hi"]))
        low_lo, low_hi = low_octaves(b["mu_lo"]), low_octaves(b["mu_hi"])
        rms_lo, rms_hi = e["mu_lo"][0], e["mu_hi"][0]
        print(
            f"  friction, octaves 1-3 together: ratio {low_hi.mean() / low_lo.mean():.2f}, margin "
            f"{margin(low_lo, low_hi):.1f} SE; overall RMS: {rms_lo.mean():.3f} -> {rms_hi.mean():.3f} N, "
            f"margin {margin(rms_lo, rms_hi):.1f} SE"
        )
        base, amp_lo = e["base"][0], e["amp_lo"][0]
        print(
            f"  axial amplitude, overall RMS {amp_lo.mean():.3f} -> {base.mean():.3f} N, margin "
            f"{margin(base, amp_lo):.1f} SE"
        )
        print("  axial amplitude 1e-3 / 2.5e-4, ratio per band:", b["amp_hi"].mean(0) / b["amp_lo"].mean(0))
        print("  axial amplitude, margin per band:", margin(b["amp_hi"], b["amp_lo"]))
        print("  casing E, ratio per band:", b["cas_hi"].mean(0) / b["cas_lo"].mean(0))
        print("  casing E, margin per band:", margin(b["cas_hi"], b["cas_lo"]))
        print("  cable E, ratio per band: ", b["cab_hi"].mean(0) / b["cab_lo"].mean(0))
        hi = slice(6, 9)
        cas = np.abs(np.log(b["cas_hi"][:, hi] / b["cas_lo"][:, hi])).mean(axis=1)
        cab = np.abs(np.log(b["cab_hi"][:, hi] / b["cab_lo"][:, hi])).mean(axis=1)
        print(
            f"  octaves 7-9, mean |log ratio| casing {cas.mean():.2f}, cable {cab.mean():.2f}, margin "
            f"{margin(cas, cab):.1f} SE"
        )
    runs = [run("base", s) for s in SEEDS_CONTACT]
    ct = np.array([r[2] for r in runs])
    first, second = bend_runs(runs[0][3])
    bends = np.concatenate([first, second])
    print("contact, seeds 1..16: bends' share per seed", ct[:, bends].sum(1) / ct.sum(1))
    later = int(np.sum(ct[:, second].sum(1) > ct[:, first].sum(1)))
    print(
        f"  pooled: bends {ct[:, bends].sum() / ct.sum():.2f}, first bend {ct[:, first].sum() / ct.sum():.2f}, "
        f"second bend {ct[:, second].sum() / ct.sum():.2f}; second > first in {later} of {len(ct)} draws"
    )
