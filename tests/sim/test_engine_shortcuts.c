/*
 * test_engine_shortcuts.c — the crank-angle engine's speed-ups of the
 * engspeed branch are identities: each shortcut gives bitwise the value of
 * the computation it replaced (the equations and the integrator are
 * untouched; test_engine_regression.c pins the model's results).
 *   en_atleast / en_atmost        = fmax / fmin against a non-NaN bound
 *   en_orifice_pair               = en_orifice on each of the two areas
 *   en_turbine_flow (en_orifice)  = en_turbine
 *   e->bs_scale                   = ts_engine_atol at 1, ledger not controlled
 * Uses the engine's internal header (engine_impl.h) on purpose.
 */
#include "test_util.h"

#include <string.h>

#include "engine_test_util.h"
#include "sim/engine_impl.h"

/* bitwise equality of two doubles (NaN == NaN of the same bits) */
static int same(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

/* EVIDENCE: identity (C11 7.12.12.2-3: fmax/fmin return the numeric argument
 * when one is NaN): en_atleast(x, lo) == fmax(x, lo) and en_atmost(x, hi) ==
 * fmin(x, hi) bitwise for x finite, infinite, zero of either sign and NaN,
 * with the bounds the engine uses (0, 1, 1e-9, 200, ...). Exact. */
static void bounds_are_fmax_fmin(void **state)
{
    (void)state;
    const double xs[] = {-1e300, -3.5, -1.0, -0.0, 0.0, 1e-12, 0.05, 0.999, 1.0, 1.5, 200.0,
                         1e300, INFINITY, -INFINITY, NAN};
    const double bounds[] = {0.0, 1.0, 1e-9, 0.05, 0.1, 30.0, 200.0, -2.0};
    for (size_t i = 0; i < sizeof xs / sizeof *xs; i++)
        for (size_t j = 0; j < sizeof bounds / sizeof *bounds; j++) {
            double x = xs[i], b = bounds[j];
            assert_true(same(en_atleast(x, b), fmax(x, b)));
            assert_true(same(en_atmost(x, b), fmin(x, b)));
        }
}

/* EVIDENCE: identity: the turbine nozzle and the wastegate bypass share one
 * pressure-ratio function (en_orifice_pair); both flows equal en_orifice on
 * each area bitwise: choked (p2/p1 = 0.3), unchoked (0.8), linearised
 * (0.995), equal pressures, reverse flow, one area shut. Exact. */
static void orifice_pair_is_two_orifices(void **state)
{
    (void)state;
    const double R = 287.0, g = 1.35, T1 = 820.0, T2 = 298.15;
    const double p1 = 3.0e5, ratios[] = {0.3, 0.5, 0.8, 0.995, 1.0, 1.2, 3.0};
    const double areas[][2] = {{1.1e-3, 4.0e-4}, {1.1e-3, 0.0}, {0.0, 4.0e-4}, {2e-5, 1e-3}};
    for (size_t i = 0; i < sizeof ratios / sizeof *ratios; i++)
        for (size_t k = 0; k < sizeof areas / sizeof *areas; k++) {
            double p2 = p1 * ratios[i], ma, mb;
            en_orifice_pair(areas[k][0], areas[k][1], p1, T1, R, g, p2, T2, R, g, &ma, &mb);
            assert_true(same(ma, en_orifice(areas[k][0], p1, T1, R, g, p2, T2, R, g)));
            assert_true(same(mb, en_orifice(areas[k][1], p1, T1, R, g, p2, T2, R, g)));
        }
}

/* EVIDENCE: identity: en_turbine_flow given en_orifice's nozzle flow is
 * en_turbine (flow, power, efficiency bitwise) over expansion ratios and
 * rotor speeds of the rated point's range. Exact. */
static void turbine_flow_is_turbine(void **state)
{
    (void)state;
    ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, TS_ENGINE_CRANK_ANGLE);
    const en_turbo *t = &e->turbo;
    const double R = 290.0, cp = 1180.0, g = cp / (cp - R), T3 = 850.0, p4 = 101325.0;
    for (double p3 = 0.9e5; p3 < 5e5; p3 *= 1.37)
        for (double w = 0.0; w < 1e4; w += 2300.0) {
            en_turb_out a, b;
            en_turbine(t, t->a_t, w, p3, T3, R, cp, p4, &a);
            en_turbine_flow(t, en_orifice(t->a_t, p3, T3, R, g, p4, T3, R, g), w, p3, T3, R, cp,
                            p4, &b);
            assert_true(same(a.mdot, b.mdot));
            assert_true(same(a.power, b.power));
            assert_true(same(a.eta, b.eta));
        }
    ts_engine_free(e);
}

/* EVIDENCE: identity: the stepper's error scales built once in ts_engine_make
 * equal ts_engine_atol at 1 on every non-wall state, the ledger's infinite
 * (not error-controlled), as the stepper computed them on every call. Exact. */
static void stepper_scales_are_atol(void **state)
{
    (void)state;
    ts_engine *e = et_make(TS_ENGINE_LHR10, TS_ENGINE_CRANK_ANGLE);
    assert_int_equal(e->off_wall, EN_CRANK_NGAS);
    assert_int_equal(ts_engine_nstate(e), EN_CRANK_NGAS + EN_CRANK_NWALLX);
    double *v = malloc(sizeof(double) * (size_t)ts_engine_nstate(e));
    assert_non_null(v);
    ts_engine_atol(e, 1.0, v);
    for (int i = 0; i < EN_LEDGER_NX; i++) v[e->off_ledger + i] = INFINITY;
    assert_memory_equal(v, e->bs_scale, sizeof e->bs_scale);
    free(v);
    ts_engine_free(e);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bounds_are_fmax_fmin),
        cmocka_unit_test(orifice_pair_is_two_orifices),
        cmocka_unit_test(turbine_flow_is_turbine),
        cmocka_unit_test(stepper_scales_are_atol),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
