/*
 * cfg_control.h — the "control" and "coupling" sections of a run config: the
 * driver (fixed rack or IVS controller, Section IV.B) and the powertrain-vehicle
 * coupling (Section IV.A). Extended by the control/coupling module.
 */
#ifndef TS_CFG_CONTROL_H
#define TS_CFG_CONTROL_H

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
