/*
 * cfg_vehicle.h — "vehicle", "terrain" and "drive" sections of a run config:
 * whole-vehicle quantities, the ground under it and the prescribed sprocket drive.
 * The multibody (hull, road arms, wheels) fields are added by the vehicle module.
 */
#ifndef TS_CFG_VEHICLE_H
#define TS_CFG_VEHICLE_H

#define TS_DRIVE_TABLE_MAX 512
#define TS_MAX_ROAD_WHEELS 10
#define TS_NAME_LEN        64
#define TS_PATH_LEN        256

typedef struct ts_vehicle_config {
    double mass;                         /* combat mass, whole vehicle [kg] */
    double sprocket_radius;              /* sprocket pitch radius [m] */
    double rolling_resistance;           /* rolling-resistance coefficient at rest [1] */
    double rolling_resistance_speed;     /* its growth with speed [s/m] */
    double rolling_resistance_smoothing; /* speed scale of its sign through standstill [m/s] */
    double cda;                          /* drag coefficient x frontal area [m^2] */
    double air_density;                  /* [kg/m^3] */
    double grade;                        /* road slope, positive uphill [rad] */
    double rotating_mass_factor;         /* effective/actual mass for point-mass runs [1] */
    /* Running-gear layout, hull-fixed, at static equilibrium on flat ground:
     * origin on the ground below the sprocket axle, x forward, z up [m]. */
    double sprocket_x, sprocket_z;         /* drive sprocket centre (rear) */
    double rear_roller_x, rear_roller_z;   /* rear ("second") support roller centre */
    double front_roller_x, front_roller_z; /* front support roller centre */
    double roller_radius;                  /* support roller radius */
    double idler_x, idler_z;               /* idler centre (front, on the adjusting link) */
    double idler_radius;
    int road_wheel_n;                        /* road wheels per side (7) */
    double road_wheel_x[TS_MAX_ROAD_WHEELS]; /* hub x, road wheel 1 (front) to 7 (rear) */
    double road_wheel_z;                     /* hub height at static equilibrium */
    double road_wheel_radius;
    /* Multibody data of the pitch-plane model (vehicle_model.h). Whole-vehicle
     * quantities unless marked "per station/side": the model is one side (one
     * track) carrying half the hull. */
    double hull_pitch_inertia; /* I_yy of the hull about its CG, whole vehicle [kg*m^2] */
    double cg_x, cg_z;         /* hull CG in the layout frame [m] */
    double road_wheel_mass;    /* dual road wheel, per station per side [kg] */
    double road_wheel_inertia; /* its spin inertia [kg*m^2] */
    double road_arm_mass;      /* road arm, per station per side [kg] */
    double road_arm_inertia;   /* road arm about its pivot [kg*m^2] */
    double road_arm_length;    /* pivot to hub [m] */
    double road_arm_angle;     /* design static arm angle below horizontal [rad] */
    double torsion_bar_rate;   /* per arm [N*m/rad] */
    int damper_station_n;
    double damper_station[TS_MAX_ROAD_WHEELS]; /* stations (1 = front) with rotary dampers */
    double damper_rate;                        /* rotary damper [N*m*s/rad] */
    int bump_stop_station_n;
    double bump_stop_station[TS_MAX_ROAD_WHEELS]; /* stations with bump stops */
    double bump_stop_angle;                       /* arm angle where the stop engages [rad] */
    double bump_stop_rate;                        /* [N*m/rad] */
    double sprocket_inertia, idler_inertia, roller_inertia; /* spin inertias [kg*m^2] */
    double track_pitch_offset;                              /* pitch line outside wheel rims [m] */
    double track_thickness;      /* rim to ground under a road wheel [m] */
    double track_damping_time;   /* Kelvin-Voigt time of the track elements [s] */
    double idler_link_angle;     /* track-adjusting link direction above hull x [rad] */
    double idler_compensation;   /* share of arm 1's loop-length change the link takes up */
    double foundation_stiffness; /* track-terrain, per road wheel [N/m] */
    double foundation_cubic;     /* cubic stiffening [N/m^3] */
    double foundation_damping;   /* [N*s/m] */
    double anchor_stiffness;     /* no-slip under the anchor wheel, tangential [N/m] */
    double anchor_damping;       /* [N*s/m] */
    int anchor_station;          /* road wheel that anchors the ground run (4) */
    double traction_limit;       /* largest drive pull over the road wheels' load [1] */
    double damping_scale; /* multiplies every damper, foundation and track damping (1; 0 for energy
                             checks) */
} ts_vehicle_config;

typedef enum ts_terrain_kind {
    TS_TERRAIN_FLAT,
    TS_TERRAIN_BUMPS,
    TS_TERRAIN_PROFILE,
    TS_NTERRAIN
} ts_terrain_kind;
extern const char *const ts_terrain_kind_names[];

#define TS_TERRAIN_BUMPS_MAX 128

typedef struct ts_terrain_config {
    int kind;                      /* ts_terrain_kind */
    char course[TS_NAME_LEN];      /* shipped course name for kind "bumps" */
    char course_dir[TS_PATH_LEN];  /* directory of shipped courses (NAME.txt) */
    char profile_csv[TS_PATH_LEN]; /* user CSV (distance m, height m) for kind "profile" */
    int bump_n;                    /* inline bump list (overrides the course file when set) */
    double bump_start[TS_TERRAIN_BUMPS_MAX]; /* [m] */
    int bump_height_n;
    double bump_height[TS_TERRAIN_BUMPS_MAX]; /* [m] */
    int bump_length_n;
    double bump_length[TS_TERRAIN_BUMPS_MAX]; /* [m] */
    double start_x; /* world x of the layout origin (below the sprocket) at t = 0 [m] */
} ts_terrain_config;

typedef enum ts_drive_kind {
    TS_DRIVE_CONSTANT,   /* constant sprocket torque */
    TS_DRIVE_RAMP,       /* linear ramp from 0 to torque over ramp_time, then constant */
    TS_DRIVE_TABLE,      /* piecewise-linear time history (table_t, table_torque) */
    TS_DRIVE_POWERTRAIN, /* torque from the engine and driveline */
    TS_NDRIVE
} ts_drive_kind;
extern const char *const ts_drive_kind_names[];

typedef struct ts_drive_config {
    int kind;                                /* ts_drive_kind */
    double torque;                           /* torque at EACH of the two sprockets [N*m] */
    double ramp_time;                        /* [s] */
    int table_n;                             /* rows in the time history */
    double table_t[TS_DRIVE_TABLE_MAX];      /* [s], increasing */
    int table_torque_n;                      /* must equal table_n */
    double table_torque[TS_DRIVE_TABLE_MAX]; /* torque at each sprocket [N*m] */
} ts_drive_config;

#endif
