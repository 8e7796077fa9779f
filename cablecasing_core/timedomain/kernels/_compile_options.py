"""Compilation options shared by every kernel of the package.

``fastmath`` is limited to contraction into FMA and two harmless flags (``FM``): NaN and infinity
keep their IEEE meaning, so the blow-up checks still work, and there is no re-association, whose
vectorised sums may depend on the arrays' alignment: a run is reproducible to the bit in any
process. ``NO_RT``: kernels that allocate nothing are compiled without numba's runtime (no
reference counting of the arrays they receive; numba documents the flag with
``register_jitable(_nrt=False)``); see the package docstring.
"""

FM = {"contract", "nsz", "arcp"}
NO_RT = dict(cache=True, fastmath=FM, error_model="numpy", _nrt=False)
