/*
 * final_drive.c — propshaft / differential / final drive (final_drive.h),
 * paper Section III.B.2.
 */
#include "final_drive.h"

ts_rc ts_final_drive_init(ts_final_drive *fd, const ts_driveline_config *c,
                          const ts_vehicle_config *v, ts_err *err)
{
    if (!(v->sprocket_radius > 0))
        return ts_err_set(err, TS_ERR_PARAM, "/vehicle/sprocket_radius",
                          "/vehicle/sprocket_radius: must be positive");
    fd->ratio = c->final_ratio;
    fd->efficiency = c->final_efficiency;
    fd->sprocket_radius = v->sprocket_radius;
    fd->output_inertia = c->output_inertia;
    return TS_OK;
}

double ts_final_drive_output_speed(const ts_final_drive *fd, double w_sprocket)
{
    return fd->ratio * w_sprocket;
}

double ts_final_drive_sprocket_torque(const ts_final_drive *fd, double output_torque)
{
    double t = fd->ratio * output_torque;
    return 0.5 * (t >= 0 ? fd->efficiency * t : t / fd->efficiency);
}

double ts_final_drive_track_force(const ts_final_drive *fd, double sprocket_torque)
{
    return sprocket_torque / fd->sprocket_radius;
}
