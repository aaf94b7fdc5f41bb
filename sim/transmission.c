/*
 * transmission.c — clutch-to-clutch four-speed automatic (transmission.h),
 * paper Section III.B.2. Leaves out: reverse gears, shift-pressure feedback
 * control, clutch thermal effects, gear lash; the planetary gear sets appear
 * only through their ratios (one clutch per range).
 */
#include "transmission.h"

#include <math.h>

#define EVENT_TIME_TOL 1e-9  /* relative slack when testing a time event at its root */
#define EVENT_SPEED_TOL 1e-6 /* relative slack when testing a speed event at its root */

ts_rc ts_transmission_init(ts_transmission *tr, const ts_driveline_config *c, ts_err *err)
{
    if (c->gear_ratio_n < 1)
        return ts_err_set(err, TS_ERR_PARAM, "/driveline/gear_ratio",
                          "/driveline/gear_ratio: need at least one gear");
    if (c->gear_efficiency_n != c->gear_ratio_n)
        return ts_err_set(err, TS_ERR_PARAM, "/driveline/gear_efficiency",
                          "/driveline/gear_efficiency: %d values for %d gears",
                          c->gear_efficiency_n, c->gear_ratio_n);
    for (int i = 1; i < c->gear_ratio_n; i++)
        if (!(c->gear_ratio[i] < c->gear_ratio[i - 1]))
            return ts_err_set(err, TS_ERR_PARAM, "/driveline/gear_ratio",
                              "/driveline/gear_ratio: ratios must decrease (gear %d)", i + 1);
    if (c->downshift_speed > 0 && !(c->downshift_speed < c->shift_speed))
        return ts_err_set(err, TS_ERR_PARAM, "/driveline/downshift_speed",
                          "/driveline/downshift_speed: must be below shift_speed");
    tr->n = c->gear_ratio_n;
    for (int i = 0; i < tr->n; i++) {
        tr->ratio[i] = c->gear_ratio[i];
        tr->efficiency[i] = c->gear_efficiency[i];
    }
    tr->shift_speed = c->shift_speed;
    tr->downshift_speed = c->downshift_speed;
    tr->shift_time = c->shift_time;
    tr->shift_dwell = c->shift_dwell;
    tr->shift_hysteresis = c->shift_hysteresis;
    tr->clutch_capacity = c->clutch_capacity;
    tr->shift_capacity_factor = c->shift_capacity_factor;
    tr->shift_capacity_floor = c->shift_capacity_floor;
    tr->slip_speed = c->clutch_slip_speed;
    return TS_OK;
}

void ts_transmission_reset(const ts_transmission *tr, ts_shift_state *st, int gear)
{
    if (gear < 1) gear = 1;
    if (gear > tr->n) gear = tr->n;
    *st = (ts_shift_state){.gear = gear, .target = 0, .t_start = 0, .capacity = 0, .shifts = 0,
                           .armed = 1, .t_end = 0};
}

static double shift_fraction(const ts_transmission *tr, const ts_shift_state *st, double t)
{
    double tau = (t - st->t_start) / tr->shift_time;
    return tau < 0 ? 0 : tau > 1 ? 1 : tau;
}

/* Clutch of gear g (1-based) with capacity cap: its input-side torque, and its
 * contribution to the output torque. */
static double clutch(const ts_transmission *tr, int g, double cap, double w_in, double w_out,
                     double *to_output, double *slip)
{
    double r = tr->ratio[g - 1], eta = tr->efficiency[g - 1];
    double s = w_in - r * w_out;
    /* slip speed scaled with the capacity: the same stiffness C_max / w_s near
     * zero slip whatever the capacity, so a capacity change of a locked clutch
     * barely moves its creep, and the explicit stability limit is fixed */
    double tq = cap > 0 ? cap * tanh(s * tr->clutch_capacity / (tr->slip_speed * cap)) : 0.0;
    *to_output = r * (tq >= 0 ? eta * tq : tq / eta);
    if (slip) *slip = s;
    return tq;
}

/* End of the post-shift capacity ramp [s] (st->capacity > 0). */
static double ramp_end(const ts_transmission *tr, const ts_shift_state *st)
{
    return st->t_start + 2.0 * tr->shift_time;
}

/* Capacity of the engaged clutch outside a shift. After a shift the clutch
 * that came on rises linearly from Cs to clutch_capacity over one more
 * shift_time (transmission.h), so a clutch still slipping when the shift
 * interval ends closes its slip under a rising torque instead of being
 * slammed shut at full capacity. Before the first shift (capacity 0):
 * clutch_capacity. */
static double applied_capacity(const ts_transmission *tr, const ts_shift_state *st, double t)
{
    if (!(st->capacity > 0)) return tr->clutch_capacity;
    double c = st->capacity + (tr->clutch_capacity - st->capacity) *
                                  ((t - st->t_start) / tr->shift_time - 1.0);
    if (c < st->capacity) c = st->capacity;
    return c < tr->clutch_capacity ? c : tr->clutch_capacity;
}

double ts_transmission_applied_capacity(const ts_transmission *tr, const ts_shift_state *st,
                                        double t)
{
    return st->target ? 0.0 : applied_capacity(tr, st, t);
}

void ts_transmission_eval(const ts_transmission *tr, const ts_shift_state *st, double t,
                          double w_in, double w_out, ts_tr_point *out)
{
    double o1, o2 = 0;
    if (!st->target) {
        out->offgoing_torque =
            clutch(tr, st->gear, applied_capacity(tr, st, t), w_in, w_out, &o1, &out->slip);
        out->oncoming_torque = 0;
        out->gear = st->gear;
    } else {
        double tau = shift_fraction(tr, st, t);
        out->offgoing_torque =
            clutch(tr, st->gear, (1 - tau) * st->capacity, w_in, w_out, &o1, &out->slip);
        out->oncoming_torque = clutch(tr, st->target, tau * st->capacity, w_in, w_out, &o2, NULL);
        out->gear = st->gear + tau * (st->target - st->gear);
    }
    out->input_torque = out->offgoing_torque + out->oncoming_torque;
    out->output_torque = o1 + o2;
}

/* The downshift condition as one function, <= 0 when it holds: the engine at
 * or below downshift_speed AND the lower gear's input speed at this output
 * speed, r(g-1) w_out, at or below it too. The second half keeps the downshift
 * for a slow vehicle: the engine also falls to downshift_speed when the rack
 * drops at speed, and a downshift there was undone by the next upshift as soon
 * as the rack came back (a speed controller made the pair hunt, 28 times a
 * minute at 16 km/h). After the downshift the turbine turns at most at
 * downshift_speed, and the upshift needs the engine at shift_speed, which the
 * converter reaches only well above that turbine speed. */
static double downshift_root(const ts_transmission *tr, const ts_shift_state *st, double w_engine,
                             double w_out)
{
    double lower = tr->ratio[st->gear - 2] * w_out;
    return fmax(w_engine, lower) - tr->downshift_speed;
}

void ts_transmission_roots(const ts_transmission *tr, const ts_shift_state *st, double t,
                           double w_engine, double w_out, double *g)
{
    double rearm = tr->shift_speed - tr->shift_hysteresis;
    if (st->target) {
        /* shift end; the engine's fall to the re-arm speed during the shift */
        g[0] = st->t_start + tr->shift_time - t;
        g[1] = !st->armed ? w_engine - rearm : 1.0;
        g[2] = g[3] = 1.0;
        return;
    }
    /* armed: the upward crossing of shift_speed; disarmed: the fall to the
     * re-arm speed, or the end of the dwell */
    g[0] = st->gear < tr->n ? w_engine - (st->armed ? tr->shift_speed : rearm) : 1.0;
    g[1] =
        (st->gear > 1 && tr->downshift_speed > 0) ? downshift_root(tr, st, w_engine, w_out) : 1.0;
    g[2] = (!st->armed && st->gear < tr->n) ? st->t_end + tr->shift_dwell - t : 1.0;
    g[3] = st->capacity > 0 ? ramp_end(tr, st) - t : 1.0;
}

int ts_transmission_update(const ts_transmission *tr, ts_shift_state *st, double t, double w_engine,
                           double w_out, double input_torque)
{
    int fell = w_engine <= (tr->shift_speed - tr->shift_hysteresis) * (1 + EVENT_SPEED_TOL);
    if (st->target) {
        /* the engine's dip during the shift re-arms the next upshift (it can
         * start once this shift is over); a change of the root functions */
        int changed = 0;
        if (!st->armed && fell) st->armed = changed = 1;
        double t_end = st->t_start + tr->shift_time;
        if (t < t_end - EVENT_TIME_TOL * (1.0 + fabs(t_end))) return changed;
        st->gear = st->target;
        st->target = 0;
        st->shifts++;
        st->t_end = t;
        return 1;
    }
    /* the engaged clutch's capacity ramp is over: fully applied */
    int ramp_done = 0;
    if (st->capacity > 0) {
        double te = ramp_end(tr, st);
        if (t >= te - EVENT_TIME_TOL * (1.0 + fabs(te))) {
            st->capacity = 0;
            ramp_done = 1;
        }
    }
    /* re-arm: the engine has come down to shift_speed - hysteresis, or the
     * dwell is over; a change of the root functions, so report it */
    if (!st->armed && (fell || t >= st->t_end + tr->shift_dwell - EVENT_TIME_TOL * (1.0 + fabs(t)))) {
        st->armed = 1;
        if (w_engine < tr->shift_speed * (1 - EVENT_SPEED_TOL)) return 1;
    }
    int to = 0;
    if (st->armed && st->gear < tr->n && w_engine >= tr->shift_speed * (1 - EVENT_SPEED_TOL))
        to = st->gear + 1;
    else if (st->gear > 1 && tr->downshift_speed > 0 &&
             downshift_root(tr, st, w_engine, w_out) <= tr->downshift_speed * EVENT_SPEED_TOL)
        to = st->gear - 1;
    if (!to) return ramp_done;
    double cs = tr->shift_capacity_factor * fabs(input_torque);
    double floor = tr->shift_capacity_floor * tr->clutch_capacity;
    st->capacity = cs > floor ? cs : floor;
    st->target = to;
    st->armed = 0;
    st->t_start = t;
    return 1;
}
