/*
 * cmd_run.c — "tanksim run": build the model of a config, run it from rest to
 * run.duration (or --until T) and write DIR/series.csv (header of channel
 * names, one row per sample) and DIR/summary.json (config echo, DOF count,
 * wall time, real-time factor, the integrators' work counters, the unit of
 * every channel, and the scenario's metrics computed from the series, e.g.
 * Table 2's acceleration times).
 */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../api/config_json.h"
#include "../api/session_json.h"
#include "cli.h"

/* Rows go to the CSV as they come and are kept for the run's metrics. */
/* SIGINT / SIGTERM during a run: the sink stops after the row it is writing
 * (a Ctrl-C had left half a row and no word). Process-wide by nature. */
static volatile sig_atomic_t stop_signal;

static void on_stop_signal(int sig)
{
    stop_signal = sig;
}

typedef struct {
    FILE *csv;
    double t_last; /* time of the last row written whole [s] */
    ts_rows rows;
    double until;      /* the run's end [s], for the progress line */
    tsc_progress prog; /* cli.h */
    int nomem;         /* the rows kept for the metrics could not grow */
} run_sink;

#define PROGRESS_EVERY 5.0 /* [s] between progress lines when stderr is not a terminal */

/* Long runs say how far they are on stderr (stdout keeps the one summary
 * line): simulated time, share of the run, real-time factor. Short runs,
 * done before TSC_PROGRESS_FIRST, print nothing. */
static void progress(run_sink *s, double t)
{
    double wall;
    if (!tsc_progress_due(&s->prog, &wall, 0)) return;
    tsc_progress_say(&s->prog, "t = %.3f of %.3f s (%.1f %%), %.1fx real time", t, s->until,
                     s->until > 0 ? 100.0 * t / s->until : 100.0, wall > 0 ? t / wall : 0.0);
}

static int write_row(void *ud, long index, double t, const double *v, int n)
{
    run_sink *s = ud;
    for (int i = 0; i < n; i++)
        fprintf(s->csv, i ? ",%.9g" : "%.9g", v[i]);
    fputc('\n', s->csv);
    s->t_last = t;
    if (ts_rows_append(&s->rows, index, t, v, n) != 0) {
        s->nomem = 1;
        return 1;
    }
    if ((index & 63) == 0) progress(s, t);
    return ferror(s->csv) || stop_signal ? 1 : 0;
}

#define OUT_PATH_MAX 1000 /* [chars] the directory; its file names are added to it */

/* mkdir -p; path is 1 to OUT_PATH_MAX characters (tsc_cmd_run checks). */
static int make_dirs(const char *path)
{
    char buf[OUT_PATH_MAX + 1];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/') continue;
        *p = '\0';
        if (mkdir(buf, 0755) != 0 && errno != EEXIST) return -1;
        *p = '/';
    }
    return (mkdir(buf, 0755) != 0 && errno != EEXIST) ? -1 : 0;
}

int tsc_cmd_run(int argc, char **argv)
{
    const char *out = tsc_option(argc, argv, "--out");
    const char *until_s = tsc_option(argc, argv, "--until");
    ts_config cfg;
    json_t *resolved = NULL;
    int rc = tsc_load_config(argc, argv, &cfg, &resolved);
    if (rc != TSC_EXIT_OK) return rc;
    if (!out) out = "out";
    double until = cfg.run.duration;
    ts_err err;
    int usage = 0;
    if (!*out || strlen(out) > OUT_PATH_MAX) {
        fprintf(stderr, "tanksim: --out: a directory name of 1 to %d characters expected\n",
                OUT_PATH_MAX);
        usage = 1;
    } else if (until_s && tsc_number(until_s, "--until", 0, cfg.run.duration, &until) != 0) {
        usage = 1;
    } else if (until_s &&
               ts_on_sample_grid(until, 1.0 / cfg.run.sample_rate, "--until", &err) != TS_OK) {
        fprintf(stderr, "tanksim: %s\n", err.msg); /* rows are only at whole sample periods */
        usage = 1;
    }
    if (usage) {
        json_decref(resolved);
        return TSC_EXIT_USAGE;
    }

    ts_model *m = NULL;
    ts_data *d = NULL;
    tsc_out series = {0}; /* in place: rows up to a stop stay */
    run_sink sink = {0};
    int status = TSC_EXIT_FAIL;
    char path[1200];

    if (tsc_model_start(&cfg, &m, &d) != 0) goto done; /* a bad config leaves DIR as it was */
    struct stat st;
    if (make_dirs(out) != 0) {
        fprintf(stderr, "tanksim: cannot create %s: %s\n", out, strerror(errno));
        goto done;
    }
    if (stat(out, &st) != 0 || !S_ISDIR(st.st_mode)) { /* mkdir's EEXIST: maybe a file */
        fprintf(stderr, "tanksim: --out: %s is not a directory\n", out);
        goto done;
    }
    /* a summary left by an earlier run must not sit beside this run's series */
    snprintf(path, sizeof path, "%s/summary.json", out);
    if (unlink(path) != 0 && errno != ENOENT) {
        fprintf(stderr, "tanksim: cannot remove the earlier %s: %s\n", path, strerror(errno));
        goto done;
    }
    snprintf(path, sizeof path, "%s/series.csv", out);
    if (tsc_out_open(&series, path, "run", 1) != 0) goto done;
    for (int i = 0; i < ts_model_nchannel(m); i++)
        fprintf(series.f, i ? ",%s" : "%s", ts_model_channel(m, i)->name);
    fputc('\n', series.f);
    sink.csv = series.f;
    sink.until = until;
    tsc_progress_start(&sink.prog, "run", PROGRESS_EVERY);
    struct sigaction sa, old_int, old_term;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop_signal;
    sa.sa_flags = SA_RESETHAND; /* a second Ctrl-C ends the program at once */
    sigemptyset(&sa.sa_mask);
    stop_signal = 0;
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
    write_row(&sink, 0, 0.0, ts_latest(d), ts_model_nchannel(m));
    ts_rc arc = stop_signal ? TS_ERR_CANCELLED : ts_advance(m, d, until, write_row, &sink, &err);
    sigaction(SIGINT, &old_int, NULL);
    sigaction(SIGTERM, &old_term, NULL);
    tsc_progress_end(&sink.prog);
    /* a write that failed is said by tsc_out_close */
    int write_failed = tsc_out_close(&series, 1) != TSC_EXIT_OK;
    if (sink.nomem) /* the sink stopped the run: say why, not "stopped by the caller" */
        ts_err_set(&err, TS_ERR_NOMEM, NULL,
                   "out of memory keeping the rows for the metrics at t = %.6g s (%ld rows of "
                   "%d channels); lower /run/sample_rate or /run/duration",
                   ts_time(d), sink.rows.n, ts_model_nchannel(m));
    else if (stop_signal)
        ts_err_set(&err, TS_ERR_CANCELLED, NULL, "stopped by signal %d at t = %.6g s",
                   (int)stop_signal, sink.t_last);
    if (arc != TS_OK || sink.nomem || write_failed || stop_signal) {
        /* a failed write stops the run as its caller ("stopped by the caller"):
         * tsc_out_close said why; a lack of memory or a signal is said too */
        if (sink.nomem || stop_signal || (arc != TS_OK && !write_failed))
            tsc_print_err("run", &err);
        if (write_failed) /* what reached the disk is not known row by row */
            fprintf(stderr,
                    "tanksim: run: %s/series.csv is incomplete (rows were being written up "
                    "to t = %.6g s, the last may be cut); no summary written\n",
                    out, sink.t_last);
        else
            fprintf(stderr,
                    "tanksim: run: %s/series.csv holds the rows up to t = %.6g s; no summary "
                    "written\n",
                    out, sink.t_last);
        if (stop_signal) status = 128 + (int)stop_signal;
        goto done;
    }

    json_t *channels = json_array();
    for (int i = 0; i < ts_model_nchannel(m); i++) {
        const ts_channel *c = ts_model_channel(m, i);
        json_array_append_new(channels, json_pack("{s:s,s:s,s:s}", "name", c->name, "unit", c->unit,
                                                  "description", c->description));
    }
    ts_metric *metrics; /* every figure the scenario has, however many (api/session_json.h) */
    int nmetric;
    if (tsa_model_metrics(m, sink.rows.v, sink.rows.n, &metrics, &nmetric, &err) != TS_OK) {
        json_decref(channels);
        tsc_print_err("run", &err);
        fprintf(stderr,
                "tanksim: run: %s/series.csv holds the rows up to t = %.6g s; no summary "
                "written\n",
                out, sink.t_last);
        goto done;
    }
    json_t *mj = json_object();
    for (int i = 0; i < nmetric; i++)
        json_object_set_new(
            mj, metrics[i].name,
            json_pack("{s:o,s:s,s:s}", "value",
                      isfinite(metrics[i].value) ? json_real(metrics[i].value) : json_null(),
                      "unit", metrics[i].unit, "description", metrics[i].description));
    free(metrics);
    double wall = ts_wall_seconds(d);
    ts_integrator_stats ist[TS_MAX_INTEGRATORS];
    int nist = ts_integrator_stats_get(m, d, ist, TS_MAX_INTEGRATORS);
    json_t *summary = json_pack(
        "{s:s,s:O,s:i,s:i,s:f,s:I,s:f,s:f,s:o,s:o,s:o}", "kind", ts_model_kind(m), "config",
        resolved, "dof", ts_model_dof(m), "nstate", ts_model_nstate(m), "t_end_s", ts_time(d),
        "samples", (json_int_t)(ts_sample_index(d) + 1), "wall_time_s", wall, "real_time_factor",
        wall > 0 ? ts_time(d) / wall : 0.0, "integrators", tsa_integrators_json(ist, nist),
        "channels", channels, "metrics", mj);
    /* 17 digits: the config echo must re-run bit for bit (10 did not) */
    snprintf(path, sizeof path, "%s/summary.json", out);
    tsc_out so;
    int written = tsc_out_open(&so, path, "run", 0) == 0;
    if (written) {
        int ok = summary && tsc_out_json(&so, summary) == 0;
        if (!ok) fprintf(stderr, "tanksim run: cannot write %s\n", path);
        written = tsc_out_close(&so, ok) == TSC_EXIT_OK;
    }
    json_decref(summary);
    if (!written) goto done;
    long steps = 0;
    for (int i = 0; i < nist; i++)
        if (ist[i].steps > 0) steps += ist[i].steps;
    char work[64] = ""; /* none for the fixed-step steppers (crank-angle point mass, dyno) */
    if (nist > 0) snprintf(work, sizeof work, ", %ld integrator steps", steps);
    printf("%s, %d DOF, %.3f s simulated in %.3f s wall (%.0fx real time%s) -> %s/\n",
           ts_model_kind(m), ts_model_dof(m), ts_time(d), wall, wall > 0 ? ts_time(d) / wall : 0.0,
           work, out);
    status = TSC_EXIT_OK;
done:
    if (series.f) tsc_out_close(&series, 0);
    ts_rows_free(&sink.rows);
    ts_data_free(d);
    ts_model_free(m);
    json_decref(resolved);
    return status;
}
