/*
 * test_coupled.c — the integrated engine–vehicle system (coupled_system.h,
 * scenario "coupled"; paper Section IV): leading–following coupling against
 * the monolithic reference, the interface inertia, shift transients on the
 * track, the flat/bump upshift comparison, the IVS controller at launch,
 * save/restore, config checks. Short runs only; the paper runs (30 s, IVS
 * 80 s) are in docs/coupled.md (tools/coupled_runs.py: presets
 * flat-coupled-rack90, bump-coupled-*) and tests/bench/bench_coupled.c.
 */
#include "test_util.h"

#include <math.h>
#include <string.h>

#include "api/config_json.h"
#include "preset_config.h"
#include "sim/coupled_system.h"
#include "sim/governor.h"
#include "sim/tanksim.h"

#define MPH 0.44704

/* Sampled histories of one run. */
#define NMAX 4000
typedef struct hist {
    int n;
    double t[NMAX], w[NMAX], v[NMAX], tension[NMAX], gear[NMAX], defl[NMAX], rack[NMAX],
        engine[NMAX];
} hist;

/* A run of method made, reset and advanced to t_to; *cm its system (free both). */
static ts_coupled_run *started(const ts_config *c, int method, double t_to, ts_coupled **cm)
{
    ts_err err;
    *cm = ts_coupled_make(c, &err);
    assert_non_null(*cm);
    ts_coupled_run *r = ts_coupled_run_make(*cm, method, &err);
    assert_non_null(r);
    assert_int_equal(ts_coupled_run_reset(r, &err), TS_OK);
    assert_int_equal(ts_coupled_run_advance(r, t_to, &err), TS_OK);
    return r;
}

static ts_rc run(const ts_config *c, int method, double t_end, double dt, hist *h, ts_err *err)
{
    ts_coupled *cm = ts_coupled_make(c, err);
    assert_non_null(cm);
    ts_coupled_run *r = ts_coupled_run_make(cm, method, err);
    assert_non_null(r);
    ts_rc rc = ts_coupled_run_reset(r, err);
    int nq = vm_nq(ts_coupled_vehicle(cm));
    h->n = 0;
    ts_coupled_obs o;
    for (int k = 0; rc == TS_OK && k * dt <= t_end + 1e-9 && k < NMAX; k++) {
        if (k > 0) rc = ts_coupled_run_advance(r, k * dt, err);
        if (rc != TS_OK) break;
        assert_int_equal(ts_coupled_run_observe(r, &o, NULL), TS_OK);
        h->t[k] = o.t;
        h->w[k] = o.sprocket_speed;
        h->v[k] = o.y_vehicle[nq];
        h->tension[k] = o.diag.tension_end1[0];
        h->gear[k] = o.pt.gear;
        h->defl[k] = o.diag.span_mid_deflection[1];
        h->rack[k] = o.rack_demand;
        h->engine[k] = o.pt.engine_speed;
        h->n = k + 1;
    }
    ts_coupled_run_free(r);
    ts_coupled_free(cm);
    return rc;
}

static double rms_rel(const double *a, const double *b, int n)
{
    double e = 0, s = 0;
    for (int i = 0; i < n; i++) {
        e += (a[i] - b[i]) * (a[i] - b[i]);
        s += b[i] * b[i];
    }
    return sqrt(e / s);
}

static hist h_ref, h_a;

/* EVIDENCE: observed order of the explicit leading-following scheme (paper
 * Section IV.A: powertrain leads with a linear predictor of (omega, alpha),
 * the vehicle follows interpolating the torque samples) against the
 * monolithic solution of the SAME equations (one integrator over powertrain
 * + vehicle): 90 % rack launch on flat ground, static track, mean-value
 * engine, 0.6 s, rtol 1e-9 so that the coupling error dominates; macro steps
 * 2, 1, 0.5 ms, lead 2 h, outputs every 20 ms (outputs synchronise the two
 * sides, so they must be far apart for the scheme not to change with h).
 * Predicted: second order, p = log2(e(h)/e(h/2)) ~ 2 (measured 1.88, 1.83,
 * e = 3.9e-3, 1.06e-3, 3.0e-4; the scheme before the fixes in docs/coupled.md
 * gave ~0.8); the test
 * asserts p > 1.6 for both halvings and e(0.5 ms) < 5e-4. Nothing
 * calibrated. */
static void leading_following_is_second_order(void **state)
{
    (void)state;
    ts_config c = test_preset_config("flat-coupled-rack90", "static");
    c.run.rtol = 1e-9;
    c.run.atol = 1e-11;
    const double t_end = 0.6, dt = 0.02;
    ts_err err;
    assert_int_equal(run(&c, TS_COUPLING_MONOLITHIC, t_end, dt, &h_ref, &err), TS_OK);
    const double hs[3] = {0.002, 0.001, 0.0005};
    double e[3];
    for (int k = 0; k < 3; k++) {
        c.coupling.leader_step = c.coupling.follower_step = hs[k];
        c.coupling.lead = 2 * hs[k];
        c.coupling.predictor_order = 1;
        assert_int_equal(run(&c, TS_COUPLING_LEADING_FOLLOWING, t_end, dt, &h_a, &err), TS_OK);
        assert_int_equal(h_a.n, h_ref.n);
        e[k] = rms_rel(h_a.w, h_ref.w, h_ref.n);
    }
    double p1 = log2(e[0] / e[1]), p2 = log2(e[1] / e[2]);
    print_message("sprocket-speed RMS rel. error: 2 ms %.3e, 1 ms %.3e (p %.2f), 0.5 ms %.3e "
                  "(p %.2f)\n",
                  e[0], e[1], p1, e[2], p2);
    assert_true(p1 > 1.6);
    assert_true(p2 > 1.6);
    assert_true(e[2] < 5e-4);
    /* and the vehicle really moved: 90 % rack from rest */
    assert_true(h_ref.v[h_ref.n - 1] > 0.5);
}

/* EVIDENCE: the cost structure of leading-following (docs/coupled.md, Real-time
 * factors): the leader's CVODE is NOT restarted at each of the ~500 vehicle
 * reports of a 0.5-s launch (flat, 90 % rack, static track, mean-value
 * engine, preset tolerances, 1-ms steps; no shift yet), only at t = 0 (a
 * restart per report cost ~40 powertrain right-hand sides per exchange), and
 * the follower reuses its Jacobian (at most one per 100 steps; CVODE's
 * default re-evaluates every 51 steps, and each costs one right-hand side
 * per state). Counts, not timings; nothing calibrated. */
static void leader_not_restarted_follower_reuses_jacobian(void **state)
{
    (void)state;
    ts_config c = test_preset_config("flat-coupled-rack90", "static");
    ts_coupled *cm;
    ts_coupled_run *r = started(&c, TS_COUPLING_LEADING_FOLLOWING, 0.5, &cm);
    ts_coupled_stats st;
    ts_coupled_run_stats(r, &st);
    print_message("messages %ld, leader restarts %ld, leader steps %ld, follower steps %ld, "
                  "Jacobians %ld, rhs %ld\n",
                  st.exchanges, st.leader_inits, st.powertrain_steps, st.vehicle_steps,
                  st.vehicle_jacs, st.vehicle_rhs);
    assert_true(st.exchanges >= 999);
    assert_true(st.leader_inits >= 1 && st.leader_inits <= 2);
    assert_true(st.vehicle_steps > 0 && 100 * st.vehicle_jacs <= st.vehicle_steps);
    /* the same counters as the model API's integrator entries (model.h) */
    ts_integrator_stats is[TS_MAX_INTEGRATORS];
    assert_int_equal(ts_coupled_run_integrators(r, is, TS_MAX_INTEGRATORS), 2);
    assert_string_equal(is[0].name, "vehicle");
    assert_int_equal(is[0].steps, st.vehicle_steps);
    assert_int_equal(is[0].jac_evals, st.vehicle_jacs);
    assert_int_equal(is[0].err_test_fails, st.vehicle_err_fails);
    assert_string_equal(is[1].name, "powertrain");
    assert_int_equal(is[1].steps, st.powertrain_steps);
    assert_int_equal(is[1].lin_setups, st.powertrain_setups);
    assert_int_equal(ts_coupled_run_integrators(r, is, 1), 1);
    ts_coupled_run_free(r);
    ts_coupled_free(cm);
}

/* EVIDENCE: added-mass instability of explicit acceleration coupling
 * (coupled_system.h): in 1st gear the turbine inertia at each sprocket,
 * J_t (g_1 f)^2 / 2 = 64 kg m^2 [D from /driveline], exceeds the vehicle
 * sprocket's (20 kg m^2), so the plain exchange (/coupling/interface_inertia
 * 0) must either fail or stray far from the monolithic run, while the
 * stabilised one stays within 1 %. Predicted from the inertia ratio; nothing
 * calibrated. */
static void plain_exchange_is_unstable_interface_inertia_fixes_it(void **state)
{
    (void)state;
    ts_config c = test_preset_config("flat-coupled-rack90", "static");
    ts_err err;
    assert_int_equal(run(&c, TS_COUPLING_MONOLITHIC, 0.5, 0.01, &h_ref, &err), TS_OK);
    assert_int_equal(run(&c, TS_COUPLING_LEADING_FOLLOWING, 0.5, 0.01, &h_a, &err), TS_OK);
    double e_stab = rms_rel(h_a.w, h_ref.w, h_ref.n);
    c.coupling.interface_inertia = 0.0;
    ts_rc rc = run(&c, TS_COUPLING_LEADING_FOLLOWING, 0.5, 0.01, &h_a, &err);
    double e_plain = h_a.n == h_ref.n ? rms_rel(h_a.w, h_ref.w, h_ref.n) : INFINITY;
    print_message("stabilised error %.3e, plain exchange: rc %d, error %.3e\n", e_stab, rc,
                  e_plain);
    assert_true(e_stab < 1e-2);
    assert_true(rc != TS_OK || e_plain > 10 * e_stab);
}

/* EVIDENCE: paper Figs. 29-30 (Section IV.C): a gear shift shows as a spike in
 * the track tension and excites the transverse span vibration. Flat ground,
 * 90 % rack, coupled track (1 + 1 modes per span), leading-following; the
 * 1-2 shift ends at ~4.3 s. Predicted (not calibrated): within 0.3 s after
 * the end of the shift the rear-roller tension departs from its level just
 * before by more than 20 % of the static tension, and the peak-to-peak
 * transverse mid-span deflection of the upper span (rear roller -> front
 * roller) over 0.4 s is more than twice that over the 0.4 s before. */
static void shift_spikes_tension_and_excites_span(void **state)
{
    (void)state;
    ts_config c = test_preset_config("flat-coupled-rack90", NULL);
    ts_err err;
    assert_int_equal(run(&c, TS_COUPLING_LEADING_FOLLOWING, 4.6, 0.005, &h_a, &err), TS_OK);
    int ie = -1;
    for (int i = 1; i < h_a.n; i++)
        if (h_a.gear[i - 1] < 2.0 && h_a.gear[i] >= 2.0) {
            ie = i;
            break;
        }
    assert_true(ie > 0);
    double te = h_a.t[ie];
    print_message("1-2 shift ends at %.3f s\n", te);
    double before = 0, dmin0 = INFINITY, dmax0 = -INFINITY, dmin1 = INFINITY, dmax1 = -INFINITY,
           dev = 0;
    int nb = 0;
    for (int i = 0; i < h_a.n; i++) {
        double t = h_a.t[i];
        if (t >= te - 0.2 && t < te - 0.02) before += h_a.tension[i], nb++;
        if (t >= te - 0.42 && t < te - 0.02) {
            dmin0 = fmin(dmin0, h_a.defl[i]);
            dmax0 = fmax(dmax0, h_a.defl[i]);
        }
        if (t >= te && t < te + 0.4) {
            dmin1 = fmin(dmin1, h_a.defl[i]);
            dmax1 = fmax(dmax1, h_a.defl[i]);
        }
    }
    assert_true(nb > 0);
    before /= nb;
    for (int i = 0; i < h_a.n; i++)
        if (h_a.t[i] >= te && h_a.t[i] < te + 0.3) dev = fmax(dev, fabs(h_a.tension[i] - before));
    print_message(
        "tension before %.0f N, largest departure %.0f N; deflection p-p %.2f -> %.2f mm\n", before,
        dev, 1e3 * (dmax0 - dmin0), 1e3 * (dmax1 - dmin1));
    assert_true(dev > 0.2 * c.track.tension);
    assert_true(dmax1 - dmin1 > 2.0 * (dmax0 - dmin0));
}

/* EVIDENCE: paper Fig. 31 (Section IV.C): over the bump course at 90 % rack
 * "the second and third gear shifts are delayed" against flat ground, as the
 * obstacles take drive torque. Preset flat-coupled-rack90 (upshift at 1750
 * rpm, engine-speed triggered, [E]) on flat ground and on the bump course,
 * coupled track, leading-following, 10 s. Measured shift starts 3.70 / 5.41 /
 * 8.43 s flat and 3.70 / 5.87 / 9.28 s on bumps (8.69 s until session 21's
 * engine corrections: the 3-4 shift on the bumps waits for the engine to
 * reach 1750 rpm between bumps). The delay is conditional on the [E]
 * upshift speed: a sweep (12-s runs, shifts half done, session 21) gives it
 * for both shifts at 1750-1800 rpm, at 1850 rpm for the 2-3 shift by 0.08 s
 * only, and not for the 2-3 shift at 1650, 1700 and 1900 rpm (at 1700 the 3-4 shift even comes earlier on the bumps). Predicted: the 1-2 shift, still
 * on the flat run-in before the first bump, at the same time (within 0.05 s); the 2-3 and 3-4
 * shifts each at least 0.15 s later on bumps. */
static double shift_start(const hist *h, double gear)
{
    for (int i = 1; i < h->n; i++)
        if (h->gear[i - 1] <= gear && h->gear[i] > gear) return h->t[i - 1];
    return INFINITY;
}

static void bumps_delay_second_and_third_upshift(void **state)
{
    (void)state;
    ts_config c = test_preset_config("flat-coupled-rack90", NULL);
    ts_err err;
    assert_int_equal(run(&c, TS_COUPLING_LEADING_FOLLOWING, 10.0, 0.01, &h_ref, &err), TS_OK);
    c.terrain.kind = TS_TERRAIN_BUMPS;
    assert_int_equal(run(&c, TS_COUPLING_LEADING_FOLLOWING, 10.0, 0.01, &h_a, &err), TS_OK);
    double f[3], b[3];
    for (int g = 0; g < 3; g++) {
        f[g] = shift_start(&h_ref, g + 1.0);
        b[g] = shift_start(&h_a, g + 1.0);
    }
    print_message("upshifts flat %.2f / %.2f / %.2f s, bumps %.2f / %.2f / %.2f s\n", f[0], f[1],
                  f[2], b[0], b[1], b[2]);
    assert_true(isfinite(b[2]) && isfinite(f[2]));
    assert_close(b[0], f[0], 0, 0.05);
    assert_true(b[1] > f[1] + 0.15);
    assert_true(b[2] > f[2] + 0.15);
}

/* EVIDENCE: paper Fig. 33 (Section IV.C): with the IVS controller at 5 mph the
 * rack goes to 100 % at launch and 5 mph is reached before the 8th second,
 * after which the rack comes back below full. Flat ground (the bump course is
 * the report's 80-s run), static track, gains of /control (kp 2 per m/s
 * CALIBRATED to Fig. 33's full rack through the launch, ti 4 s [E]: with the
 * earlier kp 0.5 this run never reaches 5 mph in 9 s). Calibrated: the time
 * to 5 mph (through kp). Predicted: the rack at 100 % at launch, back below full after the target,
 * and the speed held within 0.1 mph on average over the last 3 s (measured
 * 0.023 mph; with the integral action off, ti 1e4 s, 0.39 mph). */
static void ivs_full_rack_at_launch_then_holds_5mph(void **state)
{
    (void)state;
    ts_config c = test_preset_config("bump-coupled-ivs5mph", "static");
    c.terrain.kind = TS_TERRAIN_FLAT;
    ts_err err;
    assert_int_equal(run(&c, TS_COUPLING_LEADING_FOLLOWING, 9.0, 0.02, &h_a, &err), TS_OK);
    double vt = c.control.target_speed, t_hit = NAN, rack_launch = 0, rack_after = 1, err_abs = 0;
    int ne = 0;
    for (int i = 0; i < h_a.n; i++) {
        if (h_a.t[i] <= 0.2) rack_launch = fmax(rack_launch, h_a.rack[i]);
        if (isnan(t_hit) && h_a.v[i] >= vt) t_hit = h_a.t[i];
        if (!isnan(t_hit)) rack_after = fmin(rack_after, h_a.rack[i]);
        if (h_a.t[i] >= 6.0) err_abs += fabs(h_a.v[i] - vt), ne++;
    }
    print_message("rack at launch %.2f, 5 mph at %.2f s, lowest rack after %.2f, mean |err| %.3f "
                  "mph\n",
                  rack_launch, t_hit, rack_after, err_abs / ne / MPH);
    assert_close(rack_launch, 1.0, 0, 1e-9);
    assert_true(t_hit < 8.0);
    assert_true(rack_after < 0.9);
    assert_true(err_abs / ne < 0.1 * MPH);
}

/* EVIDENCE: no downshift-upshift hunting under the speed controller. Flat
 * ground, static track, map engine, IVS at 4.5 m/s (16.2 km/h, where 2nd gear
 * turns the turbine at ~845 rpm and 1st at ~1545 rpm), 60 s. Until the
 * downshift also required the lower gear to turn its input at most at
 * downshift_speed (transmission.h), the engine fell below the 1000-rpm
 * downshift speed whenever the controller cut the rack, the box went down to
 * 1st, the rack came back, the engine reached the 1750-rpm upshift speed and
 * it went up again: 28 downshifts and 28 upshifts 1-2 in the minute. Logic
 * check, nothing calibrated: one 1-2 upshift, no downshift, the speed held. */
static void ivs_cruise_does_not_hunt_gears(void **state)
{
    (void)state;
    ts_config c;
    ts_err err;
    json_t *doc = json_pack("{s:s, s:{s:s}, s:{s:s}, s:{s:s}, s:{s:f}}", "preset",
                            "bump-coupled-ivs5mph", "terrain", "kind", "flat", "track", "fidelity",
                            "static", "engine", "fidelity", "map", "control", "target_speed", 4.5);
    assert_int_equal(tsa_config_load(doc, &c, NULL, NULL, &err), TS_OK);
    json_decref(doc);
    assert_int_equal(run(&c, TS_COUPLING_LEADING_FOLLOWING, 60.0, 0.02, &h_a, &err), TS_OK);
    int up = 0, down = 0, ne = 0;
    double err_sum = 0;
    for (int i = 1; i < h_a.n; i++) {
        up += h_a.gear[i - 1] < 1.5 && h_a.gear[i] >= 1.5;
        down += h_a.gear[i - 1] >= 1.5 && h_a.gear[i] < 1.5;
        if (h_a.t[i] >= 30.0) err_sum += h_a.v[i] - c.control.target_speed, ne++;
    }
    print_message("1-2 upshifts %d, 2-1 downshifts %d, gear at 60 s %.2f, mean speed error "
                  "%.4f m/s over 30-60 s\n",
                  up, down, h_a.gear[h_a.n - 1], err_sum / ne);
    assert_int_equal(up, 1);
    assert_int_equal(down, 0);
    assert_true(fabs(err_sum / ne) < 0.05);
}

/* EVIDENCE: a launch from standstill starts with the engine at its idle
 * steady state ("a step increase of driver demand" [P III.C.2]), as the
 * point-mass launch of Table 2 does. Until session 18 the coupled run started
 * from ts_engine_init_state (ambient intercooler, guessed turbo speed): the
 * compressor then passed far more air than the cylinders took, Eq. 14 fuelled
 * on it, and the brake torque at 650 rpm was 11.2 kN*m at t = 0 with a 1.0-bar
 * intake (a BMEP 4 pi T / V_d of 37 bar, three times what any naturally
 * aspirated diesel reaches), decaying over ~25 ms. Bound: with the intake
 * below 1.2 bar the BMEP stays under 15 bar (T < 15e5 V_d / 4 pi = 4.5 kN*m;
 * measured 1.94 kN*m at t = 0). Flat ground, 90 % rack, mean-value engine. */
static void launch_starts_from_idle_steady_state(void **state)
{
    (void)state;
    ts_config c = test_preset_config("flat-coupled-rack90", "static");
    ts_err err;
    ts_coupled *cm;
    ts_coupled_run *r = started(&c, TS_COUPLING_LEADING_FOLLOWING, 0.0, &cm);
    const double pi = 3.141592653589793;
    const double v_d = 12.0 * pi / 4.0 * c.engine.bore * c.engine.bore * c.engine.stroke; /* V-12 */
    double worst = 0, t0_torque = NAN;
    for (int k = 0; k <= 50; k++) {
        if (k > 0) assert_int_equal(ts_coupled_run_advance(r, 1e-3 * k, &err), TS_OK);
        ts_coupled_obs o;
        assert_int_equal(ts_coupled_run_observe(r, &o, NULL), TS_OK);
        if (k == 0) t0_torque = o.pt.engine_torque;
        if (o.pt.boost < 1.2e5)
            worst = fmax(worst, o.pt.engine_torque * 4.0 * pi / v_d);
    }
    print_message("brake torque at t = 0: %.0f N*m; largest BMEP below 1.2 bar intake: %.1f bar\n",
                  t0_torque, worst / 1e5);
    assert_true(worst > 0);
    assert_true(worst < 15e5);
    ts_coupled_run_free(r);
    ts_coupled_free(cm);
}

/* EVIDENCE: back-calculation anti-windup in the coupled IVS run (Eq. 10 with
 * the Fig. 25 saturation; ivs_controller.h, Astrom & Hagglund 1995 Sec. 3.5,
 * tracking time T_t = T_I). While the PI output saturates high, u = K_p (e +
 * I/T_I) > 1, the integral's rate is e + (1 - u)/K_p = 1/K_p - I/T_I whatever
 * the error, so from I(0) = 0: I(t) = (T_I/K_p)(1 - exp(-t/T_I)), 0.2350 m at
 * 0.5 s with the preset's K_p = 2, T_I = 4 s (1e-4 relative: the integrator's
 * tolerance). With /control/anti_windup false it is the plain integral of the
 * speed error, int e dt (trapezoids over 5-ms samples, 1 %), about 1.1 m.
 * Launch of bump-coupled-ivs5mph on flat ground, static track, first 0.5 s
 * (5 mph is reached at 1.6 s). Mutation pass ctl: the coupled run's
 * integral without the back-calculation term, and /control/anti_windup false
 * ignored, both passed every test. */
static void ivs_integral_tracks_the_saturated_rack(void **state)
{
    (void)state;
    ts_config c = test_preset_config("bump-coupled-ivs5mph", "static");
    c.terrain.kind = TS_TERRAIN_FLAT;
    for (int aw = 1; aw >= 0; aw--) {
        c.control.anti_windup = aw;
        ts_coupled *cm;
        ts_coupled_run *r = started(&c, TS_COUPLING_LEADING_FOLLOWING, 0.0, &cm);
        const double kp = ts_coupled_kp(cm), ti = ts_coupled_ti(cm), dt = 5e-3;
        ts_err err;
        ts_coupled_obs o;
        assert_int_equal(ts_coupled_run_observe(r, &o, NULL), TS_OK);
        double e_prev = o.speed_error, plain = 0;
        for (int k = 1; k <= 100; k++) {
            assert_int_equal(ts_coupled_run_advance(r, k * dt, &err), TS_OK);
            assert_int_equal(ts_coupled_run_observe(r, &o, NULL), TS_OK);
            plain += 0.5 * dt * (e_prev + o.speed_error);
            e_prev = o.speed_error;
            assert_true(kp * (o.speed_error + o.integral / ti) > 1.0); /* saturated */
            assert_close(o.rack_demand, 1.0, 0, 0);
        }
        double want = aw ? ti / kp * (1.0 - exp(-0.5 / ti)) : plain;
        print_message("anti_windup %d: integral at 0.5 s %.5f m, expected %.5f m\n", aw, o.integral,
                      want);
        assert_close(o.integral, want, aw ? 1e-4 : 1e-2, 0);
        ts_coupled_run_free(r);
        ts_coupled_free(cm);
    }
}

/* EVIDENCE: the fuel actuator's two-speed governor (paper IV.B.2, governor.h)
 * acts in the coupled run: the engine gets rack = governor(demand, w_e), and
 * as the rack is cut to 0 at high_idle + high_band the engine cannot be driven
 * past that speed while the converter loads it (turbine slower than pump).
 * Flat ground, static track, 90 % rack, mean-value engine, high idle lowered
 * to 800 rpm (band 100 rpm): over the first 1.5 s the governed rack is the
 * governor law of the demand at the engine speed (1e-12), it falls below the
 * demand, and the engine stays below 900 rpm (without the governor it
 * passes 1000 rpm within the 1.5 s). Mutation pass ctl: the coupled run
 * with the governor bypassed passed every test (its speeds never reach the
 * default idles). */
static void governor_acts_in_the_coupled_run(void **state)
{
    (void)state;
    const double rpm = 3.14159265358979 / 30;
    ts_config c = test_preset_config("flat-coupled-rack90", "static");
    c.control.governor = 1;
    c.control.governor_high_idle = 800 * rpm;
    c.control.governor_high_band = 100 * rpm;
    ts_governor g;
    ts_err err;
    assert_int_equal(ts_governor_of_config(&c.control, &g, &err), TS_OK);
    ts_coupled *cm;
    ts_coupled_run *r = started(&c, TS_COUPLING_LEADING_FOLLOWING, 0.0, &cm);
    double w_max = 0;
    int cut = 0;
    for (int k = 1; k <= 150; k++) {
        assert_int_equal(ts_coupled_run_advance(r, 0.01 * k, &err), TS_OK);
        ts_coupled_obs o;
        assert_int_equal(ts_coupled_run_observe(r, &o, NULL), TS_OK);
        assert_close(o.rack_demand, 0.9, 0, 0);
        assert_close(o.rack, ts_governor_rack(&g, o.rack_demand, o.pt.engine_speed), 0, 1e-12);
        assert_close(o.pt.rack, o.rack, 0, 0);
        cut += o.rack < o.rack_demand - 0.05;
        w_max = fmax(w_max, o.pt.engine_speed);
    }
    print_message("highest engine speed %.0f rpm; %d of 150 samples with the rack cut\n",
                  w_max / rpm, cut);
    assert_true(cut > 10);
    assert_true(w_max < (800 + 100) * rpm);
    ts_coupled_run_free(r);
    ts_coupled_free(cm);
}

/* EVIDENCE: where the driveline's rotating mass goes. /driveline/output_inertia
 * is the transmission output to both sprockets, reflected to the sprocket;
 * in the pitch-plane model (one side) each sprocket spin carries its half,
 * in place of /vehicle/sprocket_inertia when larger (coupled_system.h). The
 * coupled vehicle's mass matrix at the sprocket spin must exceed the plain
 * vehicle's by max(J_out / 2, J_s) - J_s and nothing else change (1e-12).
 * Session-25 mutation test: the whole J_out per side survived. */
static void driveline_inertia_is_shared_by_the_two_sprockets(void **state)
{
    (void)state;
    ts_config c = test_preset_config("flat-coupled-rack90", NULL);
    c.engine.fidelity = TS_ENGINE_MEAN_VALUE;
    ts_err err;
    ts_coupled *cm = ts_coupled_make(&c, &err);
    if (!cm) fail_msg("%s", err.msg);
    vm *plain = test_vm(&c);
    const vm *cv = ts_coupled_vehicle(cm);
    int nq = vm_nq(plain), ny = vm_ny(plain);
    assert_int_equal(vm_nq(cv), nq);
    vm_work *w1 = vm_work_make(plain), *w2 = vm_work_make(cv);
    double *y = malloc(sizeof(double) * (size_t)ny),
           *M1 = malloc(sizeof(double) * (size_t)nq * (size_t)nq),
           *M2 = malloc(sizeof(double) * (size_t)nq * (size_t)nq);
    memcpy(y, vm_equilibrium(plain), sizeof(double) * (size_t)ny);
    vm_mass(plain, w1, y, M1);
    vm_mass(cv, w2, y, M2);
    int ks = VM_NQ_RIGID - VM_NB + VM_SPROCKET;
    double js = c.vehicle.sprocket_inertia, jo = c.driveline.output_inertia;
    printf("# sprocket spin: plain %.4f, coupled %.4f kg m^2 (J_s %.2f, J_out / 2 %.2f)\n",
           M1[ks * nq + ks], M2[ks * nq + ks], js, 0.5 * jo);
    assert_true(0.5 * jo > js); /* the case the presets run */
    for (int i = 0; i < nq; i++)
        for (int j = 0; j < nq; j++)
            assert_close(M2[i * nq + j] - M1[i * nq + j],
                         i == ks && j == ks ? fmax(0.5 * jo, js) - js : 0.0, 0,
                         1e-12 * (1 + fabs(M1[i * nq + j])));
    /* a sprocket heavier than J_out / 2 keeps its own inertia (the larger of
     * the two): 30 kg m^2 against 20, no change at all (mutation pass ctl:
     * replacing it by J_out / 2 regardless passed) */
    c.vehicle.sprocket_inertia = 0.75 * jo;
    vm_free(plain);
    ts_coupled_free(cm);
    plain = test_vm(&c);
    cm = ts_coupled_make(&c, &err);
    if (!cm) fail_msg("%s", err.msg);
    cv = ts_coupled_vehicle(cm);
    vm_work_free(w1), vm_work_free(w2);
    w1 = vm_work_make(plain), w2 = vm_work_make(cv);
    vm_mass(plain, w1, y, M1);
    vm_mass(cv, w2, y, M2);
    for (int i = 0; i < nq * nq; i++)
        assert_close(M2[i], M1[i], 0, 1e-12 * (1 + fabs(M1[i])));
    free(y), free(M1), free(M2);
    vm_work_free(w1), vm_work_free(w2);
    vm_free(plain);
    ts_coupled_free(cm);
}

/* EVIDENCE: determinism of the state snapshot: saving at 0.5 s and
 * restoring reproduces the continued run (both methods; the restart of the
 * integrators is the only difference, so agreement to integrator tolerance:
 * rtol 1e-9, asserted 1e-6 relative on sprocket and engine speed; measured
 * 2e-9 monolithic, 5e-8 leading-following). Closed-form expectation. */
static void save_restore_reproduces(void **state)
{
    (void)state;
    ts_config c = test_preset_config("flat-coupled-rack90", "static");
    c.run.rtol = 1e-9;
    c.run.atol = 1e-11;
    ts_err err;
    for (int method = 0; method < 2; method++) {
        ts_coupled *cm;
        ts_coupled_run *r = started(&c, method, 0.5, &cm);
        size_t n = ts_coupled_state_size(cm);
        void *buf = malloc(n);
        ts_coupled_run_save(r, buf);
        assert_int_equal(ts_coupled_run_advance(r, 0.8, &err), TS_OK);
        ts_coupled_obs o1, o2;
        assert_int_equal(ts_coupled_run_observe(r, &o1, NULL), TS_OK);
        double w1 = o1.sprocket_speed, we1 = o1.pt.engine_speed;
        assert_int_equal(ts_coupled_run_restore(r, buf, &err), TS_OK);
        assert_close(ts_coupled_run_time(r), 0.5, 0, 1e-12);
        assert_int_equal(ts_coupled_run_advance(r, 0.8, &err), TS_OK);
        assert_int_equal(ts_coupled_run_observe(r, &o2, NULL), TS_OK);
        assert_close(o2.sprocket_speed, w1, 1e-6, 1e-9);
        assert_close(o2.pt.engine_speed, we1, 1e-6, 1e-9);
        free(buf);
        ts_coupled_run_free(r);
        ts_coupled_free(cm);
    }
}

/* EVIDENCE: Section IV.A: the follower reports the sprocket's state relative
 * to the hull (the powertrain turns the sprocket against the hull), so the
 * leader's predictor w + alpha (t - t_k) extrapolates the relative speed with
 * the relative acceleration. The report the saved state carries (coupled_system.c
 * SAVE_HEAD: t, rack, then the report t, omega, alpha) equals the observed
 * sprocket.speed and sprocket.accel, both hull-relative (1e-12), at every
 * 10-ms output of a launch (flat, 90 % rack, static track) whose hull pitches
 * (pitch acceleration up to 0.7 rad/s^2 at the launch, asserted > 0.1). Exact by
 * definition. Mutation pass ctl: a reported alpha with the hull's pitch
 * acceleration left in (the predictor off by h theta'' per step on bumps)
 * passed every test. */
static void reported_sprocket_state_is_hull_relative(void **state)
{
    (void)state;
    ts_config c = test_preset_config("flat-coupled-rack90", "static");
    ts_coupled *cm;
    ts_coupled_run *r = started(&c, TS_COUPLING_LEADING_FOLLOWING, 0.0, &cm);
    size_t n = ts_coupled_state_size(cm);
    double *buf = malloc(n);
    assert_non_null(buf);
    int nq = vm_nq(ts_coupled_vehicle(cm));
    double pitch_acc = 0;
    ts_err err;
    for (int k = 1; k <= 50; k++) {
        assert_int_equal(ts_coupled_run_advance(r, 0.01 * k, &err), TS_OK);
        ts_coupled_obs o;
        assert_int_equal(ts_coupled_run_observe(r, &o, NULL), TS_OK);
        ts_coupled_run_save(r, buf);
        assert_close(buf[2], o.t, 0, 1e-12);
        assert_close(buf[3], o.sprocket_speed, 1e-12, 1e-12);
        assert_close(buf[4], o.sprocket_accel, 1e-12, 1e-12);
        pitch_acc = fmax(pitch_acc, fabs(o.ydot_vehicle[nq + 2])); /* q 2: hull pitch */
    }
    print_message("largest hull pitch acceleration %.3g rad/s^2\n", pitch_acc);
    assert_true(pitch_acc > 0.1);
    free(buf);
    ts_coupled_run_free(r);
    ts_coupled_free(cm);
}

/* EVIDENCE: Fig. 27 gain schedule by linear interpolation in vehicle mass
 * (closed form), and the config checks naming the field (the schedule's
 * lengths; the lead bound of Section IV.A against both macro steps). */
static void gain_schedule_and_config_errors(void **state)
{
    (void)state;
    ts_config c = test_preset_config("flat-coupled-rack90", "static");
    c.control.schedule_n = c.control.schedule_kp_n = c.control.schedule_ti_n = 2;
    c.control.schedule_x[0] = 50000, c.control.schedule_x[1] = 70000;
    c.control.schedule_kp[0] = 0.2, c.control.schedule_kp[1] = 0.4;
    c.control.schedule_ti[0] = 2.0, c.control.schedule_ti[1] = 6.0;
    c.vehicle.mass = 55000;
    ts_err err;
    ts_coupled *cm = ts_coupled_make(&c, &err);
    assert_non_null(cm);
    assert_close(ts_coupled_kp(cm), 0.25, 1e-12, 0);
    assert_close(ts_coupled_ti(cm), 3.0, 1e-12, 0);
    ts_coupled_free(cm);
    c.control.schedule_ti_n = 1;
    assert_null(ts_coupled_make(&c, &err));
    assert_int_equal(err.code, TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/control/schedule_kp");
    /* a lead shorter than the follower's step cannot be kept (the follower
     * needs torque samples to the end of its step; until session 20 the
     * leader silently ran a whole follower step ahead) */
    c = test_preset_config("flat-coupled-rack90", "static");
    c.coupling.follower_step = 0.004;
    c.coupling.leader_step = 0.001;
    c.coupling.lead = 0.002;
    cm = ts_coupled_make(&c, &err);
    assert_non_null(cm);
    assert_null(ts_coupled_run_make(cm, TS_COUPLING_LEADING_FOLLOWING, &err));
    assert_int_equal(err.code, TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/coupling/lead");
    assert_non_null(strstr(err.msg, "follower_step"));
    ts_coupled_free(cm);
}

/* EVIDENCE: a coupled run's vehicle takes its slope from the terrain;
 * /vehicle/grade only picks the gains of an IVS schedule over grade (Fig. 27).
 * Anywhere else it did nothing and is refused, naming the field. */
static void vehicle_grade_only_picks_scheduled_gains(void **state)
{
    (void)state;
    ts_config c = test_preset_config("flat-coupled-rack90", "static");
    c.vehicle.grade = 0.1;
    ts_err err;
    assert_null(ts_model_make(&c, &err));
    assert_int_equal(err.code, TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/vehicle/grade");
    c.control.mode = TS_CONTROL_IVS;
    c.control.schedule_var = TS_SCHEDULE_GRADE;
    c.control.schedule_n = c.control.schedule_kp_n = c.control.schedule_ti_n = 2;
    c.control.schedule_x[0] = 0, c.control.schedule_x[1] = 0.2;
    c.control.schedule_kp[0] = 0.2, c.control.schedule_kp[1] = 0.4;
    c.control.schedule_ti[0] = 2.0, c.control.schedule_ti[1] = 6.0;
    ts_model *m = ts_model_make(&c, &err);
    assert_non_null(m);
    ts_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(leading_following_is_second_order),
        cmocka_unit_test(leader_not_restarted_follower_reuses_jacobian),
        cmocka_unit_test(plain_exchange_is_unstable_interface_inertia_fixes_it),
        cmocka_unit_test(shift_spikes_tension_and_excites_span),
        cmocka_unit_test(bumps_delay_second_and_third_upshift),
        cmocka_unit_test(ivs_full_rack_at_launch_then_holds_5mph),
        cmocka_unit_test(ivs_cruise_does_not_hunt_gears),
        cmocka_unit_test(launch_starts_from_idle_steady_state),
        cmocka_unit_test(ivs_integral_tracks_the_saturated_rack),
        cmocka_unit_test(governor_acts_in_the_coupled_run),
        cmocka_unit_test(driveline_inertia_is_shared_by_the_two_sprockets),
        cmocka_unit_test(save_restore_reproduces),
        cmocka_unit_test(reported_sprocket_state_is_hull_relative),
        cmocka_unit_test(gain_schedule_and_config_errors),
        cmocka_unit_test(vehicle_grade_only_picks_scheduled_gains),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
