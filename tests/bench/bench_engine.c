/*
 * bench_engine.c — real-time factor of the three engine fidelities at the
 * rated point (2100 rpm, full rack, conventional): simulated seconds per wall
 * second of a free-running engine carrying its own steady brake torque as the
 * load, after a steady-state search (not timed). Ratios measured in this run.
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "api/config_json.h"
#include "sim/engine.h"
#include "sim/tanksim.h"

#define PI 3.14159265358979323846

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
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
        double t0 = now();
        if (ts_engine_advance(e, x, 0, sim_t[f], &in, work, &err) != TS_OK) return 1;
        double wall = now() - t0;
        rtf[f] = sim_t[f] / wall;
        printf("%-12s %4d states  %6.2f s simulated in %7.3f s wall: real-time factor %8.2f"
               "  (end speed %.1f rpm)\n", names[f], ts_engine_nstate(e), sim_t[f], wall, rtf[f],
               x[0] * 30 / PI);
        free(x);
        free(work);
        ts_engine_free(e);
    }
    printf("ratios: mean_value / crank_angle %.0f x, map / crank_angle %.0f x\n", rtf[1] / rtf[0],
           rtf[2] / rtf[0]);
    return 0;
}
