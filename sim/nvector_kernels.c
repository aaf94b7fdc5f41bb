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

static void prod(N_Vector xv, N_Vector yv, N_Vector zv)
{
    long n = LEN(xv);
    double *x = DATA(xv), *y = DATA(yv), *z = DATA(zv);
    for (long i = 0; i < n; i++)
        z[i] = x[i] * y[i];
}

static void divide(N_Vector xv, N_Vector yv, N_Vector zv)
{
    long n = LEN(xv);
    double *x = DATA(xv), *y = DATA(yv), *z = DATA(zv);
    for (long i = 0; i < n; i++)
        z[i] = x[i] / y[i];
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

static void add_const(N_Vector xv, double b, N_Vector zv)
{
    long n = LEN(xv);
    double *x = DATA(xv), *z = DATA(zv);
    for (long i = 0; i < n; i++)
        z[i] = x[i] + b;
}

static double dot(N_Vector xv, N_Vector yv)
{
    long n = LEN(xv);
    const double *x = DATA(xv), *y = DATA(yv);
    double s = 0.0;
    for (long i = 0; i < n; i++)
        s += x[i] * y[i];
    return s;
}

static double max_norm(N_Vector xv)
{
    long n = LEN(xv);
    const double *x = DATA(xv);
    double m = 0.0;
    for (long i = 0; i < n; i++)
        if (fabs(x[i]) > m) m = fabs(x[i]);
    return m;
}

static double wsqr_sum(N_Vector xv, N_Vector wv)
{
    long n = LEN(xv);
    const double *x = DATA(xv), *w = DATA(wv);
    double s = 0.0;
    for (long i = 0; i < n; i++) {
        double p = x[i] * w[i];
        s += p * p;
    }
    return s;
}

static double wrms_norm(N_Vector xv, N_Vector wv)
{
    return sqrt(wsqr_sum(xv, wv) / LEN(xv));
}

static double minimum(N_Vector xv)
{
    long n = LEN(xv);
    const double *x = DATA(xv);
    double m = x[0];
    for (long i = 1; i < n; i++)
        if (x[i] < m) m = x[i];
    return m;
}

static void compare(double c, N_Vector xv, N_Vector zv)
{
    long n = LEN(xv);
    double *x = DATA(xv), *z = DATA(zv);
    for (long i = 0; i < n; i++)
        z[i] = fabs(x[i]) >= c ? 1.0 : 0.0;
}

static sunbooleantype inv_test(N_Vector xv, N_Vector zv)
{
    long n = LEN(xv);
    double *x = DATA(xv), *z = DATA(zv);
    sunbooleantype none_zero = SUNTRUE;
    for (long i = 0; i < n; i++) {
        if (x[i] == 0.0)
            none_zero = SUNFALSE;
        else
            z[i] = 1.0 / x[i];
    }
    return none_zero;
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
    /* the standard operations, always present on a serial vector */
    o->nvlinearsum = linear_sum;
    o->nvconst = set_const;
    o->nvprod = prod;
    o->nvdiv = divide;
    o->nvscale = scale;
    o->nvabs = absolute;
    o->nvinv = inverse;
    o->nvaddconst = add_const;
    o->nvdotprod = dot;
    o->nvmaxnorm = max_norm;
    o->nvwrmsnorm = wrms_norm;
    o->nvmin = minimum;
    o->nvcompare = compare;
    o->nvinvtest = inv_test;
    /* their local forms, which the serial vector also lists */
    if (o->nvdotprodlocal) o->nvdotprodlocal = dot;
    if (o->nvmaxnormlocal) o->nvmaxnormlocal = max_norm;
    if (o->nvminlocal) o->nvminlocal = minimum;
    if (o->nvinvtestlocal) o->nvinvtestlocal = inv_test;
    if (o->nvwsqrsumlocal) o->nvwsqrsumlocal = wsqr_sum;
    /* fused operations: only where enabled (N_VEnableFusedOps_Serial), since
     * CVODE's fallback without them rounds differently */
    if (o->nvlinearcombination) o->nvlinearcombination = linear_combination;
    if (o->nvscaleaddmulti) o->nvscaleaddmulti = scale_add_multi;
    return 0;
}
