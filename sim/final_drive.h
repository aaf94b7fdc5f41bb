/*
 * final_drive.h — propshaft, differential and final drives to both sprockets,
 * and the sprocket pitch radius that turns sprocket torque into track force
 * (paper Section III.B.2: "the transmission output (speed and torque) is
 * further transformed by the propshaft, differential, and driveshaft modules
 * ... a single rear axle driving the track via a pair of sprockets").
 *
 * Straight running in the pitch plane: the differential splits torque equally
 * and both sprockets turn at the same speed. Losses as one efficiency on the
 * forward power path (its inverse when torque flows back). Shaft compliance
 * and lash are left out; the inertias are lumped by the caller.
 */
#ifndef TS_FINAL_DRIVE_H
#define TS_FINAL_DRIVE_H

#include "config.h"
#include "errors.h"

typedef struct ts_final_drive {
    double ratio;           /* transmission output speed / sprocket speed [1] */
    double efficiency;      /* [1] */
    double sprocket_radius; /* pitch radius [m] */
    double output_inertia;  /* transmission output .. both sprockets, at the sprocket [kg*m^2] */
} ts_final_drive;

TS_MUST_CHECK ts_rc ts_final_drive_init(ts_final_drive *fd, const ts_driveline_config *c,
                                        const ts_vehicle_config *v, ts_err *err);

/* Transmission output speed for a sprocket speed [rad/s]. */
double ts_final_drive_output_speed(const ts_final_drive *fd, double w_sprocket);

/* Torque at EACH of the two sprockets for a transmission output torque [N*m]. */
double ts_final_drive_sprocket_torque(const ts_final_drive *fd, double output_torque);

/* Track (tractive) force of one track from its sprocket torque [N]. */
double ts_final_drive_track_force(const ts_final_drive *fd, double sprocket_torque);

#endif
