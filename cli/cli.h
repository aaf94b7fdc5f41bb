/*
 * cli.h — shared pieces of the tanksim command-line runner: the command table
 * row type, config loading from "CONFIG.json" or "--preset NAME", and output
 * files written whole or not at all.
 */
#ifndef TSC_CLI_H
#define TSC_CLI_H

#include <jansson.h>

#include "../sim/tanksim.h"

typedef struct tsc_command {
    const char *name;                  /* sub-command word */
    int (*run)(int argc, char **argv); /* argv[0] is the sub-command; returns exit status */
    const char *usage;                 /* arguments, one line */
    const char *help;                  /* what it does, one line */
    const char *options;               /* each option described, lines of "  --name  what"
                                          (NULL: the usage line says it all) */
} tsc_command;

/* Exit statuses shared by every command. */
enum { TSC_EXIT_OK = 0, TSC_EXIT_FAIL = 1, TSC_EXIT_USAGE = 2 };

/* Take the config source from argv: the first non-option argument is a
 * CONFIG.json path, or "--preset NAME" names a shipped preset. Consumed
 * arguments are set to NULL in argv; any argument left over is a usage error
 * (TSC_EXIT_USAGE). argv[0] is the command: a preset made only for another
 * command (tsa_config_runnable) is refused. On failure prints every config error
 * (JSON Pointer + message) to stderr and returns non-zero. resolved (may be
 * NULL) receives the resolved document (caller json_decrefs). */
int tsc_load_config(int argc, char **argv, ts_config *cfg, json_t **resolved);

/* Value of "--name VALUE" in argv (consumed), or NULL. Every command takes
 * its options before tsc_load_config, which refuses whatever is left. */
const char *tsc_option(int argc, char **argv, const char *name);
/* 1 if the bare "--name" is in argv (consumed), else 0. */
int tsc_flag(int argc, char **argv, const char *name);
/* Parse s as a finite number in [lo, hi] into *out; else print
 * "tanksim: NAME: number in [lo, hi], got 'S'" and return -1. */
int tsc_number(const char *s, const char *name, double lo, double hi, double *out);
/* Parse s as an integer in [lo, hi] into *out (a plain decimal integer:
 * "640.5", "6.4e2", "640px" are refused, not cut to 640); else print
 * "tanksim: NAME: integer in [lo, hi], got 'S'" and return -1. Every integer
 * option goes through here (a usage error, TSC_EXIT_USAGE, for the caller). */
int tsc_integer(const char *s, const char *name, long lo, long hi, long *out);

/* Print a ts_err as "tanksim: <pointer>: message" to stderr. */
void tsc_print_err(const char *what, const ts_err *err);
/* "tanksim: config error: POINTER: MSG" on stderr, the pointer left out
 * when MSG already starts with it (pointer may be NULL or ""). */
void tsc_print_config_err(const char *pointer, const char *msg);

/* An output file written whole or not at all: a regular (or new) file is
 * written as a temporary of its own beside it, PATH.XXXXXX (created new, with
 * the mode a plain create gives: 0666 less the umask), and renamed to PATH
 * once complete, so a failure leaves no empty or half file and two runs
 * writing one PATH share no temporary; anything else that exists (a device, a
 * pipe, a symlink) is written in place, through it (renaming onto it would
 * replace the device node or the link). Open it before long work, so a bad
 * path fails at once. A name within 6 bytes of the file-name limit gets the
 * temporary DIR/.tanksim-XXXXXX instead; SIGINT, SIGTERM or SIGHUP (where the
 * command has no handler of its own) removes the open temporaries and ends
 * the process as the signal would. */
typedef struct tsc_out {
    FILE *f;
    char tmp[1100]; /* the temporary's name (not direct) */
    const char *path;
    const char *what; /* the command, for messages */
    int direct;       /* written in place: no tmp, no rename */
} tsc_out;
/* 0, or -1 with "tanksim WHAT: cannot write PATH: reason" on stderr.
 * in_place: write PATH itself (a file whose rows up to a stop are kept). */
int tsc_out_open(tsc_out *o, const char *path, const char *what, int in_place);
/* complete: the content is whole, so check the writes and put the file in
 * place (a failure is printed); 0: abandon it (the caller said why; a file
 * written in place is left as it is). Returns TSC_EXIT_OK or TSC_EXIT_FAIL. */
int tsc_out_close(tsc_out *o, int complete);
/* Write doc to o as indented JSON with 17 significant digits (a config echo
 * re-runs bit for bit) and a final newline: 0, or -1 when jansson or a write
 * failed (then abandon o: tsc_out_close(o, 0)). */
int tsc_out_json(tsc_out *o, const json_t *doc);

/* Progress of a long command on stderr, so that stdout keeps only its result:
 * lines "tanksim WHAT: TEXT". A command done within TSC_PROGRESS_FIRST wall
 * seconds prints none; after that a line at most every `every` seconds, or,
 * when stderr is a terminal, one line redrawn in place (at most every 0.5 s).
 * `run` (simulated time), `tune` (step responses) and `engine-map --spool`
 * (spool-ups) report through it. */
#define TSC_PROGRESS_FIRST 2.0 /* [s] wall time before the first line */
typedef struct tsc_progress {
    const char *what;   /* the command, for the lines */
    double wall0, next; /* monotonic start and the earliest next line [s] */
    double every;       /* [s] between lines when stderr is not a terminal */
    int tty;            /* stderr is a terminal: the line is redrawn */
    int shown;          /* a line was printed */
} tsc_progress;
void tsc_progress_start(tsc_progress *p, const char *what, double every);
/* 1 with *wall the seconds since the start when a line is due now, else 0;
 * last: the final unit of work, due once any line was shown (so the lines
 * end at 100 %). */
int tsc_progress_due(const tsc_progress *p, double *wall, int last);
/* Print "tanksim WHAT: " and the printf text as the progress line. */
void tsc_progress_say(tsc_progress *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The command is done: end a line redrawn in place with its newline. */
void tsc_progress_end(tsc_progress *p);

/* Build the model and its data for cfg and reset it (sample row 0). On failure prints the
 * error, leaves *m / *d as far as they were built (the caller frees them) and returns -1. */
int tsc_model_start(const ts_config *cfg, ts_model **m, ts_data **d);

/* Commands (cmd_*.c). */
int tsc_cmd_run(int argc, char **argv);
int tsc_cmd_modes(int argc, char **argv);
int tsc_cmd_render(int argc, char **argv);
int tsc_cmd_engine_map(int argc, char **argv);
int tsc_cmd_tune(int argc, char **argv);
int tsc_cmd_schema(int argc, char **argv);

#endif
