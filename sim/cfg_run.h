/*
 * cfg_run.h — the "run" section of a run config: which scenario, how long,
 * how often to sample and how tightly to integrate.
 */
#ifndef TS_CFG_RUN_H
#define TS_CFG_RUN_H

/* Scenario kinds (names in ts_run_kind_names, same order). */
typedef enum ts_run_kind {
    TS_RUN_POINTMASS,   /* point-mass vehicle on flat/graded ground (Section III.C) */
    TS_RUN_VEHICLE,     /* pitch-plane multibody vehicle with track (Section II.D) */
    TS_RUN_ENGINE_DYNO, /* engine held at speed on a dynamometer (Section III.B.3) */
    TS_RUN_COUPLED,     /* powertrain + vehicle, leading-following (Section IV) */
    TS_NRUN_KIND
} ts_run_kind;

extern const char *const ts_run_kind_names[];

typedef struct ts_run_config {
    int kind;            /* ts_run_kind */
    double duration;     /* simulated time of a full run [s] */
    double sample_rate;  /* output rows per simulated second [Hz] */
    double rtol;         /* integrator relative tolerance [1] */
    double atol;         /* integrator absolute tolerance, scaled per state [1] */
    double max_step;     /* largest integrator step, 0 = unlimited [s] (range in cfg_run.c) */
} ts_run_config;

#endif
