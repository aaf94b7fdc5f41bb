/*
 * test_driveline_components.c — torque converter, transmission and final drive
 * (paper Section III.B.2) against closed-form relations: converter torque
 * balance and efficiency, stall torque ratio and stall speed, over-running,
 * power through the gears with efficiency, a clutch-to-clutch shift handing
 * torque over continuously, and table validation.
 */
#include "test_util.h"

#include <string.h>

#include "api/config_json.h"
#include "sim/final_drive.h"
#include "sim/solver.h"
#include "sim/tanksim.h"
#include "sim/torque_converter.h"
#include "sim/transmission.h"

#define RPM (3.14159265358979323846 / 30.0)

#define UPSHIFT_W_OUT 40.0 /* [rad/s] output speed where no downshift applies */

static ts_config defaults(void)
{
    ts_config c;
    ts_err err;
    json_t *doc = json_pack("{s:{s:s}}", "run", "kind", "pointmass");
    assert_int_equal(tsa_config_load(doc, &c, NULL, NULL, &err), TS_OK);
    json_decref(doc);
    return c;
}

/* The default 4-speed box (defaults()) in gear `gear`, not shifting. */
static ts_transmission box_in_gear(int gear, ts_shift_state *st)
{
    ts_config c = defaults();
    ts_transmission tr;
    assert_int_equal(ts_transmission_init(&tr, &c.driveline, NULL), TS_OK);
    ts_transmission_reset(&tr, st, gear);
    return tr;
}

/* EVIDENCE: definitions T_p = (w_p/K)^2, T_t = TR T_p at the table rows of
 * driveline.json (the [E] nominal curve, not calibrated); efficiency
 * P_t/P_p = TR SR. Tol 1e-12. */
static void converter_torque_balance_and_efficiency(void **state)
{
    (void)state;
    ts_config c = defaults();
    ts_torque_converter tc;
    ts_err err;
    assert_int_equal(ts_torque_converter_init(&tc, &c.driveline, &err), TS_OK);
    const ts_driveline_config *d = &c.driveline;
    double wp = 1500 * RPM;
    for (int i = 0; i < d->tc_speed_ratio_n; i++) {
        double sr = d->tc_speed_ratio[i];
        ts_tc_point p;
        ts_torque_converter_eval(&tc, wp, sr * wp, &p);
        double k = d->tc_k_factor[i];
        assert_close(p.pump_torque, wp * wp / (k * k), 1e-12, 0);
        assert_close(p.turbine_torque, d->tc_torque_ratio[i] * p.pump_torque, 1e-12, 0);
        assert_close(p.efficiency, d->tc_torque_ratio[i] * sr, 1e-12, 1e-15);
    }
    /* between rows: TR and capacity 1/K^2 linear in SR between the table rows,
     * capacity falling linearly to 0 at SR 1 above the last row; efficiency
     * TR * SR, below 1 everywhere */
    int n = d->tc_speed_ratio_n;
    const double *srt = d->tc_speed_ratio, *trt = d->tc_torque_ratio, *kt = d->tc_k_factor;
    for (double sr = 0.01; sr < 1.0; sr += 0.0137) {
        ts_tc_point p;
        ts_torque_converter_eval(&tc, wp, sr * wp, &p);
        double tr_want, cap_want;
        if (sr >= srt[n - 1]) {
            tr_want = trt[n - 1];
            cap_want = (1.0 - (sr - srt[n - 1]) / (1.0 - srt[n - 1])) / (kt[n - 1] * kt[n - 1]);
        } else {
            int j = 0;
            while (srt[j + 1] <= sr) j++;
            double f = (sr - srt[j]) / (srt[j + 1] - srt[j]);
            tr_want = trt[j] + f * (trt[j + 1] - trt[j]);
            cap_want = (1 - f) / (kt[j] * kt[j]) + f / (kt[j + 1] * kt[j + 1]);
        }
        assert_close(p.torque_ratio, tr_want, 1e-12, 0);
        assert_close(p.pump_torque, cap_want * wp * wp, 1e-12, 1e-9);
        assert_close(p.turbine_torque, tr_want * p.pump_torque, 1e-12, 1e-9);
        assert_close(p.efficiency, tr_want * sr, 1e-12, 1e-15);
        assert_true(p.efficiency <= 1.0 + 1e-12);
        assert_true(p.pump_torque >= 0.0);
    }
}

/* EVIDENCE: stall (turbine held): TR0 = 2.8 [S HT-740 TC 470 2.83] and
 * w_stall = K0 sqrt(T) — with K0 = 23 rpm/sqrt(N*m) [E] the stall speed at
 * 5,400 N*m is 23 sqrt(5400) = 1690 rpm (reference sheet §4.1). Closed form,
 * tol 1e-3 (K given to 5 digits in rad/s units). */
static void converter_stall_torque_ratio(void **state)
{
    (void)state;
    ts_config c = defaults();
    ts_torque_converter tc;
    assert_int_equal(ts_torque_converter_init(&tc, &c.driveline, NULL), TS_OK);
    double w_stall = 23.0 * sqrt(5400.0) * RPM;
    ts_tc_point p;
    ts_torque_converter_eval(&tc, w_stall, 0.0, &p);
    assert_close(p.turbine_torque / p.pump_torque, 2.8, 1e-12, 0);
    assert_close(p.pump_torque, 5400.0, 1e-3, 0);
    /* a turbine turning backwards counts as stall */
    ts_tc_point q;
    ts_torque_converter_eval(&tc, w_stall, -5.0, &q);
    assert_close(q.turbine_torque, p.turbine_torque, 1e-12, 0);
    /* the shipped K table is its stated curve (driveline.json _sources):
     * K0 below SR 0.6, K0 [1 + 2.5 ((SR - 0.6)/0.37)^2] above, to the 5
     * digits given (rows 0.85 and 0.95 were 0.1 % low until session 21) */
    const ts_driveline_config *d = &c.driveline;
    double k0 = d->tc_k_factor[0];
    assert_close(k0, 23.0 * RPM, 2e-5, 0);
    for (int i = 0; i < d->tc_speed_ratio_n; i++) {
        double x = d->tc_speed_ratio[i] > 0.6 ? (d->tc_speed_ratio[i] - 0.6) / 0.37 : 0.0;
        assert_close(d->tc_k_factor[i], k0 * (1 + 2.5 * x * x), 2e-5, 0);
    }
}

/* EVIDENCE: no circulation at equal speeds: torque -> 0 at SR = 1, continuous
 * from both sides; over-running (turbine faster) brakes the turbine and drives
 * the pump with TR = 1 (coupling, stator freewheeling), at the efficiency of
 * power flowing backwards, P_pump / P_turbine = w_p / w_t. Qualitative/closed
 * form. */
static void converter_over_running(void **state)
{
    (void)state;
    ts_config c = defaults();
    ts_torque_converter tc;
    assert_int_equal(ts_torque_converter_init(&tc, &c.driveline, NULL), TS_OK);
    double wp = 200;
    ts_tc_point a, b, e;
    ts_torque_converter_eval(&tc, wp, wp * (1 - 1e-6), &a);
    ts_torque_converter_eval(&tc, wp, wp * (1 + 1e-6), &b);
    ts_torque_converter_eval(&tc, wp, wp, &e);
    assert_close(e.pump_torque, 0, 0, 1e-12);
    assert_true(fabs(a.pump_torque) < 0.1 && fabs(b.pump_torque) < 0.1);
    ts_tc_point o;
    ts_torque_converter_eval(&tc, wp, 1.25 * wp, &o);
    assert_true(o.turbine_torque < 0 && o.pump_torque < 0);
    assert_close(o.turbine_torque, o.pump_torque, 1e-12, 0);
    /* mirror of the forward point at SR 0.8: |T| = (w_t / K(0.8))^2 */
    double k08 = c.driveline.tc_k_factor[5];
    assert_close(o.pump_torque, -pow(1.25 * wp / k08, 2), 1e-12, 0);
    /* power flows back, turbine to pump, at equal torque: the efficiency is
     * P_pump / P_turbine = w_p / w_t = 0.8, below 1 */
    assert_close(o.efficiency, 0.8, 1e-12, 0);
    /* engine stopped, turbine driven: still braking, finite */
    ts_torque_converter_eval(&tc, 0, 50, &o);
    assert_true(o.turbine_torque < 0 && isfinite(o.turbine_torque));
    ts_torque_converter_eval(&tc, 0, 0, &o);
    assert_close(o.pump_torque, 0, 0, 0);
}

/* EVIDENCE: power conservation through a locked gear with efficiency:
 * T_out = r eta T_in forward, r T_in / eta backward; P_out = eta P_in at zero
 * slip. Closed form (gear_efficiency [E]), tol 1e-12. Final drive likewise:
 * 2 T_s w_s = eta_fd T_out w_out. */
static void gears_conserve_power_with_efficiency(void **state)
{
    (void)state;
    ts_config c = defaults();
    ts_transmission tr;
    ts_err err;
    assert_int_equal(ts_transmission_init(&tr, &c.driveline, &err), TS_OK);
    for (int g = 1; g <= tr.n; g++) {
        ts_shift_state st;
        ts_transmission_reset(&tr, &st, g);
        double w_out = 40, r = c.driveline.gear_ratio[g - 1], eta = c.driveline.gear_efficiency[g - 1];
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            double slip = sgn * 0.1; /* locked clutch creeps by a fraction of w_s */
            ts_tr_point p;
            ts_transmission_eval(&tr, &st, 0, r * w_out + slip, w_out, &p);
            double want = sgn > 0 ? r * eta * p.input_torque : r * p.input_torque / eta;
            assert_close(p.output_torque, want, 1e-12, 0);
            assert_close(p.input_torque, tr.clutch_capacity * tanh(slip / tr.slip_speed), 1e-12, 0);
            double w_in = r * w_out + slip;
            if (sgn > 0) /* P_out = eta P_in (1 - slip / w_in): gear loss and clutch slip loss */
                assert_close(p.output_torque * w_out,
                             eta * p.input_torque * w_in * (1 - slip / w_in), 1e-12, 0);
            assert_close(p.gear, g, 0, 0);
        }
    }
    ts_final_drive fd;
    assert_int_equal(ts_final_drive_init(&fd, &c.driveline, &c.vehicle, &err), TS_OK);
    double w_s = 10, t_out = 8000;
    double ts_each = ts_final_drive_sprocket_torque(&fd, t_out);
    assert_close(2 * ts_each * w_s, c.driveline.final_efficiency * t_out * ts_final_drive_output_speed(&fd, w_s), 1e-12, 0);
    assert_close(ts_final_drive_sprocket_torque(&fd, -t_out),
                 -0.5 * c.driveline.final_ratio * t_out / c.driveline.final_efficiency, 1e-12, 0);
    assert_close(ts_final_drive_track_force(&fd, ts_each), ts_each / c.vehicle.sprocket_radius, 1e-12, 0);
}

/* Turbine shaft of inertia J under a constant input torque, output speed held. */
typedef struct {
    const ts_transmission *tr;
    const ts_shift_state *st;
    double t_in, j, w_out;
} shaft;

static int shaft_rhs(double t, const double *y, double *ydot, void *ud)
{
    const shaft *s = ud;
    ts_tr_point p;
    ts_transmission_eval(s->tr, s->st, t, y[0], s->w_out, &p);
    ydot[0] = (s->t_in - p.input_torque) / s->j;
    return 0;
}

/* EVIDENCE: clutch-to-clutch handover [P III.B.2 "simultaneous disengagement
 * and engagement ... during a user-specified interval"]. Closed form of the
 * model's torque phase (off-going still locked, on-coming slipping at its
 * capacity tau Cs): T_on = tau Cs, T_off = T_in - T_on, T_out = r1 eta1 T_off +
 * r2 eta2 T_on, checked at tau = 0.1 .. 0.5 (tol 1 %); the on-coming share of
 * the input torque grows over the interval (no instant ratio jump); output
 * torque has no step larger than 3 % of r1 T_in per 1 ms in the torque phase;
 * at the end the input runs at r2 w_out (synchronised, tol 0.1 %). Nothing
 * calibrated. */
static void shift_hands_torque_over_continuously(void **state)
{
    (void)state;
    ts_config c = defaults();
    ts_transmission tr;
    ts_err err;
    assert_int_equal(ts_transmission_init(&tr, &c.driveline, &err), TS_OK);
    ts_shift_state st;
    ts_transmission_reset(&tr, &st, 1);
    shaft s = {&tr, &st, 5000.0, 1.0, 30.0};
    double r1 = tr.ratio[0], r2 = tr.ratio[1], e1 = tr.efficiency[0], e2 = tr.efficiency[1];
    double y0 = r1 * s.w_out + tr.slip_speed * atanh(s.t_in / tr.clutch_capacity); /* locked */
    ts_ode_opts o = {.rtol = 1e-8, .atol = 1e-8, .max_step = 1e-3};
    ts_ode *ode = ts_ode_make(1, shaft_rhs, &s, &o, &err);
    assert_non_null(ode);
    /* the shift starts at t = 0 on the engine-speed event */
    assert_int_equal(
        ts_transmission_update(&tr, &st, 0.0, tr.shift_speed + 1, UPSHIFT_W_OUT, s.t_in), 1);
    assert_int_equal(st.target, 2);
    assert_close(st.capacity, tr.shift_capacity_factor * s.t_in, 1e-12, 0);
    assert_int_equal(ts_ode_init(ode, 0.0, &y0, &err), TS_OK);
    double dt = tr.shift_time, prev_out = NAN, max_jump_torque_phase = 0;
    int checked = 0;
    for (int k = 1; k <= 1000; k++) {
        double t = k * 1e-3 * dt, tr_t;
        assert_int_equal(ts_ode_advance(ode, t, &tr_t, NULL, &err), TS_OK);
        double w = ts_ode_y(ode)[0], tau = t / dt;
        ts_tr_point p;
        ts_transmission_eval(&tr, &st, t, w, s.w_out, &p);
        int torque_phase = tau <= 0.6; /* off-going breaks away at tau ~ 0.83 */
        if (torque_phase && !isnan(prev_out))
            max_jump_torque_phase = fmax(max_jump_torque_phase, fabs(p.output_torque - prev_out));
        prev_out = p.output_torque;
        if (k % 100 == 0 && tau <= 0.5 + 1e-9) {
            double ton = tau * st.capacity, toff = s.t_in - ton;
            assert_close(p.oncoming_torque, ton, 1e-2, 0);
            assert_close(p.offgoing_torque, toff, 1e-2, 1);
            assert_close(p.output_torque, r1 * e1 * toff + r2 * e2 * ton, 1e-2, 0);
            checked++;
        }
        if (k == 250) assert_true(p.oncoming_torque / p.input_torque > 0.2 &&
                                  p.oncoming_torque / p.input_torque < 0.6);
        if (k == 500) assert_true(p.oncoming_torque / p.input_torque > 0.5);
    }
    assert_int_equal(checked, 5);
    assert_true(max_jump_torque_phase < 0.03 * r1 * s.t_in);
    /* interval over: the state machine completes the shift, input synchronised */
    assert_int_equal(ts_transmission_update(&tr, &st, dt, 0.0, UPSHIFT_W_OUT, 0.0), 1);
    assert_int_equal(st.gear, 2);
    assert_int_equal(st.target, 0);
    /* locked on the on-coming clutch: creep w_s (Cs/C_max) atanh(T_in/Cs) of the
     * regularised law */
    assert_close(ts_ode_y(ode)[0],
                 r2 * s.w_out + tr.slip_speed * st.capacity / tr.clutch_capacity *
                                    atanh(s.t_in / st.capacity),
                 1e-3, 0);
    ts_ode_free(ode);
}

/* EVIDENCE: shift logic [P III.B.2]: upshift root at engine speed 1850 rpm
 * (sign change of g0), shift-end root at t0 + shift_time, the engine's dip to
 * shift_speed - hysteresis during a shift re-arms the next upshift (a root;
 * no dwell wait), no upshift from the top gear, downshift below
 * downshift_speed when the lower gear's input would also turn below it (not
 * on a dropped rack at speed). Logic check, nothing calibrated. */
static void shift_events_as_roots(void **state)
{
    (void)state;
    ts_shift_state st;
    ts_transmission tr = box_in_gear(1, &st);
    assert_close(tr.shift_speed / RPM, 1850, 1e-4, 0);
    double g[TS_TRANSMISSION_NROOTS], h[TS_TRANSMISSION_NROOTS];
    ts_transmission_roots(&tr, &st, 1.0, 1849 * RPM, UPSHIFT_W_OUT, g);
    ts_transmission_roots(&tr, &st, 1.1, 1851 * RPM, UPSHIFT_W_OUT, h);
    assert_true(g[0] < 0 && h[0] > 0);
    assert_int_equal(ts_transmission_update(&tr, &st, 1.0, 1849 * RPM, UPSHIFT_W_OUT, 3000), 0);
    assert_int_equal(ts_transmission_update(&tr, &st, 1.1, 1851 * RPM, UPSHIFT_W_OUT, 3000), 1);
    ts_transmission_roots(&tr, &st, 1.1 + 0.5 * tr.shift_time, 0, UPSHIFT_W_OUT, g);
    ts_transmission_roots(&tr, &st, 1.1 + 1.01 * tr.shift_time, 0, UPSHIFT_W_OUT, h);
    assert_true(g[0] > 0 && h[0] < 0);
    double w_hi = tr.shift_speed; /* above the re-arm speed: no re-arm event */
    assert_int_equal(
        ts_transmission_update(&tr, &st, 1.1 + 0.5 * tr.shift_time, w_hi, UPSHIFT_W_OUT, 0), 0);
    assert_int_equal(st.armed, 0);
    /* the engine's dip to the re-arm speed during the shift is a root and
     * re-arms the next upshift (no dwell wait after the shift) */
    double rearm = tr.shift_speed - tr.shift_hysteresis;
    ts_transmission_roots(&tr, &st, 1.1 + 0.6 * tr.shift_time, rearm + 1, UPSHIFT_W_OUT, g);
    ts_transmission_roots(&tr, &st, 1.1 + 0.7 * tr.shift_time, rearm - 1, UPSHIFT_W_OUT, h);
    assert_true(g[1] > 0 && h[1] < 0);
    assert_int_equal(
        ts_transmission_update(&tr, &st, 1.1 + 0.7 * tr.shift_time, rearm - 1, UPSHIFT_W_OUT, 0),
        1);
    assert_int_equal(st.armed, 1);
    assert_int_equal(st.target, 2); /* the shift itself goes on */
    assert_int_equal(
        ts_transmission_update(&tr, &st, 1.1 + tr.shift_time, w_hi - 1, UPSHIFT_W_OUT, 0), 1);
    assert_int_equal(st.gear, 2);
    assert_int_equal(st.shifts, 1);
    /* armed: the engine climbing back to shift_speed starts 2-3 at once */
    assert_int_equal(
        ts_transmission_update(&tr, &st, 1.2 + tr.shift_time, w_hi + 1, UPSHIFT_W_OUT, 3000), 1);
    assert_int_equal(st.target, 3);
    ts_transmission_reset(&tr, &st, 2);
    /* downshift when the engine lugs below downshift_speed on a slow vehicle
     * (1st gear would turn the turbine at 0.9 downshift_speed) */
    double w_slow = 0.9 * tr.downshift_speed / tr.ratio[0];
    ts_transmission_roots(&tr, &st, 3.0, 1.1 * tr.downshift_speed, w_slow, g);
    ts_transmission_roots(&tr, &st, 3.0, 0.9 * tr.downshift_speed, w_slow, h);
    assert_true(g[1] > 0 && h[1] < 0);
    assert_int_equal(ts_transmission_update(&tr, &st, 3.0, 0.9 * tr.downshift_speed, w_slow, 1000),
                     1);
    assert_int_equal(st.target, 1);
    /* not when the engine falls there because the rack dropped at speed: 1st
     * gear would turn the turbine at 1.1 downshift_speed (no root either;
     * tests/sim/test_coupled.c ivs_cruise_does_not_hunt_gears) */
    ts_transmission_reset(&tr, &st, 2);
    double w_fast = 1.1 * tr.downshift_speed / tr.ratio[0];
    ts_transmission_roots(&tr, &st, 3.0, 0.5 * tr.downshift_speed, w_fast, h);
    assert_true(h[1] > 0);
    assert_int_equal(ts_transmission_update(&tr, &st, 3.0, 0.5 * tr.downshift_speed, w_fast, 1000),
                     0);
    assert_int_equal(st.target, 0);
    /* top gear: no upshift root */
    ts_transmission_reset(&tr, &st, tr.n);
    ts_transmission_roots(&tr, &st, 0, 3000 * RPM, UPSHIFT_W_OUT, g);
    assert_true(g[0] > 0);
    assert_int_equal(ts_transmission_update(&tr, &st, 0, 3000 * RPM, UPSHIFT_W_OUT, 1000), 0);
}

/* EVIDENCE: shift-end handover (issue: on-coming clutch slammed shut at full
 * capacity while slipping): the engaged clutch's capacity is continuous at the
 * end of the shift interval (Cs just before and just after, tol 1e-9) and
 * rises linearly from Cs to clutch_capacity over one more shift_time, reached
 * at the ramp-end root, where the discrete update marks it fully applied; a
 * clutch still slipping at the shift end transmits about Cs, not
 * clutch_capacity. Closed form of the law, nothing calibrated. */
static void shift_end_capacity_ramps(void **state)
{
    (void)state;
    ts_shift_state st;
    ts_transmission tr = box_in_gear(1, &st);
    assert_close(ts_transmission_applied_capacity(&tr, &st, 0.0), tr.clutch_capacity, 0, 0);
    double t0 = 2.0, dt = tr.shift_time, t_in = 4000;
    assert_int_equal(ts_transmission_update(&tr, &st, t0, tr.shift_speed + 1, UPSHIFT_W_OUT, t_in),
                     1);
    double cs = st.capacity, w_out = 40.0;
    assert_close(cs, tr.shift_capacity_factor * t_in, 1e-12, 0);
    double r2 = tr.ratio[1], w_slip = r2 * w_out + 30.0; /* on-coming still slipping */
    ts_tr_point p;
    ts_transmission_eval(&tr, &st, t0 + dt * (1 - 1e-9), w_slip, w_out, &p);
    double before = p.input_torque;
    assert_int_equal(ts_transmission_update(&tr, &st, t0 + dt, tr.shift_speed, UPSHIFT_W_OUT, 0),
                     1);
    assert_int_equal(st.gear, 2);
    ts_transmission_eval(&tr, &st, t0 + dt, w_slip, w_out, &p);
    assert_close(p.input_torque, before, 1e-6, 0);
    assert_close(p.input_torque, cs, 1e-6, 0);
    assert_close(ts_transmission_applied_capacity(&tr, &st, t0 + 1.5 * dt),
                 0.5 * (cs + tr.clutch_capacity), 1e-12, 0);
    double te = t0 + 2 * dt;
    double g[TS_TRANSMISSION_NROOTS], h[TS_TRANSMISSION_NROOTS];
    ts_transmission_roots(&tr, &st, te - 1e-3, tr.shift_speed, UPSHIFT_W_OUT, g);
    ts_transmission_roots(&tr, &st, te + 1e-3, tr.shift_speed, UPSHIFT_W_OUT, h);
    assert_true(g[3] > 0 && h[3] < 0);
    assert_close(ts_transmission_applied_capacity(&tr, &st, te - 1e-3),
                 tr.clutch_capacity - (tr.clutch_capacity - cs) * 1e-3 / dt, 1e-9, 0);
    assert_int_equal(ts_transmission_update(&tr, &st, te, tr.shift_speed - 1, UPSHIFT_W_OUT, 0), 1);
    assert_close(st.capacity, 0, 0, 0);
    assert_close(ts_transmission_applied_capacity(&tr, &st, te + 1.0), tr.clutch_capacity, 0, 0);
    ts_transmission_roots(&tr, &st, te + 1.0, tr.shift_speed, UPSHIFT_W_OUT, h);
    assert_true(h[3] > 0);
}

/* Table validation names the field; a converter table may not create power
 * (TR SR <= 1 everywhere, with the interpolation of torque_converter.c). */
static void tables_are_validated(void **state)
{
    (void)state;
    ts_config c = defaults();
    ts_torque_converter tc;
    ts_transmission tr;
    ts_err err;
    c.driveline.tc_torque_ratio_n--;
    assert_int_equal(ts_torque_converter_init(&tc, &c.driveline, &err), TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/driveline/tc_torque_ratio");
    c = defaults();
    c.driveline.tc_speed_ratio[3] = 0.1;
    assert_int_equal(ts_torque_converter_init(&tc, &c.driveline, &err), TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/driveline/tc_speed_ratio");
    /* a table that gives more power than it takes is refused: TR 1.2 at SR
     * 0.9 (efficiency 1.08; it was accepted until session 20), a last row
     * (the coupling range, held to SR 1) other than 1, or a segment whose
     * parabola TR(SR) SR peaks above 1 between rows whose own products do not
     * (rows 0.6 / 1.66 and 0.99 / 1.0: 0.996 and 0.99, top 1.057 at SR 0.79) */
    c = defaults();
    c.driveline.tc_torque_ratio[7] = 1.2;
    assert_int_equal(ts_torque_converter_init(&tc, &c.driveline, &err), TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/driveline/tc_torque_ratio");
    c = defaults();
    c.driveline.tc_torque_ratio[8] = 1.02;
    assert_int_equal(ts_torque_converter_init(&tc, &c.driveline, &err), TS_ERR_PARAM);
    assert_non_null(strstr(err.msg, "must be 1 (coupling range)"));
    c = defaults();
    c.driveline.tc_speed_ratio_n = c.driveline.tc_torque_ratio_n = c.driveline.tc_k_factor_n = 3;
    const double sr3[3] = {0.0, 0.6, 0.99}, tr3[3] = {2.0, 1.66, 1.0};
    for (int i = 0; i < 3; i++) {
        c.driveline.tc_speed_ratio[i] = sr3[i];
        c.driveline.tc_torque_ratio[i] = tr3[i];
        c.driveline.tc_k_factor[i] = 3.0;
    }
    assert_int_equal(ts_torque_converter_init(&tc, &c.driveline, &err), TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/driveline/tc_torque_ratio");
    c = defaults();
    c.driveline.gear_efficiency_n = 3;
    assert_int_equal(ts_transmission_init(&tr, &c.driveline, &err), TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/driveline/gear_efficiency");
    c = defaults();
    c.driveline.gear_ratio[2] = 2.5;
    assert_int_equal(ts_transmission_init(&tr, &c.driveline, &err), TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/driveline/gear_ratio");
    /* ratios must strictly decrease: two gears of one ratio make an upshift
     * that changes nothing, and the engine, still at shift_speed, starts the
     * next one (mutation pass ctl: `<=` passed) */
    c = defaults();
    c.driveline.gear_ratio[2] = c.driveline.gear_ratio[1];
    assert_int_equal(ts_transmission_init(&tr, &c.driveline, &err), TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/driveline/gear_ratio");
    /* a downshift speed at the upshift speed (or above) would downshift as soon
     * as an upshift pulls the engine down: refused (transmission.c; the
     * check's removal passed every test) */
    c = defaults();
    c.driveline.downshift_speed = c.driveline.shift_speed;
    assert_int_equal(ts_transmission_init(&tr, &c.driveline, &err), TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/driveline/downshift_speed");
    c.driveline.downshift_speed = 0; /* 0: never downshift, whatever shift_speed */
    assert_int_equal(ts_transmission_init(&tr, &c.driveline, &err), TS_OK);
}

/* EVIDENCE: transmission.h shift logic: a shift that ends with the engine
 * still above shift_speed - shift_hysteresis leaves the upshift disarmed; it
 * re-arms when the engine falls to that speed (a sign change of root g0 at
 * shift_speed - hysteresis, not at shift_speed) or, failing that, when
 * shift_dwell has passed since the shift ENDED (root g2 at t0 + shift_time +
 * shift_dwell), and an engine still at shift_speed then shifts at once. Logic
 * check (defaults: shift_time 0.6 s, dwell 2 s, hysteresis 50 rpm), nothing
 * calibrated. Mutation pass ctl: a g0 root at shift_speed (the re-arm fall
 * missed until the dwell: the next upshift up to 2 s late) and a dwell counted
 * from the shift START passed every test. */
static void upshift_rearms_after_the_shift(void **state)
{
    (void)state;
    ts_shift_state st;
    ts_transmission tr = box_in_gear(1, &st);
    const double t0 = 1.0, dt = tr.shift_time, w_hi = tr.shift_speed + 1;
    const double te = t0 + dt, rearm = tr.shift_speed - tr.shift_hysteresis;
    assert_int_equal(ts_transmission_update(&tr, &st, t0, w_hi, UPSHIFT_W_OUT, 3000), 1);
    assert_int_equal(ts_transmission_update(&tr, &st, te, w_hi, UPSHIFT_W_OUT, 3000), 1);
    assert_int_equal(st.gear, 2);
    assert_int_equal(st.target, 0);
    assert_int_equal(st.armed, 0); /* the engine never dipped to the re-arm speed */
    double g[TS_TRANSMISSION_NROOTS], h[TS_TRANSMISSION_NROOTS];
    /* the fall to the re-arm speed is a root of g0 ... */
    ts_transmission_roots(&tr, &st, te + 0.1, rearm + 1, UPSHIFT_W_OUT, g);
    ts_transmission_roots(&tr, &st, te + 0.1, rearm - 1, UPSHIFT_W_OUT, h);
    assert_true(g[0] > 0 && h[0] < 0);
    /* ... and the crossing of shift_speed itself is not */
    ts_transmission_roots(&tr, &st, te + 0.1, tr.shift_speed + 1, UPSHIFT_W_OUT, g);
    ts_transmission_roots(&tr, &st, te + 0.1, tr.shift_speed - 1, UPSHIFT_W_OUT, h);
    assert_true(g[0] > 0 && h[0] > 0);
    /* the dwell runs from the end of the shift */
    ts_transmission_roots(&tr, &st, te + tr.shift_dwell - 1e-3, w_hi, UPSHIFT_W_OUT, g);
    ts_transmission_roots(&tr, &st, te + tr.shift_dwell + 1e-3, w_hi, UPSHIFT_W_OUT, h);
    assert_true(g[2] > 0 && h[2] < 0);
    /* shift_dwell after the START of the shift (0.6 s before its end): still
     * disarmed (the update only ends the post-shift capacity ramp, due at t0 + 2 dt) */
    ts_transmission_update(&tr, &st, t0 + tr.shift_dwell + 1e-3, w_hi, UPSHIFT_W_OUT, 3000);
    assert_int_equal(st.armed, 0);
    assert_int_equal(st.target, 0);
    /* at the dwell's end it re-arms and, the engine above shift_speed, shifts 2-3 */
    assert_int_equal(
        ts_transmission_update(&tr, &st, te + tr.shift_dwell, w_hi, UPSHIFT_W_OUT, 3000), 1);
    assert_int_equal(st.target, 3);
}

/* EVIDENCE: transmission.h: the shift clutches' peak capacity is Cs =
 * shift_capacity_factor x |input torque at the shift start|, floored at
 * shift_capacity_floor x clutch_capacity (1.5 and 5 % of 40 kN*m [E]).
 * A 2-1 downshift begun with the vehicle driving the engine (input torque
 * -4 kN*m) gets 1.5 x 4 = 6 kN*m; an upshift begun at zero input torque gets
 * the floor, 0.05 x 40 = 2 kN*m. Closed form of the law (1e-12). Mutation
 * pass ctl: Cs from the signed torque (the downshift's clutches at the floor)
 * and a floor of 0.05 N*m (a clutch that cannot lock in the shift interval)
 * passed every test. */
static void shift_capacity_law(void **state)
{
    (void)state;
    ts_shift_state st;
    ts_transmission tr = box_in_gear(2, &st);
    double w_slow = 0.9 * tr.downshift_speed / tr.ratio[0];
    assert_int_equal(
        ts_transmission_update(&tr, &st, 3.0, 0.9 * tr.downshift_speed, w_slow, -4000.0), 1);
    assert_int_equal(st.target, 1);
    assert_close(st.capacity, tr.shift_capacity_factor * 4000.0, 1e-12, 0);
    assert_close(st.capacity, 6000.0, 1e-12, 0);
    ts_transmission_reset(&tr, &st, 1);
    assert_int_equal(ts_transmission_update(&tr, &st, 3.0, tr.shift_speed + 1, UPSHIFT_W_OUT, 0.0),
                     1);
    assert_int_equal(st.target, 2);
    assert_close(st.capacity, tr.shift_capacity_floor * tr.clutch_capacity, 1e-12, 0);
    assert_close(st.capacity, 2000.0, 1e-12, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(converter_torque_balance_and_efficiency),
        cmocka_unit_test(converter_stall_torque_ratio),
        cmocka_unit_test(converter_over_running),
        cmocka_unit_test(gears_conserve_power_with_efficiency),
        cmocka_unit_test(shift_hands_torque_over_continuously),
        cmocka_unit_test(shift_events_as_roots),
        cmocka_unit_test(shift_end_capacity_ramps),
        cmocka_unit_test(tables_are_validated),
        cmocka_unit_test(upshift_rearms_after_the_shift),
        cmocka_unit_test(shift_capacity_law),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
