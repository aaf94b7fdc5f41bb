/*
 * analysis_json.c — the engine map (Fig. 18) and the IVS tuning (Eqs. 11-12,
 * Fig. 27) as JSON documents (analysis_json.h), shared by `tanksim
 * engine-map` / `tanksim tune` (cli/cmd_engine_map.c, cli/cmd_tune.c) and the
 * daemon. The computations are in sim/engine_sweep.c and sim/ivs_tune.c; the
 * tuning document was moved here from cli/cmd_tune.c unchanged in content,
 * and the engine map's column table is the one the CLI's CSV is written from,
 * so that the command line and the server print the same numbers.
 */
#include "analysis_json.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../sim/constants.h"
#include "../sim/engine_sweep.h"
#include "../sim/ivs_tune.h"
#include "../sim/param.h"
#include "config_json.h"
#include "session_json.h"

/* ---- engine map ---- */

/* Crank speed [rad/s] at rpm, as the sweep sets it (sim/engine_sweep.c). */
static double omega(int rpm)
{
    return rpm * TS_PI / 30;
}

/* Column getters: the value of one column at a steady state. */
static double col_speed_rpm(const ts_engine_cycle *c, int rpm)
{
    (void)c;
    return rpm;
}
static double col_speed(const ts_engine_cycle *c, int rpm)
{
    (void)c;
    return omega(rpm);
}
static double col_power(const ts_engine_cycle *c, int rpm)
{
    return c->mean.brake_torque * omega(rpm);
}
/* Getters of one field of the steady cycle. */
#define FIELD_GETTER(fname, expr)                                                                  \
    static double fname(const ts_engine_cycle *c, int rpm)                                         \
    {                                                                                              \
        (void)rpm;                                                                                 \
        return (expr);                                                                             \
    }
FIELD_GETTER(col_torque, c->mean.brake_torque)
FIELD_GETTER(col_bsfc, c->bsfc * 3.6e9) /* kg/J -> g/kWh */
FIELD_GETTER(col_boost, c->mean.boost)
FIELD_GETTER(col_exhaust_temp, c->mean.exhaust_temp)
FIELD_GETTER(col_peak_pressure, c->peak_pressure)
FIELD_GETTER(col_fuel_flow, c->mean.fuel_flow)
FIELD_GETTER(col_air_flow, c->mean.air_flow)
FIELD_GETTER(col_phi, c->mean.phi)
FIELD_GETTER(col_intake_temp, c->mean.intake_temp)
FIELD_GETTER(col_turbo_speed, c->mean.turbo_speed)
FIELD_GETTER(col_eta_v, c->eta_v)
FIELD_GETTER(col_eta_i, c->eta_i)
FIELD_GETTER(col_q_wall, c->q_wall)
FIELD_GETTER(col_energy_residual, c->energy_residual)
FIELD_GETTER(col_mass_residual, c->mass_residual)
FIELD_GETTER(col_cycles, c->cycles)
#undef FIELD_GETTER

const tsa_engine_map_column tsa_engine_map_columns[TSA_ENGINE_MAP_NCOLUMN] = {
    {"speed_rpm", "rpm", "%.0f", 1, col_speed_rpm},
    {"speed", "rad/s", "%.4f", 0, col_speed},
    {"torque", "N*m", "%.2f", 0, col_torque},
    {"power", "W", "%.1f", 0, col_power},
    {"bsfc", "g/kWh", "%.2f", 0, col_bsfc},
    {"boost", "Pa", "%.0f", 0, col_boost},
    {"exhaust_temp", "K", "%.1f", 0, col_exhaust_temp},
    {"peak_pressure", "Pa", "%.0f", 0, col_peak_pressure},
    {"fuel_flow", "kg/s", "%.6f", 0, col_fuel_flow},
    {"air_flow", "kg/s", "%.5f", 0, col_air_flow},
    {"phi", "1", "%.4f", 0, col_phi},
    {"intake_temp", "K", "%.1f", 0, col_intake_temp},
    {"turbo_speed", "rad/s", "%.0f", 0, col_turbo_speed},
    {"eta_v", "1", "%.4f", 0, col_eta_v},
    {"eta_i", "1", "%.4f", 0, col_eta_i},
    {"q_wall", "1", "%.4f", 0, col_q_wall},
    {"energy_residual", "1", "%.3e", 0, col_energy_residual},
    {"mass_residual", "1", "%.3e", 0, col_mass_residual},
    {"cycles", "1", "%.0f", 1, col_cycles},
};

/* Fill err for a document jansson could not build; NULL for the caller to return. */
static json_t *no_json(ts_err *err, const char *what)
{
    ts_err_set(err, TS_ERR_NOMEM, NULL, "%s: out of memory building the JSON document", what);
    return NULL;
}

/* A number for the document: an integer column as an integer, a non-finite
 * value (e.g. bsfc at zero brake power) as null. NULL only when out of memory. */
static json_t *number(double v, int integer)
{
    return integer && isfinite(v) ? json_integer((json_int_t)llround(v)) : tsa_json_real(v);
}

/* Append a new value to an array (a NULL value or array fails); 0 on success. */
static int append(json_t *a, json_t *v)
{
    if (!v) return -1;
    return json_array_append_new(a, v);
}

/* The document from a finished sweep. */
static json_t *engine_map_doc(const ts_config *cfg, const ts_engine_cycle *rows, ts_err *err)
{
    /* the sweep validated cfg, enum indices included */
    const char *variant = ts_engine_variant_names[cfg->engine.variant];
    const char *fidelity = ts_engine_fidelity_names[cfg->engine.fidelity];
    json_t *cols = json_array(), *jrows = json_array();
    int bad = !cols || !jrows;
    for (int j = 0; !bad && j < TSA_ENGINE_MAP_NCOLUMN; j++) {
        const tsa_engine_map_column *col = &tsa_engine_map_columns[j];
        bad = append(cols, json_pack("{s:s, s:s}", "name", col->name, "unit", col->unit)) != 0;
    }
    for (int k = 0; !bad && k < TS_ENGINE_SWEEP_NPOINT; k++) {
        int rpm = TS_ENGINE_SWEEP_RPM_LO + k * TS_ENGINE_SWEEP_RPM_STEP;
        json_t *row = json_array();
        bad = append(jrows, row) != 0;
        for (int j = 0; !bad && j < TSA_ENGINE_MAP_NCOLUMN; j++) {
            const tsa_engine_map_column *col = &tsa_engine_map_columns[j];
            bad = append(row, number(col->get(&rows[k], rpm), col->integer)) != 0;
        }
    }
    if (bad) {
        json_decref(cols);
        json_decref(jrows);
        return no_json(err, "engine map");
    }
    const ts_engine_cycle *r = &rows[TS_ENGINE_SWEEP_NPOINT - 1]; /* rated speed */
    double power = col_power(r, TS_ENGINE_SWEEP_RPM_HI);
    /* jansson steals "o" references even when the pack fails */
    json_t *doc = json_pack(
        "{s:s, s:s, s:f, s:o, s:o, s:{s:i, s:o, s:o, s:o, s:{s:s, s:s, s:s, s:s}}}", "variant",
        variant, "fidelity", fidelity, "rack", cfg->control.rack, "columns", cols, "rows", jrows,
        "rated", "speed_rpm", TS_ENGINE_SWEEP_RPM_HI, "power_w", number(power, 0), "power_hp",
        number(power / TS_HP, 0), "torque", number(r->mean.brake_torque, 0), "units", "speed_rpm",
        "rpm", "power_w", "W", "power_hp", "hp", "torque", "N*m");
    return doc ? doc : no_json(err, "engine map");
}

ts_rc tsa_analysis_check(const ts_config *cfg, const char *command, ts_err *err)
{
    return strcmp(command, "tune") == 0 ? ts_ivs_tune_check(cfg, err)
                                        : ts_engine_full_load_sweep_check(cfg, err);
}

json_t *tsa_engine_map_json(const ts_config *cfg, ts_progress_fn progress, void *ud, ts_err *err)
{
    ts_engine_cycle rows[TS_ENGINE_SWEEP_NPOINT];
    if (ts_engine_full_load_sweep(cfg, rows, progress, ud, err) != TS_OK) return NULL;
    return engine_map_doc(cfg, rows, err);
}

/* ---- IVS tuning ---- */

/* The tuning document without its schedule (as `tanksim tune` printed it). */
static json_t *tune_doc(const ts_config *cfg, const char *fidelity, const ts_ivs_tune_result *o,
                        ts_err *err)
{
    json_t *doc = json_pack(
        "{s:s, s:s, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f}",
        "plant", "pointmass+powertrain", "engine_fidelity", fidelity, "rack_low",
        cfg->control.tune_rack_low, "rack_rated", 1.0, "v0", o->v0, "vb", o->vb, "settle_slope",
        o->settle_slope, "final_slope", o->final_slope, "t_inflection",
        o->zn.t_inflection - cfg->control.tune_settle, "slope", o->zn.slope, "x", o->zn.x, "y",
        o->zn.y, "kp_norm", o->zn.kp_norm, "kp", o->kp, "ti", o->zn.ti, "kp_factor",
        cfg->control.kp_factor, "ti_factor", cfg->control.ti_factor);
    json_t *units =
        json_pack("{s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s}", "rack_low", "1",
                  "rack_rated", "1", "v0", "m/s", "vb", "m/s", "settle_slope", "m/s^2",
                  "final_slope", "m/s^2", "t_inflection", "s", "slope", "1/s", "x", "s", "y", "1",
                  "kp_norm", "1", "kp", "1/(m/s)", "ti", "s", "kp_factor", "1", "ti_factor", "1");
    if (!doc || json_object_set_new(doc, "units", units) != 0) {
        json_decref(doc);
        return no_json(err, "tune");
    }
    return doc;
}

/* The "schedule" block: one tune per x[i] with the mass (or grade) set to it. */
static json_t *schedule_doc(const ts_config *cfg, int mass, const double *x, int n,
                            ts_progress_fn progress, void *ud, ts_err *err)
{
    json_t *jx = json_array(), *jk = json_array(), *jt = json_array();
    for (int i = 0; i < n; i++) {
        ts_config c = *cfg;
        if (mass)
            c.vehicle.mass = x[i];
        else
            c.vehicle.grade = x[i];
        ts_ivs_tune_result o;
        ts_rc rc = ts_ivs_tune_polled(&c, &o, progress, ud, 1 + i, 1 + n, err);
        if (rc == TS_OK && (append(jx, json_real(x[i])) != 0 || append(jk, json_real(o.kp)) != 0 ||
                            append(jt, json_real(o.zn.ti)) != 0)) {
            no_json(err, "tune");
            rc = TS_ERR_NOMEM;
        }
        if (rc == TS_OK && progress && progress(ud, 2 + i, 1 + n) != 0)
            rc = ts_err_set(err, TS_ERR_CANCELLED, NULL,
                            "tune: cancelled after %d of %d schedule points", i + 1, n);
        if (rc != TS_OK && rc != TS_ERR_CANCELLED && rc != TS_ERR_NOMEM && err) {
            /* say which point of the schedule failed (it did not) */
            char why[sizeof err->msg];
            memcpy(why, err->msg, sizeof why);
            snprintf(err->msg, sizeof err->msg, "schedule point %d of %d (%s %g): %.300s", i + 1, n,
                     mass ? "mass" : "grade", x[i], why);
        }
        if (rc != TS_OK) {
            json_decref(jx);
            json_decref(jk);
            json_decref(jt);
            return NULL;
        }
    }
    json_t *s = json_pack("{s:s, s:o, s:o, s:o, s:{s:s, s:s, s:s}}", "var", mass ? "mass" : "grade",
                          "x", jx, "kp", jk, "ti", jt, "units", "x", mass ? "kg" : "rad", "kp",
                          "1/(m/s)", "ti", "s");
    return s ? s : no_json(err, "tune");
}

/* The config field a schedule variable sets, or NULL for another name. */
static const ts_param *schedule_field(const char *var)
{
    if (var && strcmp(var, "mass") == 0) return ts_param_find("/vehicle/mass");
    if (var && strcmp(var, "grade") == 0) return ts_param_find("/vehicle/grade");
    return NULL;
}

ts_rc tsa_tune_schedule_parse(const char *text, const char *var, double *x, int *n, ts_err *err)
{
    const ts_param *field = schedule_field(var);
    *n = 0;
    if (!field)
        return ts_err_set(err, TS_ERR_PARAM, "", "the schedule variable is mass or grade");
    const char *s = text;
    for (;;) {
        const char *end = strchr(s, ',');
        size_t len = end ? (size_t)(end - s) : strlen(s);
        char item[64];
        if (*n == TSA_TUNE_SCHEDULE_MAX || len == 0 || len >= sizeof item) break;
        memcpy(item, s, len);
        item[len] = '\0';
        double v;
        if (tsa_parse_number(item, -DBL_MAX, DBL_MAX, &v) != 0 ||
            ts_param_check_number(field, v, NULL) != TS_OK)
            break;
        if (*n > 0 && !(v > x[*n - 1])) /* /control/schedule_x must increase (ivs_controller.c) */
            return ts_err_set(err, TS_ERR_PARAM, field->pointer,
                              "the %s values must increase (they become /control/schedule_x), "
                              "got %g after %g",
                              field->pointer, v, x[*n - 1]);
        x[(*n)++] = v;
        if (!end) return TS_OK;
        s = end + 1;
    }
    return ts_err_set(err, TS_ERR_PARAM, field->pointer,
                      "1 to %d comma-separated numbers in [%g, %g] %s (the range of %s) "
                      "expected",
                      TSA_TUNE_SCHEDULE_MAX, field->min, field->max, field->unit, field->pointer);
}

json_t *tsa_tune_json(const ts_config *cfg, const char *var, const double *x, int n,
                      ts_progress_fn progress, void *ud, ts_err *err)
{
    if (n < 0 || n > TSA_TUNE_SCHEDULE_MAX) {
        ts_err_set(err, TS_ERR_PARAM, "", "tune: a schedule has 0 to %d points, got %d",
                   TSA_TUNE_SCHEDULE_MAX, n);
        return NULL;
    }
    const ts_param *field = n > 0 ? schedule_field(var) : NULL;
    if (n > 0 && !field) {
        ts_err_set(err, TS_ERR_PARAM, "",
                   "tune: the schedule variable is \"mass\" or \"grade\", got %s%s%s",
                   var ? "\"" : "", var ? var : "none", var ? "\"" : "");
        return NULL;
    }
    if (n > 0 && !x) {
        ts_err_set(err, TS_ERR_PARAM, "", "tune: %d schedule values expected, got none", n);
        return NULL;
    }
    /* what ts_model_make would refuse after the base tune, refused before it */
    for (int i = 0; i < n; i++)
        if (ts_param_check_number(field, x[i], err) != TS_OK) return NULL;
    ts_ivs_tune_result o;
    if (ts_ivs_tune_polled(cfg, &o, progress, ud, 0, 1 + n, err) != TS_OK)
        return NULL; /* validates cfg; progress may stop it while its runs go */
    if (progress && progress(ud, 1, 1 + n) != 0) {
        ts_err_set(err, TS_ERR_CANCELLED, NULL, "tune: cancelled after the base tune");
        return NULL;
    }
    json_t *doc = tune_doc(cfg, ts_engine_fidelity_names[cfg->engine.fidelity], &o, err);
    if (!doc || n == 0) return doc;
    json_t *sched = schedule_doc(cfg, strcmp(var, "mass") == 0, x, n, progress, ud, err);
    if (!sched) {
        json_decref(doc);
        return NULL;
    }
    if (json_object_set_new(doc, "schedule", sched) != 0) {
        json_decref(doc);
        return no_json(err, "tune");
    }
    return doc;
}
