/*
 * cmd_schema.c — "tanksim schema": print the JSON Schema of a run config
 * (the same document the daemon serves at /v1/schema, generated from the one
 * parameter table by api/config_json.c: type, SI unit, minimum/maximum, enum
 * names, maxLength/maxItems and the default of every field). Tools such as the
 * config fuzzer (tests/fuzz/) read it instead of parsing sim/cfg_*.c.
 */
#include <stdio.h>

#include "../api/config_json.h"
#include "cli.h"

int tsc_cmd_schema(int argc, char **argv)
{
    (void)argv;
    if (argc > 1) {
        fprintf(stderr, "tanksim: schema takes no arguments\n");
        return TSC_EXIT_USAGE;
    }
    json_t *schema = tsa_config_schema();
    if (!schema) {
        fprintf(stderr, "tanksim: cannot build the schema\n");
        return TSC_EXIT_FAIL;
    }
    int rc = json_dumpf(schema, stdout, JSON_INDENT(1) | JSON_REAL_PRECISION(17)) == 0
                 ? TSC_EXIT_OK
                 : TSC_EXIT_FAIL;
    fputc('\n', stdout);
    json_decref(schema);
    return rc;
}
