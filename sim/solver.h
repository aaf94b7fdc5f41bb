/*
 * solver.h — a thin, checked wrapper over SUNDIALS CVODE (BDF, dense direct
 * linear solver) shared by every scenario.
 *
 * Set-up follows the CVODE examples in a fixed order (context -> vectors ->
 * create -> init -> tolerances -> roots -> matrix -> linear solver), every call
 * checked; SUNDIALS' own error messages are captured into the handle (sim/
 * never prints) and copied into ts_err with the failing function's name and
 * CVodeGetReturnFlagName. One SUNContext per ts_ode, no globals: ts_ode
 * handles may live on different threads.
 *
 * Ownership: ts_ode_make / ts_ode_free (NULL is a no-op).
 */
#ifndef TS_SOLVER_H
#define TS_SOLVER_H

#include "errors.h"

/* Right-hand side ydot = f(t, y). Return 0 on success, > 0 for a recoverable
 * failure (CVODE retries with a smaller step), < 0 to stop. */
typedef int (*ts_rhs_fn)(double t, const double *y, double *ydot, void *ud);
/* Root functions g_i(t, y), nroots of them; same return convention. */
typedef int (*ts_root_fn)(double t, const double *y, double *g, void *ud);

typedef struct ts_ode ts_ode;

typedef struct ts_ode_opts {
    double rtol;             /* relative tolerance */
    double atol;             /* absolute tolerance applied to every state ... */
    const double *atol_v;    /* ... or per-state absolute tolerances (n values), if non-NULL */
    double max_step;         /* 0 = unlimited [s] */
    long max_steps;          /* internal steps per call, 0 = 100000 */
    int nroots;              /* number of root functions (0: none) */
    ts_root_fn roots;        /* may be NULL when nroots == 0 */
    int second_order;        /* non-zero: y = [q, q_d] (n/2 each) with dq/dt = q_d; the Newton
                              * systems are solved by their half-size Schur complement
                              * (falls back to the full LU when a matrix lacks that form),
                              * formed from the solver's own difference-quotient Jacobian
                              * (CVODE's increments and rounding: the same steps) without
                              * CVODE's n x n matrix copies */
    int small_dense;         /* non-zero: the full n x n Newton systems by dense_small.h's LU
                              * (single-threaded, skips zeros; for small sparse-ish systems,
                              * e.g. a powertrain) instead of SUNDIALS' dense LU */
    int max_order;           /* highest BDF order (CVODE maxord, 1..5); 0 = CVODE's default (5);
                              * any other value: ts_ode_make fails (TS_ERR_SOLVER) */
    long jac_eval_frequency; /* max steps between Jacobian evaluations (CVODE msbj);
                              * 0 = CVODE's default (51). CVODE still re-evaluates
                              * on a convergence failure with a stale Jacobian. */
} ts_ode_opts;

typedef struct ts_ode_stats {
    long steps, rhs_evals, jac_evals, err_test_fails, nonlin_iters, nonlin_fails;
    long lin_setups; /* Newton-matrix factorisations */
} ts_ode_stats;

ts_ode *ts_ode_make(int n, ts_rhs_fn f, void *ud, const ts_ode_opts *opts, ts_err *err);
void ts_ode_free(ts_ode *o);

/* (Re)start at t0 from y0 (n values). Use after any discontinuity of f. */
TS_MUST_CHECK ts_rc ts_ode_init(ts_ode *o, double t0, const double *y0, ts_err *err);

/* Integrate towards tout. On return *t holds the time reached: tout, or the
 * time of a root when *root_found is set (pass NULL to ignore roots; then
 * integration continues through them). */
TS_MUST_CHECK ts_rc ts_ode_advance(ts_ode *o, double tout, double *t, int *root_found, ts_err *err);

/* Never step past tstop (> the current time) in the following advances: the
 * integrator lands exactly on it instead of stepping beyond tout and
 * interpolating back (for a right-hand side known only up to tstop, e.g. a
 * co-simulation follower's input). Cleared once reached. */
TS_MUST_CHECK ts_rc ts_ode_set_stop(ts_ode *o, double tstop, ts_err *err);

/* Which roots fired at the last root return (nroots ints, -1/0/+1 direction). */
TS_MUST_CHECK ts_rc ts_ode_root_info(ts_ode *o, int *dirs, ts_err *err);

double *ts_ode_y(ts_ode *o); /* current state (n values), owned by the handle */
int ts_ode_n(const ts_ode *o);
/* Counters since ts_ode_make, summed over every (re)start. */
void ts_ode_get_stats(ts_ode *o, ts_ode_stats *s);

/* One classical RK4 step of size h of y' = f(t, y) from (t, y), in place, for the
 * explicit paths (the crank-angle engine's macro-stepped powertrain). work holds
 * 5 n doubles. Returns 0, or non-zero if f failed or y left the finite numbers
 * (y is then unspecified). */
TS_MUST_CHECK int ts_rk4_step(int n, ts_rhs_fn f, void *ud, double t, double h, double *y,
                              double *work);

/* The same step for the m states y[idx[0..m-1]] only, every other state of y
 * held (the macro-stepped engine's driveline sub-steps: the engine's states
 * frozen within a macro step). f evaluates the whole right-hand side into
 * ydot (n doubles, scratch); work holds 5 m doubles. Same arithmetic as
 * ts_rk4_step on those states. Returns 0, or non-zero if f failed or one of
 * those states left the finite numbers (those states are then unspecified). */
TS_MUST_CHECK int ts_rk4_step_subset(int m, const int *idx, ts_rhs_fn f, void *ud, double t,
                                     double h, double *y, double *ydot, double *work);

#endif
