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

void ts_lu_solve(const double *a, int n, const int *piv, double *b)
{
    for (int k = 0; k < n; k++)
        if (piv[k] != k) {
            double t = b[k];
            b[k] = b[piv[k]];
            b[piv[k]] = t;
        }
    for (int j = 0; j < n; j++) { /* L y = P b, unit diagonal, column sweep */
        const double *cj = a + (long)j * n;
        double bj = b[j];
        if (bj != 0.0)
            for (int i = j + 1; i < n; i++)
                b[i] -= bj * cj[i];
    }
    for (int j = n - 1; j >= 0; j--) { /* U x = y */
        const double *cj = a + (long)j * n;
        b[j] /= cj[j];
        double bj = b[j];
        if (bj != 0.0)
            for (int i = 0; i < j; i++)
                b[i] -= bj * cj[i];
    }
}

int ts_chol_factor(double *a, int n, int *pat)
{
    /* right-looking, column-major lower: column j is scaled, then each trailing
     * column k with L_kj != 0 gets L_ij L_kj subtracted on the rows i >= k
     * where L_ij != 0. The rows are gathered per column (nz), so a sparse
     * matrix ordered for little fill costs ~sum over j of nnz_j^2; the skipped
     * terms are exact zeros, so the result is that of the dense loop. */
    for (int j = 0; j < n; j++) {
        double *cj = a + (long)j * n;
        double d = cj[j];
        if (!(d > 0.0)) return j + 1;
        d = sqrt(d);
        cj[j] = d;
        double inv = 1.0 / d;
        int *nz = pat + (long)j * (n + 1) + 1;
        int m = 0;
        for (int i = j + 1; i < n; i++)
            if (cj[i] != 0.0) {
                cj[i] *= inv;
                nz[m++] = i;
            }
        nz[-1] = m;
        for (int r = 0; r < m; r++) {
            int k = nz[r];
            double *ck = a + (long)k * n, f = cj[k];
            for (int t = r; t < m; t++)
                ck[nz[t]] -= f * cj[nz[t]];
        }
    }
    return 0;
}

void ts_chol_solve(const double *a, int n, const int *pat, double *b)
{
    /* the column sweeps over each column's nonzero rows only */
    for (int j = 0; j < n; j++) { /* L y = b */
        const double *cj = a + (long)j * n;
        const int *nz = pat + (long)j * (n + 1);
        b[j] /= cj[j];
        double bj = b[j];
        if (bj != 0.0)
            for (int r = 1; r <= nz[0]; r++)
                b[nz[r]] -= bj * cj[nz[r]];
    }
    for (int i = n - 1; i >= 0; i--) { /* L^T x = y: column i of L is row i of L^T */
        const double *ci = a + (long)i * n;
        const int *nz = pat + (long)i * (n + 1);
        double s = b[i];
        for (int r = 1; r <= nz[0]; r++)
            s -= ci[nz[r]] * b[nz[r]];
        b[i] = s / ci[i];
    }
}
