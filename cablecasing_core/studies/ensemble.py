"""Band levels over an ensemble of excitation seeds, as data (docs/studies.md): :class:`Ensemble`
(mean, standard error, t confidence interval per band), its CSV file (:meth:`Ensemble.save`,
:func:`load_ensemble`, :func:`pool_ensembles` of parts run apart) and the paired comparison of two
ensembles run on the same seeds (:func:`paired_difference`). The runs are made by
:func:`~cablecasing_core.studies.ensemble_runs.seed_ensemble`.

With contact, the model's response is chaotic (docs/time_domain.md, "How two records separate"):
two runs that differ by a rounding error, or by the time step, are two different draws of the same
random process after about 0.1 s. A single record's octave-band level then scatters from seed to seed
by 9-26 % (the coefficient of variation of 1 s records of the built-in scenario through Hann's
window, docs/time_domain.md "The mesh"), so a design question (does a higher friction lower
the transmission?) or a numerical one (is dt = 1e-5 s fine enough?) is answered by the expected
band level, estimated as the mean over an ensemble of excitation seeds, with its standard error.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from ..errors import ModelError
from ..model.limits import MAX_ENSEMBLE_SEED
from ..model.validators import number


@dataclass(frozen=True)
class Ensemble:
    """Band levels of one support output over an ensemble of excitation seeds.

    "Level" here is a band's RMS in the output's unit, not a level in dB (the name is kept: the
    saved files and the scripts that read them use it; :attr:`rms` is the same array under the name
    :class:`~cablecasing_core.nvh.bands.BandRMS` gives it). What each attribute holds:

    * ``seeds`` (n,): the members' excitation seeds; ``output``: the support output (``casing.B.Fz``);
    * ``labels`` (m,), ``lower`` and ``upper`` (m,): the bands' names and edges (Hz; ``BandRMS``
      calls them the same, :meth:`as_rows` ``f_low_hz`` and ``f_high_hz``);
    * ``levels`` (n, m): ``levels[i, b]`` is the RMS (N for a force, N.m for a moment; not dB) of
      ``output`` in band ``b`` of the run with seed ``seeds[i]``; :attr:`mean`, :attr:`se`,
      :meth:`ci` are in that unit too, :attr:`cv` is a ratio (-);
    * ``contact_time`` (n, nodes): ``contact_time[i, k]`` is the time (s) cable node ``k`` spent in
      contact in that run (the highest-contact-area histogram of Fig. 22; no columns without a cable);
    * ``overrides``: the model changes common to all members;
    * ``settings``: the run settings ``duration``, ``dt``, ``skip`` (s), ``window``, ``model``, a
      fingerprint of the model data with the overrides applied (what :func:`pool_ensembles` requires to
      be equal; a tabulated excitation enters by its file's content, not its path), and ``base_model``,
      the fingerprint of the model before the overrides (what a paired comparison of two ensembles,
      ``pool --against``, requires to be equal);
    * ``warnings``: the seed of each member whose run warned (a contact Newton that did not converge in
      some steps, a tolerance not met: docs/time_domain.md) to its messages, joined by `` | ``;
      members that warned nothing are not in it.
    """

    seeds: np.ndarray
    output: str
    labels: tuple
    lower: np.ndarray
    upper: np.ndarray
    levels: np.ndarray
    overrides: dict = field(default_factory=dict)
    contact_time: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    settings: dict = field(default_factory=dict)
    warnings: dict = field(default_factory=dict)

    @property
    def contact_share(self):
        """Share of the pooled contact time per cable node (-, sums to 1; Fig. 22 over all seeds).
        One record's histogram is one draw of the chaotic contact; the pooled one is the expected
        shape. NaN where no member touched."""
        total = self.contact_time.sum()
        return self.contact_time.sum(axis=0) / total if total > 0 else np.full(self.contact_time.shape[1], np.nan)

    @property
    def rms(self):
        """The band RMS of each member (N or N.m, not dB): :attr:`levels` under its other name."""
        return self.levels

    @property
    def n(self):
        """Number of members."""
        return len(self.seeds)

    @property
    def mean(self):
        """Ensemble mean of each band level (N or N.m)."""
        return self.levels.mean(axis=0)

    @property
    def se(self):
        """Standard error of the mean per band, sd / sqrt(n) (N or N.m); NaN for one member."""
        if self.n < 2:
            return np.full(self.levels.shape[1], np.nan)
        return self.levels.std(axis=0, ddof=1) / math.sqrt(self.n)

    @property
    def cv(self):
        """Seed-to-seed coefficient of variation of a single record's band level (-); NaN where the
        mean is 0 (an output zero by construction, such as a moment that no spring carries)."""
        positive = self.mean > 0
        return np.where(positive, self.se * math.sqrt(self.n) / np.where(positive, self.mean, 1.0), np.nan)

    def ci(self, confidence=0.95):
        """Student-t confidence interval of the mean per band, ``(low, high)`` (N or N.m), its lower
        end at least 0: a band level is not negative, so neither is its mean, and the interval cut
        to [0, inf) holds the mean whenever the whole one does (few seeds of a scattered band gave
        negative levels before)."""
        h = _t_factor(confidence, self.n) * self.se
        return np.maximum(self.mean - h, 0.0), self.mean + h

    def as_rows(self, confidence=0.95):
        """One dict per band: ``band`` (its label), ``f_low_hz`` and ``f_high_hz`` (its edges, Hz),
        ``mean``, ``se``, ``ci_low``, ``ci_high`` (the band RMS's mean over the members, its standard
        error and confidence interval: N or N.m, not dB), ``cv`` (-)."""
        lo, hi = self.ci(confidence)
        return [
            {
                "band": lab,
                "f_low_hz": float(a),
                "f_high_hz": float(b),
                "mean": float(m),
                "se": float(s),
                "ci_low": float(c0),
                "ci_high": float(c1),
                "cv": float(v),
            }
            for lab, a, b, m, s, c0, c1, v in zip(
                self.labels, self.lower, self.upper, self.mean, self.se, lo, hi, self.cv
            )
        ]

    def save(self, path: str | os.PathLike) -> None:
        """Write the members as CSV: the header ``seed, <band label> [<unit>], ..., contact_time_node<k>_s``
        (``oct1 [N]``: the output's unit, N or N.m; a file written before the units were named has
        the bare labels, and reads the same),
        then one line ``# cablecasing-ensemble {JSON}`` with the output, band edges (Hz), overrides,
        settings and the members' warnings by seed (a comment line: ``numpy.genfromtxt(path,
        delimiter=",", names=True)`` and ``pandas.read_csv(path, comment="#")`` read the table),
        then one row per member, written to 17 significant digits so that :func:`load_ensemble` gives
        back the same numbers."""
        from ..records import unit_of

        nodes = self.contact_time.shape[1] if self.contact_time.size else 0
        unit = unit_of(self.output)
        bands = tuple(f"{b} [{unit}]" if unit else b for b in self.labels)
        header = ",".join(("seed",) + bands + tuple(f"contact_time_node{k}_s" for k in range(nodes)))
        meta = {
            "format": 1,
            "output": self.output,
            "labels": list(self.labels),
            "f_low_hz": np.asarray(self.lower, float).tolist(),
            "f_high_hz": np.asarray(self.upper, float).tolist(),
            "overrides": _canonical(self.overrides),
            "settings": _canonical(self.settings),
        }
        if self.warnings:
            meta["warnings"] = {str(int(s)): str(w) for s, w in sorted(self.warnings.items())}
        parts = [self.seeds[:, None], self.levels] + ([self.contact_time] if nodes else [])
        from ..files import atomic_path

        with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8") as f:
            f.write(header + "\n" + _META + json.dumps(meta) + "\n")
            np.savetxt(f, np.column_stack(parts), delimiter=",", fmt=["%d"] + ["%.17g"] * (len(self.labels) + nodes))


def load_ensemble(path: str | os.PathLike) -> Ensemble:
    """Read an ensemble written by :meth:`Ensemble.save` (``cablecasing ensemble --out``).

    Raises :class:`ModelError` naming the file and what is wrong (without quoting its lines) when it
    is missing or is not such a CSV: the settings line must be the JSON object :meth:`Ensemble.save`
    writes (output, bands with finite edges 0 < f_low < f_high, overrides and settings tables), the
    rows finite numbers, the seeds whole numbers 0 to 2**53 (exact in the file's doubles), the levels
    and contact times zero or positive.
    """
    from ..files import read_csv_table

    names, table = read_csv_table(path, "path", min_rows=1)
    shown = str(path)
    with open(path, encoding="utf-8") as f:  # (read_csv_table checked it: a UTF-8 text file)
        f.readline()
        meta_line = f.readline()
    if not meta_line.startswith(_META):
        raise ModelError(
            "path",
            shown,
            "must be a CSV written by Ensemble.save or 'cablecasing ensemble --out' (its second line is not the "
            "'# cablecasing-ensemble' line)",
        )
    meta = _settings_line(shown, meta_line[len(_META) :])
    from ..records import unit_of

    labels, nb = tuple(meta["labels"]), len(meta["labels"])
    unit = unit_of(str(meta["output"]))
    named = all(  # (each band 'label [unit]' with the output's unit, or a bare label: a file saved before)
        n in (lab, f"{lab} [{unit}]") for n, lab in zip(names[1 : 1 + nb], labels)
    )
    if len(names) < 1 + nb or names[0] != "seed" or not named:
        raise ModelError(
            "path",
            shown,
            "its header must be 'seed' and the band labels of its settings line, each with its output's unit",
        )
    seeds = table[:, 0]
    bad = np.nonzero((seeds != np.round(seeds)) | (seeds < 0) | (seeds > MAX_ENSEMBLE_SEED))[0]
    if bad.size:
        raise ModelError("path", shown, f"data row {bad[0] + 1}: the seed must be a whole number from 0 to 2**53")
    neg = np.argwhere(table[:, 1:] < 0)
    if neg.size:
        r, c = neg[0]
        raise ModelError(
            "path", shown, f"data row {r + 1}, column {c + 2}: band levels and contact times must be zero or positive"
        )
    return Ensemble(
        seeds.astype(np.int64),
        meta["output"],
        labels,
        np.array(meta["f_low_hz"], float),
        np.array(meta["f_high_hz"], float),
        table[:, 1 : 1 + nb],
        meta["overrides"],
        table[:, 1 + nb :],
        _with_window(meta["settings"]),
        _warnings_by_seed(shown, meta.get("warnings", {}), seeds),
    )


def _with_window(settings):
    """An ensemble's settings with its window: one saved before the window was a setting
    (2026-12-06; it has a skip but no window) took the rectangular one, so it pools with a part of
    ``--window boxcar``."""
    if "skip" in settings and "window" not in settings:
        return {**settings, "window": "boxcar"}
    return settings


def _warnings_by_seed(shown, given, seeds):
    """The settings line's ``warnings`` ({"seed": "messages"}) as {seed: messages}, each seed one of
    the file's members (a :class:`ModelError` otherwise)."""
    members = set(int(s) for s in seeds)
    out = {}
    if not isinstance(given, dict):
        raise ModelError("path", shown, "must be an unaltered ensemble CSV: its warnings are not a table")
    for key, text in given.items():
        if not (isinstance(key, str) and key.isdigit() and int(key) in members and isinstance(text, str)):
            raise ModelError(
                "path", shown, "must be an unaltered ensemble CSV: its warnings must name members' seeds with text"
            )
        out[int(key)] = text
    return out


def _settings_line(shown, text):
    """The settings of an ensemble CSV's second line, checked (a :class:`ModelError` otherwise)."""
    from ..model.schema import is_output

    def bad(what):
        return ModelError("path", shown, f"must be an unaltered ensemble CSV: its '# cablecasing-ensemble' line {what}")

    if len(text) > 1 << 20:
        raise bad("is longer than 1 MB")
    try:
        meta = json.loads(text)
    except RecursionError:
        raise bad("nests too deeply") from None
    except ValueError as e:  # (JSONDecodeError: its position, not the content)
        raise bad(f"is not JSON (at character {getattr(e, 'pos', '?')})") from None
    if not isinstance(meta, dict):
        raise bad("is not a JSON object")
    for key, kind in (("output", str), ("labels", list), ("f_low_hz", list), ("f_high_hz", list)):
        if not isinstance(meta.get(key), kind):
            raise bad(f"has no {key} ({kind.__name__})")
    for key in ("overrides", "settings"):
        if not isinstance(meta.get(key, {}), dict):
            raise bad(f"has a {key} that is not a table")
        meta.setdefault(key, {})
    if not is_output(meta["output"]):  # (OUTPUTS, or a clip's casing.clip<i>.Fx .. Mz)
        raise bad("names an output that is not one of the model's outputs")
    nb = len(meta["labels"])
    if not nb or not all(isinstance(b, str) and b for b in meta["labels"]):
        raise bad("has no band labels")
    edges = []
    for key in ("f_low_hz", "f_high_hz"):
        v = meta[key]
        if len(v) != nb or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v):
            raise bad(f"has {key} that are not {nb} numbers")
        edges.append(np.array(v, float))
    lo, hi = edges
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(lo > 0) and np.all(hi > lo)):
        raise bad("has band edges that are not finite with 0 < f_low < f_high")
    _check_settings(meta["settings"], bad)
    return meta


def _check_settings(settings, bad):
    """The run settings of an ensemble CSV's settings line (what ``seed_ensemble`` writes: duration,
    dt in s, > 0; skip in s, >= 0; window, a name of ``nvh.bands.WINDOW_NAMES``; the model
    fingerprints, text): ``bad(what)`` (a :class:`ModelError`) for the first that is not."""
    from ..nvh.bands import WINDOW_NAMES

    def number(x):
        return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)

    for key, ok, allowed in (
        ("duration", lambda x: number(x) and x > 0, "a number of s > 0"),
        ("dt", lambda x: number(x) and x > 0, "a number of s > 0"),
        ("skip", lambda x: number(x) and x >= 0, "a number of s >= 0"),
        ("window", lambda x: x in WINDOW_NAMES, "one of " + ", ".join(WINDOW_NAMES)),
        ("model", lambda x: isinstance(x, str), "text (a model's fingerprint)"),
        ("base_model", lambda x: isinstance(x, str), "text (a model's fingerprint)"),
    ):
        if key in settings and not ok(settings[key]):
            raise bad(f"has settings {key} = {json.dumps(settings[key])}: must be {allowed}")


def pool_ensembles(ensembles: Sequence[Ensemble | str | os.PathLike]) -> Ensemble:
    """One ensemble of the members of several, sorted by seed.

    ``ensembles`` is a sequence of :class:`Ensemble` objects or paths of their CSV files
    (:func:`load_ensemble`). They must have the same output, bands, overrides and settings (model,
    duration, dt, skip, window), and no seed twice (a :class:`ModelError` names the part, by its path
    where it came from a file, the seeds and the part that holds them too). Pooling parts run on
    different machines is sound for the statistics; single records may differ between machines after
    ~0.1 s (docs/time_domain.md).
    """
    parts = [load_ensemble(e) if isinstance(e, (str, os.PathLike)) else e for e in ensembles]
    if not parts or not all(isinstance(e, Ensemble) for e in parts):
        raise ModelError("ensembles", ensembles, "must be a non-empty sequence of Ensemble objects or CSV paths")
    first = parts[0]
    # (a part by its file where it came from one: the CLI's pool names the files, not this argument)
    names = [str(e) if isinstance(e, (str, os.PathLike)) else f"ensembles[{i}]" for i, e in enumerate(ensembles)]
    for i, e in enumerate(parts[1:], 1):
        for name, mine, theirs in (
            ("output", e.output, first.output),
            (
                "bands",
                (e.labels, e.lower.tolist(), e.upper.tolist()),
                (first.labels, first.lower.tolist(), first.upper.tolist()),
            ),
            ("overrides", _canonical(e.overrides), _canonical(first.overrides)),
            ("contact_time columns", e.contact_time.shape[1:], first.contact_time.shape[1:]),
        ):
            if mine != theirs:
                raise ModelError(f"{names[i]}.{name}", mine, f"must equal that of {names[0]}, {theirs}, to pool them")
        mine, theirs = _canonical(_run_settings(e)), _canonical(_run_settings(first))
        differ = sorted(k for k in set(mine) | set(theirs) if mine.get(k) != theirs.get(k))
        if differ:  # (each setting that differs by name, with both values: not the whole table cut off)
            raise ModelError(
                f"{names[i]}.settings",
                ", ".join(differ),
                f"must equal those of {names[0]} to pool them: "
                + "; ".join(
                    f"its {_setting(k)} is {mine.get(k)!r}, that of {names[0]} {theirs.get(k)!r}" for k in differ
                )
                + (
                    " (to compare two models rather than pool them: paired_difference, or pool --against --other-model)"
                    if "model" in differ
                    else ""
                ),
            )
    _check_seeds_once(ensembles, parts, names)
    seeds = np.concatenate([e.seeds for e in parts])
    order = np.argsort(seeds, kind="stable")
    return Ensemble(
        seeds[order],
        first.output,
        first.labels,
        first.lower,
        first.upper,
        np.concatenate([e.levels for e in parts])[order],
        first.overrides,
        np.concatenate([e.contact_time for e in parts])[order],
        first.settings if all("base_model" in e.settings for e in parts) else _run_settings(first),
        {s: w for e in parts for s, w in e.warnings.items()},
    )


def _run_settings(ens):
    """An ensemble's settings without ``base_model``, which its ``model`` fingerprint (the model with
    the same overrides) implies, and which parts saved before it was kept do not have."""
    return {k: v for k, v in ens.settings.items() if k != "base_model"}


def _setting(key):
    """A setting's name as a message gives it (the ``model`` fingerprint said as what it is)."""
    return "model (the fingerprint of the model data with its overrides)" if key == "model" else key


def unpaired_setting(a, b):
    """The first run setting (``duration``, ``dt``, ``skip``, ``window``) in which the ensembles ``a``
    and ``b`` differ, as ``(name, a's value, b's value)``, or None: what two ensembles compared on
    the same seeds (:func:`paired_difference`, ``pool --against``) must share. The model
    fingerprints (``model``, ``base_model``) may differ, as may a setting that an override changed
    between the two declares (``scenario.dt`` set to another value in one: what they compare)."""
    changed = {k for k in set(a.overrides) | set(b.overrides) if a.overrides.get(k) != b.overrides.get(k)}
    mine, theirs = (
        {k: v for k, v in _canonical(e.settings).items() if k not in ("model", "base_model")} for e in (a, b)
    )
    for k in sorted(set(mine) | set(theirs)):
        if mine.get(k) != theirs.get(k) and f"scenario.{k}" not in changed:
            return k, mine.get(k), theirs.get(k)
    return None


def _check_seeds_once(given, parts, names):
    """Each seed in one of the pooled ``parts`` only, and once in it: else a :class:`ModelError` naming
    the part (``path`` and its file where it came from one, as :func:`load_ensemble` names it; else
    ``ensembles[i].seeds``), the seeds and the part that holds them too (a file given twice as such)."""

    def refuse(j, seeds, other):
        where = "more than once" if other is None else f"that {names[other]} holds too"
        why = "each member must have a seed of its own" if other is None else "each seed must be in one part only"
        if isinstance(given[j], (str, os.PathLike)):
            return ModelError(
                "path", names[j], f"holds seed{'s' if len(seeds) > 1 else ''} {_shown(seeds)} {where}: {why}"
            )
        return ModelError(f"{names[j]}.seeds", seeds, f"{why} (the part holds {_shown(seeds)} {where})")

    held = []
    for j, e in enumerate(parts):
        unique, count = np.unique(e.seeds, return_counts=True)
        if np.any(count > 1):
            raise refuse(j, unique[count > 1].tolist(), None)
        mine = set(unique.tolist())
        for i, theirs in enumerate(held):
            both = sorted(mine & theirs)
            if not both:
                continue
            paths = [given[k] for k in (i, j) if isinstance(given[k], (str, os.PathLike))]
            if len(paths) == 2 and os.path.realpath(paths[0]) == os.path.realpath(paths[1]):
                raise ModelError("path", names[j], f"is given twice (parts {i + 1} and {j + 1}): give each part once")
            raise refuse(j, both, i)
        held.append(mine)


def _shown(seeds):
    """Seeds as a message shows them: ``1, 2, 3`` (at most ten, then ``...``)."""
    return ", ".join(str(int(s)) for s in seeds[:10]) + (", ..." if len(seeds) > 10 else "")


_META = "# cablecasing-ensemble "


def _canonical(value):
    """``value`` as JSON would give it back (tuples become lists; what save/load round-trips)."""
    return json.loads(json.dumps(value, sort_keys=True, default=str))


@dataclass(frozen=True)
class PairedDifference:
    """Relative difference of two ensembles' mean band levels on the same seeds (-), per band.

    ``r = (mean a - mean b) / mean b``; ``se`` is its standard error from the paired members
    (ratio-estimator linearisation, see :func:`paired_difference`): r, se and :meth:`ci` say how
    large the change is. ``p`` (-) is the two-sided p-value of the paired t test of no change
    (H0: mean a = mean b, r = 0) on the per-seed levels: whether there is a change is read from p,
    not from r / se or whether the interval holds 0 (their standard error is taken at the estimated
    r, not at r = 0, and rejects a true "no change" more often than it says: 6-8 % at a nominal 5 %
    for skewed levels of 6 seeds; the t test's p is exact for normal differences a_i - b_i).
    """

    labels: tuple
    r: np.ndarray
    se: np.ndarray
    n: int
    p: np.ndarray

    def ci(self, confidence=0.95):
        """Student-t confidence interval of r per band, ``(low, high)`` (-), its lower end at least
        -1: r = -1 is a mean level of 0, and a level is not negative (as :meth:`Ensemble.ci` cuts
        at 0; the interval so cut holds r whenever the whole one does)."""
        h = _t_factor(confidence, self.n) * self.se
        return np.maximum(self.r - h, -1.0), self.r + h


def paired_difference(a: Ensemble | np.ndarray, b: Ensemble | np.ndarray) -> PairedDifference:
    """Relative difference of the mean band levels of ``a`` against ``b`` and its standard error.

    ``a`` and ``b`` are :class:`Ensemble` objects run on the same seeds, output, bands and run settings
    (duration, dt, skip, window: a :class:`ModelError` names a setting that differs and both values,
    :func:`unpaired_setting`; the models may differ, two model files of two designs, as may a setting
    an override changed between them declares) (or arrays ``(n, bands)`` whose rows are paired; the
    standard error is NaN for one pair; r and its standard error are NaN in a
    band where every level of ``b`` is 0, an output the setting leaves at rest). Per band,
    ``r = (mean a - mean b) / mean b``: the relative change of the expected level. Its standard
    error comes from the linearisation of the ratio estimator, ``e_i = (a_i - b_i) - r b_i``,
    ``SE(r) = sd(e) / (sqrt(n) mean b)``; pairing removes the part of the scatter that the excitation
    record explains in both.

    ``p`` is the two-sided p-value of the paired t test of no change, ``scipy.stats.ttest_rel(a, b)``
    per band (H0: mean a = mean b, the test on the differences a_i - b_i, n - 1 degrees of freedom):
    the answer to "is there a change", where r and its interval say how large it is. It is NaN for
    one pair, and in a band where a_i - b_i is the same in every member (zero variance, the t
    statistic 0/0 or x/0: r and se still say the change).

    Not the mean of the per-seed ratios ``mean(a_i / b_i) - 1``: that estimates E[a/b] - 1, which is
    positive even for two runs of the same distribution (E[1/b] > 1/E[b]) when chaos leaves them
    nearly uncorrelated; a floor of up to 5 % in the scatter of 1 s records that does not shrink
    with n.
    """
    labels = None
    if isinstance(a, Ensemble) and isinstance(b, Ensemble):
        if a.output != b.output or a.labels != b.labels:
            raise ModelError(
                "b",
                f"{b.output} {b.labels[0]}..{b.labels[-1]}",
                f"must have the output and bands of a ({a.output} {a.labels[0]}..{a.labels[-1]})",
            )
        if not np.array_equal(a.seeds, b.seeds):
            raise ModelError("b.seeds", b.seeds.tolist(), f"must be the seeds of a, {a.seeds.tolist()}, in that order")
        unpaired = unpaired_setting(a, b)
        if unpaired:
            k, mine, theirs = unpaired
            raise ModelError(
                f"b.settings['{k}']",
                theirs,
                f"must equal that of a, {mine!r}, to pair them: two ensembles compared on the same seeds must "
                "share duration, dt, skip and window (they may differ by the model and its overrides, and by "
                "a setting an override changed between them declares, such as scenario.dt)",
            )
        labels, a, b = a.labels, a.levels, b.levels
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    if a.ndim != 2 or a.shape != b.shape or a.shape[0] < 1:
        raise ModelError("a, b", f"shapes {a.shape}, {b.shape}", "must be equal (n, bands) arrays with n >= 1 pairs")
    if np.any(a < 0) or np.any(b < 0):
        raise ModelError("a, b", "a negative level", "must be band levels (RMS, at least 0)")
    n, mb = len(a), b.mean(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):  # (a band b never reaches: NaN, docstring)
        r = np.where(mb > 0, (a.mean(axis=0) - mb) / mb, np.nan)
        se = np.std((a - b) - r * b, axis=0, ddof=1) / math.sqrt(n) / mb if n > 1 else np.full_like(r, np.nan)
    p = np.full_like(r, np.nan)
    d = a - b
    defined = np.ptp(d, axis=0) > 0 if n > 1 else np.zeros(len(r), bool)  # (else the t statistic is 0/0 or x/0)
    if defined.any():
        p[defined] = stats.ttest_rel(a[:, defined], b[:, defined], axis=0).pvalue
    return PairedDifference(tuple(labels or (f"band{i + 1}" for i in range(a.shape[1]))), r, se, n, p)


def _t_factor(confidence, n):
    number("confidence", confidence, gt=0, lt=1)
    return stats.t.ppf(0.5 + confidence / 2, n - 1) if n > 1 else np.nan
