/*
 * cfg_driveline.h — the "driveline" section of a run config: torque converter,
 * four-speed automatic transmission, propshaft/differential/final drive (paper
 * Section III.B.2, Fig. 17). Values and their sources:
 * sim/data/defaults/driveline.json.
 */
#ifndef TS_CFG_DRIVELINE_H
#define TS_CFG_DRIVELINE_H

#define TS_NGEAR_MAX 8
#define TS_TC_TABLE_MAX 32

typedef struct ts_driveline_config {
    /* torque converter: tables against speed ratio SR = turbine / pump speed */
    int tc_speed_ratio_n;                     /* table rows */
    double tc_speed_ratio[TS_TC_TABLE_MAX];   /* SR, increasing from 0, below 1 [1] */
    int tc_torque_ratio_n;
    double tc_torque_ratio[TS_TC_TABLE_MAX];  /* turbine / pump torque [1] */
    int tc_k_factor_n;
    double tc_k_factor[TS_TC_TABLE_MAX];      /* pump speed / sqrt(pump torque) [rad/s/sqrt(N*m)] */
    double pump_inertia;                      /* converter pump, added to the crankshaft [kg*m^2] */
    double turbine_inertia;                   /* turbine + transmission input shaft [kg*m^2] */
    /* transmission */
    int gear_ratio_n;                         /* number of forward gears */
    double gear_ratio[TS_NGEAR_MAX];          /* transmission ratio per gear [1] */
    int gear_efficiency_n;
    double gear_efficiency[TS_NGEAR_MAX];     /* mechanical efficiency per gear [1] */
    double shift_speed;                       /* engine speed that triggers an upshift [rad/s] */
    double downshift_speed; /* downshift engine speed (and lower gear's input) [rad/s] */
    double shift_time;                        /* clutch-to-clutch shift interval [s] */
    double shift_dwell;                       /* re-arm time of the upshift after a shift [s] */
    double shift_hysteresis;                  /* re-arm the upshift this far below shift_speed [rad/s] */
    double clutch_capacity;                   /* applied clutch torque capacity, input side [N*m] */
    double shift_capacity_factor;             /* shift clutch capacity / torque at shift start [1] */
    double shift_capacity_floor;              /* least shift clutch capacity / clutch_capacity [1] */
    double clutch_slip_speed;                 /* friction regularisation slip speed [rad/s] */
    /* propshaft, differential, final drive */
    double final_ratio;                       /* transmission output to sprocket [1] */
    double final_efficiency;                  /* propshaft + differential + final drive [1] */
    double output_inertia;                    /* transmission output .. both sprockets, at the sprocket [kg*m^2] */
    /* start of a powertrain run */
    double launch_engine_speed;               /* engine speed at t = 0, vehicle at rest in 1st [rad/s] */
    double ambient_pressure;                  /* air the engine breathes [Pa] */
    double ambient_temperature;               /* [K] */
    double engine_macro_step;                 /* [s] crank-angle engine co-simulation step; 0: in the RK4 */
} ts_driveline_config;

#endif
