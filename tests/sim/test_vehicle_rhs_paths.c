/*
 * test_vehicle_rhs_paths.c — the vehicle right-hand side's shortcuts give the
 * very numbers of the plain evaluation: the mass matrix's factor reused when
 * only the coordinates M does not depend on change (vm_rhs, vm_rhs_torque),
 * bit for bit against a fresh work area that assembles and factors M anew;
 * the factorisation restricted to M's structural nonzeros (mass_structure)
 * against one that scans all of M. Numerical-method checks, no physics figures.
 */
#include "test_util.h"

#include <stdlib.h>
#include <string.h>

#include "api/config_json.h"
#include "preset_config.h"
#include "sim/dense_small.h"
#include "sim/tanksim.h"
#include "sim/vehicle_model.h"

static vm *make_vm(const char *preset)
{
    ts_config c = test_preset_config(preset, NULL);
    return test_vm(&c);
}

/* A moving state off the equilibrium: every coordinate and rate nudged by a
 * distinct small amount (hull rolling forward at 5 m/s). */
static void moving_state(const vm *v, double *y)
{
    int ny = vm_ny(v), nq = vm_nq(v);
    memcpy(y, vm_equilibrium(v), sizeof(double) * (size_t)ny);
    for (int i = 0; i < nq; i++) {
        y[i] += 1e-4 * (double)((i * 7) % 5 - 2);
        y[nq + i] = 0.05 * (double)((i * 3) % 7 - 3);
    }
    y[nq] = 5.0;
}

/* vm_rhs (or vm_rhs_torque when inertia >= 0) at y2 after an evaluation at y1
 * in the same work area, against y2 in a fresh one: identical bits. */
static void check_pair(const vm *v, const double *y1, const double *y2, double inertia1,
                       double inertia2)
{
    int ny = vm_ny(v);
    vm_work *w = vm_work_make(v), *fresh = vm_work_make(v);
    double *d1 = malloc(sizeof(double) * (size_t)ny), *d2 = malloc(sizeof(double) * (size_t)ny),
           *df = malloc(sizeof(double) * (size_t)ny);
    vm_diag g2, gf;
    memset(&g2, 0, sizeof g2);
    memset(&gf, 0, sizeof gf);
    if (inertia1 < 0) {
        assert_int_equal(vm_rhs(v, w, 0.1, y1, d1, NULL), 0);
        assert_int_equal(vm_rhs(v, w, 0.1, y2, d2, &g2), 0);
        assert_int_equal(vm_rhs(v, fresh, 0.1, y2, df, &gf), 0);
    } else {
        assert_int_equal(vm_rhs_torque(v, w, 0.1, y1, 4000.0, inertia1, d1, NULL), 0);
        assert_int_equal(vm_rhs_torque(v, w, 0.1, y2, 4000.0, inertia2, d2, &g2), 0);
        assert_int_equal(vm_rhs_torque(v, fresh, 0.1, y2, 4000.0, inertia2, df, &gf), 0);
    }
    assert_memory_equal(d2, df, sizeof(double) * (size_t)ny);
    assert_memory_equal(&g2, &gf, sizeof g2);
    free(d1), free(d2), free(df);
    vm_work_free(w), vm_work_free(fresh);
}

/* Each single coordinate or rate changed in turn (the difference-quotient
 * Jacobian's columns): the hits (spins, modes, rates) and the misses (x, z,
 * theta, arms) both give the fresh evaluation's bits. */
static void factor_reuse_is_exact(const char *preset)
{
    vm *v = make_vm(preset);
    int ny = vm_ny(v);
    double *y1 = malloc(sizeof(double) * (size_t)ny), *y2 = malloc(sizeof(double) * (size_t)ny);
    moving_state(v, y1);
    for (int j = 0; j < ny; j++) {
        memcpy(y2, y1, sizeof(double) * (size_t)ny);
        y2[j] += 1e-6 * (1.0 + fabs(y2[j]));
        check_pair(v, y1, y2, -1, -1);
        check_pair(v, y1, y2, 0.0, 0.0);
    }
    /* the same coordinates, another sprocket inertia: M differs, no reuse */
    memcpy(y2, y1, sizeof(double) * (size_t)ny);
    check_pair(v, y1, y2, 0.0, 2.5);
    check_pair(v, y1, y2, 2.5, 2.5);
    free(y1), free(y2);
    vm_free(v);
}

static void factor_reuse_static(void **state)
{
    (void)state;
    factor_reuse_is_exact("bump-prescribed-static");
}

static void factor_reuse_coupled(void **state)
{
    (void)state;
    factor_reuse_is_exact("bump-prescribed-coupled");
}

/* q's indices (vehicle_model.h): theta, and the sprocket's spin (the first
 * of the spins, after x, z, theta and the road-arm angles). */
enum { Q_THETA = 2, Q_SPROCKET_SPIN = 3 + VM_NRW + VM_SPROCKET };

/* vm_rhs's accelerations, whose factorisation looks only at the rows
 * mass_structure listed, against the full-scan ts_chol_factor_rev of
 * vm_mass's M with vm_forces's Q, at states well off the equilibrium (arms,
 * pitch and modes moved): identical bits, so no write to M lies outside the
 * structure. The same for vm_rhs_torque with an extra sprocket inertia, the
 * one write to M outside forces (rhs_cached: the pair theta, sprocket spin;
 * vm_rhs never makes it, so without this a structure missing that pair went
 * unseen; the fidelities without spans have no other write to that pair):
 * M and Q get the inertia and the torque as rhs_cached adds them, same
 * entries, same order (the factor reads M's lower triangle alone).
 * fidelity NULL: the preset's; comp: /vehicle/idler_compensation; n_long >= 0
 * replaces /track/n_long (0: the coupled fidelity's uniform-tension spans). */
static void structure_covers(const char *preset, const char *fidelity, double comp, int n_long)
{
    ts_config c = test_preset_config(preset, fidelity);
    ts_err err;
    c.vehicle.idler_compensation = comp;
    if (n_long >= 0) c.track.n_long = n_long;
    vm *v = vm_make(&c, &err);
    assert_non_null(v);
    int ny = vm_ny(v), nq = vm_nq(v);
    vm_work *w = vm_work_make(v);
    double *y = malloc(sizeof(double) * (size_t)ny), *yd = malloc(sizeof(double) * (size_t)ny);
    double *M = malloc(sizeof(double) * (size_t)(nq * nq)),
           *Q = malloc(sizeof(double) * (size_t)nq);
    int *pat = malloc(sizeof(int) * (size_t)(nq * (nq + 1)));
    for (int k = 1; k <= 3; k++) {
        moving_state(v, y);
        for (int i = 0; i < nq; i++)
            y[i] += 0.02 * k * (double)((i * 5 + k) % 9 - 4) / 4.0;
        assert_int_equal(vm_rhs(v, w, 0.1, y, yd, NULL), 0);
        vm_forces(v, w, 0.1, y, 1, Q);
        vm_mass(v, w, y, M);
        assert_int_equal(ts_chol_factor_rev(M, nq, pat), 0);
        ts_chol_solve_rev(M, nq, pat, Q);
        assert_memory_equal(yd + nq, Q, sizeof(double) * (size_t)nq);

        /* another inertia than vm_rhs's 0: no factor reuse, M factored anew */
        const double torque = 4000.0, inertia = 2.5;
        const int is = Q_SPROCKET_SPIN;
        assert_int_equal(vm_rhs_torque(v, w, 0.1, y, torque, inertia, yd, NULL), 0);
        vm_forces(v, w, 0.1, y, 0, Q);
        Q[is] += torque;
        Q[Q_THETA] -= torque;
        vm_mass(v, w, y, M);
        M[is * nq + is] += inertia;
        M[Q_THETA * nq + Q_THETA] += inertia;
        M[is * nq + Q_THETA] -= inertia;
        assert_int_equal(ts_chol_factor_rev(M, nq, pat), 0);
        ts_chol_solve_rev(M, nq, pat, Q);
        assert_memory_equal(yd + nq, Q, sizeof(double) * (size_t)nq);
    }
    free(y), free(yd), free(M), free(Q), free(pat);
    vm_work_free(w);
    vm_free(v);
}

static void mass_structure_is_complete(void **state)
{
    (void)state;
    structure_covers("bump-prescribed-static", NULL, 0.0, -1);
    structure_covers("bump-prescribed-coupled", NULL, 0.0, -1);
    structure_covers("bump-prescribed-coupled", NULL, 0.5, -1);
    structure_covers("bump-prescribed-coupled", NULL, 0.0, 0); /* Irvine's uniform tension */
    structure_covers("bump-prescribed-coupled", "lumped", 0.0, -1);
    structure_covers("bump-prescribed-coupled", "quasi_static", 0.0, -1);
    structure_covers("bump-prescribed-coupled", "longitudinal", 0.0, -1);
    structure_covers("bump-prescribed-coupled", "transverse", 0.0, -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(factor_reuse_static),
        cmocka_unit_test(factor_reuse_coupled),
        cmocka_unit_test(mass_structure_is_complete),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
