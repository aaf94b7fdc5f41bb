/*
 * test_nvector_kernels.c — sim/nvector_kernels.h's vector operations against
 * SUNDIALS' own serial ones, bit for bit: every case split of LinearSum and
 * Scale (a, b = +-1, a = +-b, the aliased z == x, z == y forms), Const,
 * Abs, Inv, the WRMS norm, the fused operations with and without aliasing;
 * that they are installed at all (else every comparison would be SUNDIALS'
 * with itself), and the refusal of a vector that is not serial. A kernel that rounded differently
 * would change every pinned bench figure; this is where that shows first.
 */
#include "test_util.h"

#include <stdlib.h>
#include <string.h>

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include "sim/nvector_kernels.h"

#define N  37 /* odd: no loop length a vectoriser could treat as whole blocks */
#define NV 4

typedef struct pair {
    SUNContext ctx;
    N_Vector ref[NV]; /* SUNDIALS' serial operations */
    N_Vector own[NV]; /* the same data, the project's kernels */
} pair;

static int setup(void **state)
{
    pair *p = calloc(1, sizeof *p);
    if (!p || SUNContext_Create(NULL, &p->ctx) != 0) return -1;
    for (int i = 0; i < NV; i++) {
        p->ref[i] = N_VNew_Serial(N, p->ctx);
        p->own[i] = N_VNew_Serial(N, p->ctx);
        if (!p->ref[i] || !p->own[i]) return -1;
        if (N_VEnableFusedOps_Serial(p->ref[i], 1) || N_VEnableFusedOps_Serial(p->own[i], 1))
            return -1;
        if (ts_nvector_use_kernels(p->own[i]) != 0) return -1;
    }
    *state = p;
    return 0;
}

static int teardown(void **state)
{
    pair *p = *state;
    for (int i = 0; i < NV; i++) {
        N_VDestroy(p->ref[i]);
        N_VDestroy(p->own[i]);
    }
    SUNContext_Free(&p->ctx);
    free(p);
    return 0;
}

/* the same random data (a zero here and there) in both sets */
static void fill(pair *p, unsigned seed)
{
    for (int v = 0; v < NV; v++) {
        double *r = N_VGetArrayPointer(p->ref[v]), *o = N_VGetArrayPointer(p->own[v]);
        for (int i = 0; i < N; i++) {
            r[i] = (i + v) % 11 == 3 ? 0.0 : 5.0 * test_urand(&seed);
            o[i] = r[i];
        }
    }
}

static void assert_same(pair *p)
{
    for (int v = 0; v < NV; v++)
        assert_memory_equal(N_VGetArrayPointer(p->ref[v]), N_VGetArrayPointer(p->own[v]),
                            N * sizeof(double));
}

static void assert_same_real(double got, double want)
{
    assert_memory_equal(&got, &want, sizeof got);
}

/* EVIDENCE: SUNDIALS 6.4 serial N_VLinearSum (the documented z = a x + b y)
 * with its special cases; identity to the bit (tolerance 0). */
static void linear_sum_matches_every_case(void **state)
{
    pair *p = *state;
    const double c[] = {1.0, -1.0, 0.0, 0.5, -0.5, 2.75, -2.75, 1e-3};
    const int nc = (int)(sizeof c / sizeof c[0]);
    unsigned seed = 1;
    for (int ia = 0; ia < nc; ia++)
        for (int ib = 0; ib < nc; ib++)
            for (int alias = 0; alias < 3; alias++) { /* z separate, z == x, z == y */
                fill(p, seed++);
                int z = alias == 0 ? 2 : alias == 1 ? 0 : 1;
                N_VLinearSum(c[ia], p->ref[0], c[ib], p->ref[1], p->ref[z]);
                N_VLinearSum(c[ia], p->own[0], c[ib], p->own[1], p->own[z]);
                assert_same(p);
            }
}

/* EVIDENCE: SUNDIALS 6.4 serial N_VScale (its z == x, c = +-1 forms),
 * N_VConst, N_VAbs, N_VInv (a zero gives inf, as there) and N_VWrmsNorm
 * (sqrt(sum (x w)^2 / n)); identity to the bit. */
static void elementwise_operations_and_norm_match(void **state)
{
    pair *p = *state;
    const double c[] = {1.0, -1.0, 0.3, -7.0};
    for (int k = 0; k < 4; k++) {
        fill(p, 100u + (unsigned)k);
        N_VScale(c[k], p->ref[0], p->ref[2]);
        N_VScale(c[k], p->own[0], p->own[2]);
        N_VScale(c[k], p->ref[1], p->ref[1]);
        N_VScale(c[k], p->own[1], p->own[1]);
        assert_same(p);
        assert_same_real(N_VWrmsNorm(p->own[0], p->own[1]), N_VWrmsNorm(p->ref[0], p->ref[1]));
    }
    fill(p, 7);
    N_VAbs(p->ref[0], p->ref[3]);
    N_VAbs(p->own[0], p->own[3]);
    N_VInv(p->ref[3], p->ref[1]);
    N_VInv(p->own[3], p->own[1]);
    N_VConst(-3.25, p->ref[2]);
    N_VConst(-3.25, p->own[2]);
    assert_same(p);
}

/* EVIDENCE: SUNDIALS 6.4 serial fused N_VLinearCombination (z = sum c_i X_i,
 * its z == X_0 and c_0 == 1 forms, and 1 or 2 vectors handed to Scale and
 * LinearSum) and N_VScaleAddMulti (Z_i = Y_i + a_i x, in place or not);
 * identity to the bit. */
static void fused_operations_match(void **state)
{
    pair *p = *state;
    double c[3][3] = {{1.0, -0.5, 0.25}, {0.7, 1.0, -1.0}, {-1.0, 3.0, 1e-2}};
    for (int k = 0; k < 3; k++)
        for (int nvec = 1; nvec <= 3; nvec++)
            for (int in_place = 0; in_place < 2; in_place++) {
                fill(p, 40u + (unsigned)(k * 10 + nvec * 2 + in_place));
                N_Vector *X = in_place ? p->ref : p->ref + 1;
                N_Vector *Xo = in_place ? p->own : p->own + 1;
                N_Vector z = p->ref[0], zo = p->own[0]; /* == X[0] when in place */
                assert_int_equal(N_VLinearCombination(nvec, c[k], X, z), 0);
                assert_int_equal(N_VLinearCombination(nvec, c[k], Xo, zo), 0);
                assert_same(p);
                N_Vector Yr[2] = {p->ref[1], p->ref[2]}, Yo[2] = {p->own[1], p->own[2]};
                N_Vector Zr[2] = {p->ref[3], p->ref[0]}, Zo[2] = {p->own[3], p->own[0]};
                int m = nvec < 3 ? nvec : 2;
                assert_int_equal(N_VScaleAddMulti(m, c[k], p->ref[3], Yr, in_place ? Yr : Zr), 0);
                assert_int_equal(N_VScaleAddMulti(m, c[k], p->own[3], Yo, in_place ? Yo : Zo), 0);
                assert_same(p);
            }
}

/* EVIDENCE: nvector_kernels.h contract: the per-step operations are the
 * project's (the comparisons above would pass trivially otherwise), the
 * others and the ones of a clone are as documented. */
static void kernels_are_installed_and_cloned(void **state)
{
    pair *p = *state;
    N_Vector_Ops r = p->ref[0]->ops, o = p->own[0]->ops;
    assert_true(o->nvlinearsum != r->nvlinearsum && o->nvscale != r->nvscale);
    assert_true(o->nvconst != r->nvconst && o->nvabs != r->nvabs && o->nvinv != r->nvinv);
    assert_true(o->nvwrmsnorm != r->nvwrmsnorm);
    assert_true(o->nvlinearcombination != r->nvlinearcombination);
    assert_true(o->nvscaleaddmulti != r->nvscaleaddmulti);
    assert_true(o->nvprod == r->nvprod); /* not per step: SUNDIALS' own */
    N_Vector c = N_VClone(p->own[0]);    /* what CVODE makes from the vector it is given */
    assert_non_null(c);
    assert_true(c->ops->nvlinearsum == o->nvlinearsum && c->ops->nvwrmsnorm == o->nvwrmsnorm);
    N_VDestroy(c);
}

/* EVIDENCE: nvector_kernels.h contract: a vector that is not serial is
 * refused (-1), its ops table not touched. */
static void refuses_other_vectors(void **state)
{
    pair *p = *state;
    assert_int_equal(ts_nvector_use_kernels(NULL), -1);
    N_Vector e = N_VNewEmpty(p->ctx); /* no ops' vector ID: not a serial vector */
    assert_non_null(e);
    N_Vector_Ops before = e->ops, copy = malloc(sizeof *copy);
    assert_non_null(copy);
    *copy = *before;
    assert_int_equal(ts_nvector_use_kernels(e), -1);
    assert_true(e->ops == before && memcmp(e->ops, copy, sizeof *copy) == 0);
    free(copy);
    N_VFreeEmpty(e);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(linear_sum_matches_every_case),
        cmocka_unit_test(elementwise_operations_and_norm_match),
        cmocka_unit_test(fused_operations_match),
        cmocka_unit_test(kernels_are_installed_and_cloned),
        cmocka_unit_test(refuses_other_vectors),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
