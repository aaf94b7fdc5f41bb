/*
 * vehicle_layout.c — the circuit's order and the CG over the ground contact
 * (vehicle_layout.h).
 *
 * Why: a layout in another order is still a closed loop of tangents, but not
 * this vehicle's: the track crosses itself or wraps a body inside-out, and a
 * run gives numbers without meaning (session-24 probe: the CG at x = 12 m ran
 * to a 100-degree pitch with the hull 6.5 m underground; a sprocket ahead of
 * the idler ran too). The CG must lie strictly between the end road wheels:
 * over wheel n itself the whole weight sits on that one wheel and the hull
 * pitches 0.3 rad at rest. The road-wheel hubs must lie below the support
 * rollers (the upper run); the sprocket and idler may sit as low as the hubs
 * (the model runs such layouts).
 */
#include "vehicle_layout.h"

#include <math.h>

ts_rc ts_vehicle_layout_check(const ts_vehicle_config *vc, ts_err *err)
{
    const double *w = vc->road_wheel_x;
    int n = vc->road_wheel_n;
    if (n < 1) return TS_OK; /* the callers say how many wheels they need */
    if (!(vc->sprocket_x < w[n - 1]))
        return ts_err_set(err, TS_ERR_PARAM, "/vehicle/sprocket_x",
                          "/vehicle/sprocket_x: the sprocket (x = %g m) must lie behind road "
                          "wheel %d (x = %g m)",
                          vc->sprocket_x, n, w[n - 1]);
    if (!(vc->idler_x > w[0]))
        return ts_err_set(err, TS_ERR_PARAM, "/vehicle/idler_x",
                          "/vehicle/idler_x: the idler (x = %g m) must lie ahead of road wheel 1 "
                          "(x = %g m)",
                          vc->idler_x, w[0]);
    for (int i = 1; i < n; i++)
        if (!(w[i] < w[i - 1]))
            return ts_err_set(err, TS_ERR_PARAM, "/vehicle/road_wheel_x",
                              "/vehicle/road_wheel_x: road wheels are listed front (1) to rear "
                              "(%d), x decreasing; wheel %d (x = %g m) is not behind wheel %d "
                              "(x = %g m)",
                              n, i + 1, w[i], i, w[i - 1]);
    if (!(vc->sprocket_x < vc->rear_roller_x))
        return ts_err_set(err, TS_ERR_PARAM, "/vehicle/rear_roller_x",
                          "/vehicle/rear_roller_x: the rear support roller (x = %g m) must lie "
                          "ahead of the rear sprocket (x = %g m)",
                          vc->rear_roller_x, vc->sprocket_x);
    if (!(vc->rear_roller_x < vc->front_roller_x))
        return ts_err_set(err, TS_ERR_PARAM, "/vehicle/front_roller_x",
                          "/vehicle/front_roller_x: the front support roller (x = %g m) must lie "
                          "ahead of the rear one (x = %g m)",
                          vc->front_roller_x, vc->rear_roller_x);
    if (!(vc->front_roller_x < vc->idler_x))
        return ts_err_set(err, TS_ERR_PARAM, "/vehicle/idler_x",
                          "/vehicle/idler_x: the front idler (x = %g m) must lie ahead of the "
                          "front support roller (x = %g m)",
                          vc->idler_x, vc->front_roller_x);
    double zmin = fmin(vc->rear_roller_z, vc->front_roller_z);
    if (!(vc->road_wheel_z < zmin))
        return ts_err_set(err, TS_ERR_PARAM, "/vehicle/road_wheel_z",
                          "/vehicle/road_wheel_z: the road-wheel hubs (z = %g m) must lie below "
                          "the support rollers' centres on the upper run (lowest z = %g m)",
                          vc->road_wheel_z, zmin);
    if (!(vc->cg_x > w[n - 1] && vc->cg_x < w[0]))
        return ts_err_set(err, TS_ERR_PARAM, "/vehicle/cg_x",
                          "/vehicle/cg_x: the hull CG (x = %g m) must lie over the ground contact, "
                          "between road wheels %d and 1 (x = %g .. %g m)",
                          vc->cg_x, n, w[n - 1], w[0]);
    /* the arm's own inertia about its centre, at mid-length (vehicle_model.c),
     * is the pivot's less m (a/2)^2 by the parallel-axis theorem */
    double i_min = vc->road_arm_mass * 0.25 * vc->road_arm_length * vc->road_arm_length;
    if (!(vc->road_arm_inertia > i_min))
        return ts_err_set(err, TS_ERR_PARAM, "/vehicle/road_arm_inertia",
                          "/vehicle/road_arm_inertia: %g kg*m^2 about the pivot is not more than "
                          "the arm's mass at its mid-length gives, m (a/2)^2 = %g kg*m^2 "
                          "(/vehicle/road_arm_mass, road_arm_length)",
                          vc->road_arm_inertia, i_min);
    return TS_OK;
}
