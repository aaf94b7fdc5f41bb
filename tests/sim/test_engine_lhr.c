/*
 * test_engine_lhr.c — the low-heat-rejection variants (0.5 and 1.0 mm zirconia,
 * paper Section III.B.3, Fig. 18) against the all-metal engine, crank-angle
 * fidelity on the dynamometer. Only the conventional rated point was
 * calibrated (wastegate area, +10.0 % over 1350 hp); everything about the LHR
 * engines is PREDICTED. This model predicts +14.2 % (0.5 mm) and +15.0 %
 * (1.0 mm) over 1350 hp against the paper's +15.7 / +19.8 %: the 0.5 mm
 * engine within 2 points, the 1.0 mm one NOT. Why (lhr_rated_energy_split):
 * the coating cuts piston + head heat by 45 % but the boost-sensing wastegate
 * bypasses a growing share of the extra exhaust energy, so boost rises ~3 %
 * while the hot walls cost ~2 % of volumetric efficiency: the air flow (and
 * with Eq. 14 the fuel) stays flat and only the indicated-efficiency gain is
 * left. The tests check the paper's trends, the 0.5 mm gain and that split.
 */
#include "test_util.h"

#include "engine_test_util.h"
#include "sim/engine_impl.h"

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
        assert_int_equal(ts_engine_rhs(e, 0, x, &in, xd, &o), 0);
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
    point p = {
        c.mean.brake_torque * c.mean.speed, c.mean.brake_torque, c.mean.boost, c.q_wall, c.eta_v,
        c.mean.piston_surface_temp,         surface_swing(e, x)};
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
 * printed, not asserted: +15.0 % vs +19.8 %). Fig. 21b: the coated piston's surface temperature
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
                  " (paper +9.9, +15.7, +19.8)\n",
                  100 * (c.power / ref - 1), 100 * (l5.power / ref - 1),
                  100 * (l10.power / ref - 1));
    print_message(
        "      boost %.2f / %.2f / %.2f bar, q_wall %.3f / %.3f / %.3f, piston %.0f / %.0f /"
        " %.0f K\n",
        c.boost / 1e5, l5.boost / 1e5, l10.boost / 1e5, c.q_wall, l5.q_wall, l10.q_wall, c.piston_t,
        l5.piston_t, l10.piston_t);
    print_message("      piston surface swing %.0f / %.0f / %.0f K\n", c.swing, l5.swing,
                  l10.swing);
    assert_true(l5.swing > 2 * c.swing && l10.swing > 2 * c.swing);
    assert_true(l5.q_wall < c.q_wall && l10.q_wall < l5.q_wall);
    assert_true(l5.piston_t > c.piston_t + 50 && l10.piston_t > l5.piston_t);
    assert_true(l5.boost > c.boost && l10.boost > c.boost);
    assert_true(l5.power > c.power && l10.power > c.power);
    assert_true(l5.power / ref - c.power / ref > 0.01);
    assert_true(l10.power > l5.power);
    assert_close(100 * (l5.power / ref - 1), 15.7, 0, 2.0); /* paper III.B.3, 2 points */
}

typedef struct split {
    double q[EN_NSURF];      /* cycle-mean heat into piston, head, liner [W], 12 cylinders */
    double t_surf[EN_NSURF]; /* cycle-mean gas-side surface temperature [K], 12 cylinders */
    double h_exhaust;        /* cycle-mean enthalpy flow leaving the exhaust manifolds [W] */
    double p_turbine;        /* turbine power, both banks [W] */
    double wg_share;         /* wastegate share of the exhaust mass flow [1] */
    double fuel_e;           /* fuel energy rate [W] */
    double q_wall;           /* the steady cycle's ledger: wall heat / fuel energy [1] */
    double boost, air, eta_v, eta_i, power;
} split;

/* The rated steady state's energy split over one more cycle (0.5-deg samples):
 * per-surface wall heat from the frozen-wall evaluation (en_crank_eval's
 * q_wall) and the turbine / wastegate split of each bank (en_turbine, the
 * actuator law and the orifice at the bank's manifold state). */
static split energy_split(int variant)
{
    ts_engine *e;
    ts_engine_cycle c;
    double *x = et_steady(variant, TS_ENGINE_CRANK_ANGLE, 2100, &e, &c);
    int n = ts_engine_nstate(e);
    double *xd = malloc(sizeof(double) * (size_t)n);
    double *work = malloc(sizeof(double) * ts_engine_work_size(e));
    assert_non_null(xd);
    assert_non_null(work);
    ts_engine_inputs in = et_full_load();
    const ts_engine_config *cc = &e->c;
    double w = c.mean.speed, q[EN_NCYL * EN_NSURF], m_t = 0, m_wg = 0;
    const int N = 1440;
    double dt = 4 * ET_PI / w / N;
    split s = {{0},
               {0},
               0,
               0,
               0,
               c.mean.fuel_flow * cc->lhv,
               c.q_wall,
               c.mean.boost,
               c.mean.air_flow,
               c.eta_v,
               c.eta_i,
               c.mean.brake_torque * w};
    ts_err err;
    for (int k = 0; k < N; k++) {
        assert_int_equal(en_crank_eval(e, x, &in, xd, NULL, q), 0);
        for (int i = 0; i < EN_NCYL; i++)
            for (int sf = 0; sf < EN_NSURF; sf++) {
                s.q[sf] += q[i * EN_NSURF + sf] * e->surf_area[sf] / N;
                s.t_surf[sf] +=
                    x[e->off_wall + (i * EN_NSURF + sf) * EN_WALL_NODES] / (EN_NCYL * N);
            }
        for (int b = 0; b < EN_NBANK; b++) {
            const double *xb = x + e->off_bank + b * EN_BANK_NX;
            en_bank_out bo;
            en_bank_read(e, xb, &bo);
            en_gas_state se;
            en_gas_eval(&e->gas, bo.T_em, bo.F_em, &se);
            en_turb_out to;
            double mw;
            en_exhaust_outflow(e, w, xb[BX_TC], &bo, &se, in.p_amb, in.T_amb, &to, &mw);
            s.p_turbine += to.power / N;
            s.h_exhaust += (to.mdot + mw) * se.h / N;
            m_t += to.mdot / N;
            m_wg += mw / N;
        }
        assert_int_equal(ts_engine_advance(e, x, 0, dt, &in, work, &err), TS_OK);
    }
    s.wg_share = m_wg / (m_t + m_wg);
    free(xd);
    free(work);
    free(x);
    ts_engine_free(e);
    return s;
}

/* EVIDENCE: diagnosis of the LHR 1.0 mm shortfall (issue 5; predicted, not
 * calibrated). Closed-form check first: the per-surface wall heat summed
 * equals the ledger's q_wall x fuel energy within 1 % (same cycle length).
 * Then the mechanism, at 2100 rpm: coating piston and head cuts their heat by
 * > 35 % (series resistance of 1 mm of k = 1 W/m/K zirconia on ~1.2e-3 m^2K/W
 * of gas film + metal + back-side film) while the uncoated liner takes MORE
 * (hotter gas); the exhaust enthalpy rises > 5 %, but the wastegate's share
 * of the exhaust rises too and the turbine power by < 1/4 of the exhaust
 * enthalpy gain, boost by < 5 %, the air flow by < 1 % (eta_v falls): the
 * power gain is the indicated-efficiency gain (eta_i ratio within 1 % of the
 * power ratio, 1.5 %: friction is the same). The numbers are printed for the
 * report. */
static void lhr_rated_energy_split(void **state)
{
    (void)state;
    split c = energy_split(TS_ENGINE_CONVENTIONAL);
    split l = energy_split(TS_ENGINE_LHR10);
    static const char *const nm[EN_NSURF] = {"piston", "head", "liner"};
    for (int sf = 0; sf < EN_NSURF; sf++)
        print_message("      %-6s heat %6.1f -> %6.1f kW, surface %4.0f -> %4.0f K\n", nm[sf],
                      c.q[sf] / 1e3, l.q[sf] / 1e3, c.t_surf[sf], l.t_surf[sf]);
    print_message("      exhaust enthalpy %.0f -> %.0f kW, turbine %.0f -> %.0f kW, wastegate share"
                  " %.1f -> %.1f %%, boost %.3f -> %.3f bar, air %.3f -> %.3f kg/s\n",
                  c.h_exhaust / 1e3, l.h_exhaust / 1e3, c.p_turbine / 1e3, l.p_turbine / 1e3,
                  100 * c.wg_share, 100 * l.wg_share, c.boost / 1e5, l.boost / 1e5, c.air, l.air);
    print_message("      eta_v %.4f -> %.4f, eta_i %.4f -> %.4f, power %.1f -> %.1f kW\n", c.eta_v,
                  l.eta_v, c.eta_i, l.eta_i, c.power / 1e3, l.power / 1e3);
    assert_close(c.q[0] + c.q[1] + c.q[2], c.q_wall * c.fuel_e, 0.01, 0);
    for (int sf = EN_PISTON; sf <= EN_HEAD; sf++) {
        assert_true(l.q[sf] < 0.65 * c.q[sf]);
        assert_true(l.t_surf[sf] > c.t_surf[sf] + 100);
    }
    assert_true(l.q[EN_LINER] > c.q[EN_LINER]);
    assert_true(l.h_exhaust > 1.05 * c.h_exhaust);
    assert_true(l.wg_share > c.wg_share);
    assert_true(l.p_turbine - c.p_turbine < 0.25 * (l.h_exhaust - c.h_exhaust));
    assert_true(l.boost > c.boost && l.boost < 1.05 * c.boost);
    assert_close(l.air, c.air, 0.01, 0);
    assert_true(l.eta_v < c.eta_v);
    assert_close(l.power / c.power, l.eta_i / c.eta_i, 0.015, 0);
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
    print_message(
        "      800 rpm: torque %.0f vs %.0f N*m, eta_v %.3f vs %.3f, boost %.2f vs %.2f bar\n",
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
        cmocka_unit_test(lhr_rated_energy_split),
    };
    return cmocka_run_group_tests_name("engine_lhr", tests, NULL, NULL);
}
