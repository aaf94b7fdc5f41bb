/*
 * vehicle_channels.h — the output channels of the multibody vehicle, one
 * definition shared by the scenarios that run it (vehicle: prescribed torque;
 * coupled: the powertrain drives it), so names, units and descriptions are
 * written once. Names are stable API (the fixed vehicle channels and the per-span,
 * per-arm and per-wheel channels of issue 4).
 *
 * Block layout (indices relative to the block's first channel):
 *   vehicle.x, vehicle.speed, hull.z, hull.pitch, hull.accel_x, hull.accel_z,
 *   track.tension.rear_roller, roller.rear.normal_force, track.anchor_force,
 *   road_arm.1..7.angle, road_wheel.1..7.load, span.<name>.tension (x5),
 *   span.<name>.deflection (x5), track.tension.quasi_static.
 */
#ifndef TS_VEHICLE_CHANNELS_H
#define TS_VEHICLE_CHANNELS_H

#include "scenario.h"
#include "vehicle_model.h"

enum {
    VM_CH_X,       /* hull CG distance travelled [m] */
    VM_CH_SPEED,   /* hull CG forward speed [m/s] */
    VM_CH_Z,       /* hull CG height [m] */
    VM_CH_PITCH,   /* hull pitch, positive nose-down [rad] */
    VM_CH_AX,      /* hull CG longitudinal acceleration [m/s^2] */
    VM_CH_AZ,      /* hull CG vertical acceleration [m/s^2] */
    VM_CH_T_RR,    /* track tension at the rear support roller [N] */
    VM_CH_N_RR,    /* track load on the rear support roller [N] */
    VM_CH_ANCHOR,  /* tangential ground force at the no-slip anchor [N] */
    VM_CH_ARM0,    /* road-arm angles, road wheel 1 (front) first [rad] */
    VM_CH_LOAD0 = VM_CH_ARM0 + VM_NRW,      /* ground load per road wheel [N] */
    VM_CH_SPAN_T0 = VM_CH_LOAD0 + VM_NRW,   /* mid-span tension per free span [N] */
    VM_CH_SPAN_V0 = VM_CH_SPAN_T0 + VM_NSPAN, /* mid-span transverse deflection [m] */
    VM_CH_T_QS = VM_CH_SPAN_V0 + VM_NSPAN, /* quasi-static rear-roller tension [N] */
    VM_NCH
};

/* Declare the VM_NCH channels, in block order, at the model's next indices. */
TS_MUST_CHECK ts_rc vm_channels_declare(ts_model *m, ts_err *err);

/* Write the block's VM_NCH values for state y (positions then velocities),
 * its derivative ydot and the diagnostics of the vm_rhs call that made ydot. */
void vm_channels_fill(const vm *v, const double *y, const double *ydot, const vm_diag *dg,
                      double *out);

/* Range-of-validity metrics over a finished run's rows (nrows rows of nc
 * values; the block starts at column first): "span_tension_min" [N], the
 * least mid-span tension of any free span, and "span_compression_fraction"
 * [1], the share of rows in which some span's is below zero. A track cannot
 * push: a massless (static-fidelity) element goes slack at zero tension, but
 * the modal spans are linear about a taut, sagging equilibrium (track_span.h)
 * and have no slack law, so rows with a negative span tension are outside the
 * model's range. Appends to out[n..] (ts_metric_add); returns the new count. */
int vm_channels_span_metrics(const double *rows, long nrows, int nc, int first, ts_metric *out,
                             int n, int max);

/* Traction metrics over the same rows: "traction_demand_max" [1], the
 * largest |anchor force| / sum of road-wheel loads over rows with a loaded
 * wheel (NaN if none), and "traction_exceeded_fraction" [1], the share of rows
 * whose anchor force exceeds limit times the loads (an unloaded row with any
 * anchor force counts). The ground run never slips (vehicle_model.c), so such
 * rows are outside the model's range. Appends to out[n..]; returns the count. */
int vm_channels_traction_metrics(const double *rows, long nrows, int nc, int first, double limit,
                                 ts_metric *out, int n, int max);

#endif
