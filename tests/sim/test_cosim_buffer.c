/*
 * test_cosim_buffer.c — the leading-following driver (cosim.h, paper §IV.A) keeps
 * every leader sample of its lead window for any admissible step choice: a
 * follower step far below the leader step (the /coupling rows allow 1e-6 s
 * against a 1e-3 s leader) and output periods shorter than the lead, which
 * cut the leader's steps at every call end. Fuzz finding: follower_step = 1e-6 s
 * ended every coupled run with "co-simulation buffer full" (TS_ERR_INTERNAL),
 * the buffer having been sized by lead / leader_step alone.
 *
 * EVIDENCE: closed form, no physics: a leader whose torque is t (exactly
 * linear, so the follower's linear interpolation is exact) and a follower that
 * records the torque it reads at its step end; tolerance 1e-12 absolute.
 * Not calibrated.
 */
#include "test_util.h"

#include <math.h>

#include "sim/cosim.h"

typedef struct {
    double t;
    double worst; /* largest |torque read - t_to| */
    long steps;
} follower_state;

static ts_rc leader_adv(void *ud, double t_to, const ts_cosim_report *last, int order,
                        ts_cosim_sample *out, ts_err *err)
{
    (void)ud, (void)last, (void)order, (void)err;
    out->t = t_to;
    out->torque = t_to;
    out->inertia = 0.0;
    return TS_OK;
}

static ts_rc follower_adv(void *ud, double t_to, const ts_cosim_torque *src, ts_cosim_report *out,
                          ts_err *err)
{
    (void)err;
    follower_state *f = ud;
    double e = fabs(ts_cosim_torque_at(src, t_to) - t_to);
    if (e > f->worst) f->worst = e;
    f->t = t_to;
    f->steps++;
    out->t = t_to;
    out->omega = 0.0;
    out->alpha = 0.0;
    return TS_OK;
}

/* Run the driver to t_end in calls of `period` seconds. */
static void run(double leader_step, double follower_step, double lead, double period,
                double t_end)
{
    follower_state f = {0};
    ts_cosim_opts o = {leader_step, follower_step, lead, 1};
    ts_cosim_leader L = {NULL, leader_adv};
    ts_cosim_follower F = {&f, follower_adv};
    ts_cosim_report r0 = {0, 0, 0};
    ts_err err;
    ts_cosim *c = ts_cosim_make(&o, L, F, 0.0, r0, 0.0, &err);
    assert_non_null(c);
    for (double t = period; t < t_end + 0.5 * period; t += period) {
        ts_rc rc = ts_cosim_advance(c, t, &err);
        if (rc != TS_OK)
            fail_msg("h_L %g h_F %g lead %g period %g: %s (%s)", leader_step, follower_step, lead,
                     period, err.msg, ts_rc_name(rc));
    }
    assert_close(ts_cosim_follower_time(c), t_end, 0, 1e-9);
    assert_true(f.worst < 1e-12);
    ts_cosim_free(c);
}

static void follower_step_far_below_leader_step(void **state)
{
    (void)state;
    run(1e-3, 1e-6, 2e-3, 5e-3, 0.02);  /* the fuzz case: defaults but follower_step min */
    run(1e-3, 1e-6, 0.1, 5e-3, 0.02);   /* lead at its maximum */
}

static void output_period_shorter_than_lead(void **state)
{
    (void)state;
    run(1e-3, 1e-3, 0.1, 5e-5, 0.02);   /* 20 kHz output inside a 0.1 s lead */
    run(1e-3, 1e-3, 2e-3, 1e-3, 0.02);  /* the shipped coupling (presets) */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(follower_step_far_below_leader_step),
        cmocka_unit_test(output_period_shorter_than_lead),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
