/*
 * test_dense_small.c — the small dense LU and Cholesky of sim/dense_small.h
 * against their defining identities (residuals of A x = b) on random, pivoting-
 * hungry and sparse (arrowhead) matrices, and their failure returns.
 */
#include "test_util.h"

#include <stdlib.h>
#include <string.h>

#include "sim/dense_small.h"

#define NMAX 40

/* max |A x - b| / (|A| |x| + |b|), A column-major n x n */
static double residual(const double *A, int n, const double *x, const double *b)
{
    double worst = 0;
    for (int i = 0; i < n; i++) {
        double r = -b[i], s = fabs(b[i]);
        for (int j = 0; j < n; j++) {
            r += A[i + j * n] * x[j];
            s += fabs(A[i + j * n] * x[j]);
        }
        worst = fmax(worst, fabs(r) / s);
    }
    return worst;
}

/* EVIDENCE: definition of the LU solve (A x = b) on random matrices with a
 * zero leading diagonal (partial pivoting required); tolerance 1e-12 relative
 * residual (rounding). */
static void lu_solves_random_systems(void **state)
{
    (void)state;
    unsigned seed = 1;
    for (int n = 1; n <= NMAX; n += 3) {
        double A[NMAX * NMAX], F[NMAX * NMAX], b[NMAX], x[NMAX];
        int piv[NMAX];
        for (int i = 0; i < n * n; i++)
            A[i] = 0.5 * test_urand(&seed);
        A[0] = 0.0; /* forces a row swap at step 0 */
        for (int i = 0; i < n; i++)
            b[i] = 0.5 * test_urand(&seed);
        if (n == 1) A[0] = 0.5;
        memcpy(F, A, sizeof(double) * (size_t)(n * n));
        memcpy(x, b, sizeof(double) * (size_t)n);
        assert_int_equal(ts_lu_factor(F, n, piv), 0);
        ts_lu_solve(F, n, piv, x);
        assert_true(residual(A, n, x, b) < 1e-12);
    }
}

/* The column-at-a-time LU sweeps (Golub & Van Loan Alg. 3.4.1's solve): the
 * reference the blocked ts_lu_solve must reproduce bit for bit. */
static void plain_lu_solve(const double *a, int n, const int *piv, double *b)
{
    for (int k = 0; k < n; k++)
        if (piv[k] != k) {
            double t = b[k];
            b[k] = b[piv[k]];
            b[piv[k]] = t;
        }
    for (int j = 0; j < n; j++) {
        double bj = b[j];
        if (bj != 0.0)
            for (int i = j + 1; i < n; i++)
                b[i] -= bj * a[i + j * n];
    }
    for (int j = n - 1; j >= 0; j--) {
        b[j] /= a[j + j * n];
        double bj = b[j];
        if (bj != 0.0)
            for (int i = 0; i < j; i++)
                b[i] -= bj * a[i + j * n];
    }
}

/* ts_lu_solve (blocked four columns at a time) gives the column-at-a-time
 * sweeps' bits, for every n up to NMAX (every remainder of the blocking), with
 * right-hand sides that have zeros (the skipped columns) and without. */
static void lu_solve_blocked_is_the_plain_sweep(void **state)
{
    (void)state;
    unsigned seed = 5;
    for (int n = 1; n <= NMAX; n++)
        for (int zeros = 0; zeros < 2; zeros++) {
            double F[NMAX * NMAX], x[NMAX], xr[NMAX];
            int piv[NMAX];
            for (int i = 0; i < n * n; i++)
                F[i] = 0.5 * test_urand(&seed);
            for (int i = 0; i < n; i++)
                F[i + i * n] += 2.0;
            assert_int_equal(ts_lu_factor(F, n, piv), 0);
            for (int i = 0; i < n; i++)
                x[i] = zeros && (i < n / 2 || i % 3 == 1) ? 0.0 : 0.5 * test_urand(&seed);
            memcpy(xr, x, sizeof(double) * (size_t)n);
            ts_lu_solve(F, n, piv, x);
            plain_lu_solve(F, n, piv, xr);
            assert_memory_equal(x, xr, sizeof(double) * (size_t)n);
        }
}

/* EVIDENCE: a singular matrix (two equal columns) reports the failing pivot. */
static void lu_reports_singular(void **state)
{
    (void)state;
    double A[9] = {1, 2, 3, 1, 2, 3, 0, 1, 5};
    int piv[3];
    assert_true(ts_lu_factor(A, 3, piv) > 0);
}

/* The dense textbook reference (Golub & Van Loan Alg. 4.2.2, right-looking,
 * column-major lower) and its two sweeps: every term, zeros included. */
static void dense_cholesky_solve(double *a, int n, double *b)
{
    for (int j = 0; j < n; j++) {
        a[j + j * n] = sqrt(a[j + j * n]);
        double inv = 1.0 / a[j + j * n]; /* scaled by the reciprocal, as ts_chol_factor */
        for (int i = j + 1; i < n; i++)
            a[i + j * n] *= inv;
        for (int k = j + 1; k < n; k++)
            for (int i = k; i < n; i++)
                a[i + k * n] -= a[k + j * n] * a[i + j * n];
    }
    for (int j = 0; j < n; j++) {
        b[j] /= a[j + j * n];
        for (int i = j + 1; i < n; i++)
            b[i] -= b[j] * a[i + j * n];
    }
    for (int i = n - 1; i >= 0; i--) {
        double s = b[i];
        for (int k = i + 1; k < n; k++)
            s -= a[k + i * n] * b[k];
        b[i] = s / a[i + i * n];
    }
}

/* EVIDENCE: definition of the Cholesky solve on random SPD matrices (B^T B +
 * n I) and on a sparse arrowhead (dense last rows, the vehicle mass matrix's
 * shape, where the zero-skipping path acts); tolerance 1e-12 relative
 * residual; the zero-skipping factor and solution equal the dense textbook
 * loops' (dense_cholesky_solve) bit for bit, the recorded rows are exactly
 * the factor's nonzeros, and the arrowhead's factor is recorded sparse (fewer
 * than n(n-1)/2 entries). A matrix with a negative pivot is refused. */
static void cholesky_solves_spd_and_refuses_indefinite(void **state)
{
    (void)state;
    unsigned seed = 7;
    for (int pass = 0; pass < 2; pass++)
        for (int n = 1; n <= NMAX; n += 3) {
            double A[NMAX * NMAX], R[NMAX * NMAX], F[NMAX * NMAX], b[NMAX], x[NMAX];
            if (pass == 0) {
                for (int i = 0; i < n * n; i++)
                    R[i] = 0.5 * test_urand(&seed);
                for (int i = 0; i < n; i++)
                    for (int j = 0; j < n; j++) {
                        double s = i == j ? n : 0;
                        for (int k = 0; k < n; k++)
                            s += R[k + i * n] * R[k + j * n];
                        A[i + j * n] = s;
                    }
            } else {
                memset(A, 0, sizeof A);
                for (int i = 0; i < n; i++)
                    A[i + i * n] = 4.0 + 0.5 * test_urand(&seed);
                for (int h = n - 3 > 0 ? n - 3 : 0; h < n; h++)
                    for (int i = 0; i < n; i++)
                        if (i != h) {
                            double c = 0.15 * test_urand(&seed) / sqrt((double)n);
                            A[i + h * n] = A[h + i * n] = c;
                        }
            }
            for (int i = 0; i < n; i++)
                b[i] = 0.5 * test_urand(&seed);
            memcpy(F, A, sizeof(double) * (size_t)(n * n));
            memcpy(x, b, sizeof(double) * (size_t)n);
            int pat[NMAX * (NMAX + 1)];
            assert_int_equal(ts_chol_factor(F, n, pat), 0);
            ts_chol_solve(F, n, pat, x);
            assert_true(residual(A, n, x, b) < 1e-12);
            double D[NMAX * NMAX], xd[NMAX];
            memcpy(D, A, sizeof(double) * (size_t)(n * n));
            memcpy(xd, b, sizeof(double) * (size_t)n);
            dense_cholesky_solve(D, n, xd);
            assert_memory_equal(x, xd, sizeof(double) * (size_t)n);
            int nnz = 0;
            for (int j = 0; j < n; j++) {
                const int *nz = pat + j * (n + 1);
                nnz += nz[0];
                int r = 1;
                for (int i = j; i < n; i++) { /* L's column j, the diagonal and below */
                    assert_true(F[i + j * n] == D[i + j * n]);
                    if (i == j || D[i + j * n] == 0.0) continue;
                    assert_true(r <= nz[0] && nz[r] == i); /* recorded, in order */
                    r++;
                }
                assert_int_equal(r, nz[0] + 1); /* nothing else recorded */
            }
            if (pass == 1 && n > 6) assert_true(nnz < n * (n - 1) / 2);
        }
    double A[4] = {1, 2, 2, 1}; /* eigenvalues 3, -1 */
    int pat[2 * 3];
    assert_int_equal(ts_chol_factor(A, 2, pat), 2);
}

/* ts_chol_factor_rev / ts_chol_solve_rev are ts_chol_factor / ts_chol_solve
 * of the reversed copy (J A J, b reversed), bit for bit: the factor at the
 * reversed positions, the same column patterns, the same solution; on an
 * arrowhead with its dense rows FIRST (last after the reversal) and on a
 * dense SPD matrix. */
static void reversed_cholesky_is_the_reversed_copys(void **state)
{
    (void)state;
    unsigned seed = 11;
    for (int pass = 0; pass < 2; pass++)
        for (int n = 1; n <= NMAX; n += 2) {
            double A[NMAX * NMAX], R[NMAX * NMAX], b[NMAX], x[NMAX], xr[NMAX];
            int nn = n * n;
            memset(A, 0, sizeof A);
            for (int i = 0; i < n; i++)
                A[i + i * n] = 4.0 + 0.5 * test_urand(&seed);
            for (int h = 0; h < (pass ? n : (n < 3 ? n : 3)); h++) /* dense rows 0..2 */
                for (int i = 0; i < n; i++)
                    if (i != h) {
                        double c = 0.15 * test_urand(&seed) / sqrt((double)n);
                        A[i + h * n] = A[h + i * n] = c;
                    }
            for (int k = 0; k < nn; k++)
                R[k] = A[nn - 1 - k];
            for (int i = 0; i < n; i++)
                b[i] = 0.5 * test_urand(&seed);
            for (int i = 0; i < n; i++)
                xr[i] = b[n - 1 - i];
            int pat[NMAX * (NMAX + 1)], patr[NMAX * (NMAX + 1)];
            assert_int_equal(ts_chol_factor(R, n, patr), 0);
            ts_chol_solve(R, n, patr, xr);
            memcpy(x, b, sizeof(double) * (size_t)n);
            assert_int_equal(ts_chol_factor_rev(A, n, pat), 0);
            ts_chol_solve_rev(A, n, pat, x);
            for (int i = 0; i < n; i++)
                assert_true(x[i] == xr[n - 1 - i]);
            for (int j = 0; j < n; j++) {
                assert_memory_equal(pat + j * (n + 1), patr + j * (n + 1),
                                    sizeof(int) * (size_t)(patr[j * (n + 1)] + 1));
                for (int i = j; i < n; i++) /* the copy's L, at the reversed positions */
                    assert_true(A[nn - 1 - (i + j * n)] == R[i + j * n]);
            }
        }
    double A[4] = {1, 2, 2, 1};
    int pat[2 * 3];
    assert_int_equal(ts_chol_factor_rev(A, 2, pat), 2);
}

/* ts_chol_factor_rev_cand with the candidates of ts_chol_symbolic_rev is
 * ts_chol_factor_rev bit for bit (the factor and its patterns) on sparse SPD
 * matrices with fill: a few dense rows and a random scatter of couplings;
 * the candidates cover the recorded rows and are fewer than the dense scan's.
 * Also on a scatter without dense rows (session-29 mutation test: the fill
 * of a column's last candidate row left out of the symbolic step survived,
 * the dense rows, eliminated last, holding every such entry already). */
static void cholesky_candidates_are_the_full_scan(void **state)
{
    (void)state;
    unsigned seed = 23;
    for (int dense = 1; dense >= 0; dense--)
        for (int n = 2; n <= NMAX; n += 3) {
            double A[NMAX * NMAX], F[NMAX * NMAX];
            unsigned char mask[NMAX * NMAX];
            int nn = n * n;
            memset(A, 0, sizeof A);
            for (int i = 0; i < n; i++)
                A[i + i * n] = 4.0 + 0.5 * test_urand(&seed);
            for (int i = 0; i < n; i++)
                for (int j = 0; j < i; j++)
                    if ((dense && j < 2) || test_urand(&seed) < (dense ? 0.15 : 0.3)) {
                        double c = 0.15 * test_urand(&seed) / sqrt((double)n);
                        A[i + j * n] = A[j + i * n] = c;
                    }
            for (int k = 0; k < nn; k++)
                mask[k] = A[k] != 0.0;
            int cand[NMAX * (NMAX + 1)], pat[NMAX * (NMAX + 1)], patf[NMAX * (NMAX + 1)];
            ts_chol_symbolic_rev(mask, n, cand);
            memcpy(F, A, sizeof(double) * (size_t)nn);
            assert_int_equal(ts_chol_factor_rev(F, n, patf), 0);
            assert_int_equal(ts_chol_factor_rev_cand(A, n, cand, pat), 0);
            assert_memory_equal(A, F, sizeof(double) * (size_t)nn);
            int ncand = 0;
            for (int j = 0; j < n; j++) {
                assert_memory_equal(pat + j * (n + 1), patf + j * (n + 1),
                                    sizeof(int) * (size_t)(patf[j * (n + 1)] + 1));
                assert_true(cand[j * (n + 1)] >= patf[j * (n + 1)]);
                ncand += cand[j * (n + 1)];
            }
            if (dense && n > 8) assert_true(ncand < n * (n - 1) / 2);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(lu_solves_random_systems),
        cmocka_unit_test(lu_reports_singular),
        cmocka_unit_test(lu_solve_blocked_is_the_plain_sweep),
        cmocka_unit_test(cholesky_solves_spd_and_refuses_indefinite),
        cmocka_unit_test(reversed_cholesky_is_the_reversed_copys),
        cmocka_unit_test(cholesky_candidates_are_the_full_scan),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
