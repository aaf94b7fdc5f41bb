/*
 * bench_coupled.c — the integrated engine–vehicle run of paper Section IV
 * (coupled_system.h): real-time factors (simulated / wall seconds, measured in
 * this run) of the bump-course run at several fidelities, and the coupling
 * error of leading–following against the monolithic reference for a range of
 * macro steps, with the observed order and wall times. Prints; asserts
 * nothing (timings are machine-dependent).
 *
 * Usage:
 *   bench_coupled                         both studies, default lengths (rtf: the 30-s run)
 *   bench_coupled rtf [T] [ENGINE TRACK METHOD]...   real-time factors, T s
 *   bench_coupled error [T] [PRESET [TRACK [0]]]   coupling-error table over T s (0: the
 *                                         hold predictor too)
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "api/config_json.h"
#include "sim/coupled_system.h"
#include "sim/tanksim.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int load(const char *preset, const char *engine, const char *track, ts_config *c)
{
    json_t *doc = json_pack("{s:s}", "preset", preset);
    if (engine) json_object_set_new(doc, "engine", json_pack("{s:s}", "fidelity", engine));
    if (track) json_object_set_new(doc, "track", json_pack("{s:s}", "fidelity", track));
    ts_err err;
    ts_rc rc = tsa_config_load(doc, c, NULL, NULL, &err);
    json_decref(doc);
    if (rc != TS_OK) printf("config error: %s\n", err.msg);
    return rc == TS_OK ? 0 : 1;
}

/* One run of t_end seconds sampled every dt: sprocket speed and rear-roller
 * tension into w[], T[] (n = t_end/dt + 1 values each, may be NULL). */
typedef struct result {
    double wall, cpu, t_end;
    ts_coupled_stats st;
    int ok;
} result;

static result run(const ts_coupled *cm, int method, double t_end, double dt, double *w,
                  double *tens, double *speed)
{
    result r = {0};
    ts_err err;
    ts_coupled_run *run = ts_coupled_run_make(cm, method, &err);
    if (!run) {
        printf("run_make: %s\n", err.msg);
        return r;
    }
    double t0 = now();
    clock_t c0 = clock();
    ts_rc rc = ts_coupled_run_reset(run, &err);
    long n = (long)floor(t_end / dt + 0.5);
    ts_coupled_obs o;
    for (long k = 0; k <= n && rc == TS_OK; k++) {
        if (k > 0) rc = ts_coupled_run_advance(run, k * dt, &err);
        if (rc != TS_OK) break;
        if (w || tens || speed) {
            rc = ts_coupled_run_observe(run, &o, &err);
            if (rc != TS_OK) break;
            if (w) w[k] = o.sprocket_speed;
            if (tens) tens[k] = o.diag.tension_end1[0];
            if (speed) speed[k] = o.y_vehicle[vm_nq(ts_coupled_vehicle(cm))];
        }
        r.t_end = k * dt;
    }
    r.wall = now() - t0;
    r.cpu = (double)(clock() - c0) / CLOCKS_PER_SEC;
    ts_coupled_run_stats(run, &r.st);
    r.ok = rc == TS_OK;
    if (!r.ok) printf("  run failed at t = %.4f: %s\n", r.t_end, err.msg);
    ts_coupled_run_free(run);
    return r;
}

static void rtf(const char *preset, const char *engine, const char *track, const char *method,
                double t_end)
{
    ts_config c;
    if (load(preset, engine, track, &c)) return;
    int mth =
        strcmp(method, "monolithic") == 0 ? TS_COUPLING_MONOLITHIC : TS_COUPLING_LEADING_FOLLOWING;
    ts_err err;
    ts_coupled *cm = ts_coupled_make(&c, &err);
    if (!cm) {
        printf("%-22s %-12s %-10s %-18s unavailable: %s\n", preset, engine, track, method, err.msg);
        return;
    }
    double v;
    result r = run(cm, mth, t_end, 0.01, NULL, NULL, NULL);
    (void)v;
    printf("%-22s %-12s %-10s %-18s %5.2f s simulated, wall %8.2f s, cpu %8.2f s, real-time x "
           "%8.3f (wall) %8.3f (cpu) (vehicle rhs %ld, wall %.2f s; powertrain rhs %ld, wall "
           "%.2f s; messages %ld)\n",
           preset, engine, track, method, r.t_end, r.wall, r.cpu, r.t_end / r.wall, r.t_end / r.cpu,
           r.st.vehicle_rhs, r.st.vehicle_wall, r.st.powertrain_rhs, r.st.powertrain_wall,
           r.st.exchanges);
    printf("    per simulated s: vehicle rhs %.0f, steps %.0f, Jacobians %.1f, error-test fails "
           "%.1f, Newton iterations %.0f (fails %.1f); powertrain rhs %.0f, leader CVODE steps "
           "%.0f, factorisations %.0f (n = %d), restarts %.0f\n",
           r.st.vehicle_rhs / r.t_end, r.st.vehicle_steps / r.t_end, r.st.vehicle_jacs / r.t_end,
           r.st.vehicle_err_fails / r.t_end, r.st.vehicle_newton / r.t_end,
           r.st.vehicle_newton_fails / r.t_end, r.st.powertrain_rhs / r.t_end,
           r.st.powertrain_steps / r.t_end, r.st.powertrain_setups / r.t_end, r.st.powertrain_n,
           r.st.leader_inits / r.t_end);
    fflush(stdout);
    ts_coupled_free(cm);
}

static double rms_rel(const double *a, const double *b, long n)
{
    double e = 0, s = 0;
    for (long i = 0; i < n; i++) {
        e += (a[i] - b[i]) * (a[i] - b[i]);
        s += b[i] * b[i];
    }
    return s > 0 ? sqrt(e / s) : NAN;
}

static double rms_rel_dev(const double *a, const double *b, long n)
{
    double mean = 0;
    for (long i = 0; i < n; i++)
        mean += b[i];
    mean /= n;
    double e = 0, s = 0;
    for (long i = 0; i < n; i++) {
        e += (a[i] - b[i]) * (a[i] - b[i]);
        s += (b[i] - mean) * (b[i] - mean);
    }
    return s > 0 ? sqrt(e / s) : NAN;
}

static void coupling_error(const char *preset, const char *track, double t_end, int with_hold)
{
    ts_config c;
    if (load(preset, NULL, track, &c)) return;
    c.run.rtol = 1e-9;
    c.run.atol = 1e-11;
    /* outputs synchronise the two sides (the leader does not run past an output
     * time, so both are observed at the same instant): the interval is 5 of the
     * largest macro steps, so that the scheme changes little with h */
    const double dt = 0.02;
    long n = (long)floor(t_end / dt + 0.5) + 1;
    double *w0 = calloc((size_t)n * 6, sizeof(double));
    double *t0 = w0 + n, *w1 = w0 + 2 * n, *t1 = w0 + 3 * n, *v0 = w0 + 4 * n, *v1 = w0 + 5 * n;
    ts_err err;
    ts_coupled *cm = ts_coupled_make(&c, &err);
    if (!cm || !w0) {
        printf("coupling error: %s\n", cm ? "out of memory" : err.msg);
        free(w0);
        ts_coupled_free(cm);
        return;
    }
    printf("coupling error, preset %s, %s engine, %s track, %.2f s, rtol %g (RMS over %ld samples "
           "at %g s; tension error relative to its RMS deviation from the mean)\n",
           preset, ts_param_find("/engine/fidelity")->enum_names[c.engine.fidelity],
           ts_param_find("/track/fidelity")->enum_names[c.track.fidelity], t_end, c.run.rtol, n,
           dt);
    result ref = run(cm, TS_COUPLING_MONOLITHIC, t_end, dt, w0, t0, v0);
    printf("  monolithic reference: wall %.2f s (rhs: %ld)\n", ref.wall, ref.st.vehicle_rhs);
    ts_coupled_free(cm);
    const double hs[] = {0.004, 0.002, 0.001, 0.0005};
    double prev_w = NAN, prev_t = NAN;
    printf("  %-8s %-6s %12s %8s %12s %8s %12s %9s %9s %9s\n", "h [ms]", "order", "speed err", "p",
           "tension err", "p", "v err", "wall [s]", "veh wall", "pt wall");
    for (int order = 1; order >= (with_hold ? 0 : 1); order--) {
        prev_w = prev_t = NAN;
        for (size_t k = 0; k < sizeof hs / sizeof hs[0]; k++) {
            c.coupling.leader_step = c.coupling.follower_step = hs[k];
            c.coupling.lead = 2 * hs[k];
            c.coupling.predictor_order = order;
            cm = ts_coupled_make(&c, &err);
            if (!cm) break;
            result r = run(cm, TS_COUPLING_LEADING_FOLLOWING, t_end, dt, w1, t1, v1);
            ts_coupled_free(cm);
            if (!r.ok) continue;
            double ew = rms_rel(w1, w0, n), et = rms_rel_dev(t1, t0, n), ev = rms_rel(v1, v0, n);
            printf("  %-8.2f %-6d %12.3e %8.2f %12.3e %8.2f %12.3e %9.2f %9.2f %9.2f\n",
                   hs[k] * 1e3, order, ew, log2(prev_w / ew), et, log2(prev_t / et), ev, r.wall,
                   r.st.vehicle_wall, r.st.powertrain_wall);
            fflush(stdout);
            prev_w = ew;
            prev_t = et;
        }
    }
    free(w0);
}

int main(int argc, char **argv)
{
    const char *what = argc > 1 ? argv[1] : "all";
    if (strcmp(what, "rtf") == 0 || strcmp(what, "all") == 0) {
        double t = argc > 2 ? atof(argv[2]) : 30.0; /* the full bump course */
        if (argc > 5) {
            for (int i = 3; i + 2 < argc; i += 3)
                rtf("bump-coupled-ivs5mph", argv[i], argv[i + 1], argv[i + 2], t);
        } else {
            rtf("bump-coupled-ivs5mph", "map", "static", "leading_following", t);
            rtf("bump-coupled-ivs5mph", "map", "static", "monolithic", t);
            rtf("bump-coupled-ivs5mph", "mean_value", "coupled", "leading_following", t);
            rtf("bump-coupled-ivs5mph", "mean_value", "coupled", "monolithic", t);
            rtf("bump-coupled-ivs5mph", "crank_angle", "coupled", "leading_following", t);
            rtf("bump-coupled-ivs5mph", "crank_angle", "static", "leading_following", t);
        }
    }
    if (strcmp(what, "error") == 0 || strcmp(what, "all") == 0) {
        double t = argc > 2 && strcmp(what, "error") == 0 ? atof(argv[2]) : 3.0;
        const char *preset =
            argc > 3 && strcmp(what, "error") == 0 ? argv[3] : "flat-coupled-rack90";
        const char *track = argc > 4 && strcmp(what, "error") == 0 ? argv[4] : NULL;
        coupling_error(preset, track, t,
                       argc > 5 && strcmp(what, "error") == 0 && atoi(argv[5]) == 0);
    }
    return 0;
}
