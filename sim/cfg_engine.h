/*
 * cfg_engine.h — the "engine" section of a run config: the virtual V-12 diesel
 * (paper Section III.A-B.1, B.3). Extended by the engine module.
 */
#ifndef TS_CFG_ENGINE_H
#define TS_CFG_ENGINE_H

typedef enum ts_engine_variant {
    TS_ENGINE_CONVENTIONAL, /* all-metal combustion chamber */
    TS_ENGINE_LHR05,        /* 0.5 mm zirconia coating */
    TS_ENGINE_LHR10,        /* 1.0 mm zirconia coating */
    TS_NENGINE_VARIANT
} ts_engine_variant;
extern const char *const ts_engine_variant_names[];

typedef enum ts_engine_fidelity {
    TS_ENGINE_CRANK_ANGLE, /* twelve 0-D crank-angle cylinders */
    TS_ENGINE_MEAN_VALUE,  /* cycle-averaged cylinder, manifolds and turbos kept */
    TS_ENGINE_MAP,         /* torque map + first-order boost lag */
    TS_NENGINE_FIDELITY
} ts_engine_fidelity;
extern const char *const ts_engine_fidelity_names[];

typedef struct ts_engine_config {
    int variant;       /* ts_engine_variant */
    int fidelity;      /* ts_engine_fidelity */
    double dyno_speed; /* speed held by the dynamometer in engine_dyno runs [rad/s] */
} ts_engine_config;

#endif
