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
 * tangent (X, Y); K_p = 0.9/|Y| (normalised) and T_I = ti_factor |X| (Eq. 12).
 *
 * Prints one JSON document:
 *   {"plant", "rack_low", "rack_rated", "v0", "vb", "settle_slope", "final_slope",
 *    "t_inflection", "slope", "x", "y", "kp_norm", "kp", "ti", "ti_factor",
 *    "schedule": {"var", "x": [...], "kp": [...], "ti": [...]}}   (SI units)
 * The schedule block is there with --schedule-mass M1,M2,... [kg] or
 * --schedule-grade G1,G2,... [rad]; its arrays fit /control/schedule_*.
 * The plant step is sim/ivs_tune.c and the document api/analysis_json.c
 * (shared with the daemon); this file parses the options and prints.
 */
#include <stdio.h>
#include <stdlib.h>

#include "../api/analysis_json.h"
#include "cli.h"

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
    json_t *doc = tsa_tune_json(&cfg, var, xs, nx, NULL, NULL, &err);
    if (!doc) {
        tsc_print_err("tune", &err);
        return TSC_EXIT_FAIL;
    }
    json_dumpf(doc, stdout, JSON_INDENT(2) | JSON_REAL_PRECISION(6));
    printf("\n");
    json_decref(doc);
    return TSC_EXIT_OK;
}
