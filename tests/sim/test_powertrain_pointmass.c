/*
 * test_powertrain_pointmass.c — the point-mass M1 driven through the whole
 * powertrain (scenario "pointmass", /drive/kind "powertrain") with the real
 * engine: Fig. 19 behaviour in the series (launch with the crank-angle engine,
 * shortened to 2 s; the three upshifts with the map engine over the full
 * 20 s), Table 2 metrics from the series with the map engine, and the
 * prescribed-torque path still in place. The full crank-angle Table 2 runs
 * (about 15 s wall each) are in tests/bench/bench_pointmass.c and
 * docs/driveline.md.
 */
#include "test_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "api/config_json.h"
#include "api/session_json.h"
#include "sim/constants.h"
#include "sim/governor.h"
#include "sim/tanksim.h"
#include "preset_config.h"

#define RPM (3.14159265358979323846 / 30.0)

typedef struct {
    ts_model *m;
    ts_rows s;
    int nc;
    ts_metric *mt;
    int nm;
} run_result;

/* A preset's config with the given engine fidelity. */
static ts_config load(const char *preset, const char *fidelity)
{
    ts_config c;
    ts_err err;
    json_t *doc = json_pack("{s:s,s:{s:s}}", "preset", preset, "engine", "fidelity", fidelity);
    assert_int_equal(tsa_config_load(doc, &c, NULL, NULL, &err), TS_OK);
    json_decref(doc);
    return c;
}

/* Run a preset with the given engine fidelity for duration seconds. */
static run_result run_config(const ts_config *cfg)
{
    ts_err err;
    run_result r = {0};
    r.m = test_run_rows(cfg, &r.s);
    r.nc = ts_model_nchannel(r.m);
    if (tsa_model_metrics(r.m, r.s.v, r.s.n, &r.mt, &r.nm, &err) != TS_OK)
        fail_msg("metrics: %s", err.msg);
    return r;
}

static run_result run_preset(const char *preset, const char *fidelity, double duration)
{
    ts_config c = load(preset, fidelity);
    c.run.duration = duration;
    return run_config(&c);
}

static void done(run_result *r)
{
    ts_rows_free(&r->s);
    free(r->mt);
    ts_model_free(r->m);
}

static double at(const run_result *r, const char *ch, double t)
{
    int k = ts_model_channel_index(r->m, ch);
    assert_true(k >= 0);
    long i = (long)(t / ts_model_sample_period(r->m) + 0.5);
    assert_true(i >= 0 && i < r->s.n);
    return r->s.v[i * r->nc + k];
}

static double metric(const run_result *r, const char *name)
{
    for (int i = 0; i < r->nm; i++)
        if (!strcmp(r->mt[i].name, name)) return r->mt[i].value;
    fail_msg("no metric %s", name);
    return NAN;
}

/* Largest and smallest value of a channel over [t0, t1]. */
static void range(const run_result *r, const char *ch, double t0, double t1, double *lo,
                  double *hi)
{
    *lo = INFINITY;
    *hi = -INFINITY;
    for (double t = t0; t <= t1 + 1e-9; t += ts_model_sample_period(r->m)) {
        double v = at(r, ch, t);
        *lo = fmin(*lo, v);
        *hi = fmax(*hi, v);
    }
}

/* EVIDENCE: Fig. 19 launch [P III.C.1], crank-angle engine, conventional,
 * first 2 s (shortened; the full run is in the bench): "engine speed shows
 * hesitation during the first second ... until the engine is able to balance
 * the external load and eventually ... start accelerating again": the engine
 * speed rises at > 3x its slowest rate of the next second, then rises faster
 * again; "significant multiplication of engine torque is experienced at the
 * T/C turbine shaft" early on: TR > 2 at 0.5 s, > 1.5 at 1 s, turbine torque
 * > pump torque throughout. Qualitative shape, nothing calibrated to it. */
static void fig19_launch_hesitation_and_multiplication(void **state)
{
    (void)state;
    run_result r = run_preset("accel-pointmass-conventional", "crank_angle", 2.0);
    double dt = 0.1;
    double rate0 = (at(&r, "engine.speed", 0.3) - at(&r, "engine.speed", 0.0)) / 0.3;
    double slowest = INFINITY;
    for (double t = 0.5; t < 1.5 - 1e-9; t += dt)
        slowest = fmin(slowest, (at(&r, "engine.speed", t + dt) - at(&r, "engine.speed", t)) / dt);
    double late = (at(&r, "engine.speed", 2.0) - at(&r, "engine.speed", 1.6)) / 0.4;
    print_message("      engine speed rate: %.0f rpm/s at launch, %.0f slowest, %.0f at 1.6-2 s\n",
                  rate0 / RPM, slowest / RPM, late / RPM);
    assert_true(rate0 > 3 * slowest);
    assert_true(late > 2 * slowest);
    assert_true(at(&r, "tc.torque_ratio", 0.5) > 2.0);
    assert_true(at(&r, "tc.torque_ratio", 1.0) > 1.5);
    for (double t = 0.05; t <= 2.0; t += 0.05)
        assert_true(at(&r, "tc.turbine.torque", t) > at(&r, "tc.pump.torque", t));
    assert_close(at(&r, "transmission.gear", 2.0), 1, 0, 0);
    assert_true(at(&r, "vehicle.speed", 2.0) > 0);
    /* Fig. 21b's channel: the crank-angle engine's piston surface, above the
     * coolant from the idle start on */
    for (double t = 0.0; t <= 2.0; t += 0.5)
        assert_true(at(&r, "piston.surface_temperature", t) >
                    ts_model_config(r.m)->engine.coolant_temp + 10.0);
    /* in the order sessions stored before session 19 have (server/channels.c
     * matches stored channels by name and order) */
    int it = ts_model_channel_index(r.m, "turbo.speed");
    assert_int_equal(ts_model_channel_index(r.m, "piston.surface_temperature"), it + 1);
    assert_int_equal(ts_model_channel_index(r.m, "engine.fuel_flow"), it + 2);
    done(&r);
}

/* EVIDENCE: Fig. 19 shifts [P III.C.1], map engine (fast), 20 s: three
 * upshifts triggered at 1850 rpm (tol 0.5 %); "a sharp decrease of engine
 * speed is observed immediately after the shift" (engine falls > 100 rpm
 * below the shift speed within 1.2 s); "a saw tooth can be identified on the
 * T/C output torque" (turbine torque rises > 30 % above its value at the shift
 * start), "with reduced amplitude ... during the next two shifts" (3rd spike
 * < 1st); "transmission-in and -out angular velocities become the same in
 * fourth gear" (tol 0.6 %, the applied clutch's creep). Qualitative shape. */
static void fig19_three_upshifts_dip_and_sawtooth(void **state)
{
    (void)state;
    ts_config c = load("accel-pointmass-conventional", "map");
    c.run.duration = 20.0;
    run_result r = run_config(&c);
    /* the gear ramps linearly over shift_time, and "began" is the first
     * sample past the old gear: half-way is T/2 after it to one sample */
    double T = c.driveline.shift_time, dt = ts_model_sample_period(r.m);
    static const char *const names[] = {"shift_1_2_began_s", "shift_2_3_began_s",
                                        "shift_3_4_began_s"};
    double prev = 0, spike[3];
    for (int k = 0; k < 3; k++) {
        double ts = metric(&r, names[k]);
        assert_true(isfinite(ts) && ts > prev + 0.6);
        /* the same shift's half-way time, as the coupled runs also report it
         * (model.c ts_metric_add_upshifts): after the start, within the shift */
        char half[48];
        snprintf(half, sizeof half, "shift_%d_%d_half_s", k + 1, k + 2);
        double th = metric(&r, half);
        print_message(
            "      shift %d half done %.3f s after it began (T/2 %.3f s, sample %.3f s)\n", k + 1,
            th - ts, 0.5 * T, dt);
        assert_true(th - ts >= 0.5 * T - dt && th - ts <= 0.5 * T + dt);
        prev = ts;
        assert_close(at(&r, "engine.speed", ts) / RPM, 1850, 5e-3, 0);
        double lo, hi;
        range(&r, "engine.speed", ts + 0.6, ts + 1.2, &lo, &hi);
        assert_true(lo < (1850 - 100) * RPM);
        double t0 = at(&r, "tc.turbine.torque", ts);
        range(&r, "tc.turbine.torque", ts, ts + 1.0, &lo, &hi);
        spike[k] = hi / t0;
        print_message("      shift %d at %.2f s: turbine torque x%.2f\n", k + 1, ts, spike[k]);
        assert_true(spike[k] > 1.3);
    }
    assert_true(spike[2] < spike[0]);
    assert_close(at(&r, "transmission.gear", 20.0), 4, 0, 0);
    assert_close(at(&r, "tc.turbine.speed", 20.0), at(&r, "transmission.out.speed", 20.0), 6e-3, 0);
    done(&r);
}

/* EVIDENCE: Table 2 [P], conventional engine, here with the MAP engine (the
 * crank-angle runs are in bench_pointmass). CALIBRATION CONSISTENCY, not a
 * prediction: the speed after 20 s, 65.67 km/h within 5 %, is the figure the
 * presets' constant rolling resistance and the final ratio 3.07 (scaled from
 * a point-mass estimate that reaches 65.7 km/h, docs/driveline.md) were chosen
 * against. The predictions checked are the shape of the launch: 0-60 km/h
 * 17.2 s and 20-60 km/h 13.2 s within 10 %. The metrics are computed from the
 * series. */
static void table2_conventional_map_engine(void **state)
{
    (void)state;
    run_result r = run_preset("accel-pointmass-conventional", "map", 20.0);
    print_message("      map engine: %.2f km/h, 0-60 %.2f s, 20-60 %.2f s\n",
                  metric(&r, "speed_at_20s_kmh"), metric(&r, "t_0_60_kmh_s"),
                  metric(&r, "t_20_60_kmh_s"));
    assert_close(metric(&r, "speed_at_20s_kmh"), 65.67, 0.05, 0);
    assert_close(metric(&r, "t_0_60_kmh_s"), 17.2, 0.10, 0);
    assert_close(metric(&r, "t_20_60_kmh_s"), 13.2, 0.10, 0);
    /* the metric agrees with the series it came from */
    assert_close(metric(&r, "speed_at_20s_kmh"), 3.6 * at(&r, "vehicle.speed", 20.0), 1e-9, 0);
    /* the map engine has no manifolds or turbochargers: no exhaust temperature
     * or turbo speed channel (they read 0 K and 0 rad/s until session 22) */
    assert_int_equal(ts_model_channel_index(r.m, "exhaust.temperature"), -1);
    assert_int_equal(ts_model_channel_index(r.m, "turbo.speed"), -1);
    assert_int_equal(ts_model_channel_index(r.m, "engine.fuel_flow"),
                     ts_model_channel_index(r.m, "driveshaft.speed") + 1);
    done(&r);
}

/* EVIDENCE: energy conservation through the driveline [P III.B.2], the
 * mean-value engine's Table 2 launch (20 s, sampled at 10 kHz). At every
 * sample each element's loss power is >= 0: converter T_p w_e - T_t w_t,
 * gearbox (clutch torques) w_t - T_out w_out, final drive T_out w_out -
 * 2 T_s w_s; and the road's is exactly the resistance's power, 2 T_s w_s -
 * M_eff a v = v (m g f_r(v) tanh(v / v_eps) + 1/2 rho CdA v |v|) on flat
 * ground (scenario_pointmass.c), to 1e-6 of the sprocket power, with M_eff =
 * rotating_mass_factor m + (J_out - 2 J_sprocket) / r_s^2: the sprockets are
 * in the factor (counted twice until session 21, 178 kg too much, which this
 * equality refuses). Over the run the turbine shaft's work equals its kinetic
 * energy, int (T_t - T_in) w_t dt = J_t (w_t(20)^2 - w_t(0)^2) / 2, within
 * 1 % of its 14.7-kJ kinetic energy (trapezoids at 10 kHz across the shifts:
 * measured 0.27 %; at 1 kHz the quadrature alone moved it 0.4-1.0 %), and the
 * vehicle's int M_eff a v dt = M_eff v(20)^2 / 2 within 1e-4 of its 10.5 MJ. A
 * wrong efficiency direction or a both-sides torque reported per side breaks
 * a loss sign; a turbine inertia 10 % off breaks the shaft balance. Closed
 * form, nothing calibrated. The channel set: the rack through the
 * two-speed governor, 3 DOF, no piston channel for an engine without walls. */
static void pointmass_driveline_conserves_energy(void **state)
{
    (void)state;
    ts_config cfg = load("accel-pointmass-conventional", "mean_value");
    cfg.run.duration = 20.0;
    cfg.run.sample_rate = 10000.0;
    run_result r = run_config(&cfg);
    const ts_config *c = ts_model_config(r.m);
    const char *names[] = {"engine.speed",
                           "tc.pump.torque",
                           "tc.turbine.speed",
                           "tc.turbine.torque",
                           "transmission.clutch.offgoing",
                           "transmission.clutch.oncoming",
                           "transmission.out.speed",
                           "transmission.out.torque",
                           "sprocket.torque",
                           "sprocket.speed",
                           "vehicle.speed",
                           "vehicle.accel"};
    enum { WE, TP, WT, TT, COFF, CON, WO, TO, TS, WS, V, A, NCH };
    int col[NCH];
    for (int k = 0; k < NCH; k++) {
        col[k] = ts_model_channel_index(r.m, names[k]);
        assert_true(col[k] >= 0);
    }
    double r_s = c->vehicle.sprocket_radius, jt = c->driveline.turbine_inertia;
    /* the sprockets are in rotating_mass_factor; the output inertia adds the
     * rest of the driveline's (scenario_pointmass.c) */
    double m_eff = c->vehicle.rotating_mass_factor * c->vehicle.mass +
                   (c->driveline.output_inertia - 2 * c->vehicle.sprocket_inertia) / (r_s * r_s);
    double dt = ts_model_sample_period(r.m), shaft = 0, road = 0, through = 0, prev[3] = {0};
    long n = r.s.n;
    assert_true(n == 200001);
    const ts_vehicle_config *vc = &c->vehicle;
    for (long i = 0; i < n; i++) {
        const double *x = r.s.v + i * r.nc;
        double p_pump = x[col[TP]] * x[col[WE]], p_turb = x[col[TT]] * x[col[WT]];
        double p_in = (x[col[COFF]] + x[col[CON]]) * x[col[WT]], p_out = x[col[TO]] * x[col[WO]];
        double p_sp = 2 * x[col[TS]] * x[col[WS]], p_kin = m_eff * x[col[A]] * x[col[V]];
        double tol = 1e-9 * fabs(p_pump) + 1e-6;
        assert_true(p_pump - p_turb >= -tol);
        assert_true(p_in - p_out >= -tol);
        assert_true(p_out - p_sp >= -tol);
        double v = x[col[V]];
        double resist = vc->mass * TS_GRAVITY *
                            (vc->rolling_resistance + vc->rolling_resistance_speed * fabs(v)) *
                            tanh(v / vc->rolling_resistance_smoothing) +
                        0.5 * vc->air_density * vc->cda * v * fabs(v);
        assert_close(p_sp - p_kin, resist * v, 0, 1e-6 * fabs(p_sp) + 1e-6);
        double now[3] = {p_turb - p_in, p_kin, p_turb};
        if (i > 0) {
            shaft += 0.5 * dt * (now[0] + prev[0]);
            road += 0.5 * dt * (now[1] + prev[1]);
            through += 0.5 * dt * (now[2] + prev[2]);
        }
        memcpy(prev, now, sizeof prev);
    }
    const double *x0 = r.s.v, *x1 = r.s.v + (n - 1) * r.nc;
    double ke_t = 0.5 * jt * (x1[col[WT]] * x1[col[WT]] - x0[col[WT]] * x0[col[WT]]);
    double ke_v = 0.5 * m_eff * (x1[col[V]] * x1[col[V]] - x0[col[V]] * x0[col[V]]);
    print_message("turbine shaft: work %.1f J, kinetic energy %.1f J; vehicle: %.7e J vs %.7e J; "
                  "turbine throughput %.4e J\n",
                  shaft, ke_t, road, ke_v, through);
    assert_true(through > 1e7);
    assert_close(shaft, ke_t, 0.01, 0);
    assert_close(road, ke_v, 1e-4, 0);
    assert_true(at(&r, "intake.pressure", 20.0) > 1.5e5);
    /* the rack the engine sees: the full rack through the two-speed governor
     * (on in the preset; the run passes high idle, where it cuts the rack) */
    ts_governor g;
    assert_int_equal(ts_governor_of_config(&c->control, &g, NULL), TS_OK);
    assert_true(g.on);
    for (double t = 0.5; t <= 20.0; t += 0.5)
        assert_close(at(&r, "rack", t), ts_governor_rack(&g, 1.0, at(&r, "engine.speed", t)), 0,
                     1e-15);
    assert_close(at(&r, "rack", 2.0), 1.0, 0, 0); /* below high idle: the rack as set */
    assert_int_equal(ts_model_dof(r.m), 3);
    /* the mean-value engine has no wall state: no piston channel (it read 0 K) */
    assert_int_equal(ts_model_channel_index(r.m, "piston.surface_temperature"), -1);
    assert_int_equal(ts_model_channel_index(r.m, "engine.fuel_flow"),
                     ts_model_channel_index(r.m, "turbo.speed") + 1);
    done(&r);
}

/* EVIDENCE: Newton's second law of the point mass (scenario_pointmass.c):
 * 2 T_s / r_s - R(v) = M a, R(v) = m g f_r(v) tanh(v / v_eps) + 1/2 rho CdA
 * v |v| on flat ground, M = rotating_mass_factor m + max(0, J_out - 2 J_s) /
 * r_s^2: /driveline/output_inertia holds both sprockets, which the factor
 * already counts, so an output inertia below the two sprockets' (10 against
 * 2 x 8 kg m^2) adds nothing and takes nothing off (the multibody model keeps
 * the larger of the two likewise, coupled_system.c). Map engine, 2-s launch,
 * every sample to 1e-6 of the thrust. Mutation pass ctl: a negative
 * remainder subtracted from the mass passed. */
static void light_driveline_takes_no_mass_off(void **state)
{
    (void)state;
    ts_config c = load("accel-pointmass-conventional", "map");
    c.run.duration = 2.0;
    c.driveline.output_inertia = 10.0;
    const ts_vehicle_config *vc = &c.vehicle;
    assert_true(c.driveline.output_inertia < 2 * vc->sprocket_inertia);
    run_result r = run_config(&c);
    int kt = ts_model_channel_index(r.m, "sprocket.torque"),
        kv = ts_model_channel_index(r.m, "vehicle.speed"),
        ka = ts_model_channel_index(r.m, "vehicle.accel");
    assert_true(kt >= 0 && kv >= 0 && ka >= 0);
    double m_eff = vc->rotating_mass_factor * vc->mass, a_max = 0;
    for (long i = 0; i < r.s.n; i++) {
        const double *x = r.s.v + i * r.nc;
        double v = x[kv], thrust = 2 * x[kt] / vc->sprocket_radius;
        double resist = vc->mass * TS_GRAVITY *
                            (vc->rolling_resistance + vc->rolling_resistance_speed * fabs(v)) *
                            tanh(v / vc->rolling_resistance_smoothing) +
                        0.5 * vc->air_density * vc->cda * v * fabs(v);
        assert_close(thrust - resist, m_eff * x[ka], 0, 1e-6 * fabs(thrust) + 1e-6);
        a_max = fmax(a_max, x[ka]);
    }
    assert_true(a_max > 0.5); /* a launch, not a standstill */
    done(&r);
}

/* Highest engine speed [rad/s] and end speed [m/s] of the mean-value
 * LHR 1.0 mm Table 2 run with the governor on or off. */
static void top_speeds(int governor, double *w_max, double *v_end)
{
    ts_config c = load("accel-pointmass-lhr10", "mean_value");
    c.control.governor = governor;
    run_result r = run_config(&c);
    int kw = ts_model_channel_index(r.m, "engine.speed");
    assert_true(kw >= 0);
    *w_max = 0;
    for (long i = 0; i < r.s.n; i++)
        *w_max = fmax(*w_max, r.s.v[(size_t)i * (size_t)r.nc + (size_t)kw]);
    *v_end = at(&r, "vehicle.speed", c.run.duration);
    done(&r);
}

/* EVIDENCE: paper IV.B.2, "the two-speed governor function of the actuator
 * prevents the engine from overspeeding": in the Table 2 run (full rack, 20 s,
 * LHR 1.0 mm, mean-value engine) the governor (/control/governor, on by
 * default) keeps the engine below the speed where it cuts all fuel (high idle
 * + band); switched off, the engine runs past high idle. Table 2's speeds at
 * 20 s (65.67 / 66.29 / 66.43 km/h) lie within 1.2 % of each other, as a
 * governed top speed would. Before session 17 the point-mass run ignored the
 * setting. */
static void governor_holds_the_engine_below_its_cut(void **state)
{
    (void)state;
    ts_config c = load("accel-pointmass-lhr10", "mean_value");
    double cut = c.control.governor_high_idle + c.control.governor_high_band;
    double w_on, v_on, w_off, v_off;
    top_speeds(1, &w_on, &v_on);
    top_speeds(0, &w_off, &v_off);
    printf("      governor on: engine max %.1f rpm, %.2f km/h; off: %.1f rpm, %.2f km/h (cut at "
           "%.1f rpm)\n",
           w_on / RPM, v_on * 3.6, w_off / RPM, v_off * 3.6, cut / RPM);
    assert_true(w_on < cut);
    assert_true(w_off > c.control.governor_high_idle);
    assert_true(w_off > w_on && v_off > v_on);
    /* a governor that cannot work is refused in this run kind too */
    c.control.governor_high_idle = c.control.governor_low_idle;
    ts_err err;
    assert_null(ts_model_make(&c, &err));
    assert_int_equal(err.code, TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/control/governor_high_idle");
}

/* EVIDENCE: paper IV.B.2, the governor's other half, "prevents the engine
 * from stalling": with the driver's rack at 0 from the idle start (650 rpm,
 * the converter at stall loading it with (w/K0)^2 ~ 0.8 kN*m) the governor
 * adds fuel below low idle and gives full rack at low idle - low band (550
 * rpm), where the engine's full-rack torque far exceeds the converter's 0.57
 * kN*m: the engine speed cannot fall below 550 rpm, while the rack the engine
 * sees rises above 0. Both integration paths: the crank-angle engine
 * co-simulated (the governor applied per macro step) and the mean-value
 * engine in CVODE, 0.5 s each. Bound from the governor law; nothing
 * calibrated. Mutation pass ctl: the co-simulated path with the governor
 * bypassed passed every test (the launches run at full rack, between the
 * idles). */
static void governor_keeps_a_zero_rack_engine_from_stalling(void **state)
{
    (void)state;
    const char *fid[2] = {"crank_angle", "mean_value"};
    for (int k = 0; k < 2; k++) {
        ts_config c = load("accel-pointmass-conventional", fid[k]);
        c.control.rack = 0.0;
        c.run.duration = 0.5;
        run_result r = run_config(&c);
        double w_lo, w_hi, rack_lo, rack_hi;
        range(&r, "engine.speed", 0.0, 0.5, &w_lo, &w_hi);
        range(&r, "rack", 0.0, 0.5, &rack_lo, &rack_hi);
        print_message("      %s, rack 0: engine %.0f-%.0f rpm, governed rack up to %.2f\n", fid[k],
                      w_lo / RPM, w_hi / RPM, rack_hi);
        assert_true(w_lo > c.control.governor_low_idle - c.control.governor_low_band);
        assert_true(rack_hi > 0.05);
        done(&r);
    }
}

/* EVIDENCE: a saved state (continuous states + gear/shift state) restores
 * the run: map engine, saved at 5 s (between the 2nd and 3rd shift),
 * continued to 12 s twice; speed and gear agree (tol 1e-5, 10 x the run's
 * rtol: restore re-initialises CVODE, whose error control then takes
 * different steps; 2.6e-6 seen with the issue-5 engine maps, 1e-6 was
 * passed before by a margin smaller than rtol). Consistency check. */
static void save_restore_mid_run(void **state)
{
    (void)state;
    ts_config c = load("accel-pointmass-conventional", "map");
    ts_err err;
    ts_model *m = ts_model_make(&c, &err);
    ts_data *d = ts_data_make(m, &err);
    assert_int_equal(ts_reset(m, d, &err), TS_OK);
    assert_int_equal(ts_advance(m, d, 5.0, NULL, NULL, &err), TS_OK);
    size_t n = ts_state_size(m);
    void *buf = malloc(n);
    assert_int_equal(ts_state_save(m, d, buf, n, &err), TS_OK);
    int iv = ts_model_channel_index(m, "vehicle.speed"), ig = ts_model_channel_index(m, "transmission.gear");
    assert_int_equal(ts_advance(m, d, 12.0, NULL, NULL, &err), TS_OK);
    double v1 = ts_latest(d)[iv], g1 = ts_latest(d)[ig];
    assert_int_equal(ts_state_restore(m, d, buf, n, &err), TS_OK);
    assert_close(ts_time(d), 5.0, 1e-12, 0);
    assert_int_equal(ts_advance(m, d, 12.0, NULL, NULL, &err), TS_OK);
    assert_close(ts_latest(d)[iv], v1, 1e-5, 0);
    assert_close(ts_latest(d)[ig], g1, 0, 0);
    assert_close(g1, 4, 0, 0);
    free(buf);
    ts_data_free(d);
    ts_model_free(m);
}

/* Crank-speed derivative at y (sprocket at rest) for the rack. */
static double crank_rate(const ts_powertrain *pt, const ts_powertrain_state *ps, const double *y,
                         double rack, double *ydot)
{
    assert_int_equal(ts_powertrain_rhs(pt, ps, 0.0, y, 0.0, rack, ydot, NULL), 0);
    return ydot[ts_powertrain_engine_speed_index(pt)];
}

/* Largest |dy_i/dt| / scale_i over the engine's states at the rack that holds
 * the crank speed (bisection), the sprocket at rest. */
static double slowest_drift(const ts_powertrain *pt, const ts_powertrain_state *ps,
                            const double *y)
{
    int n = ts_powertrain_nstate(pt);
    double *ydot = calloc((size_t)n, sizeof *ydot), *scale = calloc((size_t)n, sizeof *scale);
    assert_true(ydot && scale);
    ts_powertrain_scale(pt, scale);
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 60; it++) {
        double mid = 0.5 * (lo + hi);
        if (crank_rate(pt, ps, y, mid, ydot) < 0) lo = mid;
        else hi = mid;
    }
    crank_rate(pt, ps, y, 0.5 * (lo + hi), ydot);
    double worst = 0;
    for (int i = 0; i < n - 1; i++) /* engine states; the turbine (last) is held by its clutch */
        if (i != ts_powertrain_engine_speed_index(pt) && fabs(ydot[i]) / scale[i] > worst)
            worst = fabs(ydot[i]) / scale[i];
    free(ydot);
    free(scale);
    return worst;
}

/* EVIDENCE: definition of the launch start (powertrain.h
 * ts_powertrain_idle_start): the reset state is (near) a steady point of the
 * powertrain's own ODE at /driveline/launch_engine_speed with the converter at
 * stall. Measure: at the rack that holds the crank speed, the largest drift
 * of the other engine states per second relative to their scale
 * (ts_powertrain_scale). The idle start must drift at least 10 times less than
 * the cold start of ts_engine_init_state (measured 0.22 vs 5.8 /s with the
 * mean-value LHR engine; not 0, since the search stops at 40 cycles, 0.2 % per
 * cycle and torque within 2 %, and the fast manifold states answer the
 * instantaneous rack). Not calibrated. */
static void idle_start_is_steady_at_stall(void **state)
{
    (void)state;
    ts_config c = load("accel-pointmass-lhr10", "mean_value");
    ts_err err;
    ts_powertrain *pt = ts_powertrain_make(&c, &err);
    assert_non_null(pt);
    int n = ts_powertrain_nstate(pt);
    assert_true(n <= 64);
    double cold[64], idle[64];
    ts_powertrain_state ps;
    assert_int_equal(ts_powertrain_reset(pt, &ps, cold, 0.0, &err), TS_OK);
    assert_int_equal(ts_powertrain_idle_start(pt, &err), TS_OK);
    assert_int_equal(ts_powertrain_reset(pt, &ps, idle, 0.0, &err), TS_OK);
    int ie = ts_powertrain_engine_speed_index(pt);
    assert_close(idle[ie], c.driveline.launch_engine_speed, 0, 1e-12);
    assert_close(idle[n - 1], 0.0, 0, 0); /* turbine at rest with the vehicle */
    double d_cold = slowest_drift(pt, &ps, cold), d_idle = slowest_drift(pt, &ps, idle);
    print_message("      drift per second / scale: cold start %.3g, idle start %.3g\n", d_cold,
                  d_idle);
    assert_true(d_idle < 0.1 * d_cold);
    ts_powertrain_free(pt);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fig19_launch_hesitation_and_multiplication),
        cmocka_unit_test(fig19_three_upshifts_dip_and_sawtooth),
        cmocka_unit_test(table2_conventional_map_engine),
        cmocka_unit_test(pointmass_driveline_conserves_energy),
        cmocka_unit_test(governor_holds_the_engine_below_its_cut),
        cmocka_unit_test(governor_keeps_a_zero_rack_engine_from_stalling),
        cmocka_unit_test(light_driveline_takes_no_mass_off),
        cmocka_unit_test(save_restore_mid_run),
        cmocka_unit_test(idle_start_is_steady_at_stall),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
