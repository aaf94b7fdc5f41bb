/*
 * solver.c — CVODE wrapper (see solver.h): set-up in the examples' fixed order,
 * one failure path, SUNDIALS messages captured instead of printed.
 */
#include "solver.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dense_small.h"
#include "nvector_kernels.h"

#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

struct ts_ode {
    int n;
    struct schur_ls *sls; /* the Schur linear solver when opts.second_order (NULL otherwise) */
    ts_rhs_fn f;
    ts_root_fn g;
    int nroots;
    void *ud;
    SUNContext ctx;
    N_Vector y;
    N_Vector atol_v;
    void *mem;
    SUNMatrix A;
    SUNLinearSolver LS;
    double t;
    char last_msg[256]; /* SUNDIALS' last error message */
    ts_ode_stats acc;   /* counters of the runs before the last (re)start */
};

static void cvode_stats(void *mem, ts_ode_stats *s)
{
    memset(s, 0, sizeof *s);
    CVodeGetNumSteps(mem, &s->steps);
    CVodeGetNumRhsEvals(mem, &s->rhs_evals);
    CVodeGetNumJacEvals(mem, &s->jac_evals);
    CVodeGetNumErrTestFails(mem, &s->err_test_fails);
    CVodeGetNumNonlinSolvIters(mem, &s->nonlin_iters);
    CVodeGetNumNonlinSolvConvFails(mem, &s->nonlin_fails);
    CVodeGetNumLinSolvSetups(mem, &s->lin_setups);
}

static void stats_add(ts_ode_stats *a, const ts_ode_stats *b)
{
    a->steps += b->steps;
    a->rhs_evals += b->rhs_evals;
    a->jac_evals += b->jac_evals;
    a->err_test_fails += b->err_test_fails;
    a->nonlin_iters += b->nonlin_iters;
    a->nonlin_fails += b->nonlin_fails;
    a->lin_setups += b->lin_setups;
}

/* ---- half-size Schur complement linear solver ------------------------------
 * For a second-order system y = [q, v] with dq/dt = v (h = n/2 each), the
 * Newton matrix I - gamma J has the block form [I  D; Mbl  Mbr] with D
 * diagonal (-gamma times the difference quotient of v by v). Eliminating the
 * first half, (Mbr - Mbl D) x2 = b2 - Mbl b1 and x1 = b1 - D x2: one h x h LU
 * instead of an n x n one (8x fewer flops; dense_small.h, no BLAS threads), the same solution up to
 * round-off.
 *
 * The Newton matrix is formed by schur_linsys (CVODE's linear-system hook)
 * instead of CVODE's dense path: the same difference-quotient Jacobian J
 * (cvLsDenseDQJac's increments and arithmetic), kept in the solver's own
 * n x n array, and only the h x h Schur complement of I - gamma J formed from
 * it, so the n x n SUNDIALS matrix is never copied nor scaled (CVODE's
 * savedJ -> A copy and A = I - gamma J were ~10 % of a vehicle run).
 * schur_form checks the structure exactly on each J and falls back to the
 * full n x n LU when it does not hold, so the solver is correct for any f.
 *
 * Without the hook (opts.small_dense alone, or an odd n) the same solver
 * object is a plain n x n LU of CVODE's A (dense_small.h instead of
 * SUNDIALS' dense LU). */
typedef struct schur_ls {
    int n, h, full; /* full: the n x n LU in F (always when !ext) */
    int ext;        /* the system is formed by schur_linsys (A is not read) */
    double *S, *F, *d, *r;
    double *J;    /* ext: the Jacobian (column-major n x n) */
    double *Mbl;  /* ext, !full: -gamma J21 (column-major h x h), formed once per factorisation */
    double gamma; /* ext: of the current factorisation */
    int checked;  /* ext: full was decided on the J now in the array (schur_form) */
    int *piv;
    long last_flag;
} schur_ls;

static SUNLinearSolver_Type schur_gettype(SUNLinearSolver ls)
{
    (void)ls;
    return SUNLINEARSOLVER_DIRECT;
}

static SUNLinearSolver_ID schur_getid(SUNLinearSolver ls)
{
    (void)ls;
    return SUNLINEARSOLVER_CUSTOM;
}

static int schur_initialize(SUNLinearSolver ls)
{
    ((schur_ls *)ls->content)->last_flag = 0;
    return SUNLS_SUCCESS;
}

/* Factor I - gamma J from the solver's own J (ext mode): its Schur
 * complement when J = [0 I'; J21 J22] with I' diagonal, else the full LU.
 * The structure is checked once per J (c->checked): CVODE refactors the same
 * J with a new gamma ~10 times per Jacobian. */
static int schur_form(schur_ls *c, double gamma)
{
    const double *J = c->J;
    int n = c->n, h = c->h;
    c->gamma = gamma;
    if (!c->checked) {
        c->full = 0;
        for (int j = 0; j < h && !c->full; j++) /* top-left block of J == 0 */
            for (int i = 0; i < h; i++)
                if (J[(size_t)j * n + i] != 0.0) {
                    c->full = 1;
                    break;
                }
        for (int j = 0; j < h && !c->full; j++) /* top-right block diagonal */
            for (int i = 0; i < h; i++)
                if (i != j && J[(size_t)(h + j) * n + i] != 0.0) {
                    c->full = 1;
                    break;
                }
        c->checked = 1;
    }
    if (!c->full)
        for (int j = 0; j < h; j++)
            c->d[j] = -gamma * J[(size_t)(h + j) * n + j];
    int info;
    if (c->full) {
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++)
                c->F[(size_t)j * n + i] = -gamma * J[(size_t)j * n + i] + (i == j ? 1.0 : 0.0);
        info = ts_lu_factor(c->F, n, c->piv);
    } else {
        for (int j = 0; j < h; j++)
            for (int i = 0; i < h; i++) {
                double mbr = -gamma * J[(size_t)(h + j) * n + h + i] + (i == j ? 1.0 : 0.0);
                double mbl = -gamma * J[(size_t)j * n + h + i];
                c->Mbl[(size_t)j * h + i] = mbl;
                c->S[(size_t)j * h + i] = mbr - mbl * c->d[j];
            }
        info = ts_lu_factor(c->S, h, c->piv);
    }
    c->last_flag = info;
    return info;
}

static int schur_setup(SUNLinearSolver ls, SUNMatrix A)
{
    schur_ls *c = ls->content;
    if (c->ext) /* factored by schur_linsys */
        return c->last_flag > 0 ? SUNLS_LUFACT_FAIL : SUNLS_SUCCESS;
    /* plain LU of CVODE's A (column-major, leading dimension n) */
    int n = c->n;
    memcpy(c->F, SUNDenseMatrix_Data(A), sizeof(double) * (size_t)n * (size_t)n);
    int info = ts_lu_factor(c->F, n, c->piv);
    c->last_flag = info;
    return info > 0 ? SUNLS_LUFACT_FAIL : SUNLS_SUCCESS;
}

static int schur_solve(SUNLinearSolver ls, SUNMatrix A, N_Vector xv, N_Vector bv, sunrealtype tol)
{
    (void)tol, (void)A;
    schur_ls *c = ls->content;
    int n = c->n, h = c->h;
    N_VScale(1.0, bv, xv);
    double *x = N_VGetArrayPointer(xv);
    if (c->full) {
        ts_lu_solve(c->F, n, c->piv, x);
    } else {
        for (int i = 0; i < h; i++)
            c->r[i] = x[h + i];
        /* r -= Mbl b1 (Mbl = -gamma J21, rounded as CVODE's A = I - gamma J),
         * column by column; four columns per pass over r (each r[i] gets the
         * same subtractions in the same order, one load and store of r[i]
         * instead of four) */
        double *r = c->r;
        const double *mb = c->Mbl;
        int j = 0;
        for (; j + 4 <= h; j += 4) {
            const double *c0 = mb + (size_t)j * h, *c1 = c0 + h, *c2 = c1 + h, *c3 = c2 + h;
            double b0 = x[j], b1 = x[j + 1], b2 = x[j + 2], b3 = x[j + 3];
            for (int i = 0; i < h; i++)
                r[i] = r[i] - c0[i] * b0 - c1[i] * b1 - c2[i] * b2 - c3[i] * b3;
        }
        for (; j < h; j++) {
            const double *c0 = mb + (size_t)j * h;
            double b0 = x[j];
            for (int i = 0; i < h; i++)
                r[i] -= c0[i] * b0;
        }
        ts_lu_solve(c->S, h, c->piv, c->r);
        for (int i = 0; i < h; i++) {
            x[i] -= c->d[i] * c->r[i];
            x[h + i] = c->r[i];
        }
    }
    c->last_flag = 0;
    return SUNLS_SUCCESS;
}

static sunindextype schur_lastflag(SUNLinearSolver ls)
{
    return (sunindextype)((schur_ls *)ls->content)->last_flag;
}

static int schur_free(SUNLinearSolver ls)
{
    if (!ls) return SUNLS_SUCCESS;
    schur_ls *c = ls->content;
    if (c) {
        free(c->S), free(c->F), free(c->d), free(c->r), free(c->J), free(c->Mbl), free(c->piv);
        free(c);
        ls->content = NULL;
    }
    SUNLinSolFreeEmpty(ls);
    return SUNLS_SUCCESS;
}

/* ext: the Schur solver fed by schur_linsys (n even); otherwise a plain LU. */
static SUNLinearSolver schur_make(int n, int ext, SUNContext ctx)
{
    SUNLinearSolver ls = SUNLinSolNewEmpty(ctx);
    if (!ls) return NULL;
    ls->ops->gettype = schur_gettype;
    ls->ops->getid = schur_getid;
    ls->ops->initialize = schur_initialize;
    ls->ops->setup = schur_setup;
    ls->ops->solve = schur_solve;
    ls->ops->lastflag = schur_lastflag;
    ls->ops->free = schur_free;
    schur_ls *c = calloc(1, sizeof *c);
    ls->content = c;
    if (!c) {
        schur_free(ls);
        return NULL;
    }
    c->n = n, c->h = n / 2;
    c->ext = ext;
    c->full = !ext;
    c->J = ext ? malloc(sizeof(double) * (size_t)n * (size_t)n) : NULL;
    c->F = malloc(sizeof(double) * (size_t)n * (size_t)n);
    c->piv = malloc(sizeof(int) * (size_t)n);
    if (ext) {
        c->S = malloc(sizeof(double) * (size_t)c->h * (size_t)c->h);
        c->d = malloc(sizeof(double) * (size_t)c->h);
        c->r = malloc(sizeof(double) * (size_t)c->h);
        c->Mbl = malloc(sizeof(double) * (size_t)c->h * (size_t)c->h);
    }
    if (!c->F || !c->piv || (ext && (!c->J || !c->S || !c->d || !c->r || !c->Mbl))) {
        schur_free(ls);
        return NULL;
    }
    return ls;
}

static int rhs_tramp(sunrealtype t, N_Vector y, N_Vector ydot, void *ud)
{
    ts_ode *o = ud;
    return o->f(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot), o->ud);
}

static int root_tramp(sunrealtype t, N_Vector y, sunrealtype *g, void *ud)
{
    ts_ode *o = ud;
    return o->g(t, N_VGetArrayPointer(y), g, o->ud);
}

/* CVODE's linear-system hook for the Schur solver: when CVODE asks for a new
 * Jacobian (!jok), the difference-quotient J of cvLsDenseDQJac (same
 * increments: srur |y_j| or the minimum increment from the weighted norm of
 * f), column by column into the solver's J; then I - gamma J is factored
 * (schur_form). A is not touched. */
#define DQ_MIN_INC_MULT 1000.0 /* cvLsDenseDQJac's constant */
static int schur_linsys(sunrealtype t, N_Vector yv, N_Vector fyv, SUNMatrix A, sunbooleantype jok,
                        sunbooleantype *jcur, sunrealtype gamma, void *ud, N_Vector tmp1,
                        N_Vector tmp2, N_Vector tmp3)
{
    (void)A, (void)tmp3;
    ts_ode *o = ud;
    schur_ls *c = o->sls;
    int n = o->n;
    *jcur = SUNFALSE; /* set before any early return: CVODE counts a Jacobian by it */
    if (!jok) {
        double *y = N_VGetArrayPointer(yv), *fy = N_VGetArrayPointer(fyv);
        double *ewt = N_VGetArrayPointer(tmp1), *ft = N_VGetArrayPointer(tmp2);
        /* the step being attempted, h = gamma / l1 (CVodeGetCurrentStep gives the next one) */
        sunrealtype tn, g, rl1, hcur;
        N_Vector v1, v2, v3, v4;
        void *u;
        if (CVodeGetErrWeights(o->mem, tmp1) < 0 ||
            CVodeGetNonlinearSystemData(o->mem, &tn, &v1, &v2, &v3, &g, &rl1, &v4, &u) < 0)
            return -1;
        hcur = g / rl1;
        double hnext;
        if (CVodeGetCurrentStep(o->mem, &hnext) >= 0 && hnext * rl1 == g) hcur = hnext; /* exact */
        const double uround = SUN_UNIT_ROUNDOFF, srur = sqrt(uround);
        double fnorm = N_VWrmsNorm(fyv, tmp1);
        double min_inc = fnorm != 0.0 ? DQ_MIN_INC_MULT * fabs(hcur) * uround * n * fnorm : 1.0;
        c->checked = 0; /* J is rewritten from here on */
        for (int j = 0; j < n; j++) {
            double keep = y[j], inc = fmax(srur * fabs(keep), min_inc / ewt[j]);
            y[j] += inc;
            int rc = o->f(t, y, ft, o->ud);
            y[j] = keep;
            if (rc != 0) return rc;
            double *col = c->J + (size_t)j * n, inv = 1.0 / inc;
            for (int i = 0; i < n; i++) /* N_VLinearSum(inv, ft, -inv, fy)'s arithmetic */
                col[i] = inv * (ft[i] - fy[i]);
        }
        *jcur = SUNTRUE;
    }
    return schur_form(c, gamma) > 0 ? 1 : 0;
}

static void err_handler(int code, const char *module, const char *function, char *msg, void *ud)
{
    ts_ode *o = ud;
    snprintf(o->last_msg, sizeof o->last_msg, "%s.%s (%d): %s", module, function, code, msg);
}

/* One checker for every SUNDIALS call: flag < 0 is a failure. */
static ts_rc check(ts_ode *o, int flag, const char *fn, ts_err *err)
{
    if (flag >= 0) return TS_OK;
    char *name = CVodeGetReturnFlagName(flag);
    ts_err_set(err, TS_ERR_SOLVER, NULL, "%s failed: %s%s%s", fn, name ? name : "?",
               o->last_msg[0] ? " — " : "", o->last_msg);
    free(name);
    return TS_ERR_SOLVER;
}

ts_ode *ts_ode_make(int n, ts_rhs_fn f, void *ud, const ts_ode_opts *opts, ts_err *err)
{
    if (n <= 0 || !f || !opts) {
        ts_err_set(err, TS_ERR_PARAM, NULL, "ts_ode_make: bad arguments");
        return NULL;
    }
    ts_ode *o = calloc(1, sizeof *o);
    if (!o) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "ts_ode_make: out of memory");
        return NULL;
    }
    o->n = n;
    o->f = f;
    o->ud = ud;
    o->g = opts->roots;
    o->nroots = opts->nroots;
    if (SUNContext_Create(NULL, &o->ctx) != 0) {
        ts_err_set(err, TS_ERR_SOLVER, NULL, "SUNContext_Create failed");
        goto fail;
    }
    o->y = N_VNew_Serial(n, o->ctx);
    if (!o->y) goto nomem;
    N_VConst(0.0, o->y);
    /* CVODE's fused vector operations (one loop for its linear combinations
     * instead of a chain of N_VLinearSum): the vehicle's bench figures are the
     * same to every printed digit, ~5 % less time at n = 62 */
    if (opts->second_order && N_VEnableFusedOps_Serial(o->y, 1) != 0) goto nomem;
    /* after the fused switch: it resets those entries of the ops table */
    if (ts_nvector_use_kernels(o->y) != 0) goto nomem;
    o->mem = CVodeCreate(CV_BDF, o->ctx);
    if (!o->mem) goto nomem;
    if (check(o, CVodeSetErrHandlerFn(o->mem, err_handler, o), "CVodeSetErrHandlerFn", err))
        goto fail;
    if (check(o, CVodeInit(o->mem, rhs_tramp, 0.0, o->y), "CVodeInit", err)) goto fail;
    if (check(o, CVodeSetUserData(o->mem, o), "CVodeSetUserData", err)) goto fail;
    if (opts->atol_v) {
        o->atol_v = N_VNew_Serial(n, o->ctx);
        /* no kernels: CVODE keeps a clone of it that it only reads, and an
         * operation runs with the ops of its output vector (y's clones) */
        if (!o->atol_v) goto nomem;
        memcpy(N_VGetArrayPointer(o->atol_v), opts->atol_v, (size_t)n * sizeof(double));
        if (check(o, CVodeSVtolerances(o->mem, opts->rtol, o->atol_v), "CVodeSVtolerances", err))
            goto fail;
    } else if (check(o, CVodeSStolerances(o->mem, opts->rtol, opts->atol), "CVodeSStolerances",
                     err))
        goto fail;
    if (o->nroots > 0 &&
        check(o, CVodeRootInit(o->mem, o->nroots, root_tramp), "CVodeRootInit", err))
        goto fail;
    o->A = SUNDenseMatrix(n, n, o->ctx);
    if (!o->A) goto nomem;
    int ext = opts->second_order && n % 2 == 0;
    o->LS = ext || opts->small_dense ? schur_make(n, ext, o->ctx)
                                     : SUNLinSol_Dense(o->y, o->A, o->ctx);
    if (!o->LS) goto nomem;
    if (check(o, CVodeSetLinearSolver(o->mem, o->LS, o->A), "CVodeSetLinearSolver", err)) goto fail;
    if (ext) {
        o->sls = o->LS->content;
        if (check(o, CVodeSetLinSysFn(o->mem, schur_linsys), "CVodeSetLinSysFn", err)) goto fail;
    }
    if (opts->max_order != 0 && /* CVODE refuses orders outside 1..5 */
        check(o, CVodeSetMaxOrd(o->mem, opts->max_order), "CVodeSetMaxOrd", err))
        goto fail;
    if (opts->jac_eval_frequency > 0 &&
        check(o, CVodeSetJacEvalFrequency(o->mem, opts->jac_eval_frequency),
              "CVodeSetJacEvalFrequency", err))
        goto fail;
    if (opts->max_step > 0 &&
        check(o, CVodeSetMaxStep(o->mem, opts->max_step), "CVodeSetMaxStep", err))
        goto fail;
    if (check(o, CVodeSetMaxNumSteps(o->mem, opts->max_steps > 0 ? opts->max_steps : 100000),
              "CVodeSetMaxNumSteps", err))
        goto fail;
    return o;
nomem:
    ts_err_set(err, TS_ERR_NOMEM, NULL, "ts_ode_make: out of memory");
fail:
    ts_ode_free(o);
    return NULL;
}

void ts_ode_free(ts_ode *o)
{
    if (!o) return;
    if (o->mem) CVodeFree(&o->mem);
    if (o->LS) SUNLinSolFree(o->LS);
    if (o->A) SUNMatDestroy(o->A);
    if (o->atol_v) N_VDestroy(o->atol_v);
    if (o->y) N_VDestroy(o->y);
    if (o->ctx) SUNContext_Free(&o->ctx);
    free(o);
}

ts_rc ts_ode_init(ts_ode *o, double t0, const double *y0, ts_err *err)
{
    ts_ode_stats cur;
    cvode_stats(o->mem, &cur); /* CVodeReInit zeroes CVODE's counters */
    stats_add(&o->acc, &cur);
    memcpy(N_VGetArrayPointer(o->y), y0, (size_t)o->n * sizeof(double));
    o->t = t0;
    o->last_msg[0] = '\0';
    return check(o, CVodeReInit(o->mem, t0, o->y), "CVodeReInit", err);
}

ts_rc ts_ode_advance(ts_ode *o, double tout, double *t, int *root_found, ts_err *err)
{
    if (root_found) *root_found = 0;
    if (tout <= o->t) {
        if (t) *t = o->t;
        return TS_OK;
    }
    for (;;) {
        sunrealtype tret = o->t;
        int flag = CVode(o->mem, tout, o->y, &tret, CV_NORMAL);
        if (flag < 0) return check(o, flag, "CVode", err);
        o->t = tret;
        if (flag == CV_ROOT_RETURN) {
            if (root_found) {
                *root_found = 1;
                break;
            }
            continue; /* caller does not care: go on to tout */
        }
        break;
    }
    if (t) *t = o->t;
    return TS_OK;
}

ts_rc ts_ode_set_stop(ts_ode *o, double tstop, ts_err *err)
{
    return check(o, CVodeSetStopTime(o->mem, tstop), "CVodeSetStopTime", err);
}

ts_rc ts_ode_root_info(ts_ode *o, int *dirs, ts_err *err)
{
    return check(o, CVodeGetRootInfo(o->mem, dirs), "CVodeGetRootInfo", err);
}

double *ts_ode_y(ts_ode *o)
{
    return N_VGetArrayPointer(o->y);
}
int ts_ode_n(const ts_ode *o)
{
    return o->n;
}

void ts_ode_get_stats(ts_ode *o, ts_ode_stats *s)
{
    cvode_stats(o->mem, s);
    stats_add(s, &o->acc);
}

/* Classical RK4 on the m states y[idx[j]] (idx NULL: y[0..m-1], all of y),
 * every other state held. y itself carries each stage's state; y0 and the
 * stage slopes k live in work (5 m). With idx, f writes the whole n-vector
 * into ydot and the chosen slopes are copied out; without, f writes its
 * stage's slopes straight into k. A stage whose slopes are not finite (or
 * whose f fails) ends the step at once with y holding that stage's state:
 * the state a caller's error should describe. */
static int rk4(int m, const int *idx, ts_rhs_fn f, void *ud, double t, double h, double *y,
               double *ydot, double *work)
{
    static const double cs[4] = {0.0, 0.5, 0.5, 1.0}; /* stage times */
    double *y0 = work, *k = work + m;                /* k[s m + j]: stage s, state j */
    for (int j = 0; j < m; j++)
        y0[j] = y[idx ? idx[j] : j];
    for (int s = 0; s < 4; s++) {
        for (int j = 0; s > 0 && j < m; j++)
            y[idx ? idx[j] : j] = y0[j] + cs[s] * h * k[(s - 1) * m + j];
        if (f(t + cs[s] * h, y, idx ? ydot : k + s * m, ud)) return 1;
        for (int j = 0; j < m; j++) {
            if (idx) k[s * m + j] = ydot[idx[j]];
            if (!isfinite(k[s * m + j])) return 1;
        }
    }
    int bad = 0;
    for (int j = 0; j < m; j++) {
        double *yj = &y[idx ? idx[j] : j];
        *yj = y0[j] + h / 6.0 * (k[j] + 2 * k[m + j] + 2 * k[2 * m + j] + k[3 * m + j]);
        if (!isfinite(*yj)) bad = 1;
    }
    return bad;
}

int ts_rk4_step(int n, ts_rhs_fn f, void *ud, double t, double h, double *y, double *work)
{
    return rk4(n, NULL, f, ud, t, h, y, NULL, work);
}

int ts_rk4_step_subset(int m, const int *idx, ts_rhs_fn f, void *ud, double t, double h,
                       double *y, double *ydot, double *work)
{
    return rk4(m, idx, f, ud, t, h, y, ydot, work);
}
