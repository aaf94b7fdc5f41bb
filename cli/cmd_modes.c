/*
 * cmd_modes.c — "tanksim modes": eigenanalysis of the track (paper Section
 * II.A, Table 1, Fig. 5). Prints one JSON document to stdout:
 *   {"spans":[{"name","length_m","frequencies_hz":{"longitudinal":[...],
 *              "transverse":[...],"coupled":[...]}, ...}],
 *    "circuit":{"frequencies_hz":[...],"mode_shapes":[...], ...}, "units":{...}}
 * spans: each free span alone with both ends fixed — the five spans of the
 * /vehicle layout, or the single spans of /track/span_length. Families:
 * longitudinal = the longitudinal sine modes alone (bar), transverse = the
 * transverse modes with quasi-static (uniform-tension, Irvine) stretch,
 * coupled = all modal coordinates (Eqs. 1-2). circuit: the upper track circuit
 * with road wheels 1 and 7 fixed (Fig. 5) and its mode shapes (energy shares
 * per span, sampled deflections). All numbers SI. Config errors name the field.
 * The document is built by api/modes_json.c (shared with POST /v1/modes).
 */
#include <stdio.h>
#include <stdlib.h>

#include "../api/modes_json.h"
#include "cli.h"

int tsc_cmd_modes(int argc, char **argv)
{
    ts_config cfg;
    int rc = tsc_load_config(argc, argv, &cfg, NULL);
    if (rc != TSC_EXIT_OK) return rc;
    ts_err err;
    json_t *doc = tsa_modes_json(&cfg, &err);
    if (!doc) {
        if (err.pointer[0])
            tsc_print_config_err(err.pointer, err.msg);
        else
            tsc_print_err("modes", &err);
        return TSC_EXIT_FAIL;
    }
    int status = TSC_EXIT_FAIL;
    char *text = json_dumps(doc, JSON_INDENT(1) | JSON_REAL_PRECISION(6));
    if (text) {
        fputs(text, stdout);
        fputc('\n', stdout);
        free(text);
        status = TSC_EXIT_OK;
    } else {
        fprintf(stderr, "tanksim: modes: could not build the JSON output\n");
    }
    json_decref(doc);
    return status;
}
