/*
 * cmd_tune.c — "tanksim tune": Ziegler–Nichols open-loop tuning of the IVS
 * speed controller from a simulated step of the rack (paper Section IV.B.1,
 * Eqs. 11-12, Fig. 26), optionally repeated over vehicle masses or grades to
 * give a gain schedule (Fig. 27).
 *
 * Plant: the POINT-MASS vehicle with the powertrain (scenario_pointmass.c,
 * /drive/kind "powertrain") of the given config — engine fidelity, driveline,
 * mass, grade and resistances from it; the multibody vehicle is too slow for
 * the minutes of simulated time the two steady states need. Procedure: settle
 * at /control/tune_rack_low for /control/tune_settle s (steady state 0), save
 * the state, restore it into a second model at full rack and run
 * /control/tune_duration s more; the final speed is the rated steady state b.
 * The speed is normalised by Eq. 11 and ts_zn_reaction_curve builds the
 * tangent (X, Y); K_p = kp_factor/|Y| (normalised) and T_I = ti_factor |X| (Eq. 12).
 *
 * Prints one JSON document:
 *   {"plant", "rack_low", "rack_rated", "v0", "vb", "settle_slope", "final_slope",
 *    "t_inflection", "slope", "x", "y", "kp_norm", "kp", "ti", "kp_factor", "ti_factor",
 *    "schedule": {"var", "x": [...], "kp": [...], "ti": [...]}}   (SI units)
 * The schedule block is there with --schedule-mass M1,M2,... [kg] or
 * --schedule-grade G1,G2,... [rad]; its arrays fit /control/schedule_*.
 * The plant step is sim/ivs_tune.c and the document api/analysis_json.c
 * (shared with the daemon); this file parses the options and prints. A tune
 * that takes long (the crank-angle engine: seconds per step response) says on
 * stderr which step response (base, schedule point) is done, as `run` says
 * its simulated time (cli.h's tsc_progress); stdout keeps the document.
 */
#include <stdio.h>
#include <stdlib.h>

#include "../api/analysis_json.h"
#include "cli.h"

/* What the progress lines name: the schedule, if any. */
typedef struct {
    tsc_progress prog;
    const char *var;  /* "mass", "grade" or NULL */
    const double *xs; /* the schedule's values */
    int done;         /* step responses said done so far */
} tune_progress;

/* ts_progress_fn of tsa_tune_json: done 1 is the base tune, done 2 + i the
 * schedule point xs[i], of total 1 + n step responses. Also called every few
 * samples only to poll for a cancel (ts_ivs_tune_polled): a line is said
 * only when a step response has finished. */
static int on_step_done(void *ud, int done, int total)
{
    tune_progress *tp = ud;
    if (done == tp->done) return 0;
    tp->done = done;
    double wall;
    if (!tsc_progress_due(&tp->prog, &wall, done == total)) return 0;
    char what[96] = "base config";
    if (done > 1 && tp->var)
        snprintf(what, sizeof what, "schedule %s %g %s", tp->var, tp->xs[done - 2],
                 tp->var[0] == 'm' ? "kg" : "rad");
    tsc_progress_say(&tp->prog, "step response %d of %d done (%s), %.0f %%, %.1f s wall", done,
                     total, what, 100.0 * done / total, wall);
    return 0;
}

int tsc_cmd_tune(int argc, char **argv)
{
    const char *smass = tsc_option(argc, argv, "--schedule-mass");
    const char *sgrade = tsc_option(argc, argv, "--schedule-grade");
    ts_config cfg;
    int st = tsc_load_config(argc, argv, &cfg, NULL);
    if (st != TSC_EXIT_OK) return st;
    double xs[TSA_TUNE_SCHEDULE_MAX];
    int nx = 0;
    const char *var = NULL;
    if (smass && sgrade) {
        fprintf(stderr, "tanksim: tune: give --schedule-mass or --schedule-grade, not both\n");
        return TSC_EXIT_USAGE;
    }
    if (smass || sgrade) {
        var = smass ? "mass" : "grade";
        ts_err perr;
        if (tsa_tune_schedule_parse(smass ? smass : sgrade, var, xs, &nx, &perr) != TS_OK) {
            fprintf(stderr, "tanksim: tune: --schedule-%s: %s, got '%s'\n", var, perr.msg,
                    smass ? smass : sgrade);
            return TSC_EXIT_USAGE;
        }
    }
    ts_err err = {0};
    tune_progress tp = {.var = var, .xs = xs};
    tsc_progress_start(&tp.prog, "tune", 0); /* a line per step response after the first 2 s */
    json_t *doc = tsa_tune_json(&cfg, var, xs, nx, on_step_done, &tp, &err);
    tsc_progress_end(&tp.prog);
    if (!doc) {
        tsc_print_err("tune", &err);
        return TSC_EXIT_FAIL;
    }
    json_dumpf(doc, stdout, JSON_INDENT(2) | JSON_REAL_PRECISION(6));
    printf("\n");
    json_decref(doc);
    return TSC_EXIT_OK;
}
