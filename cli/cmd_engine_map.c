/*
 * cmd_engine_map.c — "tanksim engine-map CONFIG.json --out FILE.csv": the
 * engine's full-load curve on a dynamometer (paper Section III.B.3, Fig. 18):
 * steady states at 2100, 2000, ..., 800 rpm (a lug-down from rated, each point
 * started from the previous one), rack from /control/rack, the configured
 * variant and fidelity. Writes one row per speed, ascending, with units in the
 * header. These rows are what /engine/map_* in engine.json are made from.
 *
 * With --spool FILE.csv (instead of --out): the turbo spool-up of a launch instead, the part-boost source
 * of the mean-value and map fidelities (tools/engine_maps.py). The engine
 * starts from an idle steady state (ts_engine_idle_state at IDLE_RPM against
 * IDLE_TORQUE: idle-warm walls, idle turbo), the crank is then held at each of
 * 800, 1000, ..., 2200 rpm and
 * the rack stepped to /control/rack; one row per engine cycle for SPOOL_TIME
 * seconds, real rotor inertia and wall capacities (the walls warm up as in a
 * launch). Columns: time, speed, the cycle means and eta_v, eta_i, q_wall.
 * Ambient: /driveline/ambient_pressure and ambient_temperature (the air the
 * vehicle runs' engine breathes).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../sim/constants.h"
#include "../sim/engine.h"
#include "cli.h"

#define RPM_HI 2100
#define RPM_LO 800
#define RPM_STEP 100
#define NPOINT ((RPM_HI - RPM_LO) / RPM_STEP + 1)
#define STEADY_CYCLES 80
#define STEADY_TOL 2e-4
#define SEARCH_TURBO 8000.0 /* rotor speed the lug-down starts from [rad/s] */
#define PI TS_PI
#define SPOOL_RPM_LO 800
#define SPOOL_RPM_HI 2200
#define SPOOL_RPM_STEP 200
#define SPOOL_TIME 6.0      /* [s] of each spool-up; boost settles in ~2-4 s */
/* The idle point the stored spool-ups (sim/data/engine_maps/<variant>_spool.csv,
 * hence /engine/pb_* and spool_lag) were made from. NOT the launch's idle
 * state: ts_powertrain_idle_start idles at /driveline/launch_engine_speed
 * (68.07 rad/s) against the converter at stall, (w / K0)^2 = 799 N*m with
 * K0 = /driveline/tc_k_factor[0] (tests/sim/test_engine_idle.c: 800 N*m).
 * Kept so that the stored tables stay reproducible; taking the point from the
 * driveline config means regenerating the spool CSVs and the pb_* tables. */
#define IDLE_RPM 650.0    /* [rpm] */
#define IDLE_TORQUE 313.0 /* [N*m] */

/* --spool: crank-angle spool-up transients at held speed (see the header). */
static int spool(const ts_engine *e, const ts_config *cfg, const char *out)
{
    ts_err err;
    size_t nx = (size_t)ts_engine_nstate(e);
    double *x0 = calloc(nx, sizeof *x0), *x = calloc(nx, sizeof *x);
    double *work = malloc(sizeof(double) * ts_engine_work_size(e));
    FILE *f = NULL;
    int rc = TSC_EXIT_FAIL;
    if (!x0 || !x || !work) {
        fprintf(stderr, "tanksim engine-map: out of memory\n");
        goto done;
    }
    double p_amb = cfg->driveline.ambient_pressure, T_amb = cfg->driveline.ambient_temperature;
    if (ts_engine_idle_state(e, IDLE_RPM * PI / 30, IDLE_TORQUE, p_amb, T_amb, x0, NULL, &err) !=
        TS_OK) {
        tsc_print_err("engine-map", &err);
        goto done;
    }
    f = fopen(out, "w");
    if (!f) {
        fprintf(stderr, "tanksim engine-map: cannot write %s\n", out);
        goto done;
    }
    fprintf(f, "speed_rpm [rpm],time [s],speed [rad/s],boost [Pa],intake_temp [K],fuel_flow [kg/s],"
               "air_flow [kg/s],indicated_torque [N*m],friction_torque [N*m],brake_torque [N*m],"
               "exhaust_temp [K],turbo_speed [rad/s],eta_v [1],eta_i [1],q_wall [1]\n");
    ts_engine_inputs in = {.rack = cfg->control.rack, .fuel_per_cycle = -1, .p_amb = p_amb,
                           .T_amb = T_amb, .hold_speed = 1};
    for (int rpm = SPOOL_RPM_LO; rpm <= SPOOL_RPM_HI; rpm += SPOOL_RPM_STEP) {
        double w = rpm * PI / 30;
        memcpy(x, x0, nx * sizeof *x);
        x[TS_ENGINE_X_SPEED] = w;
        double t = 0;
        while (t < SPOOL_TIME) {
            ts_engine_cycle c;
            if (ts_engine_cycle_run(e, x, &in, work, &c, &err) != TS_OK) {
                tsc_print_err("engine-map", &err);
                goto done;
            }
            t += 4 * PI / w;
            fprintf(f, "%d,%.4f,%.4f,%.0f,%.1f,%.6f,%.5f,%.2f,%.2f,%.2f,%.1f,%.0f,%.4f,%.4f,%.4f\n", rpm,
                    t, w, c.mean.boost, c.mean.intake_temp, c.mean.fuel_flow, c.mean.air_flow,
                    c.mean.indicated_torque, c.mean.friction_torque, c.mean.brake_torque,
                    c.mean.exhaust_temp, c.mean.turbo_speed, c.eta_v, c.eta_i, c.q_wall);
        }
        fprintf(stderr, "  spool %4d rpm done\n", rpm);
    }
    rc = TSC_EXIT_OK;
done:
    if (f && fclose(f) != 0) rc = TSC_EXIT_FAIL;
    free(x0);
    free(x);
    free(work);
    return rc;
}

int tsc_cmd_engine_map(int argc, char **argv)
{
    const char *out = tsc_option(argc, argv, "--out");
    const char *spool_out = tsc_option(argc, argv, "--spool");
    ts_config cfg;
    int lrc = tsc_load_config(argc, argv, &cfg, NULL);
    if (lrc != TSC_EXIT_OK) return lrc;
    if (!out && !spool_out) {
        fprintf(stderr, "tanksim engine-map: --out FILE.csv is required\n");
        return TSC_EXIT_USAGE;
    }
    ts_err err;
    ts_engine *e = ts_engine_make(&cfg, &err);
    if (!e) {
        tsc_print_err("engine-map", &err);
        return TSC_EXIT_FAIL;
    }
    if (spool_out) {
        int src = spool(e, &cfg, spool_out);
        ts_engine_free(e);
        return src;
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
    ts_engine_inputs in = {.rack = cfg.control.rack, .fuel_per_cycle = -1,
                           .p_amb = cfg.driveline.ambient_pressure,
                           .T_amb = cfg.driveline.ambient_temperature, .hold_speed = 1};
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
