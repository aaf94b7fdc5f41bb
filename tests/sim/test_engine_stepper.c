/*
 * test_engine_stepper.c — bookkeeping of the crank-angle engine's own
 * integrator (sim/engine.c, engine_crank.c) that the speed-up of issue 6
 * relies on: the split right-hand side (en_crank_refresh re-evaluates only the
 * wall- and load-dependent part) equals a full evaluation exactly, and the
 * derivative carried from one ts_engine_advance_load call to the next changes
 * no result (runs with the carry and with it destroyed are bit-identical).
 * Uses the engine's internal header (engine_impl.h) on purpose.
 */
#include "test_util.h"

#include <string.h>

#include "engine_test_util.h"
#include "sim/engine_impl.h"

/* A running crank-angle engine (cylinders in every phase, some burning):
 * from the initial state at 2100 rpm, 40 ms at full rack against a load. */
static double *running_engine(ts_engine **e_out, ts_engine_inputs *in)
{
    ts_err err;
    ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, TS_ENGINE_CRANK_ANGLE);
    double *x = calloc((size_t)ts_engine_nstate(e), sizeof *x);
    double *work = calloc(ts_engine_work_size(e), sizeof *work);
    assert_non_null(x);
    assert_non_null(work);
    *in = et_full_load();
    in->hold_speed = 0;
    in->load_torque = 3000.0;
    ts_engine_init_state(e, ET_RPM(2100), in->p_amb, in->T_amb, x);
    ts_engine_set_turbo_speed(e, x, 8000.0);
    assert_int_equal(ts_engine_advance(e, x, 0, 0.04, in, work, &err), TS_OK);
    free(work);
    *e_out = e;
    return x;
}

/* EVIDENCE: exactness by construction (same operations on the same values):
 * after the walls change (every node +1..+12 K) and the load torque changes,
 * en_crank_refresh applied to the derivative of the old walls and load gives
 * the full evaluation's derivative and wall fluxes to the bit. Tolerance 0. */
static void refresh_equals_full_evaluation(void **state)
{
    (void)state;
    ts_engine *e;
    ts_engine_inputs in;
    double *x = running_engine(&e, &in);
    int n = e->off_wall, nx = e->nx, burning = 0;
    for (int i = 0; i < EN_NCYL; i++) {
        const double *xc = x + e->off_cyl + i * EN_CYL_NX;
        burning += xc[CX_IGN] >= 1.0 && xc[CX_BURN] < e->c.burn_duration;
    }
    assert_true(burning >= 1); /* the radiation branch is exercised too */
    double *ka = calloc((size_t)nx, sizeof *ka), *kb = calloc((size_t)nx, sizeof *kb);
    double qa[EN_NCYL * EN_NSURF], qb[EN_NCYL * EN_NSURF];
    en_crank_part part;
    assert_int_equal(en_crank_eval_part(e, x, &in, ka, NULL, qa, &part), 0);
    for (int i = n; i < nx; i++) x[i] += 1.0 + (i % 12);
    ts_engine_inputs in2 = in;
    in2.load_torque = 4321.0;
    assert_int_equal(en_crank_eval(e, x, &in2, kb, NULL, qb), 0);
    assert_true(memcmp(ka, kb, sizeof(double) * (size_t)n) != 0); /* the change is seen */
    en_crank_refresh(e, x, &in2, &part, ka, qa);
    assert_memory_equal(ka, kb, sizeof(double) * (size_t)n);
    assert_memory_equal(qa, qb, sizeof qa);
    free(ka);
    free(kb);
    free(x);
    ts_engine_free(e);
}

/* EVIDENCE: closed form (not calibrated): the valve lifts the crank-angle
 * right-hand side uses (cos of the lift phase by rotation of precomputed
 * phases, engine_crank.c) equal the plain profile en_valve_lift at each
 * cylinder's local angle, for every cylinder and valve, over two cycles
 * (negative and wrapped angles included), within 1e-9 of the peak lift; and
 * every valve opens somewhere in the cycle. */
static void valve_lift_by_rotation_matches_profile(void **state)
{
    (void)state;
    ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, TS_ENGINE_CRANK_ANGLE);
    const ts_engine_config *c = &e->c;
    const double open[2] = {c->ivo, c->evo}, close[2] = {c->ivc, c->evc};
    const double lmax[2] = {c->intake_max_lift, c->exhaust_max_lift};
    for (int v = 0; v < 2; v++)
        for (int i = 0; i < EN_NCYL; i++) {
            double peak = 0;
            for (double th = -4 * ET_PI; th < 4 * ET_PI; th += 0.0061) {
                double thl = fmod(th - e->cyl_offset[i], 4 * ET_PI);
                if (thl < 0) thl += 4 * ET_PI;
                double want = en_valve_lift(thl, open[v], close[v], lmax[v]);
                double got = en_crank_valve_lift(e, v, i, th);
                assert_close(got, want, 0, 1e-9 * lmax[v]);
                peak = fmax(peak, got);
            }
            assert_true(peak > 0.99 * lmax[v]);
        }
    ts_engine_free(e);
}

/* EVIDENCE: the derivative carried between calls is exact: twenty 1-ms calls
 * of ts_engine_advance_load with one work buffer (the carry used) and with
 * the buffer overwritten before every call (the carry never valid) end in
 * bit-identical states. Tolerance 0. */
static void carried_derivative_changes_nothing(void **state)
{
    (void)state;
    ts_engine *e;
    ts_engine_inputs in;
    double *x = running_engine(&e, &in);
    int nx = e->nx;
    size_t nw = ts_engine_work_size(e);
    double *xa = malloc(sizeof(double) * (size_t)nx), *xb = malloc(sizeof(double) * (size_t)nx);
    double *wa = calloc(nw, sizeof *wa), *wb = calloc(nw, sizeof *wb);
    memcpy(xa, x, sizeof(double) * (size_t)nx);
    memcpy(xb, x, sizeof(double) * (size_t)nx);
    ts_err err;
    for (int k = 0; k < 20; k++) {
        double t = 0.04 + 1e-3 * k;
        in.load_torque = 3000.0 + 50.0 * k; /* the load changes between calls */
        assert_int_equal(ts_engine_advance(e, xa, t, 1e-3, &in, wa, &err), TS_OK);
        memset(wb, 0xff, sizeof(double) * nw); /* NaNs: no carry */
        assert_int_equal(ts_engine_advance(e, xb, t, 1e-3, &in, wb, &err), TS_OK);
    }
    assert_memory_equal(xa, xb, sizeof(double) * (size_t)nx);
    free(xa);
    free(xb);
    free(wa);
    free(wb);
    free(x);
    ts_engine_free(e);
}

/* Energy in the wall nodes [J]: sum over cylinders and surfaces of the
 * surface's area times sum_n cap_n T_n (engine_wall.c: per-area node
 * capacities; the liner's flux is per full-liner area, engine_crank.c). */
static double wall_energy(const ts_engine *e, const double *x)
{
    double sum = 0;
    for (int i = 0; i < EN_NCYL; i++)
        for (int sf = 0; sf < EN_NSURF; sf++) {
            const double *T = x + e->off_wall + (i * EN_NSURF + sf) * EN_WALL_NODES;
            double s = 0;
            for (int n = 0; n < EN_WALL_NODES; n++)
                s += e->wall[sf].cap[n] * T[n];
            sum += e->surf_area[sf] * s;
        }
    return sum;
}

/* EVIDENCE: first law for the walls under the split stepper (engine.c, bs23:
 * "the same split": the gas states, the wall ledger among them, take the
 * Bogacki-Shampine step y1 = x + h (2/9 k1 + 1/3 k2 + 4/9 k3), and the walls one
 * Crank-Nicolson step with the flux accumulated with the same weights):
 * Crank-Nicolson conserves energy (interior conduction cancels), so with the
 * back-side film coefficients h_oil and h_coolant at 1e-9 W/m^2/K (nothing
 * leaves the back faces) the heat the walls store over one
 * ts_engine_advance, sum_cyl,surf A sum_n cap_n dT_n, equals the ledger's
 * wall heat over it, Delta ledger[LX_WALL], to rounding (1e-9 relative; with
 * the first stage's flux alone they differ by ~1e-3). */
static void walls_store_the_ledgers_wall_heat(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    c.engine.variant = TS_ENGINE_CONVENTIONAL;
    c.engine.fidelity = TS_ENGINE_CRANK_ANGLE;
    c.engine.h_oil = 1e-9;
    c.engine.h_coolant = 1e-9;
    ts_err err;
    ts_engine *e = ts_engine_make(&c, &err);
    assert_non_null(e);
    double *x = calloc((size_t)ts_engine_nstate(e), sizeof *x);
    double *work = calloc(ts_engine_work_size(e), sizeof *work);
    assert_non_null(x);
    assert_non_null(work);
    ts_engine_inputs in = et_full_load();
    in.hold_speed = 0;
    in.load_torque = 3000.0;
    ts_engine_init_state(e, ET_RPM(2100), in.p_amb, in.T_amb, x);
    ts_engine_set_turbo_speed(e, x, 8000.0);
    assert_int_equal(ts_engine_advance(e, x, 0, 0.02, &in, work, &err), TS_OK);
    for (int k = 0; k < 2; k++) { /* a carried derivative in the second call */
        double w0 = wall_energy(e, x), l0 = x[e->off_ledger + LX_WALL];
        double t = 0.02 + 0.02 * k;
        assert_int_equal(ts_engine_advance(e, x, t, 0.02, &in, work, &err), TS_OK);
        double dw = wall_energy(e, x) - w0, dl = x[e->off_ledger + LX_WALL] - l0;
        assert_true(dl > 100.0); /* the walls took heat (J over 20 ms) */
        assert_close(dw, dl, 1e-9, 0);
    }
    free(work);
    free(x);
    ts_engine_free(e);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(refresh_equals_full_evaluation),
        cmocka_unit_test(valve_lift_by_rotation_matches_profile),
        cmocka_unit_test(carried_derivative_changes_nothing),
        cmocka_unit_test(walls_store_the_ledgers_wall_heat),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
