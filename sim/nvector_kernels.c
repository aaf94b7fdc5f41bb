/*
 * nvector_kernels.c — serial N_Vector operations for CVODE (see
 * nvector_kernels.h for why). Each kernel reads the vector's length and data
 * through nvector_serial.h's accessors and follows SUNDIALS' documented
 * case split, so that the rounding of every element is the library's.
 */
#include "nvector_kernels.h"

#include <math.h>

#include <nvector/nvector_serial.h>

#define LEN(v)  ((long)NV_LENGTH_S(v))
#define DATA(v) NV_DATA_S(v)

/* ---- the element loops LinearSum picks between ---- */

static void axpy(double a, const double *x, double *y, long n) /* y += a x */
{
    if (a == 1.0)
        for (long i = 0; i < n; i++)
            y[i] += x[i];
    else if (a == -1.0)
        for (long i = 0; i < n; i++)
            y[i] -= x[i];
    else
        for (long i = 0; i < n; i++)
            y[i] += a * x[i];
}

static void linear_sum(double a, N_Vector xv, double b, N_Vector yv, N_Vector zv)
{
    long n = LEN(xv);
    double *x = DATA(xv), *y = DATA(yv), *z = DATA(zv);
    if (b == 1.0 && zv == yv) {
        axpy(a, x, y, n);
    } else if (a == 1.0 && zv == xv) {
        axpy(b, y, x, n);
    } else if (a == 1.0 && b == 1.0) {
        for (long i = 0; i < n; i++)
            z[i] = x[i] + y[i];
    } else if (a == 1.0 && b == -1.0) {
        for (long i = 0; i < n; i++)
            z[i] = x[i] - y[i];
    } else if (a == -1.0 && b == 1.0) {
        for (long i = 0; i < n; i++)
            z[i] = y[i] - x[i];
    } else if (a == 1.0) { /* z = b y + x */
        for (long i = 0; i < n; i++)
            z[i] = b * y[i] + x[i];
    } else if (b == 1.0) { /* z = a x + y */
        for (long i = 0; i < n; i++)
            z[i] = a * x[i] + y[i];
    } else if (a == -1.0) { /* z = b y - x */
        for (long i = 0; i < n; i++)
            z[i] = b * y[i] - x[i];
    } else if (b == -1.0) { /* z = a x - y */
        for (long i = 0; i < n; i++)
            z[i] = a * x[i] - y[i];
    } else if (a == b) {
        for (long i = 0; i < n; i++)
            z[i] = a * (x[i] + y[i]);
    } else if (a == -b) {
        for (long i = 0; i < n; i++)
            z[i] = a * (x[i] - y[i]);
    } else {
        for (long i = 0; i < n; i++)
            z[i] = a * x[i] + b * y[i];
    }
}

static void set_const(double c, N_Vector zv)
{
    long n = LEN(zv);
    double *z = DATA(zv);
    for (long i = 0; i < n; i++)
        z[i] = c;
}

static void scale(double c, N_Vector xv, N_Vector zv)
{
    long n = LEN(xv);
    double *x = DATA(xv), *z = DATA(zv);
    if (zv == xv)
        for (long i = 0; i < n; i++)
            x[i] *= c;
    else if (c == 1.0)
        for (long i = 0; i < n; i++)
            z[i] = x[i];
    else if (c == -1.0)
        for (long i = 0; i < n; i++)
            z[i] = -x[i];
    else
        for (long i = 0; i < n; i++)
            z[i] = c * x[i];
}

static void absolute(N_Vector xv, N_Vector zv)
{
    long n = LEN(xv);
    double *x = DATA(xv), *z = DATA(zv);
    for (long i = 0; i < n; i++)
        z[i] = fabs(x[i]);
}

static void inverse(N_Vector xv, N_Vector zv)
{
    long n = LEN(xv);
    double *x = DATA(xv), *z = DATA(zv);
    for (long i = 0; i < n; i++)
        z[i] = 1.0 / x[i];
}

static double wrms_norm(N_Vector xv, N_Vector wv) /* sqrt(sum (x w)^2 / n) */
{
    long n = LEN(xv);
    const double *x = DATA(xv), *w = DATA(wv);
    double s = 0.0;
    for (long i = 0; i < n; i++) {
        double p = x[i] * w[i];
        s += p * p;
    }
    return sqrt(s / n);
}

/* ---- fused operations ---- */

/* z = sum c[i] X[i] */
static int linear_combination(int nvec, sunrealtype *c, N_Vector *X, N_Vector zv)
{
    if (nvec < 1) return -1;
    if (nvec == 1) {
        scale(c[0], X[0], zv);
        return 0;
    }
    if (nvec == 2) {
        linear_sum(c[0], X[0], c[1], X[1], zv);
        return 0;
    }
    long n = LEN(zv);
    double *z = DATA(zv);
    if (X[0] == zv) {
        if (c[0] != 1.0)
            for (long j = 0; j < n; j++)
                z[j] *= c[0];
    } else {
        const double *x = DATA(X[0]);
        for (long j = 0; j < n; j++)
            z[j] = c[0] * x[j];
    }
    for (int i = 1; i < nvec; i++) {
        const double *x = DATA(X[i]);
        for (long j = 0; j < n; j++)
            z[j] += c[i] * x[j];
    }
    return 0;
}

/* Z[i] = Y[i] + a[i] x */
static int scale_add_multi(int nvec, sunrealtype *a, N_Vector xv, N_Vector *Y, N_Vector *Z)
{
    if (nvec < 1) return -1;
    if (nvec == 1) {
        linear_sum(a[0], xv, 1.0, Y[0], Z[0]);
        return 0;
    }
    long n = LEN(xv);
    const double *x = DATA(xv);
    for (int i = 0; i < nvec; i++) {
        double *y = DATA(Y[i]), *z = DATA(Z[i]);
        if (Y == Z)
            for (long j = 0; j < n; j++)
                y[j] += a[i] * x[j];
        else
            for (long j = 0; j < n; j++)
                z[j] = a[i] * x[j] + y[j];
    }
    return 0;
}

int ts_nvector_use_kernels(N_Vector v)
{
    if (!v || !v->ops || !v->ops->nvgetvectorid || N_VGetVectorID(v) != SUNDIALS_NVEC_SERIAL)
        return -1;
    N_Vector_Ops o = v->ops;
    /* the operations CVODE's BDF/Newton path calls every step (counted on the
     * coupled bump run: LinearSum 161k, Scale 58k, WrmsNorm 36k, Const 28k,
     * ScaleAddMulti 12k, Abs and Inv 12k each, LinearCombination 6k); the
     * rest (Prod, Div, DotProd, Min, MaxNorm, Compare, InvTest, AddConst)
     * run at most at start-up, or not at all, and stay SUNDIALS' */
    o->nvlinearsum = linear_sum;
    o->nvconst = set_const;
    o->nvscale = scale;
    o->nvabs = absolute;
    o->nvinv = inverse;
    o->nvwrmsnorm = wrms_norm;
    /* fused operations: only where enabled (N_VEnableFusedOps_Serial), since
     * CVODE's fallback without them rounds differently */
    if (o->nvlinearcombination) o->nvlinearcombination = linear_combination;
    if (o->nvscaleaddmulti) o->nvscaleaddmulti = scale_add_multi;
    return 0;
}
