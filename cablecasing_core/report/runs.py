"""The runs of a report (``cablecasing report``, ``make demo``): one set, saved under the report's
folder, from which every figure and table is drawn.

* **Variants**: the model's scenario *with the cable drive* (as it is) and *without* it (the same
  scenario less its excitations on the cable: Figs. 20-21 compare the two). A model without an
  excitation on the cable has one variant.
* **Reference records**: one run per variant with the first seed, saved as
  ``records/<variant>.npz`` (every array, :meth:`SimulationResult.save`); the time histories, the
  scalograms (Figs. 20-21), the PSD, the apparent mass and the RMS table are computed from the saved
  files, read back.
* **Ensembles**: band levels of ``casing.B.Fz`` over the excitation seeds (``seed_ensemble``), one per
  variant, saved as ``bands_<variant>.csv``; their first member is the reference record's run
  (checked: the report states the largest difference of its band levels, zero when all is well).
* **Study**: a small Monte-Carlo study (Fig. 23) over the paper's parameters that the model has,
  saved as ``study/study.csv``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..model import Model
from ..model.schema import STUDY_OUTPUT
from ..studies import Ensemble

#: The output whose band levels, scalograms and spectra the report shows (Section 4.4: the support
#: force at casing end B in z, the schema's study output).
OUTPUT = STUDY_OUTPUT
#: What the transmission at B receives, shown beside :data:`OUTPUT` (band levels of the reference
#: records, their PSD): the casing's and the cable's end forces at B together (``records.derived_terms``;
#: docs/nvh.md, "Net forces and paths"), of a model with a cable.
NET_OUTPUT = "net.B.Fz"


@dataclass
class Variant:
    """One scenario of the report: ``key`` (file names), ``title``, its ``model``, the saved
    reference record ``record`` (path), the reference ``result`` (read back from it), the
    band-level ``ensemble`` of :data:`OUTPUT` (None without a random excitation), ``net_ensemble``,
    that of :data:`NET_OUTPUT` from the same runs (None also for a model without a cable), and
    ``net_bands``, the Table 3 band RMS (``BandRMS``, N) of the reference record's casing.B.Fz,
    cable.B.Fz and :data:`NET_OUTPUT` ({name: BandRMS}; None for a model without a cable)."""

    key: str
    title: str
    model: Model
    record: Path
    seed_overrides: dict = field(default_factory=dict)
    result: object = None
    ensemble: Ensemble | None = None
    member_check: float = float("nan")
    files: list = field(default_factory=list)
    net_bands: dict | None = None
    net_ensemble: Ensemble | None = None


def cable_excitations(model: Model) -> list[str]:
    """Names of the model's excitations that drive the cable."""
    return [n for n, e in model.scenario["excitation"].items() if e["target"].startswith("cable.")]


def without_cable_drive(model: Model) -> Model | None:
    """The model with its excitations on the cable removed (None when it has none)."""
    names = cable_excitations(model)
    return model.without_excitations(names, source=f"{model.source} without the cable drive") if names else None


def drive_harmonics(model: Model, f_max: float) -> list[float]:
    """The frequencies (Hz) of the harmonic excitations on the cable and their multiples up to f_max."""
    out = set()
    for n in cable_excitations(model):
        e = model.scenario["excitation"][n]
        if e["kind"] == "harmonic":
            out.update(k * e["frequency"] for k in range(1, int(f_max // e["frequency"]) + 1))
    return sorted(out)


def variants(model: Model, out: Path, first_seed: int) -> list[Variant]:
    """The report's variants (module docstring), each with the seed overrides of ``first_seed``."""
    from ..studies import random_excitations, seed_overrides

    bare = without_cable_drive(model)
    if bare is None:  # (no cable drive to take away: the one record is the model's scenario)
        v = [Variant("scenario", "the model's scenario", model, out / "records" / "scenario.npz")]
    else:
        v = [
            Variant("nodrive", "without the cable drive", bare, out / "records" / "nodrive.npz"),
            Variant("drive", "with the cable drive", model, out / "records" / "drive.npz"),
        ]
    for var in v:
        var.seed_overrides = seed_overrides(var.model, first_seed) if random_excitations(var.model) else {}
    return v


def run_variant(
    var: Variant, duration: float, seeds: list[int], skip: float, progress: bool, scheduler: str = "serial"
) -> None:
    """The reference record (saved, then read back), the band-level ensemble of one variant and, for
    a model with a cable, the reference record's band levels of the force into B (:data:`NET_OUTPUT`)
    and its ensemble from the same runs (on ``scheduler``: ``"serial"`` or ``"threads"``)."""
    from ..records import after_skip
    from ..studies import random_excitations, seed_ensembles
    from ..timedomain.simulation import SimulationResult, simulate

    model = var.model.with_overrides(var.seed_overrides)
    res = simulate(model, duration=duration, progress=progress)
    var.record.parent.mkdir(parents=True, exist_ok=True)
    res.save(var.record)
    var.result = SimulationResult.load(var.record)
    if "cable" in var.model.bodies:
        var.net_bands = net_bands(var.result.records(), skip)
    if random_excitations(var.model) and len(seeds) >= 2:
        outputs = (OUTPUT, NET_OUTPUT) if "cable" in var.model.bodies else (OUTPUT,)
        ens = seed_ensembles(
            var.model, seeds, outputs=outputs, duration=duration, skip=skip, progress=progress, scheduler=scheduler
        )
        var.ensemble, var.net_ensemble = ens[OUTPUT], ens.get(NET_OUTPUT)
        from ..nvh.bands import octave_rms

        r = var.result
        keep = after_skip(r.time, skip)
        # (the ensemble above warned of its bands' few lines: its member's check says nothing more)
        fs = 1.0 / (r.time[1] - r.time[0])
        mine = octave_rms(r.support_force(OUTPUT)[keep], fs, "table3", name=OUTPUT, warn_few_lines=False).rms
        var.member_check = float(np.max(np.abs(mine - var.ensemble.levels[0]) / var.ensemble.levels[0]))


def net_bands(rec, skip: float) -> dict:
    """Table 3 band RMS (N; Hann's window, as the report's ensembles) of casing.B.Fz, cable.B.Fz
    and their sum :data:`NET_OUTPUT` in the record ``rec`` (a run's, from t = 0) after ``skip`` s:
    ``{name: BandRMS}``; the sum's bands are those of the summed samples, as ``cablecasing bands
    --column net.B.Fz`` gives them."""
    from ..nvh.bands import octave_rms
    from ..records import after_skip

    keep = after_skip(rec.time, skip, rec.time[0])
    names = (*rec.terms(NET_OUTPUT), NET_OUTPUT)
    return {n: octave_rms(rec.column(n)[keep], rec.fs, "table3", name=n, warn_few_lines=False, unit="N") for n in names}


def fmu_check(outputs_csv, step: float, duration: float, model: Model | None = None) -> dict:
    """The FMU's outputs (``outputs_csv``, written by ``examples/demo.py`` from an fmpy run of the
    scenario's record sampled every ``step`` s) against the core driven by the same sampled record
    (``timedomain.simulation.simulate_sampled``): the largest deviation of each support output,
    relative to its largest value, over the run. Returns a summary for the report, which names the
    outputs' file by its name: it lies in the report's folder, and the report links it from there."""
    from ..model import load_model
    from ..model.schema import OUTPUTS, SUPPORT_OUTPUTS
    from ..records import read_records
    from ..timedomain.simulation import simulate_sampled

    model = load_model() if model is None else model
    fmu = read_records(outputs_csv)
    t, core = simulate_sampled(model, step, duration)
    worst, where = 0.0, ""
    n = 0
    for name in SUPPORT_OUTPUTS:
        if name not in fmu.columns:
            continue
        a = fmu.columns[name]
        on = np.searchsorted(fmu.time, t - 1e-9 * step)  # the FMU's row at the end of each step
        ok = on < len(a)
        ref = core[ok, OUTPUTS.index(name)]
        dev = float(np.max(np.abs(a[on[ok]] - ref)) / (np.max(np.abs(ref)) + 1e-300))
        n = int(ok.sum())
        if dev >= worst:
            worst, where = dev, name
    return {
        "FMU outputs": Path(outputs_csv).name,
        "communication step (s)": step,
        "duration (s)": duration,
        "compared with": "the core driven by the same sampled record with the FMU's input reconstruction "
        "(cablecasing_core.timedomain.simulation.simulate_sampled)",
        "largest deviation, relative to the output's largest value": f"{worst:.3g} ({where}, over {n} steps)",
    }
