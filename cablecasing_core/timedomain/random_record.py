"""The random support excitation (Sections 4.1-4.2): a band-limited Gaussian-like acceleration
defined by its seed, band and RMS alone, evaluated on a run's time grid to ~1e-12 of its RMS and
between the grid's points by interpolation (below).

The record is a sum of cosines on a fixed grid of lines ``f_k = k df`` (``df =``
:data:`LINE_SPACING` = 1/64 Hz) inside the band, every line with the same amplitude and a seeded
random phase:

    a(t) = sum_k A cos(2 pi f_k t + phi_k),   A = rms sqrt(2 / K)   (K lines in the band, m/s2)
    v(t) = sum_k A / w_k sin(2 pi f_k t + phi_k),   u(t) = -sum_k A / w_k^2 cos(2 pi f_k t + phi_k)

with ``w_k = 2 pi f_k``. So the record is exactly band-limited, its mean square over a period is
exactly ``rms^2``, and displacement and velocity are its exact integrals (no drift, no DC). The phase
of line ``k`` is the k-th number of ``numpy.random.default_rng(seed).random`` (the stream is indexed
from 0 Hz, so two bands share the phases of their common lines). Nothing depends on the duration or
the time step of a run: the first T seconds of a record are the same whatever the run's length
(bit for bit), and the CLI, the core and an FMU driven by the sampled record see the same record
for a seed. At another time step the same function is evaluated on another grid: equal to ~1e-12
of the RMS, not bit for bit (measured between dt = 1e-5 and 2e-5 s: 1.4e-12 over 0.2 s, 5e-12 over
4 s). The
record repeats after ``1/df`` = 64 s. Over a window of T seconds the record looks like Gaussian noise:
its band power in a band of B Hz scatters by about ``1/sqrt(B T)`` (relative, mean square), as a
measured random excitation does.

Evaluation. At the times ``t0 + j h`` (j = 0..m-1) the sum is a chirp-z transform of the lines'
complex amplitudes, computed by Bluestein's algorithm (three FFTs of length >= K + m - 1) with the
chirp phases reduced modulo one cycle before the exponential, so the values agree with the direct
sum to ~1e-12 of the RMS over the first seconds (measured, 5 m/s2 in 10-1000 Hz: 3e-13 at
dt = 1e-5 s and 1.3e-12 at dt = 1/30000 s over 0.67 s; tested to 1e-10), the rounding of the
phases 2 pi f t growing with t (~8e-11 of the RMS at 60 s, in the direct sum as much).
``scipy.signal.czt`` is not used: it forms its chirp as
``w ** (k**2 / 2)``, whose magnitude drifts from 1 by ~eps k^2 (1e-6 at the block sizes used here).
On the grid of the run's time step ``dt`` the record is computed in fixed blocks of ``M`` samples
(block b covers the samples ``b M .. b M + M - 1``), so a sample's value does not depend on which
samples were asked for before: bitwise the same in every run. A time off that grid (the shorter
last step of a call whose length is no whole number of steps: an FMU's communication step of
2.5e-5 s at dt = 1e-5 s) takes the quintic Hermite polynomial through the u, v and a of its two
grid neighbours (:class:`~cablecasing_core.timedomain.support_motion.QuinticStep`, the FMU's
reconstruction of a step): within ~1e-12 of the RMS in u, ~1e-9 in v and ~1e-6 in a (measured, 5
m/s2 in 10-1000 Hz, 200 random times at dt = 1e-5, 2e-5 and 1/30000 s; tested to 1e-5), at the
cost of two grid samples; the direct sum, :meth:`RandomRecord.direct` (exact, K operations per
time: ~1.6 ms at 63 000 lines), made such a call 20 times dearer.
"""

from __future__ import annotations

import math
from collections import OrderedDict

import numpy as np
import scipy.fft as sfft

from ..errors import ModelError
from .support_motion import QuinticStep

#: Spacing (Hz) of the random excitation's lines; the record repeats after 1 / LINE_SPACING = 64 s.
LINE_SPACING = 1.0 / 64.0
#: Block sizes (samples) of the evaluation on the run's grid: the smallest power of two >= the number
#: of lines, within these limits (a block costs FFTs of about twice its length).
MIN_BLOCK, MAX_BLOCK = 4096, 131072
#: Blocks kept in memory (each 3 x M floats); a block dropped is computed again, bitwise the same.
KEEP_BLOCKS = 16


def _lines(band):
    """(k_lo, k_hi): the first and last line k of the grid k df (df = :data:`LINE_SPACING`) inside
    ``band`` [f_low, f_high] (Hz), its ends included to within 1e-9 of a line; a ModelError naming
    the band when it holds none."""
    df = LINE_SPACING
    k_lo = max(1, math.ceil(band[0] / df - 1e-9))
    k_hi = math.floor(band[1] / df + 1e-9)
    if k_hi < k_lo:
        raise ModelError("scenario.excitation.band", band, f"must contain a line of the {df:g} Hz grid")
    return k_lo, k_hi


def random_psd(rms, band, f_hz):
    """The one-sided PSD ((m/s2)^2/Hz) at ``f_hz`` (Hz) of the random excitation of ``rms`` (m/s2)
    in ``band`` [f_low, f_high] (Hz), whatever its seed: each of its K lines k df inside the band holds
    the mean square rms^2 / K, spread over its line spacing df (:data:`LINE_SPACING`), so the PSD is
    rms^2 / (K df) within df / 2 of the lines, [k_lo df - df / 2, k_hi df + df / 2), and 0 outside;
    its integral is rms^2."""
    k_lo, k_hi = _lines(band)
    df = LINE_SPACING
    x = np.asarray(f_hz, dtype=float) / df
    inside = (x >= k_lo - 0.5) & (x < k_hi + 0.5)
    return np.where(inside, rms**2 / ((k_hi - k_lo + 1) * df), 0.0)


class RandomRecord:
    """The random excitation of one channel: ``rms`` (m/s2), ``band`` [f_low, f_high] (Hz),
    ``seed`` (int), evaluated on the grid of time step ``dt`` (s) in blocks. Call it with times t (s)
    to get (u, v, a) in m, m/s, m/s2 (see the module docstring)."""

    def __init__(self, rms, band, seed, dt):
        df = LINE_SPACING
        k_lo, k_hi = _lines(band)
        phases = np.random.default_rng(seed).random(k_hi + 1)[k_lo:]
        self.k_lo, self.n_lines, self.dt = k_lo, k_hi - k_lo + 1, float(dt)
        w = 2 * np.pi * df * np.arange(k_lo, k_hi + 1)
        amp = rms * np.sqrt(2.0 / self.n_lines)
        c = amp * np.exp(2j * np.pi * phases)  # a(t) = Re sum c_k exp(i w_k t)
        self.coef = np.stack([-c / w**2, c / (1j * w), c])  # (3, K): u, v, a
        self.block = int(min(MAX_BLOCK, max(MIN_BLOCK, 1 << (self.n_lines - 1).bit_length())))
        self._blocks = OrderedDict()
        self._kernels = {}  # step h -> (FFT length, FFT of the chirp kernel)

    # ------------------------------------------------------------------ evaluation
    def __call__(self, t, on_grid=None):
        """(u, v, a) at times ``t`` (s, 1-D). ``on_grid``: integer sample indices ``rint(t / dt)``
        where t is on the grid of ``dt`` (a boolean mask ``on`` and indices ``k``), else computed here."""
        t = np.asarray(t, float)
        if on_grid is None:
            k = np.rint(t / self.dt)
            on = np.abs(t / self.dt - k) < 1e-9
            on_grid = (on, k.astype(np.int64))
        on, k = on_grid
        out = np.empty((3, t.size))
        if on.any():
            out[:, on] = self._on_grid(k[on])
        if not on.all():
            out[:, ~on] = self._between(t[~on])
        return out[0], out[1], out[2]

    def _between(self, t):
        """(3, n) array of u, v, a at times ``t`` (s) off the grid: the quintic Hermite polynomial
        through the u, v, a of the grid samples before and after each time (module docstring)."""
        out = np.empty((3, t.size))
        for i, ti in enumerate(t):
            k = int(math.floor(ti / self.dt))
            ends = self._on_grid(np.array([k, k + 1]))
            u, v, a = QuinticStep(k * self.dt, self.dt, ends[:, :1], ends[:, 1:])(np.array([ti]))
            out[:, i] = u[0, 0], v[0, 0], a[0, 0]
        return out

    def _on_grid(self, k):
        b0, b1 = int(k[0]) // self.block, int(k[-1]) // self.block
        if b0 == b1 and k[-1] - k[0] == k.size - 1:  # consecutive samples in one block (the engine's chunks)
            j = int(k[0]) - b0 * self.block
            return self._block(b0)[:, j : j + k.size]
        out = np.empty((3, k.size))
        blocks = k // self.block
        for b in np.unique(blocks):
            sel = blocks == b
            out[:, sel] = self._block(int(b))[:, k[sel] - b * self.block]
        return out

    def prepare(self, t_end):
        """Compute now the blocks of the run's grid that cover [0, ``t_end``] (s), at most
        :data:`KEEP_BLOCKS` of them, so that evaluating the record there only copies (the FMU does
        this in initialisation: a block costs ~30 ms, which a real-time master would meet inside one
        of its steps). Returns the time (s) up to which the blocks are ready."""
        n = min(math.ceil(max(t_end, 0.0) / (self.block * self.dt)), KEEP_BLOCKS)
        for b in range(n):
            self._block(b)
        return n * self.block * self.dt

    def _block(self, b):
        blk = self._blocks.get(b)
        if blk is None:
            blk = self.even(b * self.block * self.dt, self.dt, self.block)
            self._blocks[b] = blk
            if len(self._blocks) > KEEP_BLOCKS:
                self._blocks.popitem(last=False)
        else:
            self._blocks.move_to_end(b)
        return blk

    def even(self, t0, h, m):
        """(3, m) array of u, v, a at the times ``t0 + j h`` (s), j = 0..m-1: Bluestein's chirp-z
        transform, X_j = sum_n x_n W^(n j) with W = exp(2 pi i df h)
        = W^(j^2/2) sum_n (x_n W^(n^2/2)) W^(-(j-n)^2/2)."""
        K = self.n_lines
        c = 0.5 * LINE_SPACING * h  # cycles of W^(n^2/2) per n^2
        key = (h, m)
        if key not in self._kernels:
            L = sfft.next_fast_len(K + m - 1)
            n = np.arange(L, dtype=np.float64)
            n = np.where(n < m, n, n - L)  # kernel index m = j - n from -(K-1) to m-1, wrapped
            self._kernels = {key: (L, sfft.fft(_turns(-c * n * n)))}  # one step size at a time
        L, H = self._kernels[key]
        n = np.arange(K, dtype=np.float64)
        x = self.coef * _turns(LINE_SPACING * n * t0 + c * n * n)  # lines shifted to t0, chirped
        y = sfft.ifft(sfft.fft(x, L, axis=1) * H, axis=1)[:, :m]
        j = np.arange(m, dtype=np.float64)
        # back from the chirp and from line k_lo to its frequency: W^(j^2/2) exp(2 pi i f_lo (t0 + j h))
        post = _turns(c * j * j + LINE_SPACING * self.k_lo * (t0 + j * h))
        return np.real(y * post)

    def direct(self, t):
        """(3, n) array of u, v, a at arbitrary times ``t`` (s): the sum over the lines, K per time
        (exact: the reference the grid's evaluation and the off-grid interpolation are tested against)."""
        t = np.asarray(t, float)
        f = LINE_SPACING * np.arange(self.k_lo, self.k_lo + self.n_lines)
        out = np.empty((3, t.size))
        step = max(1, 2**20 // self.n_lines)
        for i in range(0, t.size, step):
            e = _turns(np.outer(t[i : i + step], f))  # (n, K)
            out[:, i : i + step] = np.real(self.coef @ e.T)
        return out


def _turns(cycles):
    """exp(2 pi i x) with x reduced to a fraction of a cycle first (keeps |.| = 1 and the phase exact
    for large x)."""
    return np.exp(2j * np.pi * (cycles - np.floor(cycles)))
