/*
 * test_analysis_calls.c — the off-line analyses as library calls, as the CLI
 * and the daemon make them: the full-load dynamometer sweep
 * (sim/engine_sweep.h, Fig. 18), the IVS tuning step (sim/ivs_tune.h,
 * Eqs. 11-12) and their JSON documents (api/analysis_json.h), with progress
 * reports and cancellation. The engine runs at the mean-value fidelity here
 * (fast); the crank-angle sweep is tests/cli/test_engine_map.py's and
 * tools/engine_maps.py's.
 */
#include "test_util.h"

#include <stdlib.h>
#include <string.h>

#include "api/analysis_json.h"
#include "api/config_json.h"
#include "sim/constants.h"
#include "sim/tanksim.h"

/* The config of {"preset": preset} or, with preset NULL, the mean-value
 * full-rack dynamometer config of tests/cli/test_engine_map.py. */
static ts_config load(const char *preset)
{
    ts_config c;
    ts_err err;
    json_t *doc = preset ? json_pack("{s:s}", "preset", preset)
                         : json_pack("{s:{s:s}, s:{s:s}, s:{s:f}}", "run", "kind", "engine_dyno",
                                     "engine", "fidelity", "mean_value", "control", "rack", 1.0);
    assert_int_equal(tsa_config_load(doc, &c, NULL, NULL, &err), TS_OK);
    json_decref(doc);
    return c;
}

/* What a ts_progress_fn saw; it asks to stop once done reaches stop_at (0: never). */
typedef struct calls {
    int n, done[32], total[32], stop_at;
} calls;

static int record(void *ud, int done, int total)
{
    calls *c = ud;
    if (c->n < 32) {
        c->done[c->n] = done;
        c->total[c->n] = total;
    }
    c->n++;
    return c->stop_at > 0 && done >= c->stop_at;
}

/* record for a tune: its runs also poll with the parts done so far unchanged
 * (ts_ivs_tune_polled), so only a call that moves the count is a report. */
static int record_parts(void *ud, int done, int total)
{
    calls *c = ud;
    if (done <= (c->n ? c->done[c->n - 1 < 32 ? c->n - 1 : 31] : 0))
        return c->stop_at > 0 && done >= c->stop_at;
    return record(ud, done, total);
}

static double rpm_omega(int rpm)
{
    return rpm * TS_PI / 30;
}

/* EVIDENCE: Fig. 18 full-load curve, mean-value fidelity, rack 1: 14 steady
 * states at 800..2100 rpm, the crank held at each speed (cycle-mean speed =
 * the set speed to 1e-9), power = torque x speed exactly (definition), rated
 * power in the virtual engine's 0.9-1.3 MW class (the paper's ~1100 kW;
 * tolerance as tests/cli/test_engine_map.py, not calibrated here). Progress:
 * once per speed, done = 1..14 of 14. */
static void sweep_rows_and_progress(void **state)
{
    (void)state;
    ts_config cfg = load(NULL);
    ts_engine_cycle rows[TS_ENGINE_SWEEP_NPOINT];
    calls seen = {0};
    ts_err err;
    assert_int_equal(ts_engine_full_load_sweep(&cfg, rows, record, &seen, &err), TS_OK);
    assert_int_equal(TS_ENGINE_SWEEP_NPOINT, 14);
    assert_int_equal(seen.n, TS_ENGINE_SWEEP_NPOINT);
    for (int i = 0; i < seen.n; i++) {
        assert_int_equal(seen.done[i], i + 1);
        assert_int_equal(seen.total[i], TS_ENGINE_SWEEP_NPOINT);
    }
    for (int k = 0; k < TS_ENGINE_SWEEP_NPOINT; k++) {
        int rpm = TS_ENGINE_SWEEP_RPM_LO + k * TS_ENGINE_SWEEP_RPM_STEP;
        assert_close(rows[k].mean.speed, rpm_omega(rpm), 1e-9, 0);
        if (k > 0) assert_true(rows[k].mean.speed > rows[k - 1].mean.speed);
        assert_true(rows[k].mean.brake_torque > 0);
        assert_true(rows[k].cycles >= 1);
    }
    assert_int_equal(TS_ENGINE_SWEEP_RPM_LO + 13 * TS_ENGINE_SWEEP_RPM_STEP,
                     TS_ENGINE_SWEEP_RPM_HI);
    double rated = rows[13].mean.brake_torque * rpm_omega(TS_ENGINE_SWEEP_RPM_HI);
    assert_true(rated > 0.9e6 && rated < 1.3e6);
}

/* EVIDENCE: the Fig. 18 document carries the sweep unchanged: 19 columns
 * (speed_rpm first, integers), 14 ascending rows, power = torque x speed on
 * every row (to 1e-12, definition), rated = the 2100-rpm row, power_hp =
 * power_w / 745.7 W (mechanical hp, 5e-5). Same numbers as a direct sweep
 * (the code is deterministic: bit for bit). */
static void engine_map_document(void **state)
{
    (void)state;
    ts_config cfg = load(NULL);
    ts_err err;
    ts_engine_cycle rows[TS_ENGINE_SWEEP_NPOINT];
    assert_int_equal(ts_engine_full_load_sweep(&cfg, rows, NULL, NULL, &err), TS_OK);
    json_t *doc = tsa_engine_map_json(&cfg, NULL, NULL, &err);
    assert_non_null(doc);
    assert_string_equal(json_string_value(json_object_get(doc, "variant")), "conventional");
    assert_string_equal(json_string_value(json_object_get(doc, "fidelity")), "mean_value");
    assert_close(json_real_value(json_object_get(doc, "rack")), 1.0, 0, 0);
    json_t *cols = json_object_get(doc, "columns"), *jrows = json_object_get(doc, "rows");
    assert_int_equal(json_array_size(cols), TSA_ENGINE_MAP_NCOLUMN);
    int ic[4] = {-1, -1, -1, -1}; /* speed_rpm, speed, torque, power */
    const char *want[4] = {"speed_rpm", "speed", "torque", "power"};
    for (int j = 0; j < TSA_ENGINE_MAP_NCOLUMN; j++) {
        const char *name = json_string_value(json_object_get(json_array_get(cols, j), "name"));
        assert_string_equal(name, tsa_engine_map_columns[j].name);
        assert_string_equal(json_string_value(json_object_get(json_array_get(cols, j), "unit")),
                            tsa_engine_map_columns[j].unit);
        for (int q = 0; q < 4; q++)
            if (strcmp(name, want[q]) == 0) ic[q] = j;
    }
    assert_int_equal(ic[0], 0);
    assert_true(ic[1] >= 0 && ic[2] >= 0 && ic[3] >= 0);
    assert_int_equal(json_array_size(jrows), TS_ENGINE_SWEEP_NPOINT);
    for (int k = 0; k < TS_ENGINE_SWEEP_NPOINT; k++) {
        json_t *r = json_array_get(jrows, k);
        assert_int_equal(json_array_size(r), TSA_ENGINE_MAP_NCOLUMN);
        assert_true(json_is_integer(json_array_get(r, ic[0])));
        assert_int_equal(json_integer_value(json_array_get(r, ic[0])),
                         TS_ENGINE_SWEEP_RPM_LO + k * TS_ENGINE_SWEEP_RPM_STEP);
        double w = json_number_value(json_array_get(r, ic[1]));
        double tq = json_number_value(json_array_get(r, ic[2]));
        double p = json_number_value(json_array_get(r, ic[3]));
        assert_close(p, tq * w, 1e-12, 0);
        assert_true(tq == rows[k].mean.brake_torque);
    }
    json_t *rated = json_object_get(doc, "rated");
    assert_int_equal(json_integer_value(json_object_get(rated, "speed_rpm")), 2100);
    double pw = json_real_value(json_object_get(rated, "power_w"));
    assert_close(pw, rows[13].mean.brake_torque * rpm_omega(2100), 1e-12, 0);
    assert_close(json_real_value(json_object_get(rated, "power_hp")), pw / 745.7, 5e-5, 0);
    assert_close(json_real_value(json_object_get(rated, "torque")), rows[13].mean.brake_torque,
                 1e-12, 0);
    json_decref(doc);
}

/* A progress callback asking to stop after 3 of 14 speeds: TS_ERR_CANCELLED,
 * no further calls, nothing leaked (checked under make asan). */
static void sweep_cancel(void **state)
{
    (void)state;
    ts_config cfg = load(NULL);
    ts_engine_cycle rows[TS_ENGINE_SWEEP_NPOINT];
    calls seen = {.stop_at = 3};
    ts_err err;
    assert_int_equal(ts_engine_full_load_sweep(&cfg, rows, record, &seen, &err), TS_ERR_CANCELLED);
    assert_int_equal(err.code, TS_ERR_CANCELLED);
    assert_int_equal(seen.n, 3);
    calls again = {.stop_at = 3};
    assert_null(tsa_engine_map_json(&cfg, record, &again, &err));
    assert_int_equal(err.code, TS_ERR_CANCELLED);
    assert_int_equal(again.n, 3);
}

/* Engine errors propagate with their pointer: a config ts_engine_make refuses
 * (a gas cp polynomial of 3 coefficients); no progress report. */
static void sweep_engine_error(void **state)
{
    (void)state;
    ts_config cfg = load(NULL);
    cfg.engine.cp_air_n = 3;
    ts_engine_cycle rows[TS_ENGINE_SWEEP_NPOINT];
    calls seen = {0};
    ts_err err;
    assert_int_equal(ts_engine_full_load_sweep(&cfg, rows, record, &seen, &err), TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/engine/cp_air");
    assert_int_equal(seen.n, 0);
    assert_null(tsa_engine_map_json(&cfg, NULL, NULL, &err));
    assert_int_equal(err.code, TS_ERR_PARAM);
}

/* EVIDENCE: Eq. 12 (Ziegler & Nichols 1942 PI rule) on the preset's plant
 * step: K_p = 0.9/|Y| and T_I = ti_factor |X| exactly (1e-12, they are the
 * definitions), K_p in rack per m/s by the Eq. 11 scalings
 * (ts_zn_kp_physical), the rated speed above the low-rack one (Eq. 11
 * normalises by vb - v0), a positive dead time X and a negative Y (Fig. 26:
 * an S-shaped response). */
static void ivs_tune_eq12(void **state)
{
    (void)state;
    ts_config cfg = load("bump-coupled-ivs5mph");
    ts_ivs_tune_result o;
    ts_err err;
    assert_int_equal(ts_ivs_tune(&cfg, &o, &err), TS_OK);
    assert_true(o.vb > o.v0);
    assert_true(o.zn.x > 0 && o.zn.y < 0);
    assert_close(o.zn.kp_norm, 0.9 / fabs(o.zn.y), 1e-12, 0);
    assert_close(o.zn.ti, cfg.control.ti_factor * fabs(o.zn.x), 1e-12, 0);
    assert_close(o.kp, ts_zn_kp_physical(o.zn.kp_norm, cfg.control.tune_rack_low, 1.0, o.v0, o.vb),
                 1e-12, 0);
    assert_true(fabs(o.settle_slope) < fabs(o.final_slope)); /* settled before the step */
}

/* EVIDENCE: Eq. 11 (zn_tuning.h): the reaction curve is built on V_ar = (V_a -
 * V_a0)/(V_ab - V_a0), the speed measured FROM the low-rack steady state (v0
 * = 1.43 m/s on this preset, not 0) over the span. The plant step of
 * ivs_tune.h run here by hand (the point-mass powertrain plant at
 * tune_rack_low for tune_settle s, its state restored into a full-rack
 * model for tune_duration s), its speeds normalised by Eq. 11 here and
 * given to ts_zn_reaction_curve: the same v0, vb, X, Y, slope, K_p and T_I
 * as ts_ivs_tune's (1e-12; deterministic runs). Normalising without
 * subtracting v0 shifts V_ar by v0/span = 0.08 and K_p by ~30 %. */
static void ivs_tune_normalises_by_eq11(void **state)
{
    (void)state;
    ts_config cfg = load("bump-coupled-ivs5mph");
    ts_ivs_tune_result o;
    ts_err err;
    assert_int_equal(ts_ivs_tune(&cfg, &o, &err), TS_OK);
    const ts_control_config *cc = &cfg.control;
    ts_config c = cfg;
    c.run.kind = TS_RUN_POINTMASS;
    c.terrain.kind = TS_TERRAIN_FLAT;
    c.drive.kind = TS_DRIVE_POWERTRAIN;
    c.control.mode = TS_CONTROL_RACK;
    c.control.rack = cc->tune_rack_low;
    c.run.duration = cc->tune_settle + cc->tune_duration;
    ts_model *m0 = ts_model_make(&c, &err);
    assert_non_null(m0);
    c.control.rack = 1.0;
    ts_model *m1 = ts_model_make(&c, &err);
    assert_non_null(m1);
    ts_data *d0 = ts_data_make(m0, &err), *d1 = ts_data_make(m1, &err);
    assert_non_null(d0);
    assert_non_null(d1);
    int ch = ts_model_channel_index(m0, "vehicle.speed"), nc = ts_model_nchannel(m0);
    assert_true(ch > 0); /* column 0 is time */
    ts_rows settle = {0}, step = {0};
    assert_int_equal(ts_reset(m0, d0, &err), TS_OK);
    assert_int_equal(ts_advance(m0, d0, cc->tune_settle, ts_rows_append, &settle, &err), TS_OK);
    double v0 = settle.v[(settle.n - 1) * nc + ch];
    size_t nbuf = ts_state_size(m0);
    void *buf = malloc(nbuf);
    assert_non_null(buf);
    assert_int_equal(ts_state_save(m0, d0, buf, nbuf, &err), TS_OK);
    assert_int_equal(ts_state_restore(m1, d1, buf, nbuf, &err), TS_OK);
    assert_int_equal(ts_rows_append(&step, 0, 0, ts_latest(d1), nc), 0); /* the step's start */
    assert_int_equal(ts_advance(m1, d1, c.run.duration, ts_rows_append, &step, &err), TS_OK);
    double vb = step.v[(step.n - 1) * nc + ch];
    assert_close(o.v0, v0, 1e-12, 0);
    assert_close(o.vb, vb, 1e-12, 0);
    assert_true(v0 > 0.05 * (vb - v0)); /* v0 is not 0: Eq. 11's offset matters */
    double *t = malloc(sizeof *t * (size_t)step.n), *v = malloc(sizeof *v * (size_t)step.n);
    assert_true(t && v);
    for (long i = 0; i < step.n; i++) {
        t[i] = step.v[i * nc];
        v[i] = (step.v[i * nc + ch] - v0) / (vb - v0); /* Eq. 11 */
    }
    ts_zn_result zn;
    assert_int_equal(ts_zn_reaction_curve(t, v, (int)step.n, cc->tune_settle, cc->tune_window,
                                          cc->kp_factor, cc->ti_factor, &zn, &err),
                     TS_OK);
    assert_close(o.zn.t_inflection, zn.t_inflection, 1e-12, 0);
    assert_close(o.zn.slope, zn.slope, 1e-12, 0);
    assert_close(o.zn.x, zn.x, 1e-12, 0);
    assert_close(o.zn.y, zn.y, 1e-12, 0);
    assert_close(o.zn.kp_norm, zn.kp_norm, 1e-12, 0);
    assert_close(o.zn.ti, zn.ti, 1e-12, 0);
    assert_close(o.kp, ts_zn_kp_physical(zn.kp_norm, cc->tune_rack_low, 1.0, v0, vb), 1e-12, 0);
    /* the steadiness of both ends (ivs_tune.h: the slope of the last second
     * of each run) is the secant over the last second of these very rows */
    const ts_rows *runs[2] = {&settle, &step};
    const double slopes[2] = {o.settle_slope, o.final_slope};
    for (int k = 0; k < 2; k++) {
        const ts_rows *r = runs[k];
        long last = r->n - 1, i = last;
        double t_end = r->v[last * nc];
        while (r->v[i * nc] > t_end - 1.0 + 1e-9)
            i--;
        assert_close(r->v[i * nc], t_end - 1.0, 0, 1e-9);
        assert_close(slopes[k], (r->v[last * nc + ch] - r->v[i * nc + ch]) / 1.0, 1e-9, 0);
    }
    free(buf);
    free(t);
    free(v);
    ts_rows_free(&settle);
    ts_rows_free(&step);
    ts_data_free(d0);
    ts_data_free(d1);
    ts_model_free(m0);
    ts_model_free(m1);
}

/* The tuning document: the base tune's numbers, a one-point schedule at the
 * config's own mass gives the same K_p and T_I (deterministic), progress
 * (1, 2) then (2, 2); stopping at the first report is TS_ERR_CANCELLED. */
static void tune_document_and_progress(void **state)
{
    (void)state;
    ts_config cfg = load("bump-coupled-ivs5mph");
    ts_ivs_tune_result o;
    ts_err err;
    assert_int_equal(ts_ivs_tune(&cfg, &o, &err), TS_OK);
    double x = cfg.vehicle.mass;
    calls seen = {0};
    json_t *doc = tsa_tune_json(&cfg, "mass", &x, 1, record_parts, &seen, &err);
    assert_non_null(doc);
    assert_int_equal(seen.n, 2);
    assert_int_equal(seen.done[0], 1);
    assert_int_equal(seen.done[1], 2);
    assert_int_equal(seen.total[0], 2);
    assert_int_equal(seen.total[1], 2);
    assert_true(json_real_value(json_object_get(doc, "kp")) == o.kp);
    assert_true(json_real_value(json_object_get(doc, "ti")) == o.zn.ti);
    assert_string_equal(json_string_value(json_object_get(doc, "plant")), "pointmass+powertrain");
    assert_non_null(json_object_get(json_object_get(doc, "units"), "kp"));
    json_t *s = json_object_get(doc, "schedule");
    assert_string_equal(json_string_value(json_object_get(s, "var")), "mass");
    assert_true(json_real_value(json_array_get(json_object_get(s, "kp"), 0)) == o.kp);
    assert_true(json_real_value(json_array_get(json_object_get(s, "ti"), 0)) == o.zn.ti);
    json_decref(doc);

    doc = tsa_tune_json(&cfg, NULL, NULL, 0, NULL, NULL, &err);
    assert_non_null(doc);
    assert_null(json_object_get(doc, "schedule"));
    json_decref(doc);

    calls stop = {.stop_at = 1};
    assert_null(tsa_tune_json(&cfg, "mass", &x, 1, record_parts, &stop, &err));
    assert_int_equal(err.code, TS_ERR_CANCELLED);
    assert_int_equal(stop.n, 1);
}

/* Refused before anything runs: an unknown schedule variable, too many
 * points, a missing variable, a value outside the field's range. */
static void tune_rejects_bad_schedule(void **state)
{
    (void)state;
    ts_config cfg = load("bump-coupled-ivs5mph");
    double x[TSA_TUNE_SCHEDULE_MAX + 1] = {0};
    calls seen = {0};
    ts_err err;
    assert_null(tsa_tune_json(&cfg, "speed", x, 1, record, &seen, &err));
    assert_int_equal(err.code, TS_ERR_PARAM);
    assert_true(err.msg[0] != '\0');
    assert_null(tsa_tune_json(&cfg, NULL, x, 1, record, &seen, &err));
    assert_int_equal(err.code, TS_ERR_PARAM);
    assert_null(tsa_tune_json(&cfg, "grade", x, TSA_TUNE_SCHEDULE_MAX + 1, record, &seen, &err));
    assert_int_equal(err.code, TS_ERR_PARAM);
    assert_null(tsa_tune_json(&cfg, "mass", x, -1, record, &seen, &err));
    assert_int_equal(err.code, TS_ERR_PARAM);
    assert_null(tsa_tune_json(&cfg, "mass", NULL, 1, record, &seen, &err));
    assert_int_equal(err.code, TS_ERR_PARAM);
    x[0] = 1.0; /* rad */
    assert_null(tsa_tune_json(&cfg, "grade", x, 1, record, &seen, &err));
    assert_int_equal(err.code, TS_ERR_RANGE);
    assert_string_equal(err.pointer, "/vehicle/grade");
    assert_int_equal(seen.n, 0);
}

/* The schedule as text (CLI option, query value): plain decimals only (as the
 * daemon's other query numbers), 1 to 16 of them, each in the field's range,
 * increasing; the error names the field and says what is expected. */
static void schedule_parse(void **state)
{
    (void)state;
    double x[TSA_TUNE_SCHEDULE_MAX];
    int n = -1;
    ts_err err;
    assert_int_equal(tsa_tune_schedule_parse("50000,6e4,70000.5", "mass", x, &n, &err), TS_OK);
    assert_int_equal(n, 3);
    assert_true(x[0] == 50000 && x[1] == 60000 && x[2] == 70000.5);
    assert_int_equal(tsa_tune_schedule_parse("-0.1,0,0.2", "grade", x, &n, &err), TS_OK);
    assert_int_equal(n, 3);
    assert_true(x[0] == -0.1);
    const char *bad[] = {"", "abc", "50000,", ",50000", "50000,,60000", "0x10000", " 50000",
                         "inf", "1e9" /* above /vehicle/mass's max */,
                         "50000,51000,52000,53000,54000,55000,56000,57000,58000,59000,60000,"
                         "61000,62000,63000,64000,65000,66000" /* 17 */};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal(tsa_tune_schedule_parse(bad[i], "mass", x, &n, &err), TS_ERR_PARAM);
        assert_string_equal(err.pointer, "/vehicle/mass");
        assert_non_null(strstr(err.msg, "comma-separated"));
    }
    /* the values become /control/schedule_x, which must increase */
    const char *unordered[] = {"60000,50000", "50000,50000"};
    for (size_t i = 0; i < 2; i++) {
        assert_int_equal(tsa_tune_schedule_parse(unordered[i], "mass", x, &n, &err), TS_ERR_PARAM);
        assert_string_equal(err.pointer, "/vehicle/mass");
        assert_non_null(strstr(err.msg, "must increase"));
    }
    assert_int_equal(tsa_tune_schedule_parse("0.9", "grade", x, &n, &err), TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/vehicle/grade");
    assert_int_equal(tsa_tune_schedule_parse("1", "speed", x, &n, &err), TS_ERR_PARAM);
}

/* The sweep validates its config as ts_model_make does: an enum index out of
 * range is refused naming the field (the engine indexes its tables by it). */
static void sweep_validates_config(void **state)
{
    (void)state;
    ts_config cfg = load(NULL);
    cfg.engine.variant = 7;
    ts_engine_cycle rows[TS_ENGINE_SWEEP_NPOINT];
    ts_err err;
    assert_int_not_equal(ts_engine_full_load_sweep(&cfg, rows, NULL, NULL, &err), TS_OK);
    assert_string_equal(err.pointer, "/engine/variant");
}

/* The tune's runs ask poll every few samples, with the caller's part counts
 * unchanged, and stop with TS_ERR_CANCELLED when it says so (session-24 probe:
 * a daemon tune with 1800-s runs took minutes to honour a cancel). */
typedef struct poll_count {
    int calls, stop_at, done, total;
} poll_count;

static int poll_stop(void *ud, int done, int total)
{
    poll_count *p = ud;
    p->done = done, p->total = total;
    return ++p->calls >= p->stop_at;
}

static void ivs_tune_polled_stops_when_asked(void **state)
{
    (void)state;
    ts_config cfg = load("bump-coupled-ivs5mph");
    ts_ivs_tune_result o;
    ts_err err;
    poll_count p = {0, 5, -1, -1};
    assert_int_equal(ts_ivs_tune_polled(&cfg, &o, poll_stop, &p, 3, 7, &err), TS_ERR_CANCELLED);
    assert_int_equal(p.calls, 5);
    assert_int_equal(p.done, 3);
    assert_int_equal(p.total, 7);
    assert_non_null(strstr(err.msg, "cancelled"));
    poll_count never = {0, 1 << 30, -1, -1}; /* a poll that never stops: the same tune */
    ts_ivs_tune_result a, b;
    assert_int_equal(ts_ivs_tune_polled(&cfg, &a, poll_stop, &never, 0, 1, &err), TS_OK);
    assert_int_equal(ts_ivs_tune(&cfg, &b, &err), TS_OK);
    assert_true(never.calls > 100);
    assert_true(a.kp == b.kp && a.zn.ti == b.zn.ti && a.v0 == b.v0 && a.vb == b.vb);
}

/* Finding (session 24): /control/tune_duration 10000 s (in its range) was refused as
 * "/run/duration: ... got 10060", a field the user had not set. The step response's
 * length (settle + duration) is checked against a run's longest first, naming
 * tune_duration. */
static void ivs_tune_too_long_names_tune_duration(void **state)
{
    (void)state;
    ts_config cfg = load("bump-coupled-ivs5mph");
    cfg.control.tune_duration = 10000;
    ts_ivs_tune_result o;
    ts_err err;
    assert_int_equal(ts_ivs_tune(&cfg, &o, &err), TS_ERR_RANGE);
    assert_string_equal(err.pointer, "/control/tune_duration");
    assert_non_null(strstr(err.msg, "/run/duration"));
}

/* A settle shorter than two samples is an error naming the field (it used to
 * read before the start of an empty series). */
static void ivs_tune_needs_a_settle(void **state)
{
    (void)state;
    ts_config cfg = load("bump-coupled-ivs5mph");
    cfg.control.tune_settle = 0;
    ts_ivs_tune_result o;
    ts_err err;
    assert_int_equal(ts_ivs_tune(&cfg, &o, &err), TS_ERR_RANGE);
    assert_string_equal(err.pointer, "/control/tune_settle");
}

/* The two refusals of /control/tune_rack_low are one kind of input (a value
 * in its range that does not work for this plant, as the unsteady settle or
 * step) and carry one code, TS_ERR_RANGE: "not faster" was TS_ERR_PARAM. At
 * grade 0.2 and full rack from rest the speed overshoots: 5.60 m/s at 15 s,
 * 5.45 m/s one second later, so a full-rack "step" is slower. */
static void ivs_tune_rack_low_refusals_share_a_code(void **state)
{
    (void)state;
    ts_config cfg = load("bump-coupled-ivs5mph");
    ts_ivs_tune_result o;
    ts_err err;
    cfg.vehicle.grade = 0.6; /* rolls backwards at the low rack */
    assert_int_equal(ts_ivs_tune(&cfg, &o, &err), TS_ERR_RANGE);
    assert_string_equal(err.pointer, "/control/tune_rack_low");
    assert_non_null(strstr(err.msg, "rolls backwards"));
    cfg.vehicle.grade = 0.2;
    cfg.control.tune_rack_low = 1.0;
    cfg.control.tune_settle = 15.0;
    cfg.control.tune_duration = 1.0;
    assert_int_equal(ts_ivs_tune(&cfg, &o, &err), TS_ERR_RANGE);
    assert_string_equal(err.pointer, "/control/tune_rack_low");
    assert_non_null(strstr(err.msg, "not faster"));
    assert_true(o.vb < o.v0 - 0.05); /* slower by a margin, not by round-off */
}

/* EVIDENCE: the sweep runs at the configured /control/rack (engine_sweep.h;
 * the Fig. 18 document records it): the constant-phi fuel law of Eqs. 13-14
 * injects m_f = m_air phi_tgt(n) / (A/F)_s Rack per cycle on the compressor's
 * air flow, so the fuel/air ratio of the flows is Rack phi_tgt(n) / (A/F)_s
 * and a sweep at rack 0.8 must run at 0.8 times the full-rack fuel/air ratio
 * at every speed (mean-value fidelity; cycle means, to rounding: 1e-9) and
 * with less brake torque. Session-28 mutation test: the sweep run at full
 * rack whatever the configuration said survived every test (the CLI's
 * sidecar still reported 0.8). */
static void sweep_runs_at_the_configured_rack(void **state)
{
    (void)state;
    ts_config cfg = load(NULL);
    ts_engine_cycle full[TS_ENGINE_SWEEP_NPOINT], part[TS_ENGINE_SWEEP_NPOINT];
    ts_err err;
    assert_int_equal(ts_engine_full_load_sweep(&cfg, full, NULL, NULL, &err), TS_OK);
    cfg.control.rack = 0.8;
    assert_int_equal(ts_engine_full_load_sweep(&cfg, part, NULL, NULL, &err), TS_OK);
    double worst = 0;
    for (int k = 0; k < TS_ENGINE_SWEEP_NPOINT; k++) {
        double fa_part = part[k].mean.fuel_flow / part[k].mean.air_flow,
               fa_full = full[k].mean.fuel_flow / full[k].mean.air_flow;
        worst = fmax(worst, fabs(fa_part / fa_full - 0.8));
        assert_close(fa_part, 0.8 * fa_full, 1e-9, 0);
        assert_true(part[k].mean.brake_torque < full[k].mean.brake_torque);
    }
    printf("# fuel/air ratio at rack 0.8 against rack 1: 0.8 to %.2g\n", worst);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sweep_rows_and_progress),
        cmocka_unit_test(sweep_runs_at_the_configured_rack),
        cmocka_unit_test(engine_map_document),
        cmocka_unit_test(sweep_cancel),
        cmocka_unit_test(sweep_engine_error),
        cmocka_unit_test(ivs_tune_eq12),
        cmocka_unit_test(ivs_tune_normalises_by_eq11),
        cmocka_unit_test(tune_document_and_progress),
        cmocka_unit_test(tune_rejects_bad_schedule),
        cmocka_unit_test(ivs_tune_needs_a_settle),
        cmocka_unit_test(ivs_tune_rack_low_refusals_share_a_code),
        cmocka_unit_test(ivs_tune_too_long_names_tune_duration),
        cmocka_unit_test(ivs_tune_polled_stops_when_asked),
        cmocka_unit_test(schedule_parse),
        cmocka_unit_test(sweep_validates_config),
    };
    return cmocka_run_group_tests_name("sim/analysis_calls", tests, NULL, NULL);
}
