/*
 * drive.c — prescribed sprocket-torque histories (drive.h).
 */
#include "drive.h"

#include <math.h>
#include <stdio.h>

ts_rc ts_drive_check(const ts_drive_config *c, ts_err *err)
{
    if (c->kind != TS_DRIVE_TABLE) return TS_OK;
    if (c->table_n < 1)
        return ts_err_set(err, TS_ERR_PARAM, "/drive/table_t",
                          "/drive/table_t: a table drive needs at least one row");
    if (c->table_torque_n != c->table_n)
        return ts_err_set(err, TS_ERR_PARAM, "/drive/table_torque",
                          "/drive/table_torque: %d values for %d times", c->table_torque_n,
                          c->table_n);
    for (int i = 1; i < c->table_n; i++)
        if (!(c->table_t[i] > c->table_t[i - 1]))
            return ts_err_set(err, TS_ERR_PARAM, "/drive/table_t",
                              "/drive/table_t: times must increase (row %d)", i);
    return TS_OK;
}

double ts_drive_torque(const ts_drive_config *c, double t)
{
    switch (c->kind) {
    case TS_DRIVE_CONSTANT: return c->torque;
    case TS_DRIVE_RAMP:
        if (c->ramp_time <= 0 || t >= c->ramp_time) return c->torque;
        return t <= 0 ? 0.0 : c->torque * t / c->ramp_time;
    case TS_DRIVE_TABLE: {
        int n = c->table_n;
        if (n <= 0) return 0.0;
        if (t <= c->table_t[0]) return c->table_torque[0];
        if (t >= c->table_t[n - 1]) return c->table_torque[n - 1];
        int lo = 0, hi = n - 1; /* bisection: table_t[lo] <= t < table_t[hi] */
        while (hi - lo > 1) {
            int mid = (lo + hi) / 2;
            if (c->table_t[mid] <= t) lo = mid;
            else hi = mid;
        }
        double s = (t - c->table_t[lo]) / (c->table_t[hi] - c->table_t[lo]);
        return c->table_torque[lo] + s * (c->table_torque[hi] - c->table_torque[lo]);
    }
    default: return 0.0;
    }
}

/* Largest |torque| the drive ever asks at each sprocket [N*m] (0 for kind
 * "powertrain"), and the field that sets it: *pointer "/drive/torque", or
 * "/drive/table_torque" with the row in *row (else -1). */
static double peak_torque(const ts_drive_config *c, const char **pointer, int *row)
{
    *pointer = "/drive/torque";
    *row = -1;
    switch (c->kind) {
    case TS_DRIVE_CONSTANT:
    case TS_DRIVE_RAMP:
        return fabs(c->torque);
    case TS_DRIVE_TABLE: {
        double peak = 0;
        for (int i = 0; i < c->table_n && i < c->table_torque_n; i++)
            if (fabs(c->table_torque[i]) > peak) {
                peak = fabs(c->table_torque[i]);
                *pointer = "/drive/table_torque";
                *row = i;
            }
        return peak;
    }
    default:
        return 0.0;
    }
}

ts_rc ts_drive_check_traction(const ts_drive_config *c, double sprocket_radius, double weight,
                              double limit, ts_err *err)
{
    const char *ptr;
    int row;
    double tau = peak_torque(c, &ptr, &row), pull = tau / sprocket_radius;
    if (pull <= limit * weight) return TS_OK;
    char at[64];
    if (row >= 0)
        snprintf(at, sizeof at, "%s/%d", ptr, row);
    else
        snprintf(at, sizeof at, "%s", ptr);
    return ts_err_set(err, TS_ERR_RANGE, at,
                      "%s: %g N*m at each sprocket pulls its track with %.0f N, %.2f times the "
                      "%.0f N of weight on it, past /vehicle/traction_limit %g: the model's track "
                      "does not slip, so the run would carry that pull whatever the ground gives",
                      at, tau, pull, pull / weight, weight, limit);
}
