"""numba kernels of the time domain, kept together: banded products, the block-tridiagonal
Cholesky solve, Hermite interpolation on a beam element, the contact search and contact law
(Eqs. 14-39), the implicit contact solve and the Newmark step loop; and, for the FMU's input
reconstruction (``kinematics.py``), the support motion inside a communication step.

All kernels are plain functions over arrays, compiled once with ``cache=True`` (the cache lives in
``NUMBA_CACHE_DIR`` when set). The orchestration (building matrices, factorising, evaluating the
support motion, packing results) stays in plain Python in ``engine.py`` and ``kinematics.py``.
Nothing in a step allocates: the step loop owns a workspace (:func:`contact_workspace`) and scalar
helpers return tuples.

Storage:

* Diagonal storage of a symmetric matrix of half-bandwidth b: ``Ad[k, i] = A[i, i + k - b]``,
  k = 0..2b (zero outside the matrix). Products loop over diagonals outside and rows inside, so the
  inner loop is a contiguous, vectorisable multiply-add. Vectors multiplied with it are *padded*:
  ``yp[b + j] = y[j]`` with b zeros on either side.
* The effective stiffness of the free DOFs of a beam chain is block tridiagonal in 6 x 6 node
  blocks (an element couples two neighbouring nodes). Its block LDL^T factor is kept as
  ``Dinv[i] = D_i^-1``, ``L[i] = L_i,i-1`` and ``LT[i] = L_i+1,i^T`` (built in ``engine.block_ldl``);
  a solve is two sweeps whose chain of dependencies is one 6 x 6 product per node, instead of one
  operation per DOF for a banded substitution. SciPy's banded solvers cannot be called from inside a
  compiled step loop.
* The effective compliance (dense, over all DOFs of a body, zero on the prescribed ones) gives the
  Delassus matrix of the contacts and the bodies' response to the contact forces.

``fastmath`` is limited to contraction into FMA and two harmless flags (``FM``): NaN and infinity
keep their IEEE meaning, so the blow-up checks still work, and there is no re-association, whose
vectorised sums may depend on the arrays' alignment: a run is reproducible to the bit in any
process (the FMU is checked against the core to 1e-12 on a chaotic contact run). Where a chain of
dependent additions limits speed, the kernels split it explicitly (partial sums, trees of pairs).
The small helpers of the contact solve are inlined into their callers (``inline="always"``).

Reference counting: numba increments the reference count of every array a function receives on
entry and decrements it on every exit (atomic operations, each a barrier for the memory pipeline).
LLVM's pruning pass removes these pairs in small functions, but gives up on large ones: the
contact solve (~50 arrays) paid ~100 atomic operations per step, the predictor and the ledger ~20
each. The kernels the step loop calls that still had them, and never allocate, are compiled without
the runtime (``NO_RT``); only the step loop allocates (its scratch, once per call). For the same
reason no call inside the step loop passes more than 30 arguments: Python then passes them as one
built tuple, whose every array numba counts around the call (~100 atomic operations per step
before the contact solve took its law's scalars as one tuple). docs/performance.md has the
figures.
"""
from __future__ import annotations

import numpy as np
from numba import njit

OPEN, STICK, SLIP = 0, 1, 2

# status codes of run_steps
OK, ERR_NAN, ERR_PENETRATION, ERR_SEARCH, ERR_INPUT = 0, 1, 2, 3, 4

FM = {"contract", "nsz", "arcp"}
# no runtime (reference counting, allocation) in kernels that allocate nothing: see the module's
# docstring; numba documents the flag with register_jitable(_nrt=False)
NO_RT = dict(cache=True, fastmath=FM, error_model="numpy", _nrt=False)
TINY = 1e-200   # m, m/s, m/s2: states below this are flushed to zero (see _finish)


# ------------------------------------------------------------------------------------------------
# banded products (diagonal storage) and the block-tridiagonal solve


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
        a0, a1, a2, a3 = Ad[k, r0:r0 + nr], Ad[k + 1, r0:r0 + nr], Ad[k + 2, r0:r0 + nr], Ad[k + 3, r0:r0 + nr]
        a4, a5, a6, a7 = Ad[k + 4, r0:r0 + nr], Ad[k + 5, r0:r0 + nr], Ad[k + 6, r0:r0 + nr], Ad[k + 7, r0:r0 + nr]
        y = yp[r0 + k:r0 + k + nr + 7]
        for i in range(nr):
            out[i] += (((a0[i] * y[i] + a1[i] * y[i + 1]) + (a2[i] * y[i + 2] + a3[i] * y[i + 3]))
                       + ((a4[i] * y[i + 4] + a5[i] * y[i + 5]) + (a6[i] * y[i + 6] + a7[i] * y[i + 7])))
        k += 8
    if k + 4 <= nd:
        a0, a1, a2, a3 = Ad[k, r0:r0 + nr], Ad[k + 1, r0:r0 + nr], Ad[k + 2, r0:r0 + nr], Ad[k + 3, r0:r0 + nr]
        y = yp[r0 + k:r0 + k + nr + 3]
        for i in range(nr):
            out[i] += (a0[i] * y[i] + a1[i] * y[i + 1]) + (a2[i] * y[i + 2] + a3[i] * y[i + 3])
        k += 4
    if k + 3 <= nd:
        a0, a1, a2 = Ad[k, r0:r0 + nr], Ad[k + 1, r0:r0 + nr], Ad[k + 2, r0:r0 + nr]
        y = yp[r0 + k:r0 + k + nr + 2]
        for i in range(nr):
            out[i] += (a0[i] * y[i] + a1[i] * y[i + 1]) + a2[i] * y[i + 2]
        k += 3
    for k in range(k, nd):
        ak = Ad[k, r0:r0 + nr]
        y = yp[r0 + k:r0 + k + nr]
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
    w = wp[b:b + n]
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
    unit block diagonal in L; built by ``engine.block_ldl``): forward z_i = r_i - L_i,i-1 z_i-1,
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
            x[o + r] = ((d[r, 0] * y0 + d[r, 1] * y1) + (d[r, 2] * y2 + d[r, 3] * y3)
                        + (d[r, 4] * y4 + d[r, 5] * y5))
    o = 6 * (nb - 1)
    y0, y1, y2, y3, y4, y5 = x[o], x[o + 1], x[o + 2], x[o + 3], x[o + 4], x[o + 5]
    for i in range(nb - 2, -1, -1):
        y0, y1, y2, y3, y4, y5 = _block_step(LT[i], x, 6 * i, y0, y1, y2, y3, y4, y5)


# ------------------------------------------------------------------------------------------------
# element interpolation


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _rot(R, U, o):
    """R @ U[o:o+3] as a tuple (global -> element axes)."""
    return (R[0, 0] * U[o] + R[0, 1] * U[o + 1] + R[0, 2] * U[o + 2],
            R[1, 0] * U[o] + R[1, 1] * U[o + 1] + R[1, 2] * U[o + 2],
            R[2, 0] * U[o] + R[2, 1] * U[o + 1] + R[2, 2] * U[o + 2])


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _element_dofs(Rs, Us, e):
    """Element e's end displacements and rotations in its own axes (R @ each 3-vector), as a
    12-tuple (ua, ta, ub, tb); what axis_point needs besides xi."""
    R = Rs[e]
    o = 6 * e
    return _rot(R, Us, o) + _rot(R, Us, o + 3) + _rot(R, Us, o + 6) + _rot(R, Us, o + 9)


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _axis_at(Xs, Rs, Ls, e, xi, q):
    """axis_point from the element DOFs q = _element_dofs(...) (hoisted out of the search's Newton
    iterations, which vary xi only)."""
    R = Rs[e]
    L = Ls[e]
    x2 = xi * xi
    x3 = x2 * xi
    N1, N2, N3, N4 = 1 - 3 * x2 + 2 * x3, L * (xi - 2 * x2 + x3), 3 * x2 - 2 * x3, L * (-x2 + x3)
    D1, D2, D3, D4 = -6 * xi + 6 * x2, L * (1 - 4 * xi + 3 * x2), 6 * xi - 6 * x2, L * (-2 * xi + 3 * x2)
    l0 = (1 - xi) * q[0] + xi * q[6]
    l1 = N1 * q[1] + N2 * q[5] + N3 * q[7] + N4 * q[11]
    l2 = N1 * q[2] - N2 * q[4] + N3 * q[8] - N4 * q[10]
    d0 = q[6] - q[0]
    d1 = D1 * q[1] + D2 * q[5] + D3 * q[7] + D4 * q[11]
    d2 = D1 * q[2] - D2 * q[4] + D3 * q[8] - D4 * q[10]
    px = Xs[e, 0] + xi * (Xs[e + 1, 0] - Xs[e, 0]) + R[0, 0] * l0 + R[1, 0] * l1 + R[2, 0] * l2
    py = Xs[e, 1] + xi * (Xs[e + 1, 1] - Xs[e, 1]) + R[0, 1] * l0 + R[1, 1] * l1 + R[2, 1] * l2
    pz = Xs[e, 2] + xi * (Xs[e + 1, 2] - Xs[e, 2]) + R[0, 2] * l0 + R[1, 2] * l1 + R[2, 2] * l2
    dx = Xs[e + 1, 0] - Xs[e, 0] + R[0, 0] * d0 + R[1, 0] * d1 + R[2, 0] * d2
    dy = Xs[e + 1, 1] - Xs[e, 1] + R[0, 1] * d0 + R[1, 1] * d1 + R[2, 1] * d2
    dz = Xs[e + 1, 2] - Xs[e, 2] + R[0, 2] * d0 + R[1, 2] * d1 + R[2, 2] * d2
    return px, py, pz, dx, dy, dz


@njit(cache=True, fastmath=FM, error_model="numpy")
def axis_point(Xs, Rs, Ls, Us, e, xi):
    """Deformed axis point p (m) of element e at xi in [0, 1] and its derivative dp/dxi (m), as
    (px, py, pz, dx, dy, dz): linear axial displacement and Hermite cubics for the lateral ones
    (the shape functions of Eq. 9), in the element's axes R, back to global."""
    return _axis_at(Xs, Rs, Ls, e, xi, _element_dofs(Rs, Us, e))


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _frame_block(H, r0, c0, a, b, g, e0, e1, e2):
    """H[r0:r0+3, c0:c0+3] = a I + b e e^T + g [e]x (e a unit vector, [e]x v = e x v)."""
    H[r0, c0], H[r0, c0 + 1], H[r0, c0 + 2] = a + b * e0 * e0, b * e0 * e1 - g * e2, b * e0 * e2 + g * e1
    H[r0 + 1, c0], H[r0 + 1, c0 + 1], H[r0 + 1, c0 + 2] = b * e1 * e0 + g * e2, a + b * e1 * e1, b * e1 * e2 - g * e0
    H[r0 + 2, c0], H[r0 + 2, c0 + 1], H[r0 + 2, c0 + 2] = b * e2 * e0 - g * e1, b * e2 * e1 + g * e0, a + b * e2 * e2


@njit(cache=True, fastmath=FM, error_model="numpy")
def hermite_matrix(xi, L, R, H):
    """Global 6x12 interpolation matrix H of a straight beam element at xi in [0, 1], written into H.

    Maps the element's 12 global DOFs to [ux uy uz rx ry rz] (global) at xi: Hermite cubics for
    the lateral displacements and the bending rotations (their slopes), linear for axial and twist;
    the shape functions of Eq. (9). R (3x3) is the element's direction-cosine matrix (rows: its
    local axes in global, right-handed): H = diag(R^T, R^T) H_local diag(R, R, R, R). Each local
    3x3 block is diag(axial, lateral, lateral) or lateral times the cross product with the local x
    axis, so each global block is a I + b e e^T + g [e]x with e = R[0] the element's direction,
    written directly (no products with R). The consistent nodal load of a point force F and moment
    Mo at xi is H^T [F; Mo]; it keeps the resultant and the moment of the load, because the shape
    functions reproduce rigid-body motion exactly.
    """
    x2 = xi * xi
    x3 = x2 * xi
    N1, N2, N3, N4 = 1 - 3 * x2 + 2 * x3, L * (xi - 2 * x2 + x3), 3 * x2 - 2 * x3, L * (-x2 + x3)
    D1, D2, D3, D4 = (-6 * xi + 6 * x2) / L, 1 - 4 * xi + 3 * x2, (6 * xi - 6 * x2) / L, -2 * xi + 3 * x2
    e0, e1, e2 = R[0, 0], R[0, 1], R[0, 2]
    # displacement rows: u = (1-xi) u_a e + N1 u_a,lat - N2 e x th_a + (same for b with N3, N4)
    _frame_block(H, 0, 0, N1, 1 - xi - N1, 0.0, e0, e1, e2)
    _frame_block(H, 0, 3, 0.0, 0.0, -N2, e0, e1, e2)
    _frame_block(H, 0, 6, N3, xi - N3, 0.0, e0, e1, e2)
    _frame_block(H, 0, 9, 0.0, 0.0, -N4, e0, e1, e2)
    # rotation rows: the slopes of the lateral displacement (e x u' terms) and linear twist
    _frame_block(H, 3, 0, 0.0, 0.0, D1, e0, e1, e2)
    _frame_block(H, 3, 3, D2, 1 - xi - D2, 0.0, e0, e1, e2)
    _frame_block(H, 3, 6, 0.0, 0.0, D3, e0, e1, e2)
    _frame_block(H, 3, 9, D4, xi - D4, 0.0, e0, e1, e2)


# ------------------------------------------------------------------------------------------------
# contact geometry and laws


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def contact_law(g, law, k_lin, k_hertz):
    """Normal elastic force (N) and its slope (N/m) at penetration g (m): linear (Eq. 24) or
    Hertz (Eq. 29) with k_hertz = 4/3 E* r^1/2; zero for g <= 0 (no adhesion)."""
    if g <= 0.0:
        return 0.0, 0.0
    if law == 0:
        sg = np.sqrt(g)
        return k_hertz * g * sg, 1.5 * k_hertz * sg
    return k_lin * g, k_lin


@njit(cache=True, fastmath=FM, error_model="numpy")
def contact_potential(g, law, k_lin, k_hertz):
    """Elastic energy (J) stored in contacts of penetrations g (m, one per cable node): the integral
    of :func:`contact_law`, 2/5 k_hertz g^5/2 (Hertz) or k_lin g^2 / 2 (linear), zero for g <= 0."""
    e = 0.0
    for i in range(g.shape[0]):
        if g[i] > 0.0:
            e += 0.4 * k_hertz * g[i] * g[i] * np.sqrt(g[i]) if law == 0 else 0.5 * k_lin * g[i] * g[i]
    return e


@njit(cache=True, fastmath=FM, error_model="numpy")
def line_plane_intersection(ia, ib, p0, p1, p2):
    """Eq. (39): (l, u, v) of the intersection of the line ia + (ib - ia) l with the plane
    p0 + (p1 - p0) u + (p2 - p0) v. Returns l = nan for a line parallel to the plane. (The search
    itself uses the equivalent normal-plane form (x - x1) . t1 = 0, one division; this general form
    is the paper's and checks it.)"""
    A = np.empty((3, 3))
    for r in range(3):
        A[r, 0] = ia[r] - ib[r]
        A[r, 1] = p1[r] - p0[r]
        A[r, 2] = p2[r] - p0[r]
    det = np.linalg.det(A)
    if abs(det) < 1e-300:
        return np.nan, np.nan, np.nan
    sol = np.linalg.solve(A, ia - p0)
    return sol[0], sol[1], sol[2]


@njit(cache=True, fastmath=FM, error_model="numpy")
def casing_point(Xs, Rs, Ls, Us, e, xi):
    """Deformed casing axis point (m) at xi of element e, as an array."""
    px, py, pz, _, _, _ = axis_point(Xs, Rs, Ls, Us, e, xi)
    return np.array([px, py, pz])


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _cable_node(Xc, Tc, Uc, i):
    """Deformed position (m) and tangent (not normalised; small rotations) of cable node i."""
    o = 6 * i
    T0, T1, T2 = Tc[i, 0], Tc[i, 1], Tc[i, 2]
    th0, th1, th2 = Uc[o + 3], Uc[o + 4], Uc[o + 5]
    return (Xc[i, 0] + Uc[o], Xc[i, 1] + Uc[o + 1], Xc[i, 2] + Uc[o + 2],
            T0 + th1 * T2 - th2 * T1, T1 + th2 * T0 - th0 * T2, T2 + th0 * T1 - th1 * T0)


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _chord(x0, x1, x2, t0, t1, t2, Xs, Ls, Us, e):
    """The normal plane of a cable node (point x, tangent t of any length) against the chord of
    casing element e between its deformed nodes (Eqs. 37, 39): (den, xi, reach). xi = num/den is
    where the plane cuts the chord (no cut when den = 0); reach (m) bounds the node's distance from
    the element's Hermite axis at that cut from above (to first order in the rotations, as the
    axis itself): the distance from the chord plus the most the axis can depart from it. In the
    element's axes the departure is N2 (theta_a - psi) + N4 (theta_b - psi), bending components
    only, psi = e0 x (u_b - u_a) / L the chord's rotation (e0 the element's direction, N2, N4 the
    Hermite slope functions of Eq. 9, |N2| + |N4| <= L/4): a rigidly moving element does not
    depart from its chord however far it turns."""
    o = 6 * e
    L = Ls[e]
    a0, a1, a2 = Xs[e, 0] + Us[o], Xs[e, 1] + Us[o + 1], Xs[e, 2] + Us[o + 2]
    b0, b1, b2 = Xs[e + 1, 0] + Us[o + 6], Xs[e + 1, 1] + Us[o + 7], Xs[e + 1, 2] + Us[o + 8]
    den = (b0 - a0) * t0 + (b1 - a1) * t1 + (b2 - a2) * t2
    num = (x0 - a0) * t0 + (x1 - a1) * t1 + (x2 - a2) * t2
    xi = num / den
    dl = ((a0 + xi * (b0 - a0) - x0) ** 2 + (a1 + xi * (b1 - a1) - x1) ** 2
          + (a2 + xi * (b2 - a2) - x2) ** 2)
    e0, e1, e2 = (Xs[e + 1, 0] - Xs[e, 0]) / L, (Xs[e + 1, 1] - Xs[e, 1]) / L, (Xs[e + 1, 2] - Xs[e, 2]) / L
    u0, u1, u2 = Us[o + 6] - Us[o], Us[o + 7] - Us[o + 1], Us[o + 8] - Us[o + 2]
    p0, p1, p2 = (e1 * u2 - e2 * u1) / L, (e2 * u0 - e0 * u2) / L, (e0 * u1 - e1 * u0) / L   # psi
    # |theta - psi| without the twist (psi has none: it is normal to e0), at either end
    w0, w1, w2 = Us[o + 3] - p0, Us[o + 4] - p1, Us[o + 5] - p2
    v0, v1, v2 = Us[o + 9] - p0, Us[o + 10] - p1, Us[o + 11] - p2
    tw, tv = w0 * e0 + w1 * e1 + w2 * e2, v0 * e0 + v1 * e1 + v2 * e2
    ba = np.sqrt(max(w0 * w0 + w1 * w1 + w2 * w2 - tw * tw, 0.0))
    bb = np.sqrt(max(v0 * v0 + v1 * v1 + v2 * v2 - tv * tv, 0.0))
    return den, xi, np.sqrt(dl) + 0.25 * L * (ba + bb)


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _search(x0, x1, x2, t0, t1, t2, Xs, Rs, Ls, Us, e_guess, far_below):
    """Contact search of one cable node (point x, unit tangent t, as scalars); see search_casing.
    Returns (element, xi, far, p): p = (px, py, pz) the axis point at xi when refined (else NaN)."""
    ne = Ls.shape[0]
    best_e, best_xi, best_d = -1, np.nan, 1e300
    bx, by, bz = np.nan, np.nan, np.nan
    for de in range(0, 2 * ne + 1):
        off = (de + 1) // 2 * (1 if de % 2 == 1 else -1)
        e = e_guess + off
        if e < 0 or e >= ne:
            if abs(off) > ne:
                break
            continue
        den, xi, reach = _chord(x0, x1, x2, t0, t1, t2, Xs, Ls, Us, e)     # Eq. (39) on the chord
        if abs(den) < 1e-300:
            continue
        if xi < -1e-9 or xi > 1 + 1e-9:
            if best_e >= 0 and abs(off) > 2:
                break
            continue
        if reach < far_below:       # cheap exit: a node this far inside cannot touch (returned as far)
            return e, xi, True, np.nan, np.nan, np.nan
        xi = min(max(xi, 0.0), 1.0)
        q = _element_dofs(Rs, Us, e)
        px, py, pz, dx, dy, dz = _axis_at(Xs, Rs, Ls, e, xi, q)
        for _ in range(4):  # Newton on phi(xi) = (p(xi) - x) . t on the Hermite axis
            phi = (px - x0) * t0 + (py - x1) * t1 + (pz - x2) * t2
            dphi = dx * t0 + dy * t1 + dz * t2
            if abs(dphi) < 1e-300:
                break
            xn = min(max(xi - phi / dphi, 0.0), 1.0)
            if abs(xn - xi) <= 1e-10:
                # converged: xi within ~1e-10 of the root, a few pm along the element; the distance
                # to the axis, measured in the normal plane, changes only to second order
                break
            xi = xn
            px, py, pz, dx, dy, dz = _axis_at(Xs, Rs, Ls, e, xi, q)
        d = (px - x0) ** 2 + (py - x1) ** 2 + (pz - x2) ** 2
        if best_e < 0 and 0.01 < xi < 0.99:
            # well inside the element: the plane cannot cut a neighbour within the +-2 elements
            # looked at (the axis turns by far less than a right angle over them)
            return e, xi, False, px, py, pz
        if d < best_d:
            best_d, best_e, best_xi = d, e, xi
            bx, by, bz = px, py, pz
        if abs(off) >= 2 and best_e >= 0:
            break
    return best_e, best_xi, False, bx, by, bz


@njit(cache=True, fastmath=FM, error_model="numpy")
def _far_from_wall(Xc, Tc, Uc, Xs, Ls, Us, elem, gap, far):
    """far[i]: cable node i certainly lies farther than ``gap`` (m) inside the wall, by the cheap
    test of :func:`_search` on its previous element elem[i] alone (the normal plane cuts that
    element's chord, and the node is within the gap of it by more than the Hermite axis can depart
    from the chord). Most nodes pass it in most steps; one branch-free pass over all nodes (it
    vectorises) is much cheaper than the per-node search they then skip. Nodes that fail it get the
    full search."""
    ne = Ls.shape[0]
    for i in range(Xc.shape[0]):
        x0, x1, x2, t0, t1, t2 = _cable_node(Xc, Tc, Uc, i)
        e = min(max(elem[i], 0), ne - 1)
        den, xi, reach = _chord(x0, x1, x2, t0, t1, t2, Xs, Ls, Us, e)
        far[i] = ((elem[i] == e) & (abs(den) >= 1e-300) & (xi >= -1e-9) & (xi <= 1 + 1e-9) & (reach < gap))


@njit(cache=True, fastmath=FM, error_model="numpy")
def search_casing(x1, t1, Xs, Rs, Ls, Us, e_guess, far_below):
    """Contact search (Eqs. 32-39): where the normal plane of a cable node (point x1, unit tangent
    t1) cuts the deformed casing axis. The line between two deformed casing nodes (Eq. 37) gives the
    first estimate l (Eq. 39); Newton iterations on the element's Hermite-interpolated axis refine it.
    Elements are tried outward from ``e_guess``. Returns (element, xi, far): far is True when the
    node is certainly more than ``far_below`` (m) from the axis (no refinement done); element -1 when
    the plane misses the casing."""
    e, xi, far, _, _, _ = _search(x1[0], x1[1], x1[2], t1[0], t1[1], t1[2], Xs, Rs, Ls, Us, e_guess, far_below)
    return e, xi, far


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def tangent_basis(n0, n1, n2, ta, tb):
    """Write two unit vectors completing n to a right-handed orthonormal basis into ta, tb."""
    r0, r1, r2 = (1.0, 0.0, 0.0) if abs(n0) < 0.9 else (0.0, 1.0, 0.0)
    dn = r0 * n0 + r1 * n1 + r2 * n2
    a0, a1, a2 = r0 - dn * n0, r1 - dn * n1, r2 - dn * n2
    s = np.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    ta[0], ta[1], ta[2] = a0 / s, a1 / s, a2 / s
    tb[0] = n1 * ta[2] - n2 * ta[1]
    tb[1] = n2 * ta[0] - n0 * ta[2]
    tb[2] = n0 * ta[1] - n1 * ta[0]


# ------------------------------------------------------------------------------------------------
# implicit contact forces


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _dense_solve(A, b, m, x):
    """Solve A[:m, :m] x = b[:m] by Gaussian elimination with partial pivoting (A and b are
    overwritten). Written here for the few (3 per contact) unknowns inside the step loop, where a
    LAPACK call would cost more than the solve; an exactly zero pivot leaves its unknown at zero."""
    for c in range(m):
        p = c
        big = abs(A[c, c])
        for r in range(c + 1, m):
            if abs(A[r, c]) > big:
                big = abs(A[r, c])
                p = r
        if big == 0.0:
            continue
        if p != c:
            for k in range(c, m):
                A[c, k], A[p, k] = A[p, k], A[c, k]
            b[c], b[p] = b[p], b[c]
        inv = 1.0 / A[c, c]
        for r in range(c + 1, m):
            f = A[r, c] * inv
            if f != 0.0:
                for k in range(c + 1, m):
                    A[r, k] -= f * A[c, k]
                b[r] -= f * b[c]
    for c in range(m - 1, -1, -1):
        if A[c, c] == 0.0:
            x[c] = 0.0
            continue
        s = b[c]
        for k in range(c + 1, m):
            s -= A[c, k] * x[k]
        x[c] = s / A[c, c]


def contact_workspace(nn):
    """Scratch arrays of the contact solve for nn cable nodes (allocated once per run)."""
    m = 3 * max(nn, 1)
    z = lambda *s: np.zeros(s)  # noqa: E731
    return (np.zeros(max(nn, 1), np.int64), z(nn), z(nn), z(nn, 3), z(nn, 3), z(nn, 3), z(nn, 3),
            z(nn, 6, 12), z(nn, 6, 3), z(nn, 12, 3), z(m, m), z(m, m), z(m), z(m), z(m), z(m),
            z(nn, 3), z(nn, 3), np.zeros(max(nn, 1), np.int64), z(nn, 3), z(nn), z(nn),
            np.zeros(max(nn, 1), np.bool_), z(6), z(m), np.zeros(max(nn, 1), np.bool_),
            np.zeros(max(nn, 1), np.bool_), z(m, m), z(m), z(m), np.zeros(max(nn, 1) + 1, np.int64), z(nn))


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _relative_displacement(W, P, m, d):
    """d = W[:m, :m] P: the contact points' relative displacements (m) under the forces P (N)."""
    for i in range(m):
        s = 0.0
        for j in range(m):
            s += W[i, j] * P[j]
        d[i] = s


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _unknowns(nk, nrm, ta, tb, mode, active, P, off, x):
    """The unknowns x of the contact solve and their offsets off[k] .. off[k + 1] - 1, from the
    forces P (N, 3 per contact). The force of each contact k is a linear map of its unknowns:
      slip (one unknown, N):          P_k = -N (n + mu s)    (Coulomb, Eqs. 18-23),
      stick (three, N, f_a, f_b):     P_k = -N n + f_a t_a + f_b t_b,
      inactive (none):                P_k = 0,
    so a slip contact, the usual case, costs one unknown instead of three. Returns their number r."""
    r = 0
    for k in range(nk):
        off[k] = r
        if not active[k]:
            continue
        o = 3 * k
        x[r] = -(P[o] * nrm[k, 0] + P[o + 1] * nrm[k, 1] + P[o + 2] * nrm[k, 2])
        r += 1
        if mode[k] == STICK:
            x[r] = P[o] * ta[k, 0] + P[o + 1] * ta[k, 1] + P[o + 2] * ta[k, 2]
            x[r + 1] = P[o] * tb[k, 0] + P[o + 1] * tb[k, 1] + P[o + 2] * tb[k, 2]
            r += 2
    off[nk] = r
    return r


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _forces(nk, nrm, ta, tb, sdir, mu, off, x, P):
    """P (N, 3 per contact) from the unknowns x: the map of :func:`_unknowns`."""
    for k in range(nk):
        o = 3 * k
        i = off[k]
        nu = off[k + 1] - i
        if nu == 0:
            P[o], P[o + 1], P[o + 2] = 0.0, 0.0, 0.0
        elif nu == 1:
            for c in range(3):
                P[o + c] = -x[i] * (nrm[k, c] + mu * sdir[k, c])
        else:
            for c in range(3):
                P[o + c] = -x[i] * nrm[k, c] + x[i + 1] * ta[k, c] + x[i + 2] * tb[k, c]


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _reduced_delassus(W, nk, nrm, ta, tb, sdir, mu, off, Q):
    """Q = O W C (r x r): how the observed relative displacements (m) of the contact points respond
    to the unknowns (N). C maps the unknowns to the forces (:func:`_forces`); the observations are,
    per contact, the normal displacement n.d (one per unknown N) and, for a stick contact, the
    tangential ones t_a.d and t_b.d (one per friction unknown)."""
    for k in range(nk):
        for a in range(off[k + 1] - off[k]):
            t = nrm[k] if a == 0 else (ta[k] if a == 1 else tb[k])
            row = off[k] + a
            for l in range(nk):
                nu = off[l + 1] - off[l]
                if nu == 0:
                    continue
                o, ol = 3 * k, 3 * l
                w0 = t[0] * W[o, ol] + t[1] * W[o + 1, ol] + t[2] * W[o + 2, ol]
                w1 = t[0] * W[o, ol + 1] + t[1] * W[o + 1, ol + 1] + t[2] * W[o + 2, ol + 1]
                w2 = t[0] * W[o, ol + 2] + t[1] * W[o + 1, ol + 2] + t[2] * W[o + 2, ol + 2]
                wn = w0 * nrm[l, 0] + w1 * nrm[l, 1] + w2 * nrm[l, 2]
                if nu == 1:
                    Q[row, off[l]] = -(wn + mu * (w0 * sdir[l, 0] + w1 * sdir[l, 1] + w2 * sdir[l, 2]))
                else:
                    Q[row, off[l]] = -wn
                    Q[row, off[l] + 1] = w0 * ta[l, 0] + w1 * ta[l, 1] + w2 * ta[l, 2]
                    Q[row, off[l] + 2] = w0 * tb[l, 0] + w1 * tb[l, 1] + w2 * tb[l, 2]


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _residual(Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, x, law, k_lin, k_hertz, c_n, dt,
              J, R, y, Ne, Nd, with_J):
    """Residual R (and, with_J, its Jacobian J) of the contact conditions of :func:`_newton` at the
    unknowns x; y = Q x, the observed relative displacements (m). Normal rows are in newtons; stick
    rows (m/s) are scaled by 1 / (2/dt W_kk) and touch rows (m) by 1 / W_kk to newtons like them.
    Returns the norm of R (N)."""
    c2 = 2.0 / dt
    for i in range(r):
        s = 0.0
        for j in range(r):
            s += Q[i, j] * x[j]
        y[i] = s
    norm = 0.0
    for k in range(nk):
        i = off[k]
        nu = off[k + 1] - i
        if nu == 0:
            Ne[k], Nd[k] = 0.0, 0.0       # inactive: no unknown, no force
            continue
        g = gst[k] + y[i]
        if touch[k]:
            # the step ends just touching: g = 0 with N free (0 <= N <= c_n g_dot, checked by the
            # caller)
            Ne[k], Nd[k] = 0.0, x[i]
            sc = 1.0 / wkk[k] if wkk[k] > 0.0 else 1.0
            R[i] = sc * g
            if with_J:
                for j in range(r):
                    J[i, j] = sc * Q[i, j]
        else:
            # the law (Eqs. 24/29) and the damper while compressing (Eq. 16), continuous in x;
            # the caller checks g > 0 at the solution
            gd = gdst[k] + c2 * y[i]
            fe, ke = contact_law(g, law, k_lin, k_hertz)
            fd = c_n * gd if gd > 0.0 else 0.0
            gam = ke + (c_n * c2 if gd > 0.0 else 0.0)
            Ne[k], Nd[k] = fe, fd
            R[i] = fe + fd - x[i]
            if with_J:
                for j in range(r):                       # dN/dx = gam dg/dx
                    J[i, j] = gam * Q[i, j]
                J[i, i] -= 1.0
        norm += R[i] * R[i]
        for a in range(1, nu):
            # stick: the tangential relative velocity at the end of the step vanishes; a direction
            # with no compliance at all (a contact at a clamped node) admits any force and zero is
            # taken
            ia = i + a
            t = ta[k] if a == 1 else tb[k]
            if Q[ia, ia] <= 1e-13 * wkk[k] or wkk[k] == 0.0:
                R[ia] = x[ia]
                if with_J:
                    for j in range(r):
                        J[ia, j] = 0.0
                    J[ia, ia] = 1.0
            else:
                sc = 1.0 / (c2 * wkk[k])
                R[ia] = sc * (t[0] * wst[k, 0] + t[1] * wst[k, 1] + t[2] * wst[k, 2] + c2 * y[ia])
                if with_J:
                    for j in range(r):
                        J[ia, j] = sc * c2 * Q[ia, j]
            norm += R[ia] * R[ia]
    return np.sqrt(norm)


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _newton(Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, x, law, k_lin, k_hertz, c_n, dt,
            J, R, dx, y, Ne, Nd, xt):
    """Contact forces at the end of a Newmark step for fixed stick/slip modes and active set, as
    the unknowns x of :func:`_unknowns` (N).

    The relative displacement of the contact points responds linearly to the forces through the
    Delassus matrix W (m/N, from the effective stiffness of both bodies): delta = W P, and so the
    observed displacements to the unknowns through Q = O W C (:func:`_reduced_delassus`). With the
    predicted penetration g* and rates (contact-free step), each active contact k satisfies
      normal (Eqs. 15-17, 24/29): N = law(max(g, 0)) + c_n max(g_dot, 0), g = g* + n.delta,
        g_dot = g_dot* + 2/dt n.delta;
      touch (touch[k]):  g = 0 with N free: the step in which the implicit damper alone would push
        the bodies apart past the surface (Eq. 16's switch at g = 0, read as a set);
      stick (Eqs. 18-23): the tangential relative velocity at the end of the step is zero;
      slip (Coulomb):    P_t = -mu N s, s the unit slip direction: built into P's map, no equation;
    an inactive contact has no unknown and no force. The caller keeps a contact in the law only
    while g > 0 and in touch only while 0 <= N <= c_n g_dot. Newton iterations (semi-smooth at the
    max()) from the given x, with a backtracking line search on |R|: near g = 0 the Hertz law's
    slope vanishes and full steps can cycle across the kink. At most 15 iterations: a stick that
    needs more friction than mu N has no solution here, and the caller switches it to slip.
    Returns the number of iterations, negative when not converged; Ne, Nd hold the elastic and
    damping parts of N at the final x."""
    its = -15
    r0 = _residual(Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, x, law, k_lin, k_hertz, c_n, dt,
                   J, R, y, Ne, Nd, True)
    for it in range(15):
        for i in range(r):
            R[i] = -R[i]
        _dense_solve(J, R, r, dx)
        scale = 1e-30
        step = 0.0
        for i in range(r):
            scale = max(scale, abs(x[i]))
            step = max(step, abs(dx[i]))
        alpha = 1.0
        for ls in range(12):
            for i in range(r):
                xt[i] = x[i] + alpha * dx[i]
            r1 = _residual(Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, xt, law, k_lin, k_hertz, c_n, dt,
                           J, R, y, Ne, Nd, False)
            if r1 <= (1.0 - 1e-4 * alpha) * r0 or r1 <= 1e-13 * max(scale, 1.0):
                break
            alpha *= 0.5
        for i in range(r):
            x[i] = xt[i]
        if alpha * step <= 1e-12 * max(scale, 1e-30) or r1 <= 1e-13 * max(scale, 1.0):
            its = it + 1          # Ne, Nd already belong to x (the last trial point)
            break
        r0 = _residual(Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, x, law, k_lin, k_hertz, c_n, dt,
                       J, R, y, Ne, Nd, True)
    return its


@njit(cache=True, fastmath=FM, error_model="numpy", inline="always")
def _compliance_block(Kinv, dof_k, Bk, dof_l, Bl, W, ok, ol, nq):
    """W[ok:ok+3, ol:ol+3] += Bk^T Kinv[dofs_k, dofs_l] Bl: one body's part of a 3x3 Delassus block.
    Bk, Bl map a contact force to generalized forces on the DOFs from dof_k, dof_l; Kinv is the
    effective compliance over all DOFs (zero on the prescribed ones, which do not respond). nq: the
    rows of Bk and Bl, 6 (a cable node) or 12 (a casing element), passed as a literal so that the
    loops unroll once inlined (0.3 of 7.0 us per contact solve at 4.6 contacts)."""
    w00 = w01 = w02 = w10 = w11 = w12 = w20 = w21 = w22 = 0.0
    for p in range(nq):
        row = Kinv[dof_k + p, dof_l:dof_l + nq]
        t0 = t1 = t2 = 0.0
        for q in range(nq):
            kv = row[q]
            t0 += kv * Bl[q, 0]
            t1 += kv * Bl[q, 1]
            t2 += kv * Bl[q, 2]
        b0, b1, b2 = Bk[p, 0], Bk[p, 1], Bk[p, 2]
        w00 += b0 * t0
        w01 += b0 * t1
        w02 += b0 * t2
        w10 += b1 * t0
        w11 += b1 * t1
        w12 += b1 * t2
        w20 += b2 * t0
        w21 += b2 * t1
        w22 += b2 * t2
    W[ok, ol] += w00
    W[ok, ol + 1] += w01
    W[ok, ol + 2] += w02
    W[ok + 1, ol] += w10
    W[ok + 1, ol + 1] += w11
    W[ok + 1, ol + 2] += w12
    W[ok + 2, ol] += w20
    W[ok + 2, ol + 1] += w21
    W[ok + 2, ol + 2] += w22


@njit(**NO_RT)
def _contact(Xc, Tc, Uc, Vc, Xs, Rs, Ls, Us, Vs, Kc, Ks, par,
             state, elem, xi_arr, Pn, vrel, Nout, gout, fcc, fcs, diag, ws):
    """contact_step with its scratch arrays ``ws`` (:func:`contact_workspace`) and the law's scalars
    in one tuple, par = (gap, r_in, law, k_lin, k_hertz, c_n, mu, v_stick, dt).

    At most 30 arguments on purpose: Python compiles a call with more than 30 positional
    arguments as a call with a built tuple (CALL_FUNCTION_EX), and numba then increments and
    decrements the reference count of every array in it around each call, ~100 atomic operations
    per step."""
    gap, r_in, law, k_lin, k_hertz, c_n, mu, v_stick, dt = par
    (idx, gst, gdst, wst, nrm, arm_c, arm_s, Hs, Bc, Gs, W, J, R, dx, P, d,
     ta, tb, mode, sdir, Ne, Nd, active, tmp, xt, touch, skip, Q, x, y, off, wkk) = ws
    nn = Xc.shape[0]
    nk = 0
    c2 = 2.0 / dt
    _far_from_wall(Xc, Tc, Uc, Xs, Ls, Us, elem, gap, skip)
    for i in range(nn):
        Nout[i] = 0.0
        gout[i] = 0.0
        if skip[i]:
            state[i] = OPEN
            continue
        o = 6 * i
        x0, x1, x2, t0, t1, t2 = _cable_node(Xc, Tc, Uc, i)
        tn = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
        t0, t1, t2 = t0 / tn, t1 / tn, t2 / tn
        e, xi, far, px, py, pz = _search(x0, x1, x2, t0, t1, t2, Xs, Rs, Ls, Us, elem[i], gap)
        if e >= 0:
            elem[i] = e
        if e < 0 or far:
            state[i] = OPEN
            continue
        xi_arr[i] = xi
        r0, r1, r2 = x0 - px, x1 - py, x2 - pz
        h = np.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
        g = h - gap                                   # Eqs. (14), (30)-(31)
        if g <= 0.0 or h == 0.0:
            state[i] = OPEN
            continue
        n0, n1, n2 = r0 / h, r1 / h, r2 / h
        c0, c1, c2_ = px + r_in * n0, py + r_in * n1, pz + r_in * n2   # contact point on the wall
        H = Hs[nk]
        hermite_matrix(xi, Ls[e], Rs[e], H)
        vs = tmp                                              # casing velocity and spin at xi
        for r in range(6):
            s = 0.0
            for c in range(12):
                s += H[r, c] * Vs[6 * e + c]
            vs[r] = s
        ac0, ac1, ac2 = c0 - x0, c1 - x1, c2_ - x2            # arm from the cable node
        as0, as1, as2 = c0 - px, c1 - py, c2_ - pz            # arm from the casing axis
        om0, om1, om2 = Vc[o + 3], Vc[o + 4], Vc[o + 5]
        w0 = Vc[o] + om1 * ac2 - om2 * ac1 - (vs[0] + vs[4] * as2 - vs[5] * as1)
        w1 = Vc[o + 1] + om2 * ac0 - om0 * ac2 - (vs[1] + vs[5] * as0 - vs[3] * as2)
        w2 = Vc[o + 2] + om0 * ac1 - om1 * ac0 - (vs[2] + vs[3] * as1 - vs[4] * as0)
        idx[nk] = i
        gst[nk] = g
        gdst[nk] = n0 * w0 + n1 * w1 + n2 * w2
        wst[nk, 0], wst[nk, 1], wst[nk, 2] = w0, w1, w2
        nrm[nk, 0], nrm[nk, 1], nrm[nk, 2] = n0, n1, n2
        arm_c[nk, 0], arm_c[nk, 1], arm_c[nk, 2] = ac0, ac1, ac2
        arm_s[nk, 0], arm_s[nk, 1], arm_s[nk, 2] = as0, as1, as2
        nk += 1
    fill(fcc, 0.0)
    fill(fcs, 0.0)
    diag[2] = 0.0
    diag[3] = 0.0
    if nk == 0:
        diag[0] = 0.0
        for i in range(nn):
            Pn[i, 0], Pn[i, 1], Pn[i, 2] = 0.0, 0.0, 0.0
        return 0
    # Delassus matrix W = Bc^T Kc^-1 Bc + Gs^T Ks^-1 Gs (only free DOFs respond)
    for k in range(nk):
        B = Bc[k]
        G = Gs[k]
        H = Hs[k]
        B[:, :] = 0.0
        a0, a1, a2 = arm_c[k, 0], arm_c[k, 1], arm_c[k, 2]
        B[0, 0], B[1, 1], B[2, 2] = 1.0, 1.0, 1.0
        B[3, 1], B[3, 2] = -a2, a1                 # moment a x P in rows 3..5
        B[4, 0], B[4, 2] = a2, -a0
        B[5, 0], B[5, 1] = -a1, a0
        s0, s1, s2 = arm_s[k, 0], arm_s[k, 1], arm_s[k, 2]
        for r in range(12):                        # G = H^T [-I; -[s]x]: -P and -(s x P) on the axis
            G[r, 0] = -H[0, r] - (H[4, r] * s2 - H[5, r] * s1)
            G[r, 1] = -H[1, r] - (H[5, r] * s0 - H[3, r] * s2)
            G[r, 2] = -H[2, r] - (H[3, r] * s1 - H[4, r] * s0)
    m = 3 * nk
    for i in range(m):
        for j in range(m):
            W[i, j] = 0.0
    for k in range(nk):
        ik = idx[k]
        ek = elem[ik]
        for l in range(k, nk):
            il = idx[l]
            el = elem[il]
            _compliance_block(Kc, 6 * ik, Bc[k], 6 * il, Bc[l], W, 3 * k, 3 * l, 6)   # cable
            _compliance_block(Ks, 6 * ek, Gs[k], 6 * el, Gs[l], W, 3 * k, 3 * l, 12)   # casing
            if l != k:
                for r in range(3):
                    for c in range(3):
                        W[3 * l + c, 3 * k + r] = W[3 * k + r, 3 * l + c]
    for k in range(nk):
        tangent_basis(nrm[k, 0], nrm[k, 1], nrm[k, 2], ta[k], tb[k])
        i = idx[k]
        wn = wst[k, 0] * nrm[k, 0] + wst[k, 1] * nrm[k, 1] + wst[k, 2] * nrm[k, 2]
        wt0, wt1, wt2 = wst[k, 0] - wn * nrm[k, 0], wst[k, 1] - wn * nrm[k, 1], wst[k, 2] - wn * nrm[k, 2]
        sp = np.sqrt(wt0 * wt0 + wt1 * wt1 + wt2 * wt2)
        speed = sp if state[i] == OPEN else vrel[i]
        mode[k] = STICK if speed < v_stick else SLIP
        sdir[k, 0], sdir[k, 1], sdir[k, 2] = (wt0 / sp, wt1 / sp, wt2 / sp) if sp > 0.0 else (0.0, 0.0, 0.0)
        for c in range(3):
            P[3 * k + c] = Pn[i, c] if state[i] != OPEN else 0.0
        active[k] = True
        touch[k] = False
    for k in range(nk):
        o = 3 * k
        wkk[k] = max(W[o, o], W[o + 1, o + 1], W[o + 2, o + 2])
    for outer in range(8):
        r = _unknowns(nk, nrm, ta, tb, mode, active, P, off, x)
        _reduced_delassus(W, nk, nrm, ta, tb, sdir, mu, off, Q)
        its = _newton(Q, r, nk, off, touch, gst, gdst, wst, ta, tb, wkk, x, law, k_lin, k_hertz, c_n,
                      dt, J, R, dx, y, Ne, Nd, xt)
        _forces(nk, nrm, ta, tb, sdir, mu, off, x, P)
        _relative_displacement(W, P, m, d)
        diag[4] += abs(its)
        diag[5] += 1
        if its < 0:
            diag[1] = 1.0
        changed = False
        for k in range(nk):
            if not active[k]:
                continue
            o = 3 * k
            N = Ne[k] + Nd[k]
            if N <= 0.0:
                active[k] = False
                P[o], P[o + 1], P[o + 2] = 0.0, 0.0, 0.0
                changed = True
                continue
            # the law holds for g > 0; at g <= 0 the damper alone would push the bodies apart past
            # the surface, so the step ends touching (g = 0, N <= c_n g_dot); a touching contact
            # whose force exceeds the damper's goes back to the law
            dn = nrm[k, 0] * d[o] + nrm[k, 1] * d[o + 1] + nrm[k, 2] * d[o + 2]
            if not touch[k] and gst[k] + dn <= 0.0:
                touch[k] = True
                changed = True
            elif touch[k] and N > c_n * max(gdst[k] + c2 * dn, 0.0) * (1 + 1e-12):
                touch[k] = False
                changed = True
            pn = P[o] * nrm[k, 0] + P[o + 1] * nrm[k, 1] + P[o + 2] * nrm[k, 2]
            pt0, pt1, pt2 = P[o] - pn * nrm[k, 0], P[o + 1] - pn * nrm[k, 1], P[o + 2] - pn * nrm[k, 2]
            ft = np.sqrt(pt0 * pt0 + pt1 * pt1 + pt2 * pt2)
            if mode[k] == STICK and ft > mu * N * (1 + 1e-12):
                mode[k] = SLIP
                sdir[k, 0], sdir[k, 1], sdir[k, 2] = -pt0 / ft, -pt1 / ft, -pt2 / ft
                changed = True
            elif mode[k] == SLIP:
                w0, w1, w2 = wst[k, 0] + c2 * d[o], wst[k, 1] + c2 * d[o + 1], wst[k, 2] + c2 * d[o + 2]
                wn = w0 * nrm[k, 0] + w1 * nrm[k, 1] + w2 * nrm[k, 2]
                wt0, wt1, wt2 = w0 - wn * nrm[k, 0], w1 - wn * nrm[k, 1], w2 - wn * nrm[k, 2]
                if wt0 * sdir[k, 0] + wt1 * sdir[k, 1] + wt2 * sdir[k, 2] < 0.0:
                    # friction would reverse the slip: it sticks instead
                    if v_stick > 0.0 and outer < 4:
                        mode[k] = STICK
                    else:
                        spd = np.sqrt(wt0 * wt0 + wt1 * wt1 + wt2 * wt2)
                        if spd > 0.0:
                            sdir[k, 0], sdir[k, 1], sdir[k, 2] = wt0 / spd, wt1 / spd, wt2 / spd
                    changed = True
        if not changed:
            break
    if changed:
        # the passes ran out with a change: a contact the last pass opened still counts in d
        _relative_displacement(W, P, m, d)
    gmax = 0.0
    for k in range(nk):
        i = idx[k]
        o = 3 * k
        if not active[k] or Ne[k] + Nd[k] <= 0.0:
            continue
        n0, n1, n2 = nrm[k, 0], nrm[k, 1], nrm[k, 2]
        dn = n0 * d[o] + n1 * d[o + 1] + n2 * d[o + 2]
        g = 0.0 if touch[k] else gst[k] + dn
        gout[i] = g
        Nout[i] = Ne[k] + Nd[k]
        gmax = max(gmax, g)
        w0, w1, w2 = wst[k, 0] + c2 * d[o], wst[k, 1] + c2 * d[o + 1], wst[k, 2] + c2 * d[o + 2]
        wn = w0 * n0 + w1 * n1 + w2 * n2
        wt0, wt1, wt2 = w0 - wn * n0, w1 - wn * n1, w2 - wn * n2
        state[i] = mode[k]
        vrel[i] = np.sqrt(wt0 * wt0 + wt1 * wt1 + wt2 * wt2)
        diag[2] += Nd[k] * wn                         # damping acts only while compressing
        pn = P[o] * n0 + P[o + 1] * n1 + P[o + 2] * n2
        diag[3] -= (P[o] - pn * n0) * wt0 + (P[o + 1] - pn * n1) * wt1 + (P[o + 2] - pn * n2) * wt2
        Pn[i, 0], Pn[i, 1], Pn[i, 2] = P[o], P[o + 1], P[o + 2]
        # generalized forces: +P at the cable node (with its moment), -P on the casing element
        for r in range(6):
            fcc[6 * i + r] += Bc[k, r, 0] * P[o] + Bc[k, r, 1] * P[o + 1] + Bc[k, r, 2] * P[o + 2]
        e = elem[i]
        for r in range(12):
            fcs[6 * e + r] += Gs[k, r, 0] * P[o] + Gs[k, r, 1] * P[o + 1] + Gs[k, r, 2] * P[o + 2]
    for i in range(nn):
        if Nout[i] == 0.0:
            state[i] = OPEN
            Pn[i, 0], Pn[i, 1], Pn[i, 2] = 0.0, 0.0, 0.0
    diag[0] = gmax
    return nk


def contact_step(Xc, Tc, Uc, Vc, Xs, Rs, Ls, Us, Vs, Kc, Ks,
                 gap, r_in, law, k_lin, k_hertz, c_n, mu, v_stick, dt,
                 state, elem, xi_arr, Pn, vrel, Nout, gout, fcc, fcs, diag):
    """Contact of the cable nodes with the casing at the end of a step, from the predicted
    (contact-free) state (Eqs. 14-39). Writes the generalized contact forces on the cable (fcc, N
    and N.m) and the casing (fcs), the per-node state (OPEN/STICK/SLIP: the mode the forces were
    solved in), normal force (N), penetration (m) and tangential relative speed at the end of the
    step (vrel, m/s: the next step sticks when it lies inside the band +-v_stick, Section 2.1).
    Kc, Ks: effective compliances (m/N) over all DOFs of each body (zero rows and columns on the
    prescribed DOFs). Returns the number of
    contacts examined (penetrating before the solve). diag[0] = max penetration (m), diag[1] = 1
    if Newton failed, diag[2] and diag[3] = power dissipated (W) by contact damping (N_d g_dot) and
    by friction (-P_t . w_t); diag[4] and diag[5] count Newton iterations and stick/slip passes. Allocates its scratch arrays; the step loop reuses one set."""
    return _contact(Xc, Tc, Uc, Vc, Xs, Rs, Ls, Us, Vs, Kc, Ks,
                    (gap, r_in, law, k_lin, k_hertz, c_n, mu, v_stick, dt),
                    state, elem, xi_arr, Pn, vrel, Nout, gout, fcc, fcs, diag, contact_workspace(len(Xc)))


# ------------------------------------------------------------------------------------------------
# Newmark (average acceleration, gamma = 1/2, beta = 1/4) for one body


@njit(**NO_RT)
def _predict(Md, Dinv, L, LT, g0, ng, f0, nf, alpha, beta, U, V, A, pres, pchan, cpl_i, cpl_v, up, vp, ap, step,
             dt, y1, r):
    """Contact-free Newmark predictor: prescribe the supports at t+dt (Eq. 13) and solve
    S_ff u_f = [M (c0 u + 2 c1 v + a) + C (c1 u + v)]_f - (coupling to the prescribed DOFs) for the
    free DOFs, S = K + c1 C + c0 M = ck K + cm M, C = alpha M + beta K, c0 = 4/dt^2, c1 = 2/dt,
    ck = 1 + c1 beta, cm = c0 + c1 alpha; U[free] holds the result.

    One matrix product instead of two: with z = beta (c1 u + v) on the free DOFs the stiffness part
    is K z = (S z - cm M z) / ck, so u_f = z_f / ck + S_ff^-1 ([M w]_f - [K_fp (u_p + beta v_p)]),
    w = c0 u + 2 c1 v + a + alpha (c1 u + v) - (cm / ck) z (free), -(a_p + alpha v_p) (prescribed).
    The stiffness enters only through K_fp, the few free rows next to the supports, given as
    triplets: row cpl_i[0, m], support cpl_i[1, m] (index into pres), value cpl_v[m] (N/m). The
    solve runs over the node blocks g0 .. g0+ng-1 that hold the free DOFs (prescribed DOFs among
    them are identity rows with zero right-hand side). The supports move as row ``step`` of up, vp,
    ap (m, m/s, m/s2, by channel). y1 is a padded scratch vector, r has ng."""
    b = (Md.shape[0] - 1) // 2
    n = U.shape[0]
    c0 = 4.0 / (dt * dt)
    c1 = 2.0 / dt
    ck = 1.0 + c1 * beta
    q = (c0 + c1 * alpha) / ck
    z1 = y1[b:b + n]
    cu = c0 + c1 * alpha - q * beta * c1
    cv = 2 * c1 + alpha - q * beta
    for j in range(n):
        z1[j] = cu * U[j] + cv * V[j] + A[j]
    for k in range(len(pres)):
        j = pres[k]
        ch = pchan[k]
        u, v, a = (up[step, ch], vp[step, ch], ap[step, ch]) if ch >= 0 else (0.0, 0.0, 0.0)
        U[j], V[j], A[j] = u, v, a
        y1[b + j] = -(a + alpha * v)
    for i in range(ng):
        r[i] = 0.0
    dia_product(Md, y1, g0, ng, r)
    # - K_fp (u_p + beta v_p); the triplets come row by row, and each row's terms are subtracted in a
    # register (in the same order as one at a time from r[row], so the same result): through memory,
    # each term would wait for the previous one's store
    m = 0
    nm = cpl_v.shape[0]
    while m < nm:
        row = cpl_i[0, m]
        acc = r[row - g0]
        while m < nm and cpl_i[0, m] == row:
            j = pres[cpl_i[1, m]]
            acc -= cpl_v[m] * (U[j] + beta * V[j])
            m += 1
        r[row - g0] = acc
    for k in range(len(pres)):
        if g0 <= pres[k] < g0 + ng:
            r[pres[k] - g0] = 0.0
    block_solve(Dinv, L, LT, r)
    u, v, rf = U[f0:f0 + nf], V[f0:f0 + nf], r[f0 - g0:f0 - g0 + nf]
    bk = beta / ck
    for i in range(nf):
        u[i] = rf[i] + bk * (c1 * u[i] + v[i])


@njit(cache=True, fastmath=FM, error_model="numpy")
def _correct(Kinv, fc, U, jl):
    """U += Keff^-1 fc: the bodies' exact response to the contact forces fc (linear structure).
    fc is nonzero on a few DOFs only (6 per cable contact node, 12 per casing element touched), so
    the response is the sum of those compliance rows (Kinv symmetric, zero on the prescribed
    DOFs), not a full solve; four rows per pass over U (a quarter of its loads and stores).
    jl: integer scratch of len(U)."""
    n = U.shape[0]
    m = 0
    for j in range(n):
        if fc[j] != 0.0:
            jl[m] = j
            m += 1
    k = 0
    while k + 4 <= m:
        a, b, c, d = jl[k], jl[k + 1], jl[k + 2], jl[k + 3]
        fa, fb, fc_, fd = fc[a], fc[b], fc[c], fc[d]
        ra, rb, rc, rd = Kinv[a], Kinv[b], Kinv[c], Kinv[d]
        for i in range(n):
            U[i] += (fa * ra[i] + fb * rb[i]) + (fc_ * rc[i] + fd * rd[i])
        k += 4
    for k in range(k, m):
        fa = fc[jl[k]]
        ra = Kinv[jl[k]]
        for i in range(n):
            U[i] += fa * ra[i]


@njit(cache=True, fastmath=FM, error_model="numpy")
def _finish(f0, nf, U, V, A, Uo, Vo, Ao, dt):
    """Newmark update of the free DOFs' acceleration and velocity from the new displacement; states
    below TINY are flushed to zero."""
    c0 = 4.0 / (dt * dt)
    c2 = 4.0 / dt
    u, v, a = U[f0:f0 + nf], V[f0:f0 + nf], A[f0:f0 + nf]
    uo, vo, ao = Uo[f0:f0 + nf], Vo[f0:f0 + nf], Ao[f0:f0 + nf]
    # Far from the excitation the response decays towards zero through subnormal numbers, where
    # every operation costs ~100 times more (10-50x slower steps were measured at the start of a
    # run). States below TINY (in SI units, physically nothing) are set to zero, by selects in the
    # same pass (branches in a second pass cost a third more).
    for i in range(nf):
        ui = u[i]
        ai = c0 * (ui - uo[i]) - c2 * vo[i] - ao[i]
        vi = vo[i] + 0.5 * dt * (ao[i] + ai)
        u[i] = 0.0 if abs(ui) < TINY else ui      # (NaN stays NaN, for the blow-up check)
        v[i] = 0.0 if abs(vi) < TINY else vi
        a[i] = 0.0 if abs(ai) < TINY else ai


@njit(cache=True, fastmath=FM, error_model="numpy")
def _reactions(sup, sup_lo, alpha, beta, U, V, A, fc, pres, pslot, out, off):
    """Force the body exerts on each support DOF: -(M a + C v + K u - f_contact) at the
    prescribed DOFs (Eq. 13). sup[q, 0] and sup[q, 1] are the rows of M and K of DOF pres[q] over
    the columns sup_lo[q] .. sup_lo[q] + w - 1 (its band), contiguous, so each reaction is one
    short dot product. Written into out[off + pslot[q]]."""
    w = sup.shape[2]
    for q in range(len(pres)):
        j0 = sup_lo[q]
        mr, kr = sup[q, 0], sup[q, 1]
        u, v, a = U[j0:j0 + w], V[j0:j0 + w], A[j0:j0 + w]
        sm = 0.0
        sk = 0.0
        for k in range(w):
            sm += mr[k] * (a[k] + alpha * v[k])
            sk += kr[k] * (u[k] + beta * v[k])
        out[off + pslot[q]] = fc[pres[q]] - (sm + sk)


@njit(cache=True, fastmath=FM, error_model="numpy")
def _work(U, Uo, f, fn, lo, hi):
    """Trapezoidal work (J) of the forces f (old) and fn (new) over U - Uo on DOFs lo..hi-1 (four
    partial sums, as in :func:`dot`)."""
    u, uo, a, an = U[lo:hi], Uo[lo:hi], f[lo:hi], fn[lo:hi]
    s0 = s1 = s2 = s3 = 0.0
    n = hi - lo
    i = 0
    while i + 4 <= n:
        s0 += (a[i] + an[i]) * (u[i] - uo[i])
        s1 += (a[i + 1] + an[i + 1]) * (u[i + 1] - uo[i + 1])
        s2 += (a[i + 2] + an[i + 2]) * (u[i + 2] - uo[i + 2])
        s3 += (a[i + 3] + an[i + 3]) * (u[i + 3] - uo[i + 3])
        i += 4
    for i in range(i, n):
        s0 += (a[i] + an[i]) * (u[i] - uo[i])
    return 0.5 * ((s0 + s1) + (s2 + s3))


@njit(cache=True, fastmath=FM, error_model="numpy")
def _predicted_velocity(f0, nf, U, Uo, V, Vo, dt):
    """Newmark velocity of the free DOFs from the predicted displacement: v = 2/dt (u - u_old) - v_old."""
    u, uo, v, vo = U[f0:f0 + nf], Uo[f0:f0 + nf], V[f0:f0 + nf], Vo[f0:f0 + nf]
    for i in range(nf):
        v[i] = 2.0 / dt * (u[i] - uo[i]) - vo[i]


@njit(**NO_RT)
def _body_ledger(Md, Kd, alpha, beta, U, Uo, V, Vo, pres, pslot, reac, reac_new, off, fc, fc_new,
                 contact_on, ledger_on, y, t, dt, ledger):
    """One body's share of a step in the energy ledger (J), trapezoidal rule: work of its supports
    (reactions at slots off + pslot), work of the contact forces fc -> fc_new and, with ledger_on,
    the Rayleigh dissipation (y: padded scratch, t: scratch (2, n))."""
    for q in range(len(pres)):
        j = pres[q]
        ledger[0] += -0.5 * (reac[off + pslot[q]] + reac_new[off + pslot[q]]) * (U[j] - Uo[j])
    n = U.shape[0]
    if contact_on:
        ledger[4] += _work(U, Uo, fc, fc_new, 0, n)
    if ledger_on:
        b = (Md.shape[0] - 1) // 2
        z = y[b:b + n]
        for i in range(n):
            z[i] = Vo[i] + V[i]
        ledger[1] += 0.25 * dt * dia_quadratic(Md, Kd, alpha, beta, y, t)


@njit(cache=True, fastmath=FM, error_model="numpy")
def run_steps(t0, dt, up, vp, ap,
              s_on, sMd, sKd, sDi, sL, sLT, sg0, sng, sf0, snf, salpha, sbeta, sU, sV, sA, spres, spchan,
              spslot, sKinv, ssup, ssup_lo, scpl_i, scpl_v,
              c_on, cMd, cKd, cDi, cL, cLT, cg0, cng, cf0, cnf, calpha, cbeta, cU, cV, cA, cpres, cpchan,
              cpslot, cKinv, csup, csup_lo, ccpl_i, ccpl_v,
              contact_on, Xc, Tc, Xs, Rs, Ls, gap, r_in, r_cable, law, k_lin, k_hertz, c_n, mu, v_stick,
              state, elem, xi_arr, Pn, vrel, Nn, gn, fcs, fcc, reac, ledger, contact_time, ledger_on, ws,
              rec_on, rec_F, rec_ptr, rec_node, rec_state, rec_N, rec_g, rec_off, info):
    """Advance both bodies (s: casing, c: cable) by len(up) Newmark steps of size dt (s) from time
    t0 (s). Each step: contact-free predictor of both bodies, contact search and implicit contact
    forces (:func:`contact_step`), the bodies' response to them, Newmark update, reactions.

    up, vp, ap: (n, 12) support channel displacement (m), velocity (m/s), acceleration (m/s2) at
    t0 + (k+1) dt. reac (24): force each body exerts on each support, N and N.m, in the order
    casing A, casing B, cable A, cable B, each [Fx Fy Fz Mx My Mz]. ledger (J): [work of the
    supports, Rayleigh dissipation, energy at the start (set by the engine), friction dissipation,
    work of the contact forces, contact-damping dissipation, last friction power (W), last damping
    power (W)]; the dissipations integrate the powers by the trapezoidal rule. contact_time (s, per
    cable node): time spent in contact (stick or slip), accumulated every step. ws: contact
    workspace. Returns a status code (OK or ERR_*); info = [time, node, value] of a failure, then
    the running totals of contact Newton iterations, stick/slip passes and steps in which a
    contact Newton did not converge. Non-finite support motion is refused before any step is taken
    (ERR_INPUT, info = [row, channel, 0/1/2 for up/vp/ap]), so nothing is half-written.

    With rec_on, step k writes row rec_off + k of rec_F (the reactions) and, sparse, the cable nodes
    in contact at its end: entries rec_ptr[r] .. rec_ptr[r + 1] - 1 (r = rec_off + k; rec_ptr[rec_off]
    set by the caller) of rec_node, rec_state, rec_N (N) and rec_g (m). Capacity: nn per step.
    """
    nsteps = up.shape[0]
    for q, x in enumerate((up, vp, ap)):
        for k in range(nsteps):
            for j in range(x.shape[1]):
                if not np.isfinite(x[k, j]):
                    info[0], info[1], info[2] = k, j, q
                    return ERR_INPUT
    ns = sU.shape[0]
    nc = cU.shape[0]
    sb = (sMd.shape[0] - 1) // 2
    cb = (cMd.shape[0] - 1) // 2
    sUo, sVo, sAo = sU.copy(), sV.copy(), sA.copy()
    cUo, cVo, cAo = cU.copy(), cV.copy(), cA.copy()
    sy1, sr = np.zeros(ns + 2 * sb), np.zeros(max(sng, 1))
    cy1, cr = np.zeros(nc + 2 * cb), np.zeros(max(cng, 1))
    sq, cq = np.zeros((2, ns)), np.zeros((2, nc))
    fcs_new, fcc_new = np.zeros(ns), np.zeros(nc)
    reac_new = np.zeros(24)
    jl = np.zeros(max(ns, nc), np.int64)
    diag = np.zeros(6)
    cpar = (gap, r_in, law, k_lin, k_hertz, c_n, mu, v_stick, dt)
    nn = Xc.shape[0]
    t = t0
    for k in range(nsteps):
        t = t0 + (k + 1) * dt
        if s_on:
            copy_into(sUo, sU)
            copy_into(sVo, sV)
            copy_into(sAo, sA)
            _predict(sMd, sDi, sL, sLT, sg0, sng, sf0, snf, salpha, sbeta, sU, sV, sA, spres, spchan,
                     scpl_i, scpl_v, up, vp, ap, k, dt, sy1, sr)
        if c_on:
            copy_into(cUo, cU)
            copy_into(cVo, cV)
            copy_into(cAo, cA)
            _predict(cMd, cDi, cL, cLT, cg0, cng, cf0, cnf, calpha, cbeta, cU, cV, cA, cpres, cpchan,
                     ccpl_i, ccpl_v, up, vp, ap, k, dt, cy1, cr)
        if contact_on:
            _predicted_velocity(sf0, snf, sU, sUo, sV, sVo, dt)
            _predicted_velocity(cf0, cnf, cU, cUo, cV, cVo, dt)
            diag[1] = 0.0
            nact = _contact(Xc, Tc, cU, cV, Xs, Rs, Ls, sU, sV, cKinv, sKinv, cpar,
                            state, elem, xi_arr, Pn, vrel, Nn, gn, fcc_new, fcs_new, diag, ws)
            info[5] += diag[1]
            if nact > 0:
                _correct(sKinv, fcs_new, sU, jl)
                _correct(cKinv, fcc_new, cU, jl)
            for i in range(nn):
                if state[i] != OPEN:
                    contact_time[i] += dt
            if diag[0] > r_cable:
                info[0], info[2] = t, diag[0]
                for i in range(nn):
                    if gn[i] == diag[0]:
                        info[1] = i
                return ERR_PENETRATION
        if s_on:
            _finish(sf0, snf, sU, sV, sA, sUo, sVo, sAo, dt)
            _reactions(ssup, ssup_lo, salpha, sbeta, sU, sV, sA, fcs_new, spres, spslot, reac_new, 0)
        if c_on:
            _finish(cf0, cnf, cU, cV, cA, cUo, cVo, cAo, dt)
            _reactions(csup, csup_lo, calpha, cbeta, cU, cV, cA, fcc_new, cpres, cpslot, reac_new, 12)
        # blow-up check on the cheap aggregates
        tot = 0.0
        for i in range(24):
            tot += reac_new[i]
        if not np.isfinite(tot):
            info[0], info[1], info[2] = t, -1, tot
            return ERR_NAN
        # energy ledger (trapezoidal rule, consistent with the average-acceleration scheme)
        if s_on:
            _body_ledger(sMd, sKd, salpha, sbeta, sU, sUo, sV, sVo, spres, spslot, reac, reac_new, 0,
                         fcs, fcs_new, contact_on, ledger_on, sy1, sq, dt, ledger)
        if c_on:
            _body_ledger(cMd, cKd, calpha, cbeta, cU, cUo, cV, cVo, cpres, cpslot, reac, reac_new, 12,
                         fcc, fcc_new, contact_on, ledger_on, cy1, cq, dt, ledger)
        if contact_on:
            ledger[3] += 0.5 * dt * (ledger[6] + diag[3])
            ledger[5] += 0.5 * dt * (ledger[7] + diag[2])
            ledger[6] = diag[3]
            ledger[7] = diag[2]
        copy_into(reac, reac_new)
        if contact_on:
            copy_into(fcs, fcs_new)
            copy_into(fcc, fcc_new)
        if rec_on:
            r = rec_off + k
            for i in range(24):
                rec_F[r, i] = reac[i]
            j = rec_ptr[r]
            for i in range(nn):          # only the nodes in contact (a few of them)
                if state[i] != OPEN or Nn[i] != 0.0 or gn[i] != 0.0:
                    rec_node[j] = i
                    rec_state[j] = state[i]
                    rec_N[j] = Nn[i]
                    rec_g[j] = gn[i]
                    j += 1
            rec_ptr[r + 1] = j
    info[0] = t
    info[3] += diag[4]
    info[4] += diag[5]
    return OK


# ------------------------------------------------------------------------------------------------
# support motion inside a communication step (kinematics.QuinticStep, used by the FMU)
# The arithmetic is a few hundred operations; as numpy calls it cost ~10 µs per communication step
# in call overhead alone, as much as one Newmark step.


@njit(cache=True, fastmath=FM, error_model="numpy")
def taylor_rows(state, u, v, a, h, rows):
    """rows (6 x n) = [state (u, v, a at the step start); u + v h + a h^2/2; v + a h; a]: the start
    and the Taylor target at t + h of the inputs u (m), v (m/s), a (m/s2) given at t (h in s)."""
    for j in range(state.shape[1]):
        rows[0, j], rows[1, j], rows[2, j] = state[0, j], state[1, j], state[2, j]
        rows[3, j] = u[j] + v[j] * h + (0.5 * h * h) * a[j]
        rows[4, j] = v[j] + a[j] * h
        rows[5, j] = a[j]


@njit(cache=True, fastmath=FM, error_model="numpy")
def quintic_coefficients(G, rows, c):
    """c[d, k, j] = sum_m G[3 k + d, m] rows[m, j]: the power-basis coefficients of s^k of the
    displacement (d = 0, m), velocity (1, m/s) and acceleration (2, m/s2) of channel j, from the
    18 x 6 matrix G of ``kinematics._coefficient_matrix`` and rows (6 x n, start and end states)."""
    for k in range(6):
        for d in range(3):
            for j in range(rows.shape[1]):
                s = 0.0
                for m in range(6):
                    s += G[3 * k + d, m] * rows[m, j]
                c[d, k, j] = s


@njit(cache=True, fastmath=FM, error_model="numpy")
def quintic_values(c, t0, h, t, out):
    """out[d, i, j] = sum_k c[d, k, j] s_i^k (Horner), s_i = (t_i - t0) / h clipped to [0, 1]: the
    motion (m, m/s, m/s2 for d = 0, 1, 2) of channel j at the times t (s) of the step [t0, t0 + h]."""
    for i in range(t.shape[0]):
        s = min(max((t[i] - t0) / h, 0.0), 1.0)
        for d in range(3):
            for j in range(c.shape[2]):
                acc = c[d, 5, j]
                for k in range(4, -1, -1):
                    acc = acc * s + c[d, k, j]
                out[d, i, j] = acc
