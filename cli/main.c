/*
 * main.c — tanksim, the command-line runner: one table of sub-commands, each
 * taking a CONFIG.json path or --preset NAME (a JSON file shipped under
 * sim/data/presets/). The table is the only list of commands; --help prints it,
 * and `tanksim COMMAND --help` (or -h) prints that command's row.
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

/* name, handler, usage, help — one row per sub-command. */
static const tsc_command commands[] = {
    {"run", tsc_cmd_run, "(CONFIG.json | --preset NAME) [--out DIR] [--until T]",
     "run a scenario; write DIR/series.csv and DIR/summary.json (DIR: ./out unless given)"},
    {"modes", tsc_cmd_modes, "(CONFIG.json | --preset NAME)",
     "track span and upper-circuit eigenanalysis (Table 1, Fig. 5) as JSON"},
    {"render", tsc_cmd_render,
     "(CONFIG.json | --preset NAME) --out FILE.png [--t T] [--width W] [--height H] "
     "[--view side|three_quarter] [--exaggeration E] [--color tension|plain] [--text S] "
     "[--antialias] "
     "[--span S] [--no-overlay]",
     "run to time T and draw the tank and its deformed track into a PNG"},
    {"engine-map", tsc_cmd_engine_map,
     "(CONFIG.json | --preset NAME) (--out FILE.csv | --spool FILE.csv)",
     "engine full-load steady states 800-2100 rpm on a dynamometer (Fig. 18), or with --spool the "
     "rack-step spool-ups at held speed that the faster fidelities derive their part-boost tables "
     "from; FILE.csv.json beside it records the config and units"},
    {"tune", tsc_cmd_tune,
     "(CONFIG.json | --preset NAME) [--schedule-mass M,.. | --schedule-grade G,..]",
     "Ziegler-Nichols IVS gains from a simulated rack step (Eqs. 11-12, Figs. 26-27) as JSON"},
    {"schema", tsc_cmd_schema, "",
     "print the JSON Schema of a run config (every field: type, unit, range, default)"},
};
#define NCOMMANDS (sizeof commands / sizeof commands[0])

static void usage(FILE *f)
{
    fprintf(f, "usage: tanksim COMMAND [ARGS]\n       tanksim --help | --version\n\n"
               "M1 Abrams track, vehicle and diesel-powertrain simulation (Assanis et al. 1999).\n\n"
               "commands:\n");
    for (size_t i = 0; i < NCOMMANDS; i++)
        fprintf(f, "  %-10s %s\n  %-10s   %s\n", commands[i].name, commands[i].usage, "",
                commands[i].help);
}

/* What a command printed reached stdout (a full disk, a closed pipe, /dev/full
 * fail here, at the flush, not in the command's printf): TSC_EXIT_OK or FAIL. */
static int stdout_written(void)
{
    if (fflush(stdout) == 0 && !ferror(stdout)) return TSC_EXIT_OK;
    fprintf(stderr, "tanksim: cannot write the output: %s\n", strerror(errno));
    return TSC_EXIT_FAIL;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return TSC_EXIT_USAGE;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        usage(stdout);
        return TSC_EXIT_OK;
    }
    if (strcmp(argv[1], "--version") == 0) {
        printf("tanksim %s\n", TS_VERSION);
        return TSC_EXIT_OK;
    }
    for (size_t i = 0; i < NCOMMANDS; i++) {
        if (strcmp(argv[1], commands[i].name) != 0) continue;
        for (int a = 2; a < argc; a++)
            if (strcmp(argv[a], "--help") == 0 || strcmp(argv[a], "-h") == 0) {
                printf("usage: tanksim %s%s%s\n  %s\n", commands[i].name,
                       commands[i].usage[0] ? " " : "", commands[i].usage, commands[i].help);
                return TSC_EXIT_OK;
            }
        int rc = commands[i].run(argc - 1, argv + 1);
        return rc == TSC_EXIT_OK ? stdout_written() : rc;
    }
    fprintf(stderr, "tanksim: unknown command '%s' (see tanksim --help)\n", argv[1]);
    return TSC_EXIT_USAGE;
}
