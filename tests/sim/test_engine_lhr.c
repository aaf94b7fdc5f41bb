/*
 * test_engine_lhr.c — the low-heat-rejection variants (0.5 and 1.0 mm zirconia,
 * paper Section III.B.3, Fig. 18) against the all-metal engine, crank-angle
 * fidelity on the dynamometer. Only the conventional rated point was
 * calibrated (wastegate area, +10.0 % over 1350 hp); everything about the LHR
 * engines is PREDICTED. This model predicts +13.8 % (0.5 mm) and +14.3 %
 * (1.0 mm) over 1350 hp against the paper's +15.7 / +19.8 %: the 0.5 mm
 * engine within 2 points, the 1.0 mm one NOT (its extra insulation mostly
 * heats the charge, lower eta_v, rather than the exhaust). The tests check
 * the paper's trends and the 0.5 mm gain.
 */
#include "test_util.h"

#include "engine_test_util.h"

typedef struct point {
    double power, torque, boost, q_wall, eta_v, piston_t, swing;
} point;

/* Peak-to-peak piston surface temperature of cylinder 1 over one cycle [K]. */
static double surface_swing(const ts_engine *e, double *x)
{
    int n = ts_engine_nstate(e);
    double *xd = malloc(sizeof(double) * (size_t)n);
    double *work = malloc(sizeof(double) * ts_engine_work_size(e));
    ts_engine_inputs in = et_full_load();
    ts_err err;
    double lo = 1e9, hi = 0, dt = ET_PI / 180 / x[TS_ENGINE_X_SPEED];
    for (int k = 0; k < 720; k++) {
        ts_engine_outputs o;
        ts_engine_rhs(e, 0, x, &in, xd, &o);
        lo = fmin(lo, o.piston_surface_temp);
        hi = fmax(hi, o.piston_surface_temp);
        assert_int_equal(ts_engine_advance(e, x, 0, dt, &in, work, &err), TS_OK);
    }
    free(xd);
    free(work);
    return hi - lo;
}

static point steady(int variant, double rpm)
{
    ts_engine *e;
    ts_engine_cycle c;
    double *x = et_steady(variant, TS_ENGINE_CRANK_ANGLE, rpm, &e, &c);
    point p = {c.mean.brake_torque * c.mean.speed, c.mean.brake_torque, c.mean.boost, c.q_wall,
               c.eta_v, c.mean.piston_surface_temp, surface_swing(e, x)};
    ts_engine_free(e);
    free(x);
    return p;
}

/* EVIDENCE: paper Section III.B.3 / Fig. 18a-b at 2100 rpm: LHR engines reject
 * less heat, have hotter piston surfaces, higher boost (Fig. 18b, medium-high
 * speed) and more power than the all-metal engine (+15.7 % and +19.8 % over
 * 1350 hp vs +9.9 %). Predicted (not calibrated). Checked: ordering of heat
 * loss, surface temperature, boost and power; each LHR gain exceeds the
 * all-metal gain by >= 1 point; the 1.0 mm engine above the 0.5 mm one; the
 * 0.5 mm gain within 2 points of the paper's +15.7 % (the 1.0 mm gain is
 * printed, not asserted: +14.3 % vs +19.8 %). Fig. 21b: the coated piston's surface temperature
 * swings more over a cycle (thin low-diffusivity layer). The numbers are
 * printed for the report. */
static void lhr_rated_point_trends(void **state)
{
    (void)state;
    point c = steady(TS_ENGINE_CONVENTIONAL, 2100);
    point l5 = steady(TS_ENGINE_LHR05, 2100);
    point l10 = steady(TS_ENGINE_LHR10, 2100);
    const double ref = 1350 * ET_HP;
    print_message("      gain over 1350 hp: conventional %+.1f %%, lhr05 %+.1f %%, lhr10 %+.1f %%"
                  " (paper +9.9, +15.7, +19.8)\n", 100 * (c.power / ref - 1),
                  100 * (l5.power / ref - 1), 100 * (l10.power / ref - 1));
    print_message("      boost %.2f / %.2f / %.2f bar, q_wall %.3f / %.3f / %.3f, piston %.0f / %.0f /"
                  " %.0f K\n", c.boost / 1e5, l5.boost / 1e5, l10.boost / 1e5, c.q_wall, l5.q_wall,
                  l10.q_wall, c.piston_t, l5.piston_t, l10.piston_t);
    print_message("      piston surface swing %.0f / %.0f / %.0f K\n", c.swing, l5.swing, l10.swing);
    assert_true(l5.swing > 2 * c.swing && l10.swing > 2 * c.swing);
    assert_true(l5.q_wall < c.q_wall && l10.q_wall < l5.q_wall);
    assert_true(l5.piston_t > c.piston_t + 50 && l10.piston_t > l5.piston_t);
    assert_true(l5.boost > c.boost && l10.boost > c.boost);
    assert_true(l5.power > c.power && l10.power > c.power);
    assert_true(l5.power / ref - c.power / ref > 0.01);
    assert_true(l10.power > l5.power);
    assert_close(100 * (l5.power / ref - 1), 15.7, 0, 2.0); /* paper III.B.3, 2 points */
}

/* EVIDENCE: paper Section III.B.3 / Fig. 18a: "the power output of the baseline
 * (all metal) engine at lower speeds is slightly better than that of the LHR
 * versions" because hot walls heat the charge (lower volumetric efficiency)
 * while the boost difference is small. At 800 rpm, full load, predicted:
 * LHR 1.0 mm torque below the all-metal torque (by < 10 %), lower volumetric
 * efficiency, boost within 3 %. */
static void lhr_low_speed_torque_deficit(void **state)
{
    (void)state;
    point c = steady(TS_ENGINE_CONVENTIONAL, 800);
    point l10 = steady(TS_ENGINE_LHR10, 800);
    print_message("      800 rpm: torque %.0f vs %.0f N*m, eta_v %.3f vs %.3f, boost %.2f vs %.2f bar\n",
                  c.torque, l10.torque, c.eta_v, l10.eta_v, c.boost / 1e5, l10.boost / 1e5);
    assert_true(l10.torque < c.torque && l10.torque > 0.9 * c.torque);
    assert_true(l10.eta_v < c.eta_v);
    assert_close(l10.boost, c.boost, 0.03, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(lhr_rated_point_trends),
        cmocka_unit_test(lhr_low_speed_torque_deficit),
    };
    return cmocka_run_group_tests_name("engine_lhr", tests, NULL, NULL);
}
