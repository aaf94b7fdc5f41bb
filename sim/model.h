/*
 * model.h — the generic model interface: one small API over every scenario kind.
 *
 * Split as in MuJoCo: a ts_model is built once from a ts_config and is then
 * read-only (parameters, derived constants, DOF layout, channel list) and may be
 * shared by many threads; a ts_data holds everything that changes while a run
 * advances (state, integrator, latest sample) and belongs to one thread at a
 * time. Every call takes (const ts_model *m, ts_data *d, ...).
 *
 * Output is a registry of named channels (name, SI unit, description). A run
 * produces one row of channel values per sample period (run.sample_rate), row 0
 * at t = 0 after ts_reset. The server, the CSV writer, the stream and the
 * dashboard all read the same registry.
 *
 * Ownership: ts_model_make/ts_model_free, ts_data_make/ts_data_free; *_free(NULL)
 * is a no-op. A ts_data must be freed before the ts_model it was made from.
 * Strings returned by accessors belong to the model.
 */
#ifndef TS_MODEL_H
#define TS_MODEL_H

#include <stddef.h>

#include "config.h"
#include "errors.h"
#include "geometry.h"

typedef struct ts_model ts_model;
typedef struct ts_data ts_data;

typedef struct ts_channel {
    const char *name;        /* stable API name, e.g. "vehicle.speed" */
    const char *unit;        /* SI unit, e.g. "m/s"; "1" for dimensionless */
    const char *description; /* one line */
} ts_channel;

/* A channel in a table whose channels depend on a component's build, with
 * the bits it needs (e.g. engine.h TS_ENGINE_MODELS_*; 0: always present). */
typedef struct ts_channel_need {
    ts_channel ch;
    unsigned needs;
} ts_channel_need;

/* ---- model: built once, read-only ---------------------------------------- */

/* Build a model from a config (copied). NULL on failure with err filled. */
ts_model *ts_model_make(const ts_config *cfg, ts_err *err);
void ts_model_free(ts_model *m);

const ts_config *ts_model_config(const ts_model *m);
const char *ts_model_kind(const ts_model *m);     /* scenario kind name, "pointmass" */
int ts_model_dof(const ts_model *m);              /* mechanical degrees of freedom */
int ts_model_nstate(const ts_model *m);           /* first-order states integrated */
int ts_model_nchannel(const ts_model *m);
const ts_channel *ts_model_channel(const ts_model *m, int i); /* NULL if out of range */
int ts_model_channel_index(const ts_model *m, const char *name); /* -1 if unknown */
double ts_model_sample_period(const ts_model *m);  /* 1 / run.sample_rate [s] */

/* Sample rows are dt apart: TS_OK if t is a whole number of them (relative
 * slack 1e-9), else TS_ERR_PARAM naming pointer with the two nearest times.
 * ts_model_make checks /run/duration with it; callers their own end times. */
TS_MUST_CHECK ts_rc ts_on_sample_grid(double t, double dt, const char *pointer, ts_err *err);
/* Index of the last sample row at or before t, a time within that slack of a
 * row counting as the row: the row ts_advance(t) ends on (a time that
 * ts_on_sample_grid accepts ends exactly there). */
long ts_grid_row(double t, double dt);

/* ---- data: one per running instance -------------------------------------- */

ts_data *ts_data_make(const ts_model *m, ts_err *err);
void ts_data_free(ts_data *d);

/* Initial conditions (static equilibrium where the scenario has one), t = 0,
 * sample row 0 computed. Must be called before ts_advance. */
TS_MUST_CHECK ts_rc ts_reset(const ts_model *m, ts_data *d, ts_err *err);

/* Called once per sample row: index counts from 0 at t = 0; values holds
 * ts_model_nchannel numbers in channel order. Return non-zero to stop the run
 * (ts_advance then returns TS_ERR_CANCELLED, the state stays consistent at t). */
typedef int (*ts_sample_fn)(void *ud, long index, double t, const double *values, int n);

/* Progress of a multi-part computation: called after each part (done of total).
 * A non-zero return asks the computation to stop; it then returns TS_ERR_CANCELLED. */
typedef int (*ts_progress_fn)(void *ud, int done, int total);

/* Integrate up to t_end (clamped to run.duration), calling fn (may be NULL) for
 * every sample row after the current one. On error the data keeps the last good
 * sample time and the error is sticky until ts_reset or ts_state_restore. */
TS_MUST_CHECK ts_rc ts_advance(const ts_model *m, ts_data *d, double t_end, ts_sample_fn fn,
                               void *ud, ts_err *err);

double ts_time(const ts_data *d);            /* time of the latest sample row [s] */
long ts_sample_index(const ts_data *d);      /* index of the latest sample row */
const double *ts_latest(const ts_data *d);   /* latest row, ts_model_nchannel values */
double ts_wall_seconds(const ts_data *d);    /* wall time spent inside ts_advance [s] */

/* Monotonic wall clock [s] (CLOCK_MONOTONIC): what ts_wall_seconds and the
 * coupled system's per-side timers count with, for callers' progress too. */
double ts_monotonic_seconds(void);

/* ---- integrator work --------------------------------------------------------- */

/* Work counters of one integrator of a run, since ts_data_make (summed over the
 * integrator's restarts: events, ts_reset, ts_state_restore): what the run
 * cost beside its wall time. -1 where the method has no such counter. */
typedef struct ts_integrator_stats {
    const char *name;    /* the part it carries: "vehicle", "powertrain", ... */
    const char *method;  /* e.g. "CVODE BDF, Newton" */
    long steps;          /* accepted steps */
    long rhs_evals;      /* right-hand sides the integrator asked for (a difference-
                          * quotient Jacobian's columns not included) */
    long jac_evals;      /* Jacobian evaluations */
    long lin_setups;     /* Newton-matrix factorisations */
    long err_test_fails; /* steps rejected by the local error test */
    long newton_iters;   /* Newton iterations */
    long newton_fails;   /* Newton convergence failures */
} ts_integrator_stats;

#define TS_MAX_INTEGRATORS 4

/* Fill at most max entries for d's integrators; returns how many (0: the
 * scenario keeps no counters, e.g. the fixed-step engine dynamometer). Not
 * while another thread advances d. */
int ts_integrator_stats_get(const ts_model *m, const ts_data *d, ts_integrator_stats *out,
                            int max);

/* ---- figures of a finished run --------------------------------------------- */

typedef struct ts_metric {
    char name[64];         /* e.g. "speed_at_20s_kmh" */
    char unit[16];         /* unit of value ("km/h", "s", "N") */
    double value;          /* NAN when the run does not reach it */
    char description[256]; /* one line, says "predicted" or "calibrated to" where it matters */
} ts_metric;

/* A growing copy of a run's sample rows, for ts_model_metrics: pass
 * ts_rows_append as ts_advance's fn with a zeroed ts_rows as ud. Owns v;
 * ts_rows_free releases it. */
typedef struct ts_rows {
    double *v; /* n rows of the sample width, row-major */
    long n, cap;
} ts_rows;
int ts_rows_append(void *ud, long index, double t, const double *values, int n);
void ts_rows_free(ts_rows *r);

/* Scenario-specific figures computed from a run's sample rows (nrows rows of
 * ts_model_nchannel values, row-major, as ts_advance produced them), e.g. the
 * Table 2 acceleration times. Returns how many figures the scenario has for
 * these rows and writes the first min(that, max) of them to out (as snprintf
 * does): a return above max means out was too small and the rest is missing,
 * so call again with a larger out (max 0 and out NULL: the count only, at
 * the cost of computing every figure). How many there are depends on the
 * scenario and its config (a gear channel, the IVS controller, cylinders).
 * The one call on a shared model that is NOT safe on several threads at once:
 * the vehicle kind's spectrum figures plan FFTs (fft.h: FFTW's planner is not
 * thread-safe), so serialise it with every other FFT user (tanksimd holds
 * tsd_server.fft_lock around it in /summary, as around its /fft route). */
int ts_model_metrics(const ts_model *m, const double *rows, long nrows, ts_metric *out, int max);

/* ---- state snapshots (persistence, re-rendering past times) --------------- */

size_t ts_state_size(const ts_model *m);  /* bytes of a saved state */
TS_MUST_CHECK ts_rc ts_state_save(const ts_model *m, const ts_data *d, void *buf, size_t n,
                                  ts_err *err);
TS_MUST_CHECK ts_rc ts_state_restore(const ts_model *m, ts_data *d, const void *buf, size_t n,
                                     ts_err *err);

/* ---- geometry for renderers ----------------------------------------------- */

/* Fill a read-only geometric snapshot of the current state (see geometry.h).
 * TS_ERR_UNSUPPORTED for scenarios without running gear (engine_dyno). */
TS_MUST_CHECK ts_rc ts_geometry(const ts_model *m, const ts_data *d, ts_geom *out, ts_err *err);

#endif
