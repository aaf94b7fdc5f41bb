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

/* render's options: what each draws. --view-width was --span, which a reader
 * of a track simulator took for a track span; the old name is still taken. */
static const char RENDER_OPTIONS[] =
    "  --out FILE.png     the PNG to write (required); written whole or not at all\n"
    "  --t T              simulated time to draw [s], 0 to the config's run.duration: the\n"
    "                     model runs from rest to T first (default 0)\n"
    "  --width W          image width [px], 16 to 4096 (default 1280)\n"
    "  --height H         image height [px], 16 to 4096 (default 720)\n"
    "  --view V           side: orthographic elevation from the right, hull centred\n"
    "                     (default); three_quarter: perspective from front-right, above\n"
    "  --view-width M     side view: metres of the scene across the image width (zoom),\n"
    "                     0 to 1000; 0 (default): 13 m (the 7.9 m hull and ground either\n"
    "                     side). Not a track span; three_quarter frames the hull itself\n"
    "                     and ignores it. --span M is its older name, still accepted\n"
    "  --exaggeration E   factor on the track spans' vibration (the modal deflection\n"
    "                     added to the quasi-static pitch line) as drawn, 0 to 1000\n"
    "                     (default 1: true scale; 0: the quasi-static line alone)\n"
    "  --color C          plain (default), or tension: track shoes coloured by their\n"
    "                     tension (blue slack, grey at the static tension, red at twice\n"
    "                     it) with a legend\n"
    "  --text S           one more overlay line, printable ASCII, at most 95 characters\n"
    "  --antialias        4x multisampled edges (about 2.5x the drawing time)\n"
    "  --no-overlay       no text in the top-left corner (t, speed, gear and --text)\n";

/* The options of the other commands; every command takes CONFIG.json (a
 * path, - for stdin) or --preset NAME (tanksim schema: every field, SI). */
static const char RUN_OPTIONS[] =
    "  --out DIR          directory for series.csv (one row per sample, channel names in\n"
    "                     the header) and summary.json (config, DOF, wall time, every\n"
    "                     channel's SI unit, the metrics); made if missing (default ./out)\n"
    "  --until T          stop at T [s], on the sample grid, 0 to /run/duration (default\n"
    "                     /run/duration)\n";
static const char ENGINE_MAP_OPTIONS[] =
    "  --out FILE.csv     full-load sweep 800-2100 rpm in 100-rpm steps: speed, brake torque\n"
    "                     [N*m], power [W], bsfc [g/kWh], boost [Pa], exhaust temperature\n"
    "                     [K], peak cylinder pressure [Pa] and more, each unit in the header\n"
    "  --spool FILE.csv   instead: the rack-step spool-ups at held speed (one row per cycle)\n"
    "  Either writes FILE.csv.json beside a regular file: the config and the units.\n";
static const char TUNE_OPTIONS[] =
    "  --schedule-mass M,..   also tune at each vehicle mass [kg] (Fig. 27), comma-separated\n"
    "                         plain decimals, at most 16, each within /vehicle/mass's range\n"
    "  --schedule-grade G,..  or at each road grade [rad] (/vehicle/grade's range)\n"
    "  Prints the step response's X [s] and Y [1] (Eqs. 11-12), K_p [1/(m/s)] and T_I [s]\n"
    "  as JSON, with every field's unit under \"units\".\n";

/* name, handler, usage, help, options — one row per sub-command. */
static const tsc_command commands[] = {
    {"run", tsc_cmd_run, "(CONFIG.json | --preset NAME) [--out DIR] [--until T]",
     "run a scenario; write DIR/series.csv and DIR/summary.json (DIR: ./out unless given)",
     RUN_OPTIONS},
    {"modes", tsc_cmd_modes, "(CONFIG.json | --preset NAME)",
     "track span and upper-circuit eigenanalysis (Table 1, Fig. 5) as JSON", NULL},
    {"render", tsc_cmd_render,
     "(CONFIG.json | --preset NAME) --out FILE.png [--t T] [--width W] [--height H] "
     "[--view side|three_quarter] [--view-width M] [--exaggeration E] [--color tension|plain] "
     "[--text S] [--antialias] [--no-overlay]",
     "run to time T and draw the tank and its deformed track into a PNG", RENDER_OPTIONS},
    {"engine-map", tsc_cmd_engine_map,
     "(CONFIG.json | --preset NAME) (--out FILE.csv | --spool FILE.csv)",
     "engine full-load steady states 800-2100 rpm on a dynamometer (Fig. 18), or with --spool the "
     "rack-step spool-ups at held speed that the faster fidelities derive their part-boost tables "
     "from; FILE.csv.json beside it records the config and units",
     ENGINE_MAP_OPTIONS},
    {"tune", tsc_cmd_tune,
     "(CONFIG.json | --preset NAME) [--schedule-mass M,.. | --schedule-grade G,..]",
     "Ziegler-Nichols IVS gains from a simulated rack step (Eqs. 11-12, Figs. 26-27) as JSON",
     TUNE_OPTIONS},
    {"schema", tsc_cmd_schema, "",
     "print the JSON Schema of a run config (every field: type, unit, range, default)", NULL},
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
    fprintf(f, "\ntanksim COMMAND --help describes the command's options.\n");
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
                if (commands[i].options) printf("\noptions:\n%s", commands[i].options);
                return TSC_EXIT_OK;
            }
        int rc = commands[i].run(argc - 1, argv + 1);
        return rc == TSC_EXIT_OK ? stdout_written() : rc;
    }
    fprintf(stderr, "tanksim: unknown command '%s' (see tanksim --help)\n", argv[1]);
    return TSC_EXIT_USAGE;
}
