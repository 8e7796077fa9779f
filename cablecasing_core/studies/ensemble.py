"""Band levels as ensemble means over the seeds of the random excitation (docs/studies.md).

With contact, the model's response is chaotic (docs/time_domain.md, "How two records separate"):
two runs that differ by a rounding error, or by the time step, are two different draws of the same
random process after about 0.1 s. A single record's octave-band level then scatters from seed to seed
by 3-20 % (1 s records of the built-in scenario), so a design question (does a higher friction lower
the transmission?) or a numerical one (is dt = 1e-5 s fine enough?) is answered by the expected
band level, estimated as the mean over an ensemble of excitation seeds, with its standard error.

* :func:`seed_ensemble` runs the model once per seed (member ``s`` is exactly the single run with
  the varied random excitations' seeds set by :func:`seed_overrides`) and returns the band RMS of one
  support output per member (:class:`Ensemble`: mean, standard error, t confidence interval).
* :func:`paired_difference` compares two ensembles run on the same seeds: the relative difference
  of their means per band, r = (mean a - mean b) / mean b, and its standard error.
* :meth:`Ensemble.save` / :func:`load_ensemble` / :func:`pool_ensembles`: an ensemble run in parts
  (seed ranges on several machines, or on several days) is written to CSV with its settings, read
  back, and pooled into one, refused if the parts were not run with the same model and settings.

The runs go through the Monte-Carlo study's per-sample function and executor
(:func:`~cablecasing_core.studies.evaluators.default_evaluate`; serial, or dask.distributed), so an
ensemble member is computed exactly like a study sample.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from ..errors import ModelError
from ..model.schema import SUPPORT_OUTPUTS
from ..model.validators import Choice, integer, number, seconds
from .evaluators import DEFAULT_EVALUATE
from .executor import execute
from .octave import Bands, octave_bands


def random_excitations(model):
    """Names of the model's random excitations (``[scenario.excitation.NAME]`` with kind random), in
    the order of the model file."""
    return tuple(name for name, e in model.scenario["excitation"].items() if e["kind"] == "random")


def seed_overrides(model, seed, excitations=None):
    """The model overrides of ensemble member ``seed``: ``{"scenario.excitation.NAME.seed": int}``.

    With one varied excitation, member ``s`` gives it seed ``s``, so a member is the single run of the
    model with that seed. With k excitations, the j-th (0-based, in ``excitations`` order) gets
    ``s * k + j``: distinct records across excitations and members (two excitations with the same
    seed and band would get the same record, fully correlated).
    """
    names = _check_excitations(model, excitations)
    s = integer("seeds", seed, 0)
    k = len(names)
    return {f"scenario.excitation.{n}.seed": s * k + j for j, n in enumerate(names)}


@dataclass(frozen=True)
class Ensemble:
    """Band levels of one support output over an ensemble of excitation seeds.

    ``levels[i, b]`` is the RMS (N for a force, N.m for a moment) of ``output`` in band ``b`` of the run
    with seed ``seeds[i]``; the bands' edges are in Hz. ``contact_time[i, k]`` is the time (s) cable
    node ``k`` spent in contact in that run (the highest-contact-area histogram of Fig. 22; no
    columns without a cable). ``overrides`` are the model changes common to all members;
    ``settings`` the run settings ``duration``, ``dt``, ``skip`` (s) and ``model``, a fingerprint of
    the model data with the overrides applied (what :func:`pool_ensembles` requires to be equal; a
    tabulated excitation enters by its file name, not by the file's content).
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

    @property
    def contact_share(self):
        """Share of the pooled contact time per cable node (-, sums to 1; Fig. 22 over all seeds).
        One record's histogram is one draw of the chaotic contact; the pooled one is the expected
        shape. NaN where no member touched."""
        total = self.contact_time.sum()
        return self.contact_time.sum(axis=0) / total if total > 0 else np.full(self.contact_time.shape[1], np.nan)

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
        """Seed-to-seed coefficient of variation of a single record's band level (-)."""
        return self.se * math.sqrt(self.n) / self.mean

    def ci(self, confidence=0.95):
        """Student-t confidence interval of the mean per band, ``(low, high)`` (N or N.m)."""
        h = _t_factor(confidence, self.n) * self.se
        return self.mean - h, self.mean + h

    def as_rows(self, confidence=0.95):
        """One dict per band: label, f_low_hz, f_high_hz, mean, se, ci_low, ci_high, cv."""
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

    def save(self, path):
        """Write the members as CSV: the header ``seed, <band labels> (N or N.m), contact_time_node<k>_s``,
        then one line ``# cablecasing-ensemble {JSON}`` with the output, band edges (Hz), overrides and
        settings (a comment line: ``numpy.genfromtxt(path, delimiter=",", names=True)`` and
        ``pandas.read_csv(path, comment="#")`` read the table), then one row per member, written
        to 17 significant digits so that :func:`load_ensemble` gives back the same numbers."""
        nodes = self.contact_time.shape[1] if self.contact_time.size else 0
        header = ",".join(("seed",) + tuple(self.labels) + tuple(f"contact_time_node{k}_s" for k in range(nodes)))
        meta = {
            "format": 1,
            "output": self.output,
            "labels": list(self.labels),
            "f_low_hz": np.asarray(self.lower, float).tolist(),
            "f_high_hz": np.asarray(self.upper, float).tolist(),
            "overrides": _canonical(self.overrides),
            "settings": _canonical(self.settings),
        }
        parts = [self.seeds[:, None], self.levels] + ([self.contact_time] if nodes else [])
        with open(path, "w", encoding="utf-8") as f:
            f.write(header + "\n" + _META + json.dumps(meta) + "\n")
            np.savetxt(f, np.column_stack(parts), delimiter=",", fmt=["%d"] + ["%.17g"] * (len(self.labels) + nodes))


def load_ensemble(path):
    """Read an ensemble written by :meth:`Ensemble.save` (``cablecasing ensemble --out``).

    Raises :class:`ModelError` naming the file when it is missing or is not such a CSV.
    """
    try:
        f = open(path, encoding="utf-8")
    except OSError as e:
        raise ModelError("path", str(path), f"must be a readable ensemble CSV ({e.strerror})") from None
    with f:
        columns, meta_line = f.readline().strip().split(","), f.readline()
        if not meta_line.startswith(_META):
            raise ModelError(
                "path",
                str(path),
                "must be a CSV written by Ensemble.save or 'cablecasing ensemble "
                "--out' (its second line is not the '# cablecasing-ensemble' line)",
            )
        try:
            meta = json.loads(meta_line[len(_META) :])
            labels, output = tuple(meta["labels"]), meta["output"]
            overrides, settings = meta["overrides"], meta["settings"]
            lower, upper = np.array(meta["f_low_hz"], float), np.array(meta["f_high_hz"], float)
            table = np.loadtxt(f, delimiter=",", ndmin=2)  # the rows after the settings line
        except (ValueError, KeyError, TypeError) as e:  # JSONDecodeError is a ValueError
            raise ModelError(
                "path", str(path), f"must be an unaltered ensemble CSV ({type(e).__name__}: {e})"
            ) from None
    nb = len(labels)
    if table.shape[1] != len(columns) or len(columns) < 1 + nb:
        raise ModelError("path", str(path), f"must have the {len(columns)} columns of its header in every row")
    return Ensemble(
        table[:, 0].astype(int),
        output,
        labels,
        lower,
        upper,
        table[:, 1 : 1 + nb],
        overrides,
        table[:, 1 + nb :],
        settings,
    )


def pool_ensembles(ensembles):
    """One ensemble of the members of several, sorted by seed.

    ``ensembles`` is a sequence of :class:`Ensemble` objects or paths of their CSV files
    (:func:`load_ensemble`). They must have the same output, bands, overrides and settings (model,
    duration, dt, skip), and no seed twice. Pooling parts run on different machines is sound for the
    statistics; single records may differ between machines after ~0.1 s (docs/time_domain.md).
    """
    parts = [load_ensemble(e) if isinstance(e, (str, os.PathLike)) else e for e in ensembles]
    if not parts or not all(isinstance(e, Ensemble) for e in parts):
        raise ModelError("ensembles", ensembles, "must be a non-empty sequence of Ensemble objects or CSV paths")
    first = parts[0]
    for i, e in enumerate(parts[1:], 1):
        for name, mine, theirs in (
            ("output", e.output, first.output),
            (
                "bands",
                (e.labels, e.lower.tolist(), e.upper.tolist()),
                (first.labels, first.lower.tolist(), first.upper.tolist()),
            ),
            ("overrides", _canonical(e.overrides), _canonical(first.overrides)),
            ("settings", _canonical(e.settings), _canonical(first.settings)),
            ("contact_time columns", e.contact_time.shape[1:], first.contact_time.shape[1:]),
        ):
            if mine != theirs:
                raise ModelError(
                    f"ensembles[{i}].{name}", mine, f"must equal that of ensembles[0], {theirs}, to pool them"
                )
    seeds = np.concatenate([e.seeds for e in parts])
    unique, count = np.unique(seeds, return_counts=True)
    twice = unique[count > 1].tolist()
    if twice:
        raise ModelError("seeds", twice, "must each be in one of the pooled ensembles only")
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
        first.settings,
    )


_META = "# cablecasing-ensemble "


def _canonical(value):
    """``value`` as JSON would give it back (tuples become lists; what save/load round-trips)."""
    return json.loads(json.dumps(value, sort_keys=True, default=str))


def _fingerprint(model):
    """A short hash of the model's data (SI values after overrides), equal for equal models."""
    text = json.dumps(model.data, sort_keys=True, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class PairedDifference:
    """Relative difference of two ensembles' mean band levels on the same seeds (-), per band.

    ``r = (mean a - mean b) / mean b``; ``se`` is its standard error from the paired members
    (ratio-estimator linearisation, see :func:`paired_difference`).
    """

    labels: tuple
    r: np.ndarray
    se: np.ndarray
    n: int

    def ci(self, confidence=0.95):
        """Student-t confidence interval of r per band, ``(low, high)`` (-)."""
        h = _t_factor(confidence, self.n) * self.se
        return self.r - h, self.r + h


def paired_difference(a, b):
    """Relative difference of the mean band levels of ``a`` against ``b`` and its standard error.

    ``a`` and ``b`` are :class:`Ensemble` objects run on the same seeds (or arrays ``(n, bands)`` whose
    rows are paired; the standard error is NaN for one pair). Per band,
    ``r = (mean a - mean b) / mean b``: the relative change of the expected level. Its standard
    error comes from the linearisation of the ratio estimator, ``e_i = (a_i - b_i) - r b_i``,
    ``SE(r) = sd(e) / (sqrt(n) mean b)``; pairing removes the part of the scatter that the excitation
    record explains in both.

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
        labels, a, b = a.labels, a.levels, b.levels
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    if a.ndim != 2 or a.shape != b.shape or a.shape[0] < 1:
        raise ModelError("a, b", f"shapes {a.shape}, {b.shape}", "must be equal (n, bands) arrays with n >= 1 pairs")
    n, mb = len(a), b.mean(axis=0)
    if np.any(mb <= 0):
        raise ModelError("b", mb.tolist(), "must have a positive mean level in every band")
    r = (a.mean(axis=0) - mb) / mb
    se = np.std((a - b) - r * b, axis=0, ddof=1) / math.sqrt(n) / mb if n > 1 else np.full_like(r, np.nan)
    return PairedDifference(tuple(labels or (f"band{i + 1}" for i in range(a.shape[1]))), r, se, n)


def seed_ensemble(
    model=None,
    seeds=8,
    *,
    output="casing.B.Fz",
    bands="table3",
    duration=None,
    dt=None,
    skip=0.05,
    overrides=None,
    excitations=None,
    scheduler="serial",
    n_workers=None,
    progress=False,
):
    """Band levels of a support output over an ensemble of excitation seeds.

    Parameters
    ----------
    model : Model, str or None
        The model (a :class:`~cablecasing_core.model.Model`, a TOML path, or None for the built-in
        specimen); its ``[scenario]`` drives every member.
    seeds : int or sequence of int
        ``n`` gives seeds 1..n (n >= 2); or the seeds themselves (unique, >= 0).
    output : str
        Support output, e.g. ``"casing.B.Fz"`` (N) or ``"casing.B.Mx"`` (N.m).
    bands : str or Bands
        Band set (``"table3"``, ``"octave"``, ``"third"``; Hz).
    duration, dt : float, optional
        s; default the scenario's.
    skip : float
        s; start of each record left out of the band levels (fade-in and first transient).
    overrides : dict, optional
        ``{dotted.key: value}`` applied to every member (e.g. ``{"contact.friction": 0.2}``).
    excitations : sequence of str, optional
        Random excitations whose seed is varied (default all; :func:`seed_overrides`).
    scheduler : "serial", None, "local", address or distributed.Client
        As :func:`~cablecasing_core.studies.study.run_study`; default ``"serial"``: members one
        after the other in this process (no dask needed).
    progress : bool
        Show a tqdm bar of the members done (if tqdm is installed).

    Returns
    -------
    Ensemble

    Raises
    ------
    ModelError
        For bad input (before any run), and when a member fails (naming its seed and the error).
    """
    from ..model import Model, load_model

    if model is None or isinstance(model, (str, os.PathLike)):
        model = load_model(model)
    if not isinstance(model, Model):
        raise ModelError("model", model, "must be a Model, a model TOML path or None (the built-in specimen)")
    seeds = _check_seeds(seeds)
    seconds("duration", duration, none_ok=True)
    seconds("dt", dt, none_ok=True)
    seconds("skip", skip, zero_ok=True)
    Choice(*SUPPORT_OUTPUTS)("output", output)
    band_set = bands if isinstance(bands, Bands) else octave_bands(bands)
    names = _check_excitations(model, excitations)
    overrides = dict(overrides or {})
    clash = sorted(set(overrides) & set(seed_overrides(model, 0, names)))
    if clash:
        raise ModelError("overrides", clash, "must not set the seeds that the ensemble varies")
    base = model.with_overrides(overrides)  # validates the overrides before any run
    length = (base.scenario["duration"] if duration is None else duration) - skip
    narrow = int(np.argmin(band_set.upper - band_set.lower))
    need = 1.0 / (band_set.upper[narrow] - band_set.lower[narrow])
    if not length >= need:  # the band would hold less than one FFT bin (octave_rms refuses it)
        raise ModelError(
            "duration",
            duration,
            f"must leave at least {need:.4g} s after skip = {skip} s for band "
            f"{band_set.labels[narrow]!r} ({band_set.lower[narrow]:g}-{band_set.upper[narrow]:g} Hz)",
        )
    step = base.scenario["dt"] if dt is None else dt
    if not 0.5 / step >= band_set.upper.max():  # (octave_rms's rule, checked before the runs)
        raise ModelError(
            "dt",
            dt,
            f"must be at most {0.5 / band_set.upper.max():.4g} s so that every band lies "
            f"below the Nyquist frequency (highest edge {band_set.upper.max():g} Hz)",
        )
    kwargs = {
        "duration": duration,
        "dt": dt,
        "skip": skip,
        "model": base,
        "output": output,
        "bands": band_set,
        "contact_time": True,
    }
    nodes = base.geometry["n_elements"] + 1 if "cable" in base.bodies else 0
    outputs = tuple(band_set.labels) + tuple(f"contact_time_{k}" for k in range(nodes))
    todo = [(i, seed_overrides(base, s, names)) for i, s in enumerate(seeds)]

    rows = _Rows()
    bar = _progress_bar(len(todo), progress)
    try:
        execute(todo, DEFAULT_EVALUATE, kwargs, outputs, rows, bar, scheduler, n_workers)
    finally:
        bar.close()
    failed = [(seeds[i], r["error"]) for i, r in sorted(rows.rows.items()) if r["status"] != "ok"]
    if failed:
        s, err = failed[0]
        raise ModelError("seeds", s, f"run failed ({err}); {len(failed)} of {len(seeds)} members failed")
    table = np.array([[rows.rows[i][o] for o in outputs] for i in range(len(seeds))])
    nb = len(band_set.labels)
    settings = {
        "duration": float(base.scenario["duration"] if duration is None else duration),
        "dt": float(step),
        "skip": float(skip),
        "model": _fingerprint(base),
    }
    return Ensemble(
        np.array(seeds),
        output,
        tuple(band_set.labels),
        np.asarray(band_set.lower, float),
        np.asarray(band_set.upper, float),
        table[:, :nb],
        overrides,
        table[:, nb:],
        settings,
    )


class _NoBar:
    def update(self, n):
        pass

    def close(self):
        pass


def _progress_bar(total, progress):
    """A tqdm bar of the members done (tqdm comes with the ``study`` extra; without it, none)."""
    if progress:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            return _NoBar()
        return tqdm(total=total, unit="run", desc="ensemble", dynamic_ncols=True)
    return _NoBar()


class _Rows:
    """Collects the executor's rows by index (the ``writer`` of ``executor.execute``)."""

    def __init__(self):
        self.rows = {}

    def write(self, row):
        self.rows[row["index"]] = row


def _t_factor(confidence, n):
    number("confidence", confidence, gt=0, lt=1)
    return stats.t.ppf(0.5 + confidence / 2, n - 1) if n > 1 else np.nan


def _check_seeds(seeds):
    if isinstance(seeds, (int, np.integer)) and not isinstance(seeds, bool):
        if seeds < 2:
            raise ModelError("seeds", seeds, "must be at least 2 (seeds 1..n), or a sequence of seeds")
        return list(range(1, int(seeds) + 1))
    try:
        out = [integer("seeds", s, 0) for s in seeds]
    except TypeError:
        raise ModelError("seeds", seeds, "must be a count n >= 2 or a sequence of non-negative integer seeds") from None
    if len(out) < 2 or len(set(out)) != len(out):
        raise ModelError("seeds", seeds, "must hold at least 2 seeds, each once")
    return out


def _check_excitations(model, excitations):
    available = random_excitations(model)
    if excitations is None:
        if not available:
            raise ModelError(
                "scenario.excitation",
                sorted(model.scenario["excitation"]),
                "an ensemble over seeds needs at least one excitation of kind 'random'",
            )
        return available
    names = tuple(excitations)
    bad = [n for n in names if n not in available]
    if bad or not names or len(set(names)) != len(names):
        raise ModelError(
            "excitations",
            list(names),
            "must name random excitations of the model, each once: " + (", ".join(available) or "(the model has none)"),
        )
    return names
