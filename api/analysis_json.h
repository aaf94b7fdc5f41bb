/*
 * analysis_json.h — the two off-line analyses as JSON documents, for
 * `tanksim engine-map` / `tanksim tune` and the daemon's routes:
 *
 * Engine map (paper Section III.B.3, Fig. 18; sim/engine_sweep.h):
 *   {"variant", "fidelity", "rack",
 *    "columns": [{"name": "speed_rpm", "unit": "rpm"}, ...],   (tsa_engine_map_columns)
 *    "rows": [[800, ...], ..., [2100, ...]],                   (ascending speed)
 *    "rated": {"speed_rpm", "power_w", "power_hp", "torque"}}  (the 2100-rpm row)
 * IVS tuning (Section IV.B.1, Eqs. 11-12, Fig. 26-27; sim/ivs_tune.h):
 *   {"plant", "engine_fidelity", "rack_low", "rack_rated", "v0", "vb", "settle_slope",
 *    "final_slope", "t_inflection", "slope", "x", "y", "kp_norm", "kp", "ti", "kp_factor",
 * "ti_factor", "units": {...}, "schedule": {"var", "x": [...], "kp": [...], "ti": [...]}}
 *   t_inflection is measured from the rack step; "schedule" only with a schedule; its
 *   arrays fit /control/schedule_*. All numbers SI, at full double precision.
 */
#ifndef TSA_ANALYSIS_JSON_H
#define TSA_ANALYSIS_JSON_H

#include <jansson.h>

#include "../sim/config.h"
#include "../sim/engine.h"
#include "../sim/errors.h"
#include "../sim/model.h"

/* One column of the engine map: the JSON "columns" entry, the CSV header
 * "name [unit]" and the CSV cell printf(format, get(c, rpm)). */
typedef struct tsa_engine_map_column {
    const char *name;   /* "torque" */
    const char *unit;   /* "N*m" */
    const char *format; /* printf conversion of one double for the CSV cell ("%.2f") */
    int integer;        /* 1: a whole number (speed_rpm, cycles), a JSON integer */
    double (*get)(const ts_engine_cycle *c, int rpm); /* value at that steady state */
} tsa_engine_map_column;

#define TSA_ENGINE_MAP_NCOLUMN 19

/* The engine map's columns in document and CSV order (static data). */
extern const tsa_engine_map_column tsa_engine_map_columns[TSA_ENGINE_MAP_NCOLUMN];

/* Fig. 18 full-load sweep as JSON. New reference, or NULL with err filled:
 * ts_engine_full_load_sweep's errors (TS_ERR_CANCELLED if progress, which may be
 * NULL and is called with total 14 after each speed, returned non-zero). */
json_t *tsa_engine_map_json(const ts_config *cfg, ts_progress_fn progress, void *ud, ts_err *err);

/* Eqs. 11-12 tuning, optionally a Fig. 27 schedule: var "mass" [kg] or "grade" [rad]
 * (NULL: none), x[n] values, n <= TSA_TUNE_SCHEDULE_MAX (16). */
#define TSA_TUNE_SCHEDULE_MAX 16
/* New reference, or NULL with err filled: ts_ivs_tune's errors; TS_ERR_CANCELLED
 * if progress (may be NULL; called with total 1 + n after the base tune and after
 * each schedule point, and every few samples of each tune's runs with the parts
 * done so far, to ask whether to stop) returned non-zero; TS_ERR_PARAM for a var other than
 * "mass"/"grade" with n > 0, n outside 0..16 or x NULL with n > 0; TS_ERR_RANGE
 * (pointer /vehicle/mass or /vehicle/grade) for a schedule value outside that
 * field's range, checked before anything runs. */
json_t *tsa_tune_json(const ts_config *cfg, const char *var, const double *x, int n,
                      ts_progress_fn progress, void *ud, ts_err *err);

/* The refusals of cfg that tsa_engine_map_json ("engine-map") or tsa_tune_json
 * ("tune") would make, without running anything: TS_OK or their error. */
TS_MUST_CHECK ts_rc tsa_analysis_check(const ts_config *cfg, const char *command, ts_err *err);

/* Read a schedule typed as text, "X1,X2,..." (the CLI's --schedule-mass, the
 * daemon's ?schedule_mass=), for var "mass" or "grade": 1 to
 * TSA_TUNE_SCHEDULE_MAX plain decimals (tsa_is_decimal), each within the
 * range of /vehicle/mass or /vehicle/grade, into x[*n]. TS_ERR_PARAM with
 * that field's pointer and a message saying what is expected (not the text,
 * which the caller quotes) otherwise. */
TS_MUST_CHECK ts_rc tsa_tune_schedule_parse(const char *text, const char *var, double *x, int *n,
                                            ts_err *err);

#endif
