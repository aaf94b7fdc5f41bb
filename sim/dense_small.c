/*
 * dense_small.c — small dense LU and Cholesky (dense_small.h): the textbook
 * right-looking LU with partial pivoting (Golub & Van Loan Alg. 3.4.1, the
 * trailing update column by column so the inner loop runs down contiguous
 * memory) and the right-looking (outer-product) Cholesky, likewise column by
 * column (Alg. 4.2.2), touching only each column's nonzero rows, so a sparse
 * matrix ordered for little fill (e.g. an arrowhead with its dense rows last)
 * costs little. Leaves out blocking: meant for n below ~100.
 */
#include "dense_small.h"

#include <math.h>
#include <stddef.h>

int ts_lu_factor(double *a, int n, int *piv)
{
    int bad = 0;
    for (int k = 0; k < n; k++) {
        double *ck = a + (long)k * n;
        int p = k;
        double amax = fabs(ck[k]);
        for (int i = k + 1; i < n; i++)
            if (fabs(ck[i]) > amax) amax = fabs(ck[i]), p = i;
        piv[k] = p;
        if (p != k)
            for (int j = 0; j < n; j++) {
                double *cj = a + (long)j * n, t = cj[k];
                cj[k] = cj[p];
                cj[p] = t;
            }
        if (ck[k] == 0.0) {
            if (!bad) bad = k + 1;
            continue;
        }
        double inv = 1.0 / ck[k];
        for (int i = k + 1; i < n; i++)
            ck[i] *= inv;
        for (int j = k + 1; j < n; j++) {
            double *cj = a + (long)j * n, f = cj[k];
            if (f == 0.0) continue;
            for (int i = k + 1; i < n; i++)
                cj[i] -= f * ck[i];
        }
    }
    return bad;
}

/* b[i] -= bk ck[i] for the rows i in [i0, i1), for the columns k of a block
 * of four, in column order (k = 0..3) as the column-at-a-time sweep; the
 * columns whose multiplier is zero are skipped, as there. One pass over b when
 * all four are nonzero. */
static void sweep4(double *b, int i0, int i1, const double *c[4], const double bk[4])
{
    if (bk[0] != 0.0 && bk[1] != 0.0 && bk[2] != 0.0 && bk[3] != 0.0) {
        const double *c0 = c[0], *c1 = c[1], *c2 = c[2], *c3 = c[3];
        double b0 = bk[0], b1 = bk[1], b2 = bk[2], b3 = bk[3];
        for (int i = i0; i < i1; i++)
            b[i] = b[i] - b0 * c0[i] - b1 * c1[i] - b2 * c2[i] - b3 * c3[i];
        return;
    }
    for (int k = 0; k < 4; k++)
        if (bk[k] != 0.0)
            for (int i = i0; i < i1; i++)
                b[i] -= bk[k] * c[k][i];
}

void ts_lu_solve(const double *a, int n, const int *piv, double *b)
{
    for (int k = 0; k < n; k++)
        if (piv[k] != k) {
            double t = b[k];
            b[k] = b[piv[k]];
            b[piv[k]] = t;
        }
    /* L y = P b, unit diagonal, column sweep; columns in blocks of four: the
     * block's own 4 x 4 triangle first, column by column, then the rows below
     * it in one pass (sweep4): every b[i] gets the subtractions of the
     * column-at-a-time loop in the same order */
    int j = 0;
    for (; j + 4 <= n; j += 4) {
        const double *c[4];
        double bk[4];
        for (int k = 0; k < 4; k++) {
            c[k] = a + (long)(j + k) * n;
            bk[k] = b[j + k];
            if (bk[k] != 0.0)
                for (int i = j + k + 1; i < j + 4; i++)
                    b[i] -= bk[k] * c[k][i];
        }
        sweep4(b, j + 4, n, c, bk);
    }
    for (; j < n; j++) {
        const double *cj = a + (long)j * n;
        double bj = b[j];
        if (bj != 0.0)
            for (int i = j + 1; i < n; i++)
                b[i] -= bj * cj[i];
    }
    /* U x = y, from the last column; the same blocking (rows above the block) */
    j = n - 1;
    for (; j - 3 >= 0; j -= 4) {
        const double *c[4];
        double bk[4];
        for (int k = 0; k < 4; k++) {
            int jk = j - k;
            c[k] = a + (long)jk * n;
            b[jk] /= c[k][jk];
            bk[k] = b[jk];
            if (bk[k] != 0.0)
                for (int i = j - 3; i < jk; i++)
                    b[i] -= bk[k] * c[k][i];
        }
        sweep4(b, 0, j - 3, c, bk);
    }
    for (; j >= 0; j--) {
        const double *cj = a + (long)j * n;
        b[j] /= cj[j];
        double bj = b[j];
        if (bj != 0.0)
            for (int i = 0; i < j; i++)
                b[i] -= bj * cj[i];
    }
}

/* The Cholesky loops over a matrix seen through a stride: element k of the
 * column-major array is a0[sg k], sg = +1 (the array itself) or -1 (a0 the
 * array's LAST element: the matrix with its rows and columns in reverse
 * order, J A J, without a copy). Inlined with a constant sg, so each entry
 * gets the same operations in the same order either way. */
static inline int chol_factor_s(double *a0, long sg, int n, const int *cand, int *pat)
{
    /* right-looking, column-major lower: column j is scaled, then each trailing
     * column k with L_kj != 0 gets L_ij L_kj subtracted on the rows i >= k
     * where L_ij != 0. The rows are gathered per column (nz), so a sparse
     * matrix ordered for little fill costs ~sum over j of nnz_j^2; the skipped
     * terms are exact zeros, so the result is that of the dense loop. With
     * cand, only its rows are looked at (the others are zeros of L). */
    for (int j = 0; j < n; j++) {
        double *cj = a0 + sg * (long)j * n;
        double d = cj[sg * j];
        if (!(d > 0.0)) return j + 1;
        d = sqrt(d);
        cj[sg * j] = d;
        double inv = 1.0 / d;
        int *nz = pat + (long)j * (n + 1) + 1;
        int m = 0;
        if (cand) {
            const int *cr = cand + (long)j * (n + 1);
            for (int t = 1; t <= cr[0]; t++)
                if (cj[sg * cr[t]] != 0.0) {
                    cj[sg * cr[t]] *= inv;
                    nz[m++] = cr[t];
                }
        } else
            for (int i = j + 1; i < n; i++)
                if (cj[sg * i] != 0.0) {
                    cj[sg * i] *= inv;
                    nz[m++] = i;
                }
        nz[-1] = m;
        for (int r = 0; r < m; r++) {
            int k = nz[r];
            double *ck = a0 + sg * (long)k * n, f = cj[sg * k];
            for (int t = r; t < m; t++)
                ck[sg * nz[t]] -= f * cj[sg * nz[t]];
        }
    }
    return 0;
}

/* b is seen through the same stride as a (b0 its last element when sg = -1). */
static inline void chol_solve_s(const double *a0, long sg, int n, const int *pat, double *b0)
{
    /* the column sweeps over each column's nonzero rows only */
    for (int j = 0; j < n; j++) { /* L y = b */
        const double *cj = a0 + sg * (long)j * n;
        const int *nz = pat + (long)j * (n + 1);
        b0[sg * j] /= cj[sg * j];
        double bj = b0[sg * j];
        if (bj != 0.0)
            for (int r = 1; r <= nz[0]; r++)
                b0[sg * nz[r]] -= bj * cj[sg * nz[r]];
    }
    for (int i = n - 1; i >= 0; i--) { /* L^T x = y: column i of L is row i of L^T */
        const double *ci = a0 + sg * (long)i * n;
        const int *nz = pat + (long)i * (n + 1);
        double s = b0[sg * i];
        for (int r = 1; r <= nz[0]; r++)
            s -= ci[sg * nz[r]] * b0[sg * nz[r]];
        b0[sg * i] = s / ci[sg * i];
    }
}

int ts_chol_factor(double *a, int n, int *pat)
{
    return chol_factor_s(a, 1, n, NULL, pat);
}

void ts_chol_solve(const double *a, int n, const int *pat, double *b)
{
    chol_solve_s(a, 1, n, pat, b);
}

int ts_chol_factor_rev(double *a, int n, int *pat)
{
    return chol_factor_s(a + (long)n * n - 1, -1, n, NULL, pat);
}

int ts_chol_factor_rev_cand(double *a, int n, const int *cand, int *pat)
{
    return chol_factor_s(a + (long)n * n - 1, -1, n, cand, pat);
}

void ts_chol_symbolic_rev(unsigned char *mask, int n, int *cand)
{
    /* mask[i' + j' n] for the reversed indices, i' = n - 1 - i: symmetric, so
     * a's row-major or column-major mask read backwards. Column j' of L has
     * the rows of A's column j' below the diagonal and, for every earlier
     * column k' with L_j'k' != 0, that column's rows below j' (its update). */
    unsigned char *s = mask + (long)n * n - 1; /* s[-(i' + j' n)] */
    for (int j = 0; j < n; j++) {
        int *cr = cand + (long)j * (n + 1), m = 0;
        for (int i = j + 1; i < n; i++)
            if (s[-(i + (long)j * n)]) cr[++m] = i;
        cr[0] = m;
        for (int r = 1; r <= m; r++) /* fill: column cr[r] gets rows cr[t], t >= r */
            for (int t = r; t <= m; t++)
                s[-(cr[t] + (long)cr[r] * n)] = s[-(cr[r] + (long)cr[t] * n)] = 1;
    }
}

void ts_chol_solve_rev(const double *a, int n, const int *pat, double *b)
{
    chol_solve_s(a + (long)n * n - 1, -1, n, pat, b + n - 1);
}
