/*
 * cfg_powertrain.h — "engine", "driveline", "control" and "coupling" sections of
 * a run config (paper Sections III-IV). Extended by those modules as they grow.
 */
#ifndef TS_CFG_POWERTRAIN_H
#define TS_CFG_POWERTRAIN_H

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

#define TS_NGEAR_MAX 8

typedef struct ts_driveline_config {
    int gear_ratio_n;                 /* number of forward gears */
    double gear_ratio[TS_NGEAR_MAX];  /* transmission ratio per gear [1] */
    double final_ratio;               /* overall final-drive ratio [1] */
    double shift_speed;               /* engine speed that triggers an upshift [rad/s] */
    double shift_time;                /* clutch-to-clutch shift interval [s] */
} ts_driveline_config;

typedef enum ts_control_mode { TS_CONTROL_RACK, TS_CONTROL_IVS, TS_NCONTROL_MODE } ts_control_mode;
extern const char *const ts_control_mode_names[];

typedef struct ts_control_config {
    int mode;            /* ts_control_mode: fixed rack or the IVS speed controller */
    double rack;         /* fixed rack position for mode "rack" [1] */
    double target_speed; /* IVS set speed [m/s] */
} ts_control_config;

typedef enum ts_coupling_method { TS_COUPLING_MONOLITHIC, TS_COUPLING_LEADING_FOLLOWING, TS_NCOUPLING } ts_coupling_method;
extern const char *const ts_coupling_method_names[];

typedef struct ts_coupling_config {
    int method;             /* ts_coupling_method */
    double lead;            /* how far the powertrain may run ahead [s] */
    int predictor_order;    /* 0: hold, 1: linear in (omega, alpha) */
} ts_coupling_config;

#endif
