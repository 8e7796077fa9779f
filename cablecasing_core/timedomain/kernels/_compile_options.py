"""Compilation options shared by every kernel of the package.

``FM``: no ``fastmath`` flag at all. Every operation keeps its IEEE meaning, so a kernel's result
does not depend on how it was compiled. With contraction into FMA (``contract``) or reciprocal
approximations (``arcp``), LLVM fuses or rewrites operations across a call only when it inlines
the callee, and it inlines a callee only when the callee was compiled in the same process: one
loaded from numba's cache is linked as machine code. A run with a cold cache then differed from a
run with a warm one at the rounding level, which a chaotic contact run turns into a different
record (measured on an AVX-512 machine: the FMU's process, loading the cache, disagreed with the
test process that had just compiled; tests/fmu/test_fmu.py checks a compiling and a loading
cache to the bit). Without the flags the two are the same machine arithmetic; the cost was within
the A/B method's resolution (installed 1.03, default 0.995, docs/performance-history.md). NaN and infinity
keep their meaning too, so the blow-up checks work.

``NO_RT``: kernels that allocate nothing are compiled without numba's runtime (no reference
counting of the arrays they receive; numba documents the flag with ``register_jitable(_nrt=False)``);
see the package docstring.
"""

FM = False
NO_RT = dict(cache=True, fastmath=FM, error_model="numpy", _nrt=False)
