/*
 * dense_small.h — LU (partial pivoting) and Cholesky factorisations of small
 * dense matrices (n up to a few dozen), in plain C.
 *
 * Why: the vehicle model solves its 21..31-DOF mass matrix on every
 * right-hand side and CVODE's Newton matrix on every step. At these sizes the
 * threaded BLAS behind LAPACK costs more in call overhead and in idle threads
 * spinning (sched_yield) than the arithmetic itself; these loops are
 * single-threaded, allocation-free and deterministic. Numerical methods only,
 * no physics (Golub & Van Loan, Alg. 3.4.1 and 4.2.2).
 *
 * Storage: COLUMN-major n x n, a[i + j*n]. ts_chol_* read only the lower
 * triangle (i >= j) and overwrite it by L; a symmetric row-major matrix may
 * be passed as it is (its upper triangle is read).
 */
#ifndef TS_DENSE_SMALL_H
#define TS_DENSE_SMALL_H

#include "errors.h"

/* LU with partial pivoting of the n x n column-major a, in place: P a = L U,
 * piv[k] = row swapped with k at step k. Returns 0, or k + 1 when the pivot of
 * column k is exactly zero. */
TS_MUST_CHECK int ts_lu_factor(double *a, int n, int *piv);
/* Solve (L U) x = P b in place in b with the output of ts_lu_factor. */
void ts_lu_solve(const double *a, int n, const int *piv, double *b);

/* Cholesky a = L L^T of the symmetric positive-definite n x n column-major a
 * (lower triangle read and overwritten by L), skipping zeros: it records the
 * nonzero rows of each column of L below the diagonal in pat (n (n + 1) ints,
 * caller's: pat[j (n + 1)] = count, then the rows). The skipped terms are
 * exact zeros, so L is that of the dense right-looking loop bit for bit.
 * Returns 0, or j + 1 when the leading minor of order j + 1 is not positive. */
TS_MUST_CHECK int ts_chol_factor(double *a, int n, int *pat);
/* Solve L L^T x = b in place in b with the output of ts_chol_factor, sweeping
 * only the recorded rows (again the dense sweeps' result). */
void ts_chol_solve(const double *a, int n, const int *pat, double *b);

/* The same two in REVERSED order, in place and without a copy: factor J a J
 * (J the exchange matrix: rows and columns n-1..0) as ts_chol_factor would
 * factor that reordered copy, leaving its L at the reversed positions (the
 * copy's element k at a[n n - 1 - k]; so its lower triangle is a's upper
 * one, column-major), and solve a x = b with it, b and x in a's own order.
 * Bit for bit the results of reversing, calling ts_chol_factor /
 * ts_chol_solve and reversing back. For a matrix whose dense rows come first
 * (e.g. a vehicle's hull coordinates): eliminated last, they fill in little. */
TS_MUST_CHECK int ts_chol_factor_rev(double *a, int n, int *pat);
void ts_chol_solve_rev(const double *a, int n, const int *pat, double *b);

/* For a matrix with a fixed sparsity: the rows where column j of the
 * reversed factor's L can be nonzero, fill included (cand, pat's layout,
 * n (n + 1) ints), from the structural nonzeros of a (mask, n x n, 1 where
 * a can be nonzero, symmetric; updated in place to the structure of L + L^T).
 * ts_chol_factor_rev_cand is ts_chol_factor_rev looking at those rows only,
 * instead of scanning every row of every column for nonzeros: the same L and
 * pat bit for bit, provided a's nonzeros lie within mask. */
void ts_chol_symbolic_rev(unsigned char *mask, int n, int *cand);
TS_MUST_CHECK int ts_chol_factor_rev_cand(double *a, int n, const int *cand, int *pat);

#endif
