/*
 * vehicle_channels.c — the multibody vehicle's channel block (vehicle_channels.h).
 */
#include "vehicle_channels.h"

#include <math.h>
#include <stdio.h>

static ts_rc add(ts_model *m, const char *name, const char *unit, const char *desc, ts_err *err)
{
    return ts_model_add_channel(m, name, unit, desc, err) < 0 ? (err ? err->code : TS_ERR_INTERNAL)
                                                              : TS_OK;
}

ts_rc vm_channels_declare(ts_model *m, ts_err *err)
{
    static const ts_channel ch[] = {
        {"vehicle.x", "m", "distance travelled by the hull CG"},
        {"vehicle.speed", "m/s", "hull CG forward speed"},
        {"hull.z", "m", "hull CG height above the course datum"},
        {"hull.pitch", "rad", "hull pitch, positive nose-down"},
        {"hull.accel_x", "m/s^2",
         "hull CG longitudinal acceleration, positive forward (Fig. 11 plots -x)"},
        {"hull.accel_z", "m/s^2", "hull CG vertical acceleration"},
        {"track.tension.rear_roller", "N",
         "track tension at the rear support roller (Figs. 12, 29, 35)"},
        {"roller.rear.normal_force", "N",
         "track load on the rear support roller (Fig. 14); negative when the spans' end "
         "forces pull it up (the track is held on the roller: no lift-off)"},
        {"track.anchor_force", "N", "tangential ground force at the no-slip anchor (thrust)"},
    };
    ts_rc rc = ts_model_add_channels(m, ch, (int)(sizeof ch / sizeof ch[0]), err);
    char name[96], desc[160];
    for (int i = 0; i < VM_NRW && rc == TS_OK; i++) {
        snprintf(name, sizeof name, "road_arm.%d.angle", i + 1);
        snprintf(desc, sizeof desc, "road arm %d angle below hull x (1 = front)", i + 1);
        rc = add(m, name, "rad", desc, err);
    }
    for (int i = 0; i < VM_NRW && rc == TS_OK; i++) {
        snprintf(name, sizeof name, "road_wheel.%d.load", i + 1);
        snprintf(desc, sizeof desc, "ground load under road wheel %d, one side (normal to the ground)", i + 1);
        rc = add(m, name, "N", desc, err);
    }
    for (int s = 0; s < VM_NSPAN && rc == TS_OK; s++) {
        snprintf(name, sizeof name, "span.%s.tension", vm_span_names[s]);
        snprintf(desc, sizeof desc, "track tension at mid-span, span %s", vm_span_names[s]);
        rc = add(m, name, "N", desc, err);
    }
    for (int s = 0; s < VM_NSPAN && rc == TS_OK; s++) {
        snprintf(name, sizeof name, "span.%s.deflection", vm_span_names[s]);
        snprintf(desc, sizeof desc,
                 "dynamic transverse mid-span deflection (outward), span %s (Fig. 30; 0 "
                 "without modes)",
                 vm_span_names[s]);
        rc = add(m, name, "m", desc, err);
    }
    if (rc == TS_OK)
        rc = add(m, "track.tension.quasi_static", "N",
                 "rear-roller tension a massless track would have for the current support "
                 "positions and sprocket torque (static element law, no damping); "
                 "track.tension.rear_roller minus this is the dynamic part (Fig. 12)",
                 err);
    return rc;
}

void vm_channels_fill(const vm *v, const double *y, const double *ydot, const vm_diag *dg,
                      double *out)
{
    int nq = vm_nq(v);
    const double *q = y, *qd = y + nq, *qdd = ydot + nq;
    out[VM_CH_X] = q[0] - vm_x0(v);
    out[VM_CH_SPEED] = qd[0];
    out[VM_CH_Z] = q[1];
    out[VM_CH_PITCH] = q[2];
    out[VM_CH_AX] = qdd[0];
    out[VM_CH_AZ] = qdd[1];
    out[VM_CH_T_RR] = dg->tension_end1[0];
    out[VM_CH_N_RR] = dg->rear_roller_normal;
    out[VM_CH_ANCHOR] = dg->anchor_force;
    for (int i = 0; i < VM_NRW; i++) {
        out[VM_CH_ARM0 + i] = dg->arm_angle[i];
        out[VM_CH_LOAD0 + i] = dg->wheel_load[i];
    }
    for (int s = 0; s < VM_NSPAN; s++) {
        /* a massless (static-fidelity) span has no mid-span value: its element tension */
        double mid = dg->span_mid_tension[s];
        out[VM_CH_SPAN_T0 + s] = mid != 0 ? mid : dg->tension[vm_span_element[s]];
        out[VM_CH_SPAN_V0 + s] = dg->span_mid_deflection[s];
    }
    out[VM_CH_T_QS] = dg->tension_quasi_static;
}

int vm_channels_span_metrics(const double *rows, long nrows, int nc, int first, ts_metric *out,
                             int n, int max)
{
    double tmin = INFINITY;
    long slack = 0;
    for (long i = 0; i < nrows; i++) {
        const double *r = rows + i * nc + first + VM_CH_SPAN_T0;
        double ri = INFINITY;
        for (int k = 0; k < VM_NSPAN; k++) ri = fmin(ri, r[k]);
        tmin = fmin(tmin, ri);
        slack += ri < 0;
    }
    n = ts_metric_add(out, n, max, "span_tension_min", "N", nrows > 0 ? tmin : NAN,
                      "least mid-span tension of any free span (a massless static-fidelity "
                      "element goes slack at 0; a modal span has no slack law, so below zero it "
                      "is outside its range: a track cannot push)");
    n = ts_metric_add(out, n, max, "span_compression_fraction", "1",
                      nrows > 0 ? (double)slack / (double)nrows : NAN,
                      "share of output rows in which some free span's mid-span tension is below "
                      "zero (model outside its range there)");
    return n;
}

int vm_channels_traction_metrics(const double *rows, long nrows, int nc, int first, double limit,
                                 ts_metric *out, int n, int max)
{
    double qmax = NAN;
    long over = 0;
    for (long i = 0; i < nrows; i++) {
        const double *r = rows + i * nc + first;
        double load = 0, fa = fabs(r[VM_CH_ANCHOR]);
        for (int k = 0; k < VM_NRW; k++)
            load += r[VM_CH_LOAD0 + k];
        if (load > 0) qmax = fmax(qmax, fa / load); /* fmax skips the NaN start */
        over += fa > limit * load;
    }
    n = ts_metric_add(out, n, max, "traction_demand_max", "1", qmax,
                      "largest |track.anchor_force| over the sum of the road-wheel loads, rows "
                      "with a wheel on the ground: the traction coefficient the no-slip track "
                      "asks of the ground");
    n = ts_metric_add(out, n, max, "traction_exceeded_fraction", "1",
                      nrows > 0 ? (double)over / (double)nrows : NAN,
                      "share of output rows whose anchor force exceeds /vehicle/traction_limit "
                      "times the road-wheel loads, every wheel in the air included: the track "
                      "would slip there, which the model does not (outside its range)");
    return n;
}
