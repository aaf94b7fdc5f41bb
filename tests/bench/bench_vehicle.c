/*
 * bench_vehicle.c — the paper's Section II.D runs (presets bump-prescribed-
 * static/longitudinal/coupled: from rest over the apg4-synth bump course under
 * the same prescribed sprocket torque, 30 s) with their figures printed beside
 * the paper's, and each run's real-time factor (simulated / wall seconds,
 * measured in this run; goal for the coupled run: >= 500x).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "api/config_json.h"
#include "sim/tanksim.h"

typedef struct sink {
    int nc;
    long n, cap;
    double *rows;
} sink;

static int keep(void *ud, long index, double t, const double *v, int n)
{
    (void)index, (void)t;
    sink *s = ud;
    if (s->n == s->cap) {
        long cap = s->cap ? 2 * s->cap : 8192;
        double *r = realloc(s->rows, sizeof(double) * (size_t)(cap * n));
        if (!r) return 1;
        s->rows = r;
        s->cap = cap;
    }
    memcpy(s->rows + s->n * n, v, sizeof(double) * (size_t)n);
    s->n++;
    return 0;
}

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double metric(const ts_metric *m, int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(m[i].name, name) == 0) return m[i].value;
    return NAN;
}

static int run(const char *preset)
{
    ts_config c;
    ts_err err;
    json_t *doc = json_pack("{s:s}", "preset", preset);
    if (tsa_config_load(doc, &c, NULL, NULL, &err) != TS_OK) {
        printf("%s: %s\n", preset, err.msg);
        return 1;
    }
    json_decref(doc);
    ts_model *m = ts_model_make(&c, &err);
    if (!m) {
        printf("%s: %s\n", preset, err.msg);
        return 1;
    }
    ts_data *d = ts_data_make(m, &err);
    sink s = {ts_model_nchannel(m), 0, 0, NULL};
    double c0 = cpu_now();
    if (!d || ts_reset(m, d, &err) != TS_OK) {
        printf("%s: %s\n", preset, err.msg);
        return 1;
    }
    keep(&s, 0, 0, ts_latest(d), s.nc);
    if (ts_advance(m, d, c.run.duration, keep, &s, &err) != TS_OK) {
        printf("%s: %s\n", preset, err.msg);
        return 1;
    }
    double cpu = cpu_now() - c0, wall = ts_wall_seconds(d);
    ts_metric mt[32];
    int nm = ts_model_metrics(m, s.rows, s.n, mt, 32);
    if (strstr(preset, "coupled")) printf("\n(goal for the coupled run: >= 500x real time)");
    printf("\n%s: %d DOF, %.0f s simulated in %.2f s wall / %.2f s CPU: "
           "real-time factor %.0fx (wall), %.0fx (CPU)\n",
           preset, ts_model_dof(m), c.run.duration, wall, cpu, c.run.duration / wall,
           c.run.duration / cpu);
    printf("  %-34s %12s   %s\n", "figure", "model", "paper");
    printf("  %-34s %12.1f   %s\n", "top speed [mph] (torque calibrated)",
           metric(mt, nm, "top_speed_mph"), "~25 (II.D), 27 (IV.C)");
    printf("  %-34s %12.0f   %s\n", "static tension [lbf]",
           metric(mt, nm, "static_tension") / 4.44822, "~15,000 (inferred)");
    printf("  %-34s %12.0f   %s\n", "peak rear-roller tension [lbf]",
           metric(mt, nm, "peak_tension_lb"), "~30,000 (Fig. 12)");
    printf("  %-34s %12.2f   %s\n", "peak / static tension",
           metric(mt, nm, "tension_amplification"), "~2 ('nearly 100 %'), dynamic models");
    printf("  %-34s %12.2f   %s\n", "peak |accel_x| [m/s^2]", metric(mt, nm, "peak_abs_accel_x"),
           "static model largest (Fig. 11)");
    printf("  %-34s %12.2f   %s\n", "tension FFT peak 2-6 Hz [Hz]",
           metric(mt, nm, "tension_peak_2_6hz"), "3.7 (coupled only, Fig. 13c)");
    printf("  %-34s %12.0f   %s\n", "  its amplitude [N]", metric(mt, nm, "tension_peak_2_6hz_amp"),
           "");
    printf("  %-34s %12.2f   %s\n", "tension FFT peak 13-20 Hz [Hz]",
           metric(mt, nm, "tension_peak_13_20hz"), "14.0 (dynamic models, Fig. 13b-c)");
    printf("  %-34s %12.0f   %s\n", "  its amplitude [N]",
           metric(mt, nm, "tension_peak_13_20hz_amp"), "");
    printf("  %-34s %12.2f   %s\n", "roller force FFT peak 2-4.6 Hz",
           metric(mt, nm, "roller_force_peak_2_4.6hz"), "3.7 (coupled, Fig. 14b)");
    printf("  %-34s %12.0f   %s\n", "  its amplitude [N]",
           metric(mt, nm, "roller_force_peak_2_4.6hz_amp"), "static: null");
    printf("  %-34s %12.2f   %s\n", "roller force FFT peak 4.6-7 Hz",
           metric(mt, nm, "roller_force_peak_4.6_7hz"), "5.5 (coupled, Fig. 14b)");
    printf("  %-34s %12.0f   %s\n", "  its amplitude [N]",
           metric(mt, nm, "roller_force_peak_4.6_7hz_amp"), "static: null");
    free(s.rows);
    ts_data_free(d);
    ts_model_free(m);
    return 0;
}

int main(void)
{
    int rc = 0;
    rc |= run("bump-prescribed-static");
    rc |= run("bump-prescribed-longitudinal");
    rc |= run("bump-prescribed-coupled");
    return rc;
}
