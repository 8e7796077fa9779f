"""NVH outputs of any time record (a run, an FMU's outputs, a measurement): power spectral density
(Welch), levels in dB re a documented reference, octave and third-octave band levels, and the
apparent mass and force transmissibility estimated from the support signals with their coherence.

>>> from cablecasing_core.records import read_records
>>> rec = read_records("run.npz")                     # or .csv, .uff; cc.simulate(...).records()
>>> p = psd(rec.column("casing.B.Fz"), rec.fs, unit="N")          # N^2/Hz
>>> p.level_db()                                      # dB re 1 N^2/Hz
>>> M = apparent_mass(rec, "casing.A.az", "casing.B.Fz")         # kg, H1 with coherence
>>> bands = octave_rms(rec.column("casing.B.Fz"), rec.fs, "third", unit="N")   # band RMS, N
>>> bands.level_db()                                  # dB re 1 N (the unit's reference, as the PSD's)

Modules: ``spectra`` (PSD, levels, references, sums over bands), ``bands`` (the band sets of Table 3
and IEC 61260-1, the band levels' windows, band RMS by Parseval: :func:`~cablecasing_core.nvh.bands.octave_rms`),
``transfer`` (apparent mass, transmissibility), ``plots``. See docs/nvh.md.
"""

from .bands import octave_rms
from .spectra import PSD, REFERENCES, level_db, level_unit, psd, reference
from .transfer import Transfer, apparent_mass, transmissibility

__all__ = [
    "PSD",
    "REFERENCES",
    "Transfer",
    "apparent_mass",
    "level_db",
    "level_unit",
    "octave_rms",
    "psd",
    "reference",
    "transmissibility",
]
