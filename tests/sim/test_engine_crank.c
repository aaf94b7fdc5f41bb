/*
 * test_engine_crank.c — the crank-angle V-12 (paper Section III.B.1, B.3) at its
 * rated point: rated power, per-cycle energy and mass balances, plausible peak
 * pressure / exhaust temperature / BSFC and the shape of the diesel cycle.
 */
#include "test_util.h"

#include <string.h>

#include "engine_test_util.h"

typedef struct rated {
    ts_engine *e;
    double *x;
    ts_engine_cycle cyc;
} rated;

static int setup(void **state)
{
    rated *r = calloc(1, sizeof *r);
    r->x = et_steady(TS_ENGINE_CONVENTIONAL, TS_ENGINE_CRANK_ANGLE, 2100, &r->e, &r->cyc);
    *state = r;
    return 0;
}

static int teardown(void **state)
{
    rated *r = *state;
    ts_engine_free(r->e);
    free(r->x);
    free(r);
    return 0;
}

/* EVIDENCE: paper Section III.B.3 — the all-metal virtual engine delivers 9.9 %
 * over the KTTA38's 1350 hp at 2100 rpm, i.e. 1484 hp (1106 kW). CALIBRATED: the
 * wastegate area (/engine/wg_area) was set to this point. Tolerance 3 %. */
static void rated_power_conventional(void **state)
{
    rated *r = *state;
    double p = r->cyc.mean.brake_torque * r->cyc.mean.speed;
    print_message("      rated: %.1f kW = %.0f hp, %.0f N*m, boost %.2f bar\n", p / 1e3, p / ET_HP,
                  r->cyc.mean.brake_torque, r->cyc.mean.boost / 1e5);
    assert_close(p / ET_HP, 1484.0, 0.03, 0);
}

/* EVIDENCE: first law over one engine cycle of all 12 cylinders (closed form):
 * fuel energy = indicated work + wall heat + (enthalpy out - in) + change of
 * cylinder internal energy. The model integrates temperature, not energy, so
 * closure tests the derivation and the integration. Tolerance 1 % of the fuel
 * energy; mass: in + fuel - out - change within 0.1 % of the inducted mass.
 * Also periodicity at steady state: the cylinders' energy changes < 1 %.
 * The ledger's totals integrate the very rates the cylinder states are
 * integrated from, so closure alone cannot see a wrong term (review, session
 * 20: the fuel energy raised 30 % still closed to 1e-9); its work is checked
 * against the pressure trace in indicated_work_is_the_pressure_loop, and the
 * plausibility ranges below bound the rest. */
static void cycle_energy_and_mass_balance(void **state)
{
    rated *r = *state;
    ts_engine_ledger l0, l1;
    ts_engine_ledger_get(r->e, r->x, &l0);
    double *work = malloc(sizeof(double) * ts_engine_work_size(r->e));
    ts_engine_inputs in = et_full_load();
    ts_engine_cycle c;
    ts_err err;
    assert_int_equal(ts_engine_cycle_run(r->e, r->x, &in, work, &c, &err), TS_OK);
    free(work);
    ts_engine_ledger_get(r->e, r->x, &l1);
    double fuel = l1.fuel_energy - l0.fuel_energy;
    double w = l1.work - l0.work, q = l1.wall_heat - l0.wall_heat;
    double hnet = (l1.enthalpy_out - l0.enthalpy_out) - (l1.enthalpy_in - l0.enthalpy_in);
    double dE = l1.cyl_energy - l0.cyl_energy;
    print_message("      per cycle: fuel %.0f J = work %.0f + wall %.0f + exhaust %.0f + dE %.0f"
                  " (residual %.2e)\n", fuel, w, q, hnet, dE, c.energy_residual);
    assert_true(fuel > 0);
    assert_close(w + q + hnet + dE, fuel, 0.01, 0);
    assert_true(fabs(dE) < 0.01 * fuel);
    double min = l1.mass_in - l0.mass_in, mout = l1.mass_out - l0.mass_out;
    double mf = l1.fuel_mass - l0.fuel_mass, dm = l1.cyl_mass - l0.cyl_mass;
    assert_close(mout + dm, min + mf, 1e-3, 0);
    assert_true(fabs(c.mass_residual) < 1e-3);
    /* the fuel burned per cycle is the fuel commanded (Watson burn completes) */
    assert_close(l1.fuel_mass - l0.fuel_mass, 12 * c.mean.fuel_per_cycle, 0.01, 0);
}

/* EVIDENCE: plausibility ranges for a highly rated HD diesel (Heywood 1988
 * ch. 1, 14; KTA38 data 207 g/kWh [S13]): peak cylinder pressure 120-230 bar
 * (the paper allows "higher maximum combustion pressure", III.B.3), exhaust
 * manifold 650-950 K, BSFC 190-240 g/kWh, volumetric efficiency (air through
 * the intake valves) 0.8-1.05, in-cylinder heat loss 8-25 % of fuel energy.
 * Not calibrated to any of these. (The delivered phi equals Eq. 13's target
 * by construction of Eq. 14 on the same air flow: no longer asserted.) */
static void rated_point_is_plausible(void **state)
{
    rated *r = *state;
    const ts_engine_cycle *c = &r->cyc;
    double bsfc = c->bsfc * 3.6e9;
    print_message("      peak %.0f bar, exhaust %.0f K, bsfc %.1f g/kWh, eta_v %.3f, q_wall %.3f\n",
                  c->peak_pressure / 1e5, c->mean.exhaust_temp, bsfc, c->eta_v, c->q_wall);
    assert_in_range(c->peak_pressure / 1e5, 120, 230);
    assert_in_range(c->mean.exhaust_temp, 650, 950);
    assert_in_range(bsfc, 190, 240);
    assert_in_range(c->eta_v * 100, 80, 105);
    assert_in_range(c->q_wall * 100, 8, 25);
}

/* A copy of the rated state to advance, with the rhs and work buffers. */
typedef struct scratch {
    double *x, *xd, *work;
} scratch;

static scratch scratch_of(const rated *r)
{
    size_t n = (size_t)ts_engine_nstate(r->e);
    scratch s = {malloc(sizeof(double) * n), malloc(sizeof(double) * n),
                 malloc(sizeof(double) * ts_engine_work_size(r->e))};
    assert_true(s.x && s.xd && s.work);
    memcpy(s.x, r->x, sizeof(double) * n);
    return s;
}

static void scratch_free(scratch *s)
{
    free(s->x);
    free(s->xd);
    free(s->work);
}

/* EVIDENCE: shape of a DI diesel cycle (Heywood Figs. 10-4, 10-8): no heat
 * release before injection, an ignition delay after start of injection,
 * pressure peak within 0-25 deg after firing TDC above the compression
 * pressure at TDC... peak bulk temperature 1500-2400 K, heat release
 * concentrated within ~60 deg after ignition, exhaust blowdown after EVO
 * (130 deg): by 220 deg the pressure has fallen below half its 120-deg value. */
static void crank_angle_trace_is_a_diesel_cycle(void **state)
{
    rated *r = *state;
    const ts_engine *e = r->e;
    scratch sc = scratch_of(r);
    double *x = sc.x, *xd = sc.xd, *work = sc.work;
    ts_engine_inputs in = et_full_load();
    ts_err err;
    /* advance to cylinder 1's -180 deg (BDC before firing TDC) */
    double w = x[TS_ENGINE_X_SPEED];
    double th = fmod(x[TS_ENGINE_X_ANGLE], 4 * ET_PI);
    double to = fmod(3 * ET_PI - th + 4 * ET_PI, 4 * ET_PI);
    assert_int_equal(ts_engine_advance(e, x, 0, to / w, &in, work, &err), TS_OK);
    double p_peak = 0, a_peak = 0, T_peak = 0, p_tdc = 0, a_hrr = -1, q_total = 0, q_60 = 0;
    double p_evo_before = 0, p_evo_after = 0;
    double dt = ET_PI / 180 / w; /* 1 deg steps */
    print_message("      deg   p[bar]   T[K]   dQ/dth[J/deg]\n");
    for (int k = -180; k <= 240; k++) {
        ts_engine_outputs o;
        assert_int_equal(ts_engine_rhs(e, 0, x, &in, xd, &o), 0);
        if (k % 30 == 0 || k == -10 || k == 5 || k == 10)
            print_message("      %4d %8.1f %6.0f %10.1f\n", k, o.cyl_pressure / 1e5, o.cyl_temp,
                          o.heat_release * dt);
        if (o.cyl_pressure > p_peak) p_peak = o.cyl_pressure, a_peak = k;
        if (o.cyl_temp > T_peak) T_peak = o.cyl_temp;
        if (k == 0) p_tdc = o.cyl_pressure;
        if (o.heat_release > 0 && a_hrr < -0.5 && k > -60) a_hrr = k;
        if (k < -12 || k > 180) assert_true(o.heat_release == 0); /* outside combustion */
        q_total += o.heat_release * dt;
        if (a_hrr > -0.5 && k <= a_hrr + 60) q_60 += o.heat_release * dt;
        if (k == 120) p_evo_before = o.cyl_pressure;
        if (k == 220) p_evo_after = o.cyl_pressure;
        assert_int_equal(ts_engine_advance(e, x, 0, dt, &in, work, &err), TS_OK);
    }
    print_message("      peak %.1f bar at %.0f deg ATDC, Tmax %.0f K, first heat release %.0f deg\n",
                  p_peak / 1e5, a_peak, T_peak, a_hrr);
    assert_in_range(a_peak, 0, 25);
    assert_true(p_peak > p_tdc);
    assert_in_range(T_peak, 1500, 2400);
    assert_true(a_hrr > -10 && a_hrr < 10); /* SOI -10 deg + a short delay */
    assert_true(q_60 > 0.8 * q_total);
    assert_true(p_evo_after < 0.5 * p_evo_before); /* blowdown */
    scratch_free(&sc);
}

/* Cylinder volume [m^3] at crank angle th from firing TDC: the slider-crank
 * of Heywood Eq. 2.4, written here from the config's geometry (bore, stroke,
 * rod, compression ratio), not taken from the engine's own kinematics. */
static double cylinder_volume(const ts_engine_config *g, double th)
{
    double a = 0.5 * g->stroke, l = g->rod_length, area = 0.25 * ET_PI * g->bore * g->bore;
    double vd = area * g->stroke, vc = vd / (g->compression_ratio - 1.0);
    double sn = sin(th);
    return vc + area * (l + a - a * cos(th) - sqrt(l * l - a * a * sn * sn));
}

/* EVIDENCE: the indicated work of the first law above (the ledger's p dV
 * total, integrated with the cylinder states), checked against quantities
 * the ledger does not compute: cylinder 1's sampled pressure trace over one
 * cycle (0.25-deg steps), integrated as a closed p dV loop with the test's
 * own slider-crank volume, times 12 cylinders. The cylinders differ only by
 * their manifold phase (measured 12 W_1 / W = 1.0015); tolerance 1 %. A
 * wrong dV/dtheta, a work term per bank instead of per engine, or a pressure
 * trace out of phase with its cylinder's motion fails.
 * Closed form, nothing calibrated. */
static void indicated_work_is_the_pressure_loop(void **state)
{
    rated *r = *state;
    const ts_engine *e = r->e;
    ts_engine_config g = et_defaults().engine;
    scratch sc = scratch_of(r);
    double *x = sc.x, *xd = sc.xd, *work = sc.work;
    ts_engine_inputs in = et_full_load();
    ts_err err;
    double w = x[TS_ENGINE_X_SPEED], step = 0.25 * ET_PI / 180;
    double th = fmod(x[TS_ENGINE_X_ANGLE], 4 * ET_PI); /* cylinder 1's angle */
    ts_engine_ledger l0, l1;
    ts_engine_ledger_get(e, x, &l0);
    ts_engine_outputs o;
    assert_int_equal(ts_engine_rhs(e, 0, x, &in, xd, &o), 0);
    double loop = 0, p_prev = o.cyl_pressure, v_prev = cylinder_volume(&g, th);
    for (int k = 1; k <= 720 * 4; k++) {
        assert_int_equal(ts_engine_advance(e, x, 0, step / w, &in, work, &err), TS_OK);
        assert_int_equal(ts_engine_rhs(e, 0, x, &in, xd, &o), 0);
        double v = cylinder_volume(&g, th + k * step);
        loop += 0.5 * (o.cyl_pressure + p_prev) * (v - v_prev);
        p_prev = o.cyl_pressure, v_prev = v;
    }
    ts_engine_ledger_get(e, x, &l1);
    double ledger = l1.work - l0.work;
    print_message("      indicated work per cycle: ledger %.0f J, 12 x cylinder 1's p dV loop %.0f "
                  "J (ratio %.4f)\n",
                  ledger, 12 * loop, 12 * loop / ledger);
    assert_close(12 * loop, ledger, 0.01, 0);
    scratch_free(&sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(rated_power_conventional),
        cmocka_unit_test(cycle_energy_and_mass_balance),
        cmocka_unit_test(rated_point_is_plausible),
        cmocka_unit_test(crank_angle_trace_is_a_diesel_cycle),
        cmocka_unit_test(indicated_work_is_the_pressure_loop),
    };
    return cmocka_run_group_tests_name("engine_crank", tests, setup, teardown);
}
