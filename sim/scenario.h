/*
 * scenario.h — how a scenario kind plugs into the generic model interface.
 * Internal to sim/: implementers include it, callers use model.h only.
 *
 * A scenario is a table of operations (as MuJoCo's plugins are): model_init
 * derives constants and declares channels into the ts_model; data_init takes
 * every allocation the run will need (the step path does not allocate);
 * step_to integrates to exactly the requested time; sample writes one row of
 * channel values for the current state. model.c owns the sampling loop, the
 * time bookkeeping, wall-clock accounting and cancellation.
 */
#ifndef TS_SCENARIO_H
#define TS_SCENARIO_H

#include "model.h"
#include "solver.h"

#define TS_MAX_CHANNELS 256

typedef struct ts_scenario_ops {
    const char *kind; /* run.kind name this table serves */
    /* Fill m->impl, m->dof, m->nstate and declare channels (ts_model_add_channel). */
    ts_rc (*model_init)(ts_model *m, ts_err *err);
    void (*model_fini)(ts_model *m);
    /* Allocate d->impl (integrator, scratch). */
    ts_rc (*data_init)(const ts_model *m, ts_data *d, ts_err *err);
    void (*data_fini)(const ts_model *m, ts_data *d);
    /* Initial state at t = 0 (static equilibrium where applicable). */
    ts_rc (*reset)(const ts_model *m, ts_data *d, ts_err *err);
    /* Integrate from the current time to exactly t. */
    ts_rc (*step_to)(const ts_model *m, ts_data *d, double t, ts_err *err);
    /* Write nchannel values for the current state at the current time; fails
     * when the model's equations cannot be evaluated there (values are then
     * unspecified and the advance stops with the error). */
    ts_rc (*sample)(const ts_model *m, const ts_data *d, double *values, ts_err *err);
    /* Saved-state size and (de)serialisation; restore re-initialises the integrator. */
    size_t (*state_size)(const ts_model *m);
    ts_rc (*state_save)(const ts_model *m, const ts_data *d, void *buf, ts_err *err);
    ts_rc (*state_restore)(const ts_model *m, ts_data *d, const void *buf, ts_err *err);
    /* Optional: figures of a finished run; returns how many there are, writing
     * at most max (see ts_model_metrics; ts_metric_add counts past max). */
    int (*metrics)(const ts_model *m, const double *rows, long nrows, ts_metric *out, int max);
    /* Optional (NULL: TS_ERR_UNSUPPORTED). */
    ts_rc (*geometry)(const ts_model *m, const ts_data *d, ts_geom *out, ts_err *err);
    /* Optional: integrator counters (see ts_integrator_stats_get); returns the count. */
    int (*integrator_stats)(const ts_model *m, const ts_data *d, ts_integrator_stats *out,
                            int max);
} ts_scenario_ops;

struct ts_model {
    ts_config cfg;                    /* private copy of the config */
    const ts_scenario_ops *ops;       /* scenario kind */
    void *impl;                       /* scenario's derived constants (model_init) */
    int dof;                          /* mechanical DOF (model_init) */
    int nstate;                       /* first-order states (model_init) */
    int nchannel;                     /* channels declared (model_init) */
    ts_channel channel[TS_MAX_CHANNELS];
    char *channel_strings;            /* owned copies of dynamic channel names */
    size_t channel_strings_used, channel_strings_cap;
};

struct ts_data {
    const ts_model *m;
    void *impl;           /* scenario state (data_init) */
    double t;             /* time of the latest sample row [s] */
    long index;           /* index of the latest sample row */
    double *latest;       /* latest row (nchannel) */
    int ready;            /* ts_reset done */
    ts_rc sticky;         /* non-OK after a failed advance until reset/restore */
    double wall;          /* wall seconds inside ts_advance */
};

/* Declare a channel during model_init. Names and units are copied. Returns its
 * index or -1 (err filled) when the registry is full or the name is taken. */
TS_MUST_CHECK int ts_model_add_channel(ts_model *m, const char *name, const char *unit,
                                       const char *description, ts_err *err);

/* Declare n channels from a table (name, unit, description) in order; the
 * first failure's code, with err filled. */
TS_MUST_CHECK ts_rc ts_model_add_channels(ts_model *m, const ts_channel *rows, int n, ts_err *err);

/* Helpers for a scenario's metrics (ts_scenario_ops.metrics). */
/* out[n] = {name, unit, value, desc} (strings truncated to the fields) when
 * n < max; returns the new count n + 1 either way, so a metrics function
 * returns how many figures it has even when out is full (ts_model_metrics). */
int ts_metric_add(ts_metric *out, int n, int max, const char *name, const char *unit, double value,
                  const char *desc);
/* First time the sampled column col crosses level upwards (rows: nrows rows
 * of nc values, time in column 0; linear interpolation), NAN if never. */
double ts_rows_first_crossing(const double *rows, long nrows, int nc, int col, double level);
/* The three upshifts' times from the fractional gear column gear_col (the
 * transmission's gear, g + shift fraction during a g -> g+1 shift), the same
 * pair for every scenario that has a transmission: shift_G_H_began_s (gear
 * leaves g) and shift_G_H_half_s (gear passes g + 0.5). Appends to out[n..];
 * returns the new count. */
int ts_metric_add_upshifts(const double *rows, long nrows, int nc, int gear_col, ts_metric *out,
                           int n, int max);

/* A CVODE handle's counters (ts_ode_get_stats) as one ts_integrator_stats entry;
 * name and method must outlive it (string literals). */
void ts_integrator_stats_of_ode(ts_ode *o, const char *name, const char *method,
                                ts_integrator_stats *out);

/* Scenario tables, one per kind (scenario_*.c). */
extern const ts_scenario_ops ts_scenario_pointmass;
extern const ts_scenario_ops ts_scenario_engine_dyno;
extern const ts_scenario_ops ts_scenario_vehicle;
extern const ts_scenario_ops ts_scenario_coupled;

#endif
