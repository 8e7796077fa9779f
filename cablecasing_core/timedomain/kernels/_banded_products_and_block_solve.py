"""Banded products in diagonal storage and the block-tridiagonal LDL^T solve (the Newmark
predictor's linear algebra, Eq. 18).

* Diagonal storage of a symmetric matrix of half-bandwidth b: ``Ad[k, i] = A[i, i + k - b]``,
  k = 0..2b (zero outside the matrix). Products loop over diagonals outside and rows inside, so the
  inner loop is a contiguous, vectorisable multiply-add. Vectors multiplied with it are *padded*:
  ``yp[b + j] = y[j]`` with b zeros on either side.
* The effective stiffness of the free DOFs of a beam chain is block tridiagonal in 6 x 6 node
  blocks (an element couples two neighbouring nodes). Its block LDL^T factor is kept as
  ``Dinv[i] = D_i^-1``, ``L[i] = L_i,i-1`` and ``LT[i] = L_i+1,i^T`` (built in
  ``timedomain.body_storage.block_ldl``); a solve is two sweeps whose chain of dependencies is one 6 x 6
  product per node, instead of one operation per DOF for a banded substitution. SciPy's banded
  solvers cannot be called from inside a compiled step loop.

Where a chain of dependent additions limits speed, the kernels split it explicitly (partial sums,
trees of pairs), written out so that no re-association is asked of the compiler.
"""

from __future__ import annotations

from numba import njit

from ._compile_options import FM, NO_RT


@njit(cache=True, fastmath=FM, error_model="numpy")
def copy_into(dst, src):
    """dst[:] = src as a plain loop (numba's slice assignment goes through a general broadcasting
    path that costs several times more on these short vectors)."""
    for i in range(src.shape[0]):
        dst[i] = src[i]


@njit(cache=True, fastmath=FM, error_model="numpy")
def fill(dst, value):
    """dst[:] = value for a 1-D array (a plain loop, see copy_into)."""
    for i in range(dst.shape[0]):
        dst[i] = value


@njit(cache=True, fastmath=FM, error_model="numpy")
def dia_product(Ad, yp, r0, nr, out):
    """out[i - r0] += sum_j A[i, j] y[j] for rows i = r0 .. r0+nr-1 (yp padded)."""
    # the loop is bound by its loads: eight diagonals per pass over out (then four, three, one) cut
    # the loads and stores of out to an eighth, and each pass's setup is paid fewer times; slices
    # indexed from 0 let numba drop the negative-index checks, so the loops vectorise
    nd = Ad.shape[0]
    k = 0
    while k + 8 <= nd:
        a0, a1, a2, a3 = Ad[k, r0 : r0 + nr], Ad[k + 1, r0 : r0 + nr], Ad[k + 2, r0 : r0 + nr], Ad[k + 3, r0 : r0 + nr]
        a4, a5, a6, a7 = (
            Ad[k + 4, r0 : r0 + nr],
            Ad[k + 5, r0 : r0 + nr],
            Ad[k + 6, r0 : r0 + nr],
            Ad[k + 7, r0 : r0 + nr],
        )
        y = yp[r0 + k : r0 + k + nr + 7]
        for i in range(nr):
            out[i] += ((a0[i] * y[i] + a1[i] * y[i + 1]) + (a2[i] * y[i + 2] + a3[i] * y[i + 3])) + (
                (a4[i] * y[i + 4] + a5[i] * y[i + 5]) + (a6[i] * y[i + 6] + a7[i] * y[i + 7])
            )
        k += 8
    if k + 4 <= nd:
        a0, a1, a2, a3 = Ad[k, r0 : r0 + nr], Ad[k + 1, r0 : r0 + nr], Ad[k + 2, r0 : r0 + nr], Ad[k + 3, r0 : r0 + nr]
        y = yp[r0 + k : r0 + k + nr + 3]
        for i in range(nr):
            out[i] += (a0[i] * y[i] + a1[i] * y[i + 1]) + (a2[i] * y[i + 2] + a3[i] * y[i + 3])
        k += 4
    if k + 3 <= nd:
        a0, a1, a2 = Ad[k, r0 : r0 + nr], Ad[k + 1, r0 : r0 + nr], Ad[k + 2, r0 : r0 + nr]
        y = yp[r0 + k : r0 + k + nr + 2]
        for i in range(nr):
            out[i] += (a0[i] * y[i] + a1[i] * y[i + 1]) + a2[i] * y[i + 2]
        k += 3
    for k in range(k, nd):
        ak = Ad[k, r0 : r0 + nr]
        y = yp[r0 + k : r0 + k + nr]
        for i in range(nr):
            out[i] += ak[i] * y[i]


@njit(cache=True, fastmath=FM, error_model="numpy")
def dot(x, y):
    """sum_i x[i] y[i] in four interleaved partial sums, added as ((s0 + s1) + (s2 + s3)): a quarter
    of the single chain's latency, and the same result in any process (the order is written out)."""
    n = x.shape[0]
    s0 = s1 = s2 = s3 = 0.0
    i = 0
    while i + 4 <= n:
        s0 += x[i] * y[i]
        s1 += x[i + 1] * y[i + 1]
        s2 += x[i + 2] * y[i + 2]
        s3 += x[i + 3] * y[i + 3]
        i += 4
    for i in range(i, n):
        s0 += x[i] * y[i]
    return (s0 + s1) + (s2 + s3)


@njit(**NO_RT)
def dia_quadratic(Md, Kd, cm, ck, wp, t):
    """w^T (cm M + ck K) w (e.g. the Rayleigh dissipation rate with cm = alpha, ck = beta; wp padded),
    as cm w.(M w) + ck w.(K w) with the products of :func:`dia_product`; t: scratch (2, n)."""
    b = (Md.shape[0] - 1) // 2
    n = Md.shape[1]
    w = wp[b : b + n]
    tm, tk = t[0], t[1]
    fill(tm, 0.0)
    fill(tk, 0.0)
    dia_product(Md, wp, 0, n, tm)
    dia_product(Kd, wp, 0, n, tk)
    return cm * dot(w, tm) + ck * dot(w, tk)


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _block_step(B, x, o, y0, y1, y2, y3, y4, y5):
    """x[o:o+6] -= B y for one 6 x 6 block B; returns the new x[o:o+6]. The 6-term dot products
    are summed as a tree of pairs (written out, so no re-association is asked of the compiler):
    the sweeps are chains of these, and the tree halves each link's latency."""
    r0 = x[o + 0] - ((B[0, 0] * y0 + B[0, 1] * y1) + (B[0, 2] * y2 + B[0, 3] * y3) + (B[0, 4] * y4 + B[0, 5] * y5))
    r1 = x[o + 1] - ((B[1, 0] * y0 + B[1, 1] * y1) + (B[1, 2] * y2 + B[1, 3] * y3) + (B[1, 4] * y4 + B[1, 5] * y5))
    r2 = x[o + 2] - ((B[2, 0] * y0 + B[2, 1] * y1) + (B[2, 2] * y2 + B[2, 3] * y3) + (B[2, 4] * y4 + B[2, 5] * y5))
    r3 = x[o + 3] - ((B[3, 0] * y0 + B[3, 1] * y1) + (B[3, 2] * y2 + B[3, 3] * y3) + (B[3, 4] * y4 + B[3, 5] * y5))
    r4 = x[o + 4] - ((B[4, 0] * y0 + B[4, 1] * y1) + (B[4, 2] * y2 + B[4, 3] * y3) + (B[4, 4] * y4 + B[4, 5] * y5))
    r5 = x[o + 5] - ((B[5, 0] * y0 + B[5, 1] * y1) + (B[5, 2] * y2 + B[5, 3] * y3) + (B[5, 4] * y4 + B[5, 5] * y5))
    x[o], x[o + 1], x[o + 2], x[o + 3], x[o + 4], x[o + 5] = r0, r1, r2, r3, r4, r5
    return r0, r1, r2, r3, r4, r5


@njit(cache=True, fastmath=FM, error_model="numpy")
def block_solve(Dinv, L, LT, x):
    """In place x <- A^-1 x for the block-tridiagonal SPD matrix A = L D L^T (node blocks of 6,
    unit block diagonal in L; built by ``timedomain.body_storage.block_ldl``): forward z_i = r_i - L_i,i-1 z_i-1,
    then w_i = D_i^-1 z_i (independent blocks), backward x_i = w_i - L_i+1,i^T x_i+1. Each sweep is
    a chain of one 6 x 6 product per node."""
    nb = Dinv.shape[0]
    y0, y1, y2, y3, y4, y5 = x[0], x[1], x[2], x[3], x[4], x[5]
    for i in range(1, nb):
        y0, y1, y2, y3, y4, y5 = _block_step(L[i], x, 6 * i, y0, y1, y2, y3, y4, y5)
    for i in range(nb):
        o = 6 * i
        d = Dinv[i]
        y0, y1, y2, y3, y4, y5 = x[o], x[o + 1], x[o + 2], x[o + 3], x[o + 4], x[o + 5]
        for r in range(6):
            x[o + r] = (d[r, 0] * y0 + d[r, 1] * y1) + (d[r, 2] * y2 + d[r, 3] * y3) + (d[r, 4] * y4 + d[r, 5] * y5)
    o = 6 * (nb - 1)
    y0, y1, y2, y3, y4, y5 = x[o], x[o + 1], x[o + 2], x[o + 3], x[o + 4], x[o + 5]
    for i in range(nb - 2, -1, -1):
        y0, y1, y2, y3, y4, y5 = _block_step(LT[i], x, 6 * i, y0, y1, y2, y3, y4, y5)
