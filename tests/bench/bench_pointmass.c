/*
 * bench_pointmass.c — the paper's full-rack point-mass acceleration (Table 2,
 * presets accel-pointmass-*) with each engine fidelity: real-time factor
 * (simulated / wall seconds, measured in this run) and the Table 2 figures
 * beside the paper's. Prints; asserts nothing (timings are machine-dependent).
 *
 * Usage: bench_pointmass [FIDELITY ...] [--variants]   (default: all three
 * fidelities, conventional engine; --variants runs all three variants).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api/config_json.h"
#include "sim/tanksim.h"

typedef struct {
    double *rows;
    long n, cap;
    int nc;
} sink;

static int keep(void *ud, long i, double t, const double *v, int n)
{
    (void)i;
    (void)t;
    sink *s = ud;
    if (s->n == s->cap) {
        long cap = s->cap ? 2 * s->cap : 4096;
        double *r = realloc(s->rows, (size_t)cap * (size_t)n * sizeof *r);
        if (!r) return 1;
        s->rows = r;
        s->cap = cap;
    }
    memcpy(s->rows + (size_t)s->n * (size_t)n, v, (size_t)n * sizeof *v);
    s->n++;
    return 0;
}

static const char *const variants[] = {"conventional", "lhr05", "lhr10"};
static const double paper[3][3] = {{65.67, 17.2, 13.2}, {66.29, 16.95, 12.9}, {66.43, 16.9, 12.8}};

static int run_one(const char *variant, const char *fidelity, int vi)
{
    char preset[64];
    snprintf(preset, sizeof preset, "accel-pointmass-%s", variant);
    json_t *doc = json_pack("{s:s,s:{s:s}}", "preset", preset, "engine", "fidelity", fidelity);
    ts_config c;
    ts_err err;
    if (tsa_config_load(doc, &c, NULL, NULL, &err) != TS_OK) {
        printf("%-12s %-12s config error: %s\n", variant, fidelity, err.msg);
        json_decref(doc);
        return 1;
    }
    json_decref(doc);
    ts_model *m = ts_model_make(&c, &err);
    if (!m) {
        printf("%-12s %-12s unavailable: %s\n", variant, fidelity, err.msg);
        return 1;
    }
    ts_data *d = ts_data_make(m, &err);
    sink s = {NULL, 0, 0, ts_model_nchannel(m)};
    ts_rc rc = d ? ts_reset(m, d, &err) : TS_ERR_NOMEM;
    if (rc == TS_OK) {
        keep(&s, 0, 0, ts_latest(d), s.nc);
        rc = ts_advance(m, d, c.run.duration, keep, &s, &err);
    }
    if (rc != TS_OK) {
        printf("%-12s %-12s run failed: %s\n", variant, fidelity, err.msg);
    } else {
        ts_metric mt[16];
        int nm = ts_model_metrics(m, s.rows, s.n, mt, 16);
        double wall = ts_wall_seconds(d);
        printf("%-12s %-12s wall %8.2f s  real-time x %7.2f |", variant, fidelity, wall,
               c.run.duration / wall);
        for (int k = 0; k < nm && k < 3; k++)
            printf("  %s %.2f (paper %.2f)", mt[k].name, mt[k].value, paper[vi][k]);
        for (int k = 3; k < nm; k++) printf("  %s %.2f", mt[k].name, mt[k].value);
        printf("\n");
    }
    free(s.rows);
    ts_data_free(d);
    ts_model_free(m);
    fflush(stdout);
    return rc != TS_OK;
}

int main(int argc, char **argv)
{
    const char *fid[8];
    int nf = 0, all_variants = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--variants")) all_variants = 1;
        else if (nf < 8) fid[nf++] = argv[i];
    }
    if (!nf) {
        fid[nf++] = "map";
        fid[nf++] = "mean_value";
        fid[nf++] = "crank_angle";
    }
    printf("bench_pointmass: 20-s full-rack acceleration, point-mass M1 (Table 2)\n");
    int bad = 0;
    for (int f = 0; f < nf; f++)
        for (int v = 0; v < (all_variants ? 3 : 1); v++) bad += run_one(variants[v], fid[f], v);
    if (bad) printf("bench_pointmass: %d run(s) did not complete (see above)\n", bad);
    return 0; /* a bench reports; it does not gate the other benches */
}
