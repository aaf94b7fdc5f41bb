/*
 * cosim.c — leading–following co-simulation driver (cosim.h, paper §IV.A).
 *
 * Invariants: t_F <= t_L <= t_F + lead (+ rounding); the sample buffer always
 * covers [t_F, t_L]; samples older than t_F are dropped. The buffer is sized at
 * make time from lead / min(leader_step, follower_step), so advancing does not
 * allocate unless calls end many times inside one lead window (then it doubles).
 */
#include "cosim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct ts_cosim_torque {
    const ts_cosim_sample *s;
    int n;
};

struct ts_cosim {
    ts_cosim_opts o;
    ts_cosim_leader leader;
    ts_cosim_follower follower;
    double t_l, t_f;
    ts_cosim_report last;
    ts_cosim_sample *buf; /* published samples, increasing t */
    int n, cap;
    long exchanges;
};

double ts_cosim_predict(const ts_cosim_report *last, int order, double t)
{
    return order >= 1 ? last->omega + last->alpha * (t - last->t) : last->omega;
}

/* One sample field: 0 torque, 1 inertia. */
static double field(const ts_cosim_sample *s, int which) { return which ? s->inertia : s->torque; }

/* Linear interpolation of one sample field in time. */
static double interp(const ts_cosim_torque *src, double t, int which)
{
    const ts_cosim_sample *s = src->s;
    int n = src->n;
    if (n <= 0) return 0.0;
    if (t <= s[0].t) return field(&s[0], which);
    if (t >= s[n - 1].t) return field(&s[n - 1], which);
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (s[mid].t <= t) lo = mid;
        else hi = mid;
    }
    double w = (t - s[lo].t) / (s[hi].t - s[lo].t);
    return field(&s[lo], which) + w * (field(&s[hi], which) - field(&s[lo], which));
}

double ts_cosim_torque_at(const ts_cosim_torque *src, double t)
{
    return interp(src, t, 0);
}

double ts_cosim_inertia_at(const ts_cosim_torque *src, double t)
{
    return interp(src, t, 1);
}

double ts_cosim_torque_end(const ts_cosim_torque *src)
{
    return src->n > 0 ? src->s[src->n - 1].t : -HUGE_VAL;
}

ts_cosim *ts_cosim_make(const ts_cosim_opts *o, ts_cosim_leader leader, ts_cosim_follower follower,
                        double t0, ts_cosim_report initial, double torque0, ts_err *err)
{
    ts_cosim_sample s0 = {t0, torque0, 0.0};
    return ts_cosim_make_sample(o, leader, follower, t0, initial, s0, err);
}

ts_rc ts_cosim_check(const ts_cosim_opts *o, ts_err *err)
{
    if (!(o->leader_step > 0) || !(o->follower_step > 0) || o->predictor_order < 0 ||
        o->predictor_order > 1)
        return ts_err_set(err, TS_ERR_PARAM, "/coupling",
                          "/coupling: steps must be > 0, predictor order 0 or 1");
    /* the follower's step needs the leader's torque to its end: a lead
     * shorter than either step could not be kept */
    if (!(o->lead >= o->leader_step) || !(o->lead >= o->follower_step))
        return ts_err_set(err, TS_ERR_PARAM, "/coupling/lead",
                          "/coupling/lead: %g s must be at least /coupling/leader_step (%g s) and "
                          "/coupling/follower_step (%g s)",
                          o->lead, o->leader_step, o->follower_step);
    return TS_OK;
}

ts_cosim *ts_cosim_make_sample(const ts_cosim_opts *o, ts_cosim_leader leader,
                               ts_cosim_follower follower, double t0, ts_cosim_report initial,
                               ts_cosim_sample sample0, ts_err *err)
{
    if (ts_cosim_check(o, err) != TS_OK) return NULL;
    ts_cosim *c = calloc(1, sizeof *c);
    if (!c) goto nomem;
    c->o = *o;
    c->leader = leader;
    c->follower = follower;
    c->t_l = c->t_f = t0;
    c->last = initial;
    c->last.t = t0;
    /* samples in the window [t_F, t_L]: the leader's steps are leader_step long, but
     * while it waits at the horizon t_F + lead it moves up with every follower step,
     * so the spacing can be as small as follower_step (fuzz finding: follower_step
     * 1e-6 s overflowed a buffer sized by leader_step alone) */
    double spacing = fmin(o->leader_step, o->follower_step);
    c->cap = (int)ceil((o->lead + o->follower_step) / spacing) + 4;
    c->buf = calloc((size_t)c->cap, sizeof *c->buf);
    if (!c->buf) goto nomem;
    c->buf[0] = sample0;
    c->buf[0].t = t0;
    c->n = 1;
    return c;
nomem:
    ts_cosim_free(c);
    ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    return NULL;
}

void ts_cosim_free(ts_cosim *c)
{
    if (!c) return;
    free(c->buf);
    free(c);
}

/* Drop samples entirely before t_f, keeping the one at or just before it. */
static void trim(ts_cosim *c)
{
    int k = 0;
    while (k + 1 < c->n && c->buf[k + 1].t <= c->t_f) k++;
    if (k > 0) {
        memmove(c->buf, c->buf + k, (size_t)(c->n - k) * sizeof *c->buf);
        c->n -= k;
    }
}

/* Double the sample buffer. Only reached when calls end (t_end) many times inside
 * one lead window (output periods shorter than the lead), each cutting a leader
 * step short; the make-time size covers the steps themselves. */
static int grow(ts_cosim *c)
{
    ts_cosim_sample *nb = realloc(c->buf, (size_t)c->cap * 2 * sizeof *c->buf);
    if (!nb) return -1;
    c->buf = nb;
    c->cap *= 2;
    return 0;
}

ts_rc ts_cosim_advance(ts_cosim *c, double t_end, ts_err *err)
{
    const double eps = 1e-12 * (1 + fabs(t_end));
    while (c->t_f < t_end - eps) {
        /* Leader leads: up to `lead` ahead of the follower (and not past t_end). */
        double horizon = fmin(c->t_f + c->o.lead, t_end);
        double need = fmin(c->t_f + c->o.follower_step, t_end);
        while (c->t_l < horizon - eps || c->t_l < need - eps) {
            double t_to = fmin(c->t_l + c->o.leader_step, fmax(horizon, need));
            if (c->n >= c->cap) trim(c);
            if (c->n >= c->cap && grow(c) != 0)
                return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory for co-simulation samples");
            ts_cosim_sample s = {0, 0, 0};
            ts_rc rc = c->leader.advance(c->leader.ud, t_to, &c->last, c->o.predictor_order, &s, err);
            if (rc != TS_OK) return rc;
            c->buf[c->n++] = s;
            c->t_l = t_to;
            c->exchanges++;
        }
        /* Follower follows to its next step, never past the leader. */
        double t_to = fmin(need, c->t_l);
        ts_cosim_torque src = {c->buf, c->n};
        ts_cosim_report r;
        ts_rc rc = c->follower.advance(c->follower.ud, t_to, &src, &r, err);
        if (rc != TS_OK) return rc;
        c->last = r;
        c->t_f = t_to;
        c->exchanges++;
        trim(c);
    }
    return TS_OK;
}

double ts_cosim_follower_time(const ts_cosim *c) { return c->t_f; }
double ts_cosim_leader_time(const ts_cosim *c) { return c->t_l; }
const ts_cosim_report *ts_cosim_last_report(const ts_cosim *c) { return &c->last; }
long ts_cosim_exchanges(const ts_cosim *c) { return c->exchanges; }
