"""Compiled linear algebra of the time loop: band storage, band LDLᵀ and its inverse, small dense
solves, and the Woodbury solve of the condensed contact step."""

from __future__ import annotations

import numpy as np

from pounding._numba import jit, jit_inline, jit_internal


@jit
def bandwidth(M, C, K):
    """Half bandwidth of the pattern of M, C and K (0 for diagonal; n − 1 when dense)."""
    n = M.shape[0]
    bw = 0
    for i in range(n):
        for j in range(n):
            if abs(i - j) > bw and (M[i, j] != 0.0 or C[i, j] != 0.0 or K[i, j] != 0.0):
                bw = abs(i - j)
    return bw


@jit
def to_band(A, bw):
    """Band rows of A: Ab[i, k] = A[i, i − bw + k], k = 0..2 bw."""
    n = A.shape[0]
    Ab = np.zeros((n, 2 * bw + 1))
    for i in range(n):
        for k in range(2 * bw + 1):
            j = i - bw + k
            if 0 <= j < n:
                Ab[i, k] = A[i, j]
    return Ab


@jit
def _band_matvec_add(Ab, bw, x, scale, out):
    """out += scale * A x for A in band rows: O(n bw), linear in the size of a shear-building row."""
    n = x.size
    for i in range(n):
        acc = 0.0
        for k in range(max(0, bw - i), min(2 * bw + 1, n - i + bw)):
            acc += Ab[i, k] * x[i - bw + k]
        out[i] += scale * acc


@jit
def _band_quadratic(AbT, bw, x):
    """xᵀ A x for A given by its diagonals (:func:`_band_bilinear`)."""
    return _band_bilinear(AbT, bw, x, x)


@jit_inline
def _band_bilinear(AbT, bw, x, y):
    """xᵀ A y for A given by its diagonals, ``AbT`` = band rows transposed ((2 bw + 1) × n,
    contiguous), one diagonal at a time (row-wise loops with clipped bounds cost several times
    more at these sizes), each in four partial sums: one sum is a chain of dependent additions,
    which the compiler may not reorder."""
    n = AbT.shape[1]  # A's order, not the vector's length (a scratch row may be longer)
    total = 0.0
    for k in range(2 * bw + 1):
        off = k - bw
        hi = min(n, n - off)
        i = max(0, -off)
        a0 = a1 = a2 = a3 = 0.0
        while i + 4 <= hi:
            a0 += AbT[k, i] * x[i] * y[i + off]
            a1 += AbT[k, i + 1] * x[i + 1] * y[i + 1 + off]
            a2 += AbT[k, i + 2] * x[i + 2] * y[i + 2 + off]
            a3 += AbT[k, i + 3] * x[i + 3] * y[i + 3 + off]
            i += 4
        while i < hi:
            a0 += AbT[k, i] * x[i] * y[i + off]
            i += 1
        total += (a0 + a1) + (a2 + a3)
    return total


@jit
def band_ldl(Jb, bw):
    """LDLᵀ factors of a symmetric positive definite band matrix given by band rows (no pivoting is
    needed: the Newmark tangent c0 M + w(c1 C + K) is SPD). L[i, k] holds L(i, i − bw + k), k < bw;
    D is returned as the inverse pivots."""
    n = Jb.shape[0]
    L = np.zeros((n, bw + 1))
    D = np.zeros(n)
    band_ldl_into(Jb, bw, L, D)
    return L, D


@jit
def band_ldl_into(Jb, bw, L, D):
    """:func:`band_ldl` into given arrays (L zeroed here), for code that must not allocate."""
    n = Jb.shape[0]
    for i in range(n):
        for k in range(bw + 1):
            L[i, k] = 0.0
    for j in range(n):
        s = Jb[j, bw]
        for k in range(max(0, j - bw), j):
            lk = L[j, k - j + bw]
            s -= lk * lk * D[k]
        D[j] = s
        for i in range(j + 1, min(n, j + bw + 1)):
            s = Jb[i, j - i + bw]
            for k in range(max(0, i - bw), j):
                s -= L[i, k - i + bw] * L[j, k - j + bw] * D[k]
            L[i, j - i + bw] = s / D[j]
    for j in range(n):
        D[j] = 1.0 / D[j]  # stored inverted: the solve multiplies


@jit
def band_solve(L, D, bw, r, x):
    """x = (L D⁻¹ Lᵀ)⁻¹ r in O(n bw), D holding the inverse pivots (x and r distinct arrays)."""
    band_solve_range(L, D, bw, r, x, np.int64(0), r.size)  # not a literal 0: one specialisation


@jit_internal
def band_solve_range(L, D, bw, r, x, lo, hi):
    """:func:`band_solve` on rows lo..hi−1 alone: exact when the matrix couples no row of that
    range with another (a range of whole diagonal blocks, :func:`band_blocks`) and r is zero
    outside it; x outside is left as it was."""
    for i in range(lo, hi):
        s = r[i]
        for j in range(max(lo, i - bw), i):
            s -= L[i, j - i + bw] * x[j]
        x[i] = s
    for i in range(lo, hi):
        x[i] *= D[i]
    for i in range(hi - 1, lo - 1, -1):
        s = x[i]
        for j in range(i + 1, min(hi, i + bw + 1)):
            s -= L[j, i - j + bw] * x[j]
        x[i] = s


@jit
def band_blocks(Pb, bw):
    """First and one-past-last row of the diagonal block holding each row (``blk[0]``,
    ``blk[1]``) of the band pattern Pb: no nonzero couples two blocks (separate buildings), so the
    band LDLᵀ factors are block diagonal too and a column J⁻¹ b is found on the blocks of b's dofs
    alone (:func:`band_column`)."""
    n = Pb.shape[0]
    blk = np.zeros((2, n), dtype=np.int64)
    start = 0
    for i in range(1, n + 1):
        cut = True
        for j in range(max(0, i - bw), i):
            for k in range(i, min(n, j + bw + 1)):
                if Pb[j, k - j + bw] != 0.0:
                    cut = False
        if cut:
            for m in range(start, i):
                blk[0, m] = start
                blk[1, m] = i
            start = i
    return blk


@jit
def _band_inverse(L, D, bw, out):
    """out = A⁻¹ (dense) from the band LDLᵀ factors of A, one column per unit vector (the setup of a
    run; explicit loops compile in a fraction of the time of numba's LAPACK bindings)."""
    n = D.size
    e = np.zeros(n)
    x = np.zeros(n)
    for j in range(n):
        e[j] = 1.0
        band_solve(L, D, bw, e, x)
        e[j] = 0.0
        for i in range(n):
            out[i, j] = x[i]


@jit
def _transpose(A):
    """A contiguous copy of Aᵀ."""
    out = np.empty((A.shape[1], A.shape[0]))
    for i in range(A.shape[0]):
        for j in range(A.shape[1]):
            out[j, i] = A[i, j]
    return out


@jit
def _gauss_solve(J, r, x):
    """x = J⁻¹ r by Gaussian elimination with partial pivoting; J and r are overwritten (a general
    square matrix: the tangent with a stuck slab's constraint rows is not symmetric)."""
    n = r.size
    b = r
    for col in range(n):
        piv = col
        for row in range(col + 1, n):
            if abs(J[row, col]) > abs(J[piv, col]):
                piv = row
        if piv != col:
            for q in range(n):
                J[col, q], J[piv, q] = J[piv, q], J[col, q]
            b[col], b[piv] = b[piv], b[col]
        p = J[col, col]
        for row in range(col + 1, n):
            f = J[row, col] / p
            if f != 0.0:
                for q in range(col, n):
                    J[row, q] -= f * J[col, q]
                b[row] -= f * b[col]
    for col in range(n - 1, -1, -1):
        acc = b[col]
        for q in range(col + 1, n):
            acc -= J[col, q] * x[q]
        x[col] = acc / J[col, col]


@jit_inline
def _solve_small(S, m):
    """Solve the m × m system in S[:m, :m] for the right-hand side in S's last column, in place
    (Gaussian elimination with partial pivoting). Returns False when it is singular."""
    rhs_col = S.shape[1] - 1
    for col in range(m):
        piv = col
        for row in range(col + 1, m):
            if abs(S[row, col]) > abs(S[piv, col]):
                piv = row
        if S[piv, col] == 0.0:
            return False
        if piv != col:
            for q in range(m):
                S[col, q], S[piv, q] = S[piv, q], S[col, q]
            S[col, rhs_col], S[piv, rhs_col] = S[piv, rhs_col], S[col, rhs_col]
        for row in range(col + 1, m):
            f = S[row, col] / S[col, col]
            for q in range(col, m):
                S[row, q] -= f * S[col, q]
            S[row, rhs_col] -= f * S[col, rhs_col]
    for col in range(m - 1, -1, -1):
        acc = S[col, rhs_col]
        for q in range(col + 1, m):
            acc -= S[col, q] * S[q, rhs_col]
        S[col, rhs_col] = acc / S[col, col]
    return True


@jit
def _dense_matvec_add(A, x, scale, out):
    """out += scale * A x, dense loops (small systems, where band bookkeeping costs more)."""
    n = x.size
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += A[i, j] * x[j]
        out[i] += scale * acc


@jit
def _mv(A, Ab, bw, dense, x, scale, out):
    """out += scale * A x in the cheaper form for the system size."""
    if dense:
        _dense_matvec_add(A, x, scale, out)
    else:
        _band_matvec_add(Ab, bw, x, scale, out)


@jit_internal
def band_column(L, D, bw, blk, dof, sign, c, e, x):
    """x = J⁻¹ b_c from J's band LDLᵀ factors, b_c the signs of row c at its dofs (a dof of −1 is
    the ground), solved on the diagonal blocks ``blk`` of its dofs (for a gap between two
    buildings, their floors alone) and zero elsewhere; ``e`` is zero on entry and on return."""
    n = e.size
    lo = n
    hi = np.int64(0)  # (a literal 0 compiled band_solve_range once more)
    for s in range(dof.shape[1]):
        k = dof[c, s]
        if k >= 0:
            e[k] += sign[c, s]
            lo = min(lo, blk[0, k])
            hi = max(hi, blk[1, k])
    for i in range(n):
        x[i] = 0.0
    band_solve_range(L, D, bw, e, x, lo, hi)
    for s in range(dof.shape[1]):
        k = dof[c, s]
        if k >= 0:
            e[k] = 0.0


#: An entry of J⁻¹ e_k below this fraction of the largest found so far ends the solve in that
#: direction (2⁻⁶⁴ ≈ 5e-20): far below the rounding of the sums the column enters.
DECAY = 2.0**-64


@jit_internal
def unit_column(L, D, bw, k, lo_b, hi_b, y):
    """y = J⁻¹ e_k from J's band LDLᵀ factors, on the rows of its diagonal block lo_b..hi_b−1 where
    it is not negligible; returns (lo, hi), the rows written (y zero elsewhere, as on entry).

    J = c0 M + w(c1 C + K) of a shear building is tridiagonal and strictly diagonally dominant, so
    its LDLᵀ multipliers are below 1 in magnitude and J⁻¹'s entries decay geometrically away from
    the diagonal, by a factor of about k_story/(c0 m) per floor: ~1e-5 at a contact's sub-step.
    The forward and back substitutions therefore stop once ``bw`` consecutive entries have fallen
    below :data:`DECAY` times the largest: a few floors instead of the whole building. Where the
    entries do not decay (a long step, a stiff building) they run to the block's ends and the
    column is the full solve."""
    y[k] = 1.0
    f = k + 1
    tail = 0
    while f < hi_b:  # L z = e_k: zero above k, |z| falls below k
        s = 0.0
        for j in range(max(k, f - bw), f):
            s -= L[f, j - f + bw] * y[j]
        y[f] = s
        f += 1
        if abs(s) <= DECAY:
            tail += 1
            if tail >= bw:
                break
        else:
            tail = 0
    for i in range(k, f):
        y[i] *= D[i]
    big = 0.0
    tail = 0
    lo = lo_b
    for i in range(f - 1, lo_b - 1, -1):  # Lᵀ y = D z on rows f−1 … lo
        s = y[i]
        for j in range(i + 1, min(f, i + bw + 1)):
            s -= L[j, i - j + bw] * y[j]
        y[i] = s
        big = max(big, abs(s))
        if i < k and abs(s) <= DECAY * big:
            tail += 1
            if tail >= bw:
                lo = i
                break
        else:
            tail = 0
    return lo, f


@jit
def woodbury_band_solve(L, D, bw, blk, R, x_dof, x_sign, kc, Zr, have, S, y, x, e):
    """x = −(J + Σ kc_c b_c b_cᵀ)⁻¹ R from the band LDLᵀ factors of J alone: J⁻¹ R by a band solve,
    and the columns J⁻¹ b_c of the rows with kc_c != 0 by band solves kept in Zr[:, c] (``have[c]``)
    for the later iterations of the same step: O(n bw) per iteration plus O(n bw) per row the first
    time it acts. Then the Sherman–Morrison–Woodbury correction (kc_c = inf: a constraint). ``e``
    is scratch (n). Returns False when the small system is singular."""
    n = R.size
    band_solve(L, D, bw, R, y)
    for i in range(n):
        y[i] = -y[i]
        e[i] = 0.0
    m = np.int64(0)  # int64 from the start: a literal 0 compiles _woodbury_correct twice
    for c in range(kc.size):
        if kc[c] == 0.0:
            continue
        m += 1
        if have[c]:
            continue
        band_column(L, D, bw, blk, x_dof, x_sign, c, e, x)
        for i in range(n):
            Zr[i, c] = x[i]
        have[c] = True
    for i in range(n):
        x[i] = y[i]
    if m == 0:
        return True
    return _woodbury_correct(n, x_dof, x_sign, kc, Zr, S, y, x, m)


@jit
def _woodbury_correct(n, x_dof, x_sign, kc, Zr, S, y, x, m):
    """x −= Z (D⁻¹ + Uᵀ Z)⁻¹ Uᵀ y over the m rows with kc != 0, Z[:, c] = J⁻¹ b_c of row c."""
    rhs_col = S.shape[1] - 1
    r = 0
    for c in range(kc.size):
        if kc[c] == 0.0:
            continue
        q = 0
        for c2 in range(kc.size):
            if kc[c2] == 0.0:
                continue
            acc = 0.0
            for s in range(x_dof.shape[1]):
                k = x_dof[c, s]
                if k >= 0:
                    acc += x_sign[c, s] * Zr[k, c2]
            S[r, q] = acc + (1.0 / kc[c] if r == q else 0.0)
            q += 1
        acc = 0.0
        for s in range(x_dof.shape[1]):
            k = x_dof[c, s]
            if k >= 0:
                acc += x_sign[c, s] * y[k]
        S[r, rhs_col] = acc
        r += 1
    if not _solve_small(S, m):
        return False
    q = 0
    for c in range(kc.size):
        if kc[c] == 0.0:
            continue
        g = S[q, rhs_col]
        for i in range(n):
            x[i] -= Zr[i, c] * g
        q += 1
    return True


@jit_internal
def inverse_column(J_inv, dof, sign, c, z):
    """z = J⁻¹ b_c, b_c the signs of row c at its dofs (a dof of −1 is the ground); ``z`` a column
    or a row of the caller's array."""
    for i in range(J_inv.shape[0]):
        acc = 0.0
        for s in range(dof.shape[1]):
            k = dof[c, s]
            if k >= 0:
                acc += J_inv[i, k] * sign[c, s]
        z[i] = acc


@jit
def _woodbury_solve(J_inv, R, el_dof, el_sign, kc, Z, S, y, x):
    """x = −(J + Σ kc_c b_c b_cᵀ)⁻¹ R using the dense J⁻¹ (small systems) and the
    Sherman–Morrison–Woodbury identity.

    b_c holds the element's two signs at its dofs; only elements with kc_c != 0 enter, so the small
    system has the size of the active set. kc_c = inf is a constraint b_cᵀ x = 0 (1/kc = 0: a stuck
    slab). Returns False when that system is singular."""
    n = R.size
    n_el = kc.size
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += J_inv[i, j] * R[j]
        y[i] = -acc
        x[i] = -acc
    m = np.int64(0)
    for c in range(n_el):
        if kc[c] == 0.0:
            continue
        inverse_column(J_inv, el_dof, el_sign, c, Z[:, c])
        m += 1
    if m == 0:
        return True
    return _woodbury_correct(n, el_dof, el_sign, kc, Z, S, y, x, m)
