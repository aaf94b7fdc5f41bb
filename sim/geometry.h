/*
 * geometry.h — a read-only snapshot of the vehicle's geometry at one instant,
 * in SI and in the world frame, for renderers (render/ never sees ts_data).
 *
 * Frame (fixed for the whole project): x forward along the direction of travel,
 * z up, origin on the undisturbed ground at the start line; pitch positive
 * nose-down. A snapshot is a plain value: copy it freely.
 */
#ifndef TS_GEOMETRY_H
#define TS_GEOMETRY_H

#define TS_GEOM_MAX_WHEELS 16
#define TS_GEOM_MAX_TRACK 512
#define TS_GEOM_MAX_TERRAIN 512

typedef enum ts_wheel_role {
    TS_WHEEL_ROAD,     /* road wheel on a road arm */
    TS_WHEEL_SPROCKET, /* drive sprocket */
    TS_WHEEL_IDLER,    /* idler on the track-adjusting link */
    TS_WHEEL_ROLLER,   /* support roller */
    TS_NWHEEL_ROLE
} ts_wheel_role;

typedef struct ts_geom_wheel {
    int role;           /* ts_wheel_role */
    double x, z;        /* centre [m] */
    double radius;      /* [m] */
    double angle;       /* spin angle [rad] */
    double pivot_x, pivot_z; /* road-arm pivot for road wheels (else = centre) [m] */
} ts_geom_wheel;

typedef struct ts_geom {
    double t;                  /* simulated time [s] */
    double hull_x, hull_z;     /* hull reference point (CG) [m] */
    double hull_pitch;         /* [rad], positive nose-down */
    double hull_length, hull_height; /* overall hull box for framing [m] */
    double speed;              /* vehicle speed [m/s] */
    int gear;                  /* transmission gear (0 if none) */
    int nwheel;
    ts_geom_wheel wheel[TS_GEOM_MAX_WHEELS];
    int ntrack;                /* closed polyline of the track pitch line */
    double track_x[TS_GEOM_MAX_TRACK], track_z[TS_GEOM_MAX_TRACK];   /* quasi-static
                                  centreline: supports' current positions + static sag [m] */
    double track_dx[TS_GEOM_MAX_TRACK], track_dz[TS_GEOM_MAX_TRACK]; /* modal (vibration)
                                  deflection to add, scaled by a renderer's exaggeration [m] */
    double track_tension[TS_GEOM_MAX_TRACK]; /* total tension P0 + tau at each point [N] */
    double track_static_tension; /* for colour scaling [N] */
    double track_pitch;          /* shoe pitch, for drawing the shoes [m]; 0: a band, no shoes */
    double track_pitch_offset;   /* pitch line outside the wheels' rims, the shoe body inside
                                    it [m]; 0: not given (a renderer's default) */
    int nterrain;              /* terrain profile under and around the vehicle */
    double terrain_x[TS_GEOM_MAX_TERRAIN], terrain_z[TS_GEOM_MAX_TERRAIN]; /* [m] */
} ts_geom;

#endif
