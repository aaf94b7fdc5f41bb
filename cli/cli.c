/*
 * cli.c — config loading and option helpers shared by the tanksim commands.
 */
#include "cli.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "../api/config_json.h"

const char *tsc_option(int argc, char **argv, const char *name)
{
    for (int i = 1; i < argc - 1; i++) {
        if (argv[i] && strcmp(argv[i], name) == 0) {
            const char *v = argv[i + 1];
            argv[i] = argv[i + 1] = NULL;
            return v;
        }
    }
    return NULL;
}

int tsc_flag(int argc, char **argv, const char *name)
{
    for (int i = 1; i < argc; i++)
        if (argv[i] && strcmp(argv[i], name) == 0) {
            argv[i] = NULL;
            return 1;
        }
    return 0;
}

int tsc_number(const char *s, const char *name, double lo, double hi, double *out)
{
    /* a plain decimal numeral, as the daemon's query numbers: no blanks, no hexadecimal */
    if (tsa_parse_number(s, lo, hi, out) == 0) return 0;
    fprintf(stderr, "tanksim: %s: number in [%g, %g], got '%s'\n", name, lo, hi, s);
    return -1;
}

int tsc_integer(const char *s, const char *name, long lo, long hi, long *out)
{
    if (tsa_parse_integer(s, lo, hi, out) == 0) return 0;
    fprintf(stderr, "tanksim: %s: integer in [%ld, %ld], got '%s'\n", name, lo, hi, s);
    return -1;
}

/* "tanksim: LEAD: POINTER: MSG (CODE)" on stderr: the field at fault first, as
 * cli.h promises (a user fixes the config by its pointer), left out when MSG
 * already starts with it, as many messages do; no CODE when code is NULL. */
static void print_line(const char *lead, const char *pointer, const char *msg, const char *code)
{
    size_t np = pointer ? strlen(pointer) : 0;
    int with_ptr = np && strncmp(msg, pointer, np) != 0;
    fprintf(stderr, "tanksim: %s: %s%s%s%s%s%s\n", lead, with_ptr ? pointer : "",
            with_ptr ? ": " : "", msg, code ? " (" : "", code ? code : "", code ? ")" : "");
}

void tsc_print_err(const char *what, const ts_err *err)
{
    print_line(what, err->pointer, err->msg, ts_rc_name(err->code));
}

void tsc_print_config_err(const char *pointer, const char *msg)
{
    print_line("config error", pointer, msg, NULL);
}

void tsc_progress_start(tsc_progress *p, const char *what, double every)
{
    p->what = what;
    p->wall0 = ts_monotonic_seconds();
    p->next = p->wall0 + TSC_PROGRESS_FIRST;
    p->every = every;
    p->tty = isatty(fileno(stderr));
    p->shown = 0;
}

int tsc_progress_due(const tsc_progress *p, double *wall, int last)
{
    double now = ts_monotonic_seconds();
    *wall = now - p->wall0;
    return now >= p->next || (last && p->shown);
}

void tsc_progress_say(tsc_progress *p, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "%stanksim %s: ", p->tty ? "\r" : "", p->what);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputs(p->tty ? "   " : "\n", stderr);
    fflush(stderr);
    p->shown = 1;
    p->next = ts_monotonic_seconds() + (p->tty ? 0.5 : p->every);
}

void tsc_progress_end(tsc_progress *p)
{
    if (p->shown && p->tty) fputc('\n', stderr);
    p->shown = 0;
}

int tsc_model_start(const ts_config *cfg, ts_model **m, ts_data **d)
{
    ts_err err;
    *d = NULL;
    *m = ts_model_make(cfg, &err);
    if (!*m) {
        tsc_print_err("model", &err);
        return -1;
    }
    *d = ts_data_make(*m, &err);
    if (!*d) {
        tsc_print_err("data", &err);
        return -1;
    }
    if (ts_reset(*m, *d, &err) != TS_OK) {
        tsc_print_err("reset", &err);
        return -1;
    }
    return 0;
}

int tsc_load_config(int argc, char **argv, ts_config *cfg, json_t **resolved)
{
    const char *preset = tsc_option(argc, argv, "--preset");
    const char *path = NULL;
    for (int i = 1; i < argc; i++) {
        if (argv[i] && argv[i][0] != '-') {
            path = argv[i];
            argv[i] = NULL;
            break;
        }
    }
    /* every option a command knows was consumed before this call: what is
     * left is a typo ("--untill"), a "--name=value" form, an option given
     * without its value, or a second CONFIG.json; refuse it, not ignore it */
    for (int i = 1; i < argc; i++) {
        if (!argv[i]) continue;
        fprintf(stderr,
                "tanksim: %s: unknown argument '%s' (an unknown option, an option without its "
                "value, \"--name=value\" instead of \"--name value\", or a second config; see "
                "tanksim %s --help)\n",
                argv[0], argv[i], argv[0]);
        return TSC_EXIT_USAGE;
    }
    if (!!preset == !!path) {
        fprintf(stderr, "tanksim: give either CONFIG.json or --preset NAME\n");
        return TSC_EXIT_USAGE;
    }
    ts_err err;
    json_t *errors = json_array();
    ts_rc rc;
    if (preset) {
        json_t *doc = json_pack("{s:s}", "preset", preset);
        rc = tsa_config_load(doc, cfg, resolved, errors, &err);
        json_decref(doc);
    } else {
        rc = tsa_config_load_path(path, cfg, resolved, errors, &err);
    }
    /* a preset made for one command only (the eigenanalysis ones) is not run */
    if (rc == TS_OK && strcmp(argv[0], "modes") != 0) {
        json_t *doc = preset ? json_pack("{s:s}", "preset", preset)
                             : json_load_file(path, JSON_REJECT_DUPLICATES, NULL);
        rc = doc ? tsa_config_runnable(doc, argv[0], &err) : TS_OK;
        json_decref(doc);
        if (rc != TS_OK && resolved) {
            json_decref(*resolved);
            *resolved = NULL;
        }
    }
    if (rc != TS_OK) {
        if (json_array_size(errors) > 0) {
            size_t i;
            json_t *e;
            json_array_foreach(errors, i, e)
                tsc_print_config_err(json_string_value(json_object_get(e, "pointer")),
                                     json_string_value(json_object_get(e, "message")));
        } else {
            tsc_print_err("config", &err);
        }
    }
    json_decref(errors);
    return rc == TS_OK ? TSC_EXIT_OK : TSC_EXIT_FAIL;
}

/* The temporaries now open, for on_kill_signal: a run killed by SIGINT,
 * SIGTERM or SIGHUP removes them (each name is unique, so no later run would
 * reuse and replace one). Process-wide by nature: signals are. */
#define TMP_SLOTS 4
static const char *volatile live_tmp[TMP_SLOTS];

static void on_kill_signal(int sig)
{
    for (int i = 0; i < TMP_SLOTS; i++)
        if (live_tmp[i]) unlink(live_tmp[i]);
    signal(sig, SIG_DFL); /* then die of it as before (async-signal-safe calls only) */
    raise(sig);
}

/* Register (on != 0) or drop o->tmp; the handler goes on the signals still
 * at their default action at the first registration (a command's own
 * handler, as run's, is left in place). */
static void track_tmp(tsc_out *o, int on)
{
    static int installed;
    if (on && !installed) {
        installed = 1;
        const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
        for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++) {
            struct sigaction old, sa;
            if (sigaction(sigs[i], NULL, &old) != 0 || old.sa_handler != SIG_DFL) continue;
            memset(&sa, 0, sizeof sa);
            sa.sa_handler = on_kill_signal;
            sigemptyset(&sa.sa_mask);
            sigaction(sigs[i], &sa, NULL);
        }
    }
    for (int i = 0; i < TMP_SLOTS; i++)
        if (on ? !live_tmp[i] : live_tmp[i] == o->tmp) {
            live_tmp[i] = on ? o->tmp : NULL;
            return;
        }
}

/* Hold SIGINT, SIGTERM and SIGHUP (block != 0, the old mask saved in *old)
 * or restore *old: a temporary is created and registered, or renamed or
 * removed and dropped, as one step, so a signal between the two can neither
 * leave a file the handler does not know nor remove a name no longer ours
 * (the CLI is single-threaded: the mask is the process's). */
static void hold_kill_signals(int block, sigset_t *old)
{
    if (!block) {
        sigprocmask(SIG_SETMASK, old, NULL);
        return;
    }
    sigset_t s;
    sigemptyset(&s);
    sigaddset(&s, SIGINT);
    sigaddset(&s, SIGTERM);
    sigaddset(&s, SIGHUP);
    sigprocmask(SIG_BLOCK, &s, old);
}

/* Create o->tmp as "PATH.XXXXXX" (6 characters from [0-9A-Za-z]) with
 * O_CREAT | O_EXCL and mode 0666, so the umask (and a default ACL) applies as
 * to a plain fopen(PATH, "w"): mkstemp's 0600 would make outputs private. A
 * name that exists (another run's temporary, anyone's file or link) is never
 * opened: the next one is tried. The descriptor, or -1 with errno. */
static int create_tmp(tsc_out *o)
{
    static const char digits[] = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz";
    size_t n = strlen(o->tmp);
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    unsigned long long x = (unsigned long long)ts.tv_nsec ^ ((unsigned long long)ts.tv_sec << 30) ^
                           ((unsigned long long)getpid() << 12);
    for (int attempt = 0; attempt < 100; attempt++) {
        x = x * 6364136223846793005ULL + 1442695040888963407ULL; /* an LCG step */
        unsigned long long y = x >> 16;
        for (size_t i = n - 6; i < n; i++, y /= 62)
            o->tmp[i] = digits[y % 62];
        int fd = open(o->tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST) return fd;
    }
    return -1; /* errno EEXIST */
}

int tsc_out_open(tsc_out *o, const char *path, const char *what, int in_place)
{
    struct stat st;
    o->path = path;
    o->what = what;
    o->f = NULL;
    o->tmp[0] = '\0';
    /* lstat: a symlink (/dev/stdout, a user's link) is written through, in
     * place; renaming a tmp file onto it would replace the link itself */
    o->direct = in_place || (lstat(path, &st) == 0 && !S_ISREG(st.st_mode));
    if (strlen(path) > sizeof o->tmp - 8) {
        fprintf(stderr, "tanksim %s: %s: path too long\n", what, path);
        return -1;
    }
    if (o->direct) {
        o->f = fopen(path, "w");
    } else {
        /* a temporary of this run's own beside PATH: a fixed PATH.tmp was
         * shared by two runs writing one output (the second truncated the
         * first's, and one rename then failed) and clobbered a PATH.tmp of
         * the user's, or wrote through a link of that name */
        snprintf(o->tmp, sizeof o->tmp, "%s.XXXXXX", path);
        sigset_t mask;
        hold_kill_signals(1, &mask);
        int fd = create_tmp(o);
        if (fd < 0 && errno == ENAMETOOLONG) {
            /* PATH's name is within 6 bytes of the file-name limit: a short
             * hidden name in the same directory (rename stays within it) */
            const char *slash = strrchr(path, '/');
            int dir = slash ? (int)(slash - path + 1) : 0;
            snprintf(o->tmp, sizeof o->tmp, "%.*s.tanksim-XXXXXX", dir, path);
            fd = create_tmp(o);
        }
        if (fd >= 0) track_tmp(o, 1);
        if (fd >= 0 && !(o->f = fdopen(fd, "w"))) {
            int e = errno;
            close(fd);
            unlink(o->tmp);
            track_tmp(o, 0);
            errno = e;
        }
        int e = errno;
        hold_kill_signals(0, &mask);
        errno = e;
    }
    if (!o->f) {
        fprintf(stderr, "tanksim %s: cannot write %s: %s\n", what, path, strerror(errno));
        return -1;
    }
    return 0;
}

int tsc_out_json(tsc_out *o, const json_t *doc)
{
    return json_dumpf(doc, o->f, JSON_INDENT(2) | JSON_REAL_PRECISION(17)) == 0 &&
                   fputc('\n', o->f) != EOF
               ? 0
               : -1;
}

int tsc_out_close(tsc_out *o, int complete)
{
    if (!o->f) return TSC_EXIT_FAIL;
    int bad = ferror(o->f) != 0;
    errno = 0;
    if (fclose(o->f) != 0) bad = 1;
    o->f = NULL;
    sigset_t mask;
    if (!o->direct) hold_kill_signals(1, &mask);
    if (complete && !bad && (o->direct || rename(o->tmp, o->path) == 0)) {
        if (!o->direct) {
            track_tmp(o, 0);
            hold_kill_signals(0, &mask);
        }
        return TSC_EXIT_OK;
    }
    if (complete) {
        int e = errno;
        fprintf(stderr, "tanksim %s: cannot write %s: %s\n", o->what, o->path,
                e ? strerror(e) : "a write failed (a full disk or an I/O error)");
    }
    if (!o->direct) {
        unlink(o->tmp);
        track_tmp(o, 0);
        hold_kill_signals(0, &mask);
    }
    return TSC_EXIT_FAIL;
}
