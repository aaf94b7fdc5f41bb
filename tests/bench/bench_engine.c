/*
 * bench_engine.c — real-time factor of the three engine fidelities at the
 * rated point (2100 rpm, full rack, conventional): simulated seconds per wall
 * second of a free-running engine carrying its own steady brake torque as the
 * load, after a steady-state search (not timed). Ratios measured in this run,
 * on process CPU time (the wall-clock factor is printed beside it).
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "api/config_json.h"
#include "sim/engine.h"
#include "sim/tanksim.h"

#define PI 3.14159265358979323846

static double clock_s(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
static double now(void) { return clock_s(CLOCK_MONOTONIC); }
/* CPU time of this process: the machine is shared, wall time varies with load */
static double cpu(void) { return clock_s(CLOCK_PROCESS_CPUTIME_ID); }

typedef struct conv_load {
    double T0, slope, w0;
} conv_load;

static double conv(void *ud, double t, double w)
{
    (void)t;
    const conv_load *l = ud;
    return l->T0 + l->slope * (w - l->w0);
}

int main(void)
{
    ts_config c;
    ts_err err;
    json_t *doc = json_pack("{s:{s:s}}", "run", "kind", "engine_dyno");
    if (tsa_config_load(doc, &c, NULL, NULL, &err) != TS_OK) return 1;
    json_decref(doc);
    static const char *const names[] = {"crank_angle", "mean_value", "map"};
    const double sim_t[] = {0.5, 20.0, 200.0};
    double rtf[3] = {0};
    for (int f = 0; f < 3; f++) {
        c.engine.fidelity = f;
        ts_engine *e = ts_engine_make(&c, &err);
        if (!e) return 1;
        double *x = calloc((size_t)ts_engine_nstate(e), sizeof *x);
        double *work = calloc(ts_engine_work_size(e), sizeof *work);
        ts_engine_inputs in = {.rack = 1, .fuel_per_cycle = -1, .p_amb = 101325, .T_amb = 298.15};
        double w = 2100 * PI / 30;
        ts_engine_init_state(e, w, in.p_amb, in.T_amb, x);
        ts_engine_set_turbo_speed(e, x, 8000);
        ts_engine_cycle cyc;
        if (ts_engine_steady(e, x, w, &in, 80, 2e-4, &cyc, &err) != TS_OK) return 1;
        in.load_torque = cyc.mean.brake_torque;
        double t0 = now(), c0 = cpu();
        if (ts_engine_advance(e, x, 0, sim_t[f], &in, work, &err) != TS_OK) return 1;
        double wall = now() - t0, cpu_s = cpu() - c0;
        rtf[f] = sim_t[f] / cpu_s;
        printf("%-12s %4d states  %6.2f s simulated in %7.3f s CPU (%7.3f s wall): real-time"
               " factor %8.2f CPU, %8.2f wall  (end speed %.1f rpm)\n", names[f],
               ts_engine_nstate(e), sim_t[f], cpu_s, wall, rtf[f], sim_t[f] / wall,
               x[0] * 30 / PI);
        free(x);
        free(work);
        ts_engine_free(e);
    }
    printf("ratios: mean_value / crank_angle %.0f x, map / crank_angle %.0f x\n", rtf[1] / rtf[0],
           rtf[2] / rtf[0]);
    /* The crank-angle engine as a powertrain co-simulates it: 1-ms macro steps
     * of ts_engine_advance_load with a converter-like load (slope 45 N*m*s/rad,
     * pump inertia 1.5 kg*m^2) at 2100 and 1200 rpm, and the reference
     * integrator (RK4 of all states at /engine/ca_step through ts_engine_rhs,
     * what a caller's own RK4 does) at 2100 rpm for the speed-up ratio. */
    c.engine.fidelity = TS_ENGINE_CRANK_ANGLE;
    ts_engine *e = ts_engine_make(&c, &err);
    if (!e) return 1;
    int n = ts_engine_nstate(e);
    double *x = calloc((size_t)n, sizeof *x), *work = calloc(ts_engine_work_size(e), sizeof *work);
    double *k = calloc(5 * (size_t)n, sizeof *k);
    const double rpm[2] = {2100, 1200};
    for (int r = 0; r < 2; r++) {
        ts_engine_inputs in = {.rack = 1, .fuel_per_cycle = -1, .p_amb = 101325, .T_amb = 298.15,
                               .load_inertia = 1.5};
        double w = rpm[r] * PI / 30;
        ts_engine_init_state(e, w, in.p_amb, in.T_amb, x);
        ts_engine_set_turbo_speed(e, x, 8000);
        ts_engine_cycle cyc;
        if (ts_engine_steady(e, x, w, &in, 80, 2e-4, &cyc, &err) != TS_OK) return 1;
        conv_load cl = {cyc.mean.brake_torque, 45.0, w};
        double T = 0.5, c0 = cpu();
        for (int j = 0; j < 500; j++)
            if (ts_engine_advance_load(e, x, j * 1e-3, 1e-3, &in, conv, &cl, work, &err) != TS_OK)
                return 1;
        double cpu_s = cpu() - c0;
        printf("crank_angle co-simulated in 1-ms macro steps at %4.0f rpm: real-time factor %6.2f"
               " CPU (end speed %.1f rpm)\n", rpm[r], T / cpu_s, x[0] * 30 / PI);
        if (r == 0) {
            in.load_torque = cyc.mean.brake_torque;
            double Tr = 0.05, t = 0;
            c0 = cpu();
            while (t < Tr) { /* classical RK4 of all 512 states, as a caller would */
                double h = c.engine.ca_step / x[0], *k1 = k, *k2 = k + n, *k3 = k + 2 * n;
                double *k4 = k + 3 * n, *xt = k + 4 * n;
                int bad = ts_engine_rhs(e, t, x, &in, k1, NULL);
                for (int i = 0; i < n; i++) xt[i] = x[i] + 0.5 * h * k1[i];
                bad |= ts_engine_rhs(e, t, xt, &in, k2, NULL);
                for (int i = 0; i < n; i++) xt[i] = x[i] + 0.5 * h * k2[i];
                bad |= ts_engine_rhs(e, t, xt, &in, k3, NULL);
                for (int i = 0; i < n; i++) xt[i] = x[i] + h * k3[i];
                bad |= ts_engine_rhs(e, t, xt, &in, k4, NULL);
                if (bad) {
                    fprintf(stderr,
                            "bench_engine: the caller's RK4 left the engine's domain at "
                            "t = %g s\n",
                            t);
                    return 1;
                }
                for (int i = 0; i < n; i++) x[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
                t += h;
            }
            cpu_s = cpu() - c0;
            printf("crank_angle caller's RK4 of all %d states at ca_step, 2100 rpm: real-time factor"
                   " %6.2f CPU\n", n, Tr / cpu_s);
        }
    }
    free(k);
    free(x);
    free(work);
    ts_engine_free(e);
    return 0;
}
