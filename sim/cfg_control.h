/*
 * cfg_control.h — the "control" and "coupling" sections of a run config: the
 * driver (fixed rack or IVS controller, Section IV.B: PI law Eq. 10 with gain
 * schedule Fig. 27, the two-speed governor of the fuel actuator, the reaction-
 * curve tuning Eqs. 11-12) and the powertrain-vehicle coupling (Section IV.A).
 */
#ifndef TS_CFG_CONTROL_H
#define TS_CFG_CONTROL_H

#define TS_CONTROL_SCHEDULE_MAX 16 /* = TS_IVS_SCHEDULE_MAX */

typedef enum ts_control_mode { TS_CONTROL_RACK, TS_CONTROL_IVS, TS_NCONTROL_MODE } ts_control_mode;
extern const char *const ts_control_mode_names[];

typedef enum ts_schedule_var {
    TS_SCHEDULE_MASS,
    TS_SCHEDULE_GRADE,
    TS_NSCHEDULE_VAR
} ts_schedule_var;
extern const char *const ts_schedule_var_names[];

typedef struct ts_control_config {
    int mode;            /* ts_control_mode: fixed rack or the IVS speed controller */
    double rack;         /* fixed rack position for mode "rack" [1] */
    double target_speed; /* IVS set speed [m/s] */
    /* IVS PI law (Eq. 10) */
    double kp;        /* proportional gain [rack per m/s] */
    double ti;        /* integral time [s] */
    int anti_windup;  /* back-calculation anti-windup on/off */
    int schedule_var; /* ts_schedule_var: what the gain table is indexed by */
    int schedule_n;
    double schedule_x[TS_CONTROL_SCHEDULE_MAX]; /* vehicle mass [kg] or grade [rad] */
    int schedule_kp_n;
    double schedule_kp[TS_CONTROL_SCHEDULE_MAX]; /* [rack per m/s] */
    int schedule_ti_n;
    double schedule_ti[TS_CONTROL_SCHEDULE_MAX]; /* [s] */
    /* two-speed governor of the fuel actuator (Section IV.B.2) */
    int governor;              /* on/off */
    double governor_low_idle;  /* [rad/s] */
    double governor_low_band;  /* [rad/s] */
    double governor_high_idle; /* [rad/s] */
    double governor_high_band; /* [rad/s] */
    /* reaction-curve tuning (tanksim tune; Eqs. 11-12, Fig. 26) */
    double tune_rack_low; /* rack of the steady state before the step [1] */
    double tune_settle;   /* time to reach that steady state [s] */
    double tune_duration; /* simulated time after the step [s] */
    double kp_factor;     /* K_p = kp_factor / |Y| (normalised) [1] */
    double ti_factor;     /* T_I = ti_factor |X| [1] */
    int tune_window;      /* samples in the slope fit (odd) */
} ts_control_config;

typedef enum ts_coupling_method {
    TS_COUPLING_MONOLITHIC,
    TS_COUPLING_LEADING_FOLLOWING,
    TS_NCOUPLING
} ts_coupling_method;
extern const char *const ts_coupling_method_names[];

typedef struct ts_coupling_config {
    int method;               /* ts_coupling_method */
    double lead;              /* how far the powertrain may run ahead [s] */
    int predictor_order;      /* 0: hold, 1: linear in (omega, alpha) */
    double leader_step;       /* powertrain macro step [s] */
    double follower_step;     /* vehicle macro step [s] */
    double interface_inertia; /* factor on the turbine inertia reflected through the applied
                                 clutch, carried by the follower (coupled_system.h) [1] */
} ts_coupling_config;

#endif
