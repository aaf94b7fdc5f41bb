/*
 * drive.h — prescribed sprocket torque (paper Section II.D: "sprocket drive
 * torque curves can be specified via data files"): constant, a ramp, or a
 * piecewise-linear time history. Used by the point-mass and vehicle scenarios.
 */
#ifndef TS_DRIVE_H
#define TS_DRIVE_H

#include "config.h"

/* Check a drive config's internal consistency (table lengths, increasing times). */
TS_MUST_CHECK ts_rc ts_drive_check(const ts_drive_config *c, ts_err *err);

/* Prescribed torque at EACH sprocket at time t [N*m]. For kind "powertrain"
 * this returns 0: the torque then comes from the powertrain. */
double ts_drive_torque(const ts_drive_config *c, double t);

/* The drive's largest pull on a track, peak torque / sprocket_radius, against
 * limit times weight, the weight on that track's ground run [N]. No scenario
 * lets the track slip, so past the limit it would carry a pull the ground
 * cannot give: TS_ERR_RANGE naming the torque field and /vehicle/traction_limit. */
TS_MUST_CHECK ts_rc ts_drive_check_traction(const ts_drive_config *c, double sprocket_radius,
                                            double weight, double limit, ts_err *err);

#endif
