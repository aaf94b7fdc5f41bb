/*
 * cmd_engine_map.c — "tanksim engine-map CONFIG.json --out FILE.csv": the
 * engine's full-load curve on a dynamometer (paper Section III.B.3, Fig. 18):
 * steady states at 2100, 2000, ..., 800 rpm (a lug-down from rated, each point
 * started from the previous one), rack from /control/rack, the configured
 * variant and fidelity. Writes one row per speed, ascending, with units in the
 * header. These rows are what /engine/map_* in engine.json are made from.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "../sim/engine.h"
#include "cli.h"

#define RPM_HI 2100
#define RPM_LO 800
#define RPM_STEP 100
#define NPOINT ((RPM_HI - RPM_LO) / RPM_STEP + 1)
#define STEADY_CYCLES 80
#define STEADY_TOL 2e-4
#define SEARCH_TURBO 8000.0 /* rotor speed the lug-down starts from [rad/s] */
#define PI 3.14159265358979323846

int tsc_cmd_engine_map(int argc, char **argv)
{
    const char *out = tsc_option(argc, argv, "--out");
    ts_config cfg;
    if (tsc_load_config(argc, argv, &cfg, NULL) != 0) return TSC_EXIT_USAGE;
    if (!out) {
        fprintf(stderr, "tanksim engine-map: --out FILE.csv is required\n");
        return TSC_EXIT_USAGE;
    }
    ts_err err;
    ts_engine *e = ts_engine_make(&cfg, &err);
    if (!e) {
        tsc_print_err("engine-map", &err);
        return TSC_EXIT_FAIL;
    }
    double *x = calloc((size_t)ts_engine_nstate(e), sizeof *x);
    ts_engine_cycle *rows = calloc(NPOINT, sizeof *rows);
    if (!x || !rows) {
        fprintf(stderr, "tanksim engine-map: out of memory\n");
        free(x);
        free(rows);
        ts_engine_free(e);
        return TSC_EXIT_FAIL;
    }
    ts_engine_inputs in = {.rack = cfg.control.rack, .fuel_per_cycle = -1, .p_amb = 101325.0,
                           .T_amb = 298.15, .hold_speed = 1};
    ts_engine_init_state(e, RPM_HI * PI / 30, in.p_amb, in.T_amb, x);
    ts_engine_set_turbo_speed(e, x, SEARCH_TURBO);
    int rc = TSC_EXIT_OK;
    for (int k = NPOINT - 1; k >= 0; k--) {
        double w = (RPM_LO + k * RPM_STEP) * PI / 30;
        if (ts_engine_steady(e, x, w, &in, STEADY_CYCLES, STEADY_TOL, &rows[k], &err) != TS_OK) {
            tsc_print_err("engine-map", &err);
            rc = TSC_EXIT_FAIL;
            break;
        }
        fprintf(stderr, "  %4d rpm  %7.1f N*m  %7.1f kW\n", RPM_LO + k * RPM_STEP,
                rows[k].mean.brake_torque, rows[k].mean.brake_torque * w / 1e3);
    }
    FILE *f = rc == TSC_EXIT_OK ? fopen(out, "w") : NULL;
    if (rc == TSC_EXIT_OK && !f) {
        fprintf(stderr, "tanksim engine-map: cannot write %s\n", out);
        rc = TSC_EXIT_FAIL;
    }
    if (f) {
        fprintf(f, "speed_rpm [rpm],speed [rad/s],torque [N*m],power [W],bsfc [g/kWh],"
                   "boost [Pa],exhaust_temp [K],peak_pressure [Pa],fuel_flow [kg/s],"
                   "air_flow [kg/s],phi [1],intake_temp [K],turbo_speed [rad/s],eta_v [1],"
                   "eta_i [1],q_wall [1],energy_residual [1],mass_residual [1],cycles [1]\n");
        for (int k = 0; k < NPOINT; k++) {
            const ts_engine_cycle *c = &rows[k];
            double w = (RPM_LO + k * RPM_STEP) * PI / 30;
            fprintf(f, "%d,%.4f,%.2f,%.1f,%.2f,%.0f,%.1f,%.0f,%.6f,%.5f,%.4f,%.1f,%.0f,%.4f,%.4f,"
                       "%.4f,%.3e,%.3e,%d\n",
                    RPM_LO + k * RPM_STEP, w, c->mean.brake_torque, c->mean.brake_torque * w,
                    c->bsfc * 3.6e9, c->mean.boost, c->mean.exhaust_temp, c->peak_pressure,
                    c->mean.fuel_flow, c->mean.air_flow, c->mean.phi, c->mean.intake_temp,
                    c->mean.turbo_speed, c->eta_v, c->eta_i, c->q_wall, c->energy_residual,
                    c->mass_residual, c->cycles);
        }
        if (fclose(f) != 0) rc = TSC_EXIT_FAIL;
    }
    free(x);
    free(rows);
    ts_engine_free(e);
    return rc;
}
