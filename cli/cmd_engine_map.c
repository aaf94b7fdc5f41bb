/*
 * cmd_engine_map.c — "tanksim engine-map CONFIG.json --out FILE.csv": the
 * engine's full-load curve on a dynamometer (paper Section III.B.3, Fig. 18):
 * steady states at 2100, 2000, ..., 800 rpm (a lug-down from rated, each point
 * started from the previous one), rack from /control/rack, the configured
 * variant and fidelity. Writes one row per speed, ascending, with units in the
 * header. These rows are what /engine/map_* in engine.json are made from.
 *
 * With --spool FILE.csv (instead of --out): the turbo spool-up of a launch instead, the part-boost
 * source of the mean-value and map fidelities (tools/engine_maps.py). The engine starts from an
 * idle steady state (ts_engine_idle_state at IDLE_RPM against IDLE_TORQUE: idle-warm walls, idle
 * turbo), the crank is then held at each of 800, 1000, ..., 2200 rpm and the rack stepped to
 * /control/rack; one row per engine cycle for SPOOL_TIME seconds, real rotor inertia and wall
 * capacities (the walls warm up as in a launch). Columns: time, speed, the cycle means and eta_v,
 * eta_i, q_wall. Ambient: /driveline/ambient_pressure and ambient_temperature (the air the vehicle
 * runs' engine breathes).
 *
 * The full-load sweep is sim/engine_sweep.c and its columns (name, unit,
 * format) are api/analysis_json.c's table, shared with the daemon's JSON
 * document; this file writes them as CSV. The spool-ups are only here.
 *
 * Beside either CSV goes a sidecar, its name with ".json" added (FILE.csv ->
 * FILE.csv.json: not FILE.json, which is often the config the map was made
 * from, e.g. tools/wastegate_sweep.py's), saying what produced it, as run's
 * summary.json does: {"kind": "engine_map" | "engine_spool", "csv", "variant",
 * "fidelity", "rack", "ambient_pressure", "ambient_temperature", (the spool-ups:
 * "idle_speed_rpm", "idle_torque", "spool_time"), "units", "columns": [{"name",
 * "unit"}], "config": the resolved config echo}. The CSV stays as it was (its
 * readers: tools/engine_maps.py, tools/wastegate_sweep.py, the tests). The two
 * are put in place together; a CSV written to a device or pipe (/dev/stdout)
 * has no sidecar.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../api/analysis_json.h"
#include "../sim/constants.h"
#include "../sim/engine.h"
#include "../sim/engine_sweep.h"
#include "cli.h"

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

/* The spool-ups' CSV columns, in order (the map's column type; each row's
 * values are computed in place, so no get). */
static const tsa_engine_map_column spool_columns[] = {
    {"speed_rpm", "rpm", "%.0f", 1, NULL},
    {"time", "s", "%.4f", 0, NULL},
    {"speed", "rad/s", "%.4f", 0, NULL},
    {"boost", "Pa", "%.0f", 0, NULL},
    {"intake_temp", "K", "%.1f", 0, NULL},
    {"fuel_flow", "kg/s", "%.6f", 0, NULL},
    {"air_flow", "kg/s", "%.5f", 0, NULL},
    {"indicated_torque", "N*m", "%.2f", 0, NULL},
    {"friction_torque", "N*m", "%.2f", 0, NULL},
    {"brake_torque", "N*m", "%.2f", 0, NULL},
    {"exhaust_temp", "K", "%.1f", 0, NULL},
    {"turbo_speed", "rad/s", "%.0f", 0, NULL},
    {"eta_v", "1", "%.4f", 0, NULL},
    {"eta_i", "1", "%.4f", 0, NULL},
    {"q_wall", "1", "%.4f", 0, NULL},
};
#define NSPOOL_COLUMN ((int)(sizeof spool_columns / sizeof spool_columns[0]))

/* A CSV header "name [unit],..." of n columns. */
static void put_header(FILE *f, const tsa_engine_map_column *cols, int n)
{
    for (int j = 0; j < n; j++)
        fprintf(f, "%s%s [%s]", j ? "," : "", cols[j].name, cols[j].unit);
    fputc('\n', f);
}

/* A CSV row of n values in their columns' formats; a value the fidelity does
 * not model (NaN) is an empty cell. */
static void put_cells(FILE *f, const tsa_engine_map_column *cols, const double *v, int n)
{
    for (int j = 0; j < n; j++) {
        if (j) fputc(',', f);
        if (isfinite(v[j])) fprintf(f, cols[j].format, v[j]);
    }
    fputc('\n', f);
}

#define NSPOOL_SPEED ((SPOOL_RPM_HI - SPOOL_RPM_LO) / SPOOL_RPM_STEP + 1)

/* --spool: crank-angle spool-up transients at held speed (see the header), as
 * CSV rows into f. Progress through cli.h's tsc_progress, as run's and tune's:
 * a line per spool-up done after the first 2 s (the crank-angle spool-ups take
 * ~1 s each; the other fidelities are done before then), the last one always
 * once lines were shown. Nothing reads these lines (the sweep's are read). */
static int spool(const ts_engine *e, const ts_config *cfg, FILE *f)
{
    ts_err err;
    tsc_progress prog;
    tsc_progress_start(&prog, "engine-map", 0);
    size_t nx = (size_t)ts_engine_nstate(e);
    double *x0 = calloc(nx, sizeof *x0), *x = calloc(nx, sizeof *x);
    double *work = malloc(sizeof(double) * ts_engine_work_size(e));
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
    put_header(f, spool_columns, NSPOOL_COLUMN);
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
                tsc_progress_end(&prog); /* a redrawn line ends before the error */
                tsc_print_err("engine-map", &err);
                goto done;
            }
            t += 4 * PI / w;
            const double v[] = {rpm,
                                t,
                                w,
                                c.mean.boost,
                                c.mean.intake_temp,
                                c.mean.fuel_flow,
                                c.mean.air_flow,
                                c.mean.indicated_torque,
                                c.mean.friction_torque,
                                c.mean.brake_torque,
                                c.mean.exhaust_temp,
                                c.mean.turbo_speed,
                                c.eta_v,
                                c.eta_i,
                                c.q_wall};
            _Static_assert(sizeof v / sizeof v[0] == NSPOOL_COLUMN, "one value per column");
            put_cells(f, spool_columns, v, NSPOOL_COLUMN);
        }
        int k = (rpm - SPOOL_RPM_LO) / SPOOL_RPM_STEP + 1;
        double wall;
        if (tsc_progress_due(&prog, &wall, k == NSPOOL_SPEED))
            tsc_progress_say(&prog, "spool-up at %d rpm done (%d of %d), %.0f %%, %.1f s wall", rpm,
                             k, NSPOOL_SPEED, 100.0 * k / NSPOOL_SPEED, wall);
    }
    tsc_progress_end(&prog);
    rc = TSC_EXIT_OK;
done:
    free(x0);
    free(x);
    free(work);
    return rc;
}

/* ts_progress_fn of the sweep: one line per speed on stderr, from rated down.
 * Not through tsc_progress: these lines are the map's results as they come
 * (speed, torque, power: a table on a terminal), every one of them printed
 * at once, and tools/wastegate_sweep.py reads the first (rated power) and
 * stops the run there. The helper would hold the first 2 s back (the whole
 * mean-value sweep, most of a crank-angle one), print rows only as due and
 * redraw them over each other on a terminal. */
static int sweep_progress(void *ud, int done, int total)
{
    const ts_engine_cycle *rows = ud;
    int k = total - done; /* the row just finished (engine_sweep.h) */
    int rpm = TS_ENGINE_SWEEP_RPM_LO + k * TS_ENGINE_SWEEP_RPM_STEP;
    double w = rpm * PI / 30;
    fprintf(stderr, "  %4d rpm  %7.1f N*m  %7.1f kW\n", rpm, rows[k].mean.brake_torque,
            rows[k].mean.brake_torque * w / 1e3);
    return 0;
}

/* The sweep's rows as CSV, ascending speed, columns as in the JSON document. */
static void write_csv(FILE *f, const ts_engine_cycle *rows)
{
    put_header(f, tsa_engine_map_columns, TSA_ENGINE_MAP_NCOLUMN);
    for (int k = 0; k < TS_ENGINE_SWEEP_NPOINT; k++) {
        int rpm = TS_ENGINE_SWEEP_RPM_LO + k * TS_ENGINE_SWEEP_RPM_STEP;
        double v[TSA_ENGINE_MAP_NCOLUMN];
        for (int j = 0; j < TSA_ENGINE_MAP_NCOLUMN; j++)
            v[j] = tsa_engine_map_columns[j].get(&rows[k], rpm);
        put_cells(f, tsa_engine_map_columns, v, TSA_ENGINE_MAP_NCOLUMN);
    }
}

/* The sidecar document (see the header); NULL when out of memory. */
static json_t *sidecar_doc(const ts_config *cfg, json_t *resolved, const char *csv, int spool_ups)
{
    const char *base = strrchr(csv, '/');
    json_t *cols = json_array();
    const tsa_engine_map_column *col = spool_ups ? spool_columns : tsa_engine_map_columns;
    int n = spool_ups ? NSPOOL_COLUMN : TSA_ENGINE_MAP_NCOLUMN;
    for (int j = 0; cols && j < n; j++) {
        if (json_array_append_new(
                cols, json_pack("{s:s, s:s}", "name", col[j].name, "unit", col[j].unit)) != 0) {
            json_decref(cols);
            return NULL;
        }
    }
    /* jansson steals "o" references even when the pack fails */
    json_t *doc =
        json_pack("{s:s, s:s, s:s, s:s, s:f, s:f, s:f, s:{s:s, s:s, s:s}, s:o, s:O}", "kind",
                  spool_ups ? "engine_spool" : "engine_map", "csv", base ? base + 1 : csv,
                  "variant", ts_engine_variant_names[cfg->engine.variant], "fidelity",
                  ts_engine_fidelity_names[cfg->engine.fidelity], "rack", cfg->control.rack,
                  "ambient_pressure", cfg->driveline.ambient_pressure, "ambient_temperature",
                  cfg->driveline.ambient_temperature, "units", "rack", "1", "ambient_pressure",
                  "Pa", "ambient_temperature", "K", "columns", cols, "config", resolved);
    if (doc && spool_ups) {
        json_t *units = json_object_get(doc, "units");
        if (json_object_set_new(doc, "idle_speed_rpm", json_real(IDLE_RPM)) != 0 ||
            json_object_set_new(doc, "idle_torque", json_real(IDLE_TORQUE)) != 0 ||
            json_object_set_new(doc, "spool_time", json_real(SPOOL_TIME)) != 0 ||
            json_object_set_new(units, "idle_speed_rpm", json_string("rpm")) != 0 ||
            json_object_set_new(units, "idle_torque", json_string("N*m")) != 0 ||
            json_object_set_new(units, "spool_time", json_string("s")) != 0) {
            json_decref(doc);
            return NULL;
        }
    }
    return doc;
}

/* Put the sidecar (side->f NULL: none), then the CSV in place, or abandon
 * both when !complete: a new CSV never stands without its record. When the
 * CSV then fails, the new sidecar is removed again (it would describe a CSV
 * that is not there). TSC_EXIT_OK or TSC_EXIT_FAIL (said on stderr). */
static int close_pair(tsc_out *csv, tsc_out *side, int complete)
{
    if (!side->f) return tsc_out_close(csv, complete);
    if (tsc_out_close(side, complete) != TSC_EXIT_OK) {
        tsc_out_close(csv, 0);
        if (complete) fprintf(stderr, "tanksim engine-map: %s not written either\n", csv->path);
        return TSC_EXIT_FAIL;
    }
    if (tsc_out_close(csv, 1) == TSC_EXIT_OK) return TSC_EXIT_OK;
    if (!side->direct && unlink(side->path) != 0 && errno != ENOENT)
        fprintf(stderr, "tanksim engine-map: cannot remove %s: %s\n", side->path, strerror(errno));
    return TSC_EXIT_FAIL;
}

int tsc_cmd_engine_map(int argc, char **argv)
{
    const char *out = tsc_option(argc, argv, "--out");
    const char *spool_out = tsc_option(argc, argv, "--spool");
    ts_config cfg;
    json_t *resolved = NULL;
    int rc = tsc_load_config(argc, argv, &cfg, &resolved);
    if (rc != TSC_EXIT_OK) return rc;
    if (!out == !spool_out) { /* the usage's alternatives: one of them */
        fprintf(stderr, "tanksim engine-map: %s\n",
                out ? "give --out FILE.csv (the map) or --spool FILE.csv (the spool-ups), not both"
                    : "--out FILE.csv (the map) or --spool FILE.csv (the spool-ups) is required");
        json_decref(resolved);
        return TSC_EXIT_USAGE;
    }
    const char *path = spool_out ? spool_out : out;
    ts_err err;
    ts_engine *e = NULL;
    tsc_out o = {0}, side = {0};
    char side_path[sizeof o.tmp + 8]; /* tsc_out_open refuses what does not fit its tmp */
    json_t *doc = NULL;
    rc = TSC_EXIT_FAIL;
    if (spool_out && !(e = ts_engine_make(&cfg, &err))) {
        tsc_print_err("engine-map", &err);
        goto done;
    }
    /* both opened before the long work, so a bad path fails at once */
    if (tsc_out_open(&o, path, "engine-map", 0) != 0) goto done;
    snprintf(side_path, sizeof side_path, "%s.json", path);
    if (!o.direct && tsc_out_open(&side, side_path, "engine-map", 0) != 0) goto done;
    if (spool_out) {
        rc = spool(e, &cfg, o.f);
    } else {
        ts_engine_cycle rows[TS_ENGINE_SWEEP_NPOINT];
        if (ts_engine_full_load_sweep(&cfg, rows, sweep_progress, rows, &err) != TS_OK)
            tsc_print_err("engine-map", &err);
        else {
            write_csv(o.f, rows);
            rc = TSC_EXIT_OK;
        }
    }
    if (rc == TSC_EXIT_OK && side.f) {
        /* a sidecar that fails takes the CSV with it: neither is put in place */
        doc = sidecar_doc(&cfg, resolved, path, spool_out != NULL);
        if (!doc || tsc_out_json(&side, doc) != 0) {
            fprintf(stderr, "tanksim engine-map: cannot write %s; %s not written either\n",
                    side_path, path);
            rc = TSC_EXIT_FAIL;
        }
    }
done:
    if (o.f)
        rc = close_pair(&o, &side, rc == TSC_EXIT_OK);
    else if (side.f)
        tsc_out_close(&side, 0);
    json_decref(doc);
    json_decref(resolved);
    ts_engine_free(e);
    return rc;
}
