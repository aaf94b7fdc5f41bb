/*
 * test_vehicle_amplification.c — the quasi-static reference of the rear-roller
 * tension (channel track.tension.quasi_static, vehicle_model.h vm_diag) and the
 * dynamic amplification over it (paper Section II.D, Fig. 12: "the static
 * model shows no dynamic amplification"; the dynamic track models do), on
 * short runs of the Section II.D presets over the first bump of apg4-synth;
 * and the spectra of whole runs (Figs. 13-14).
 */
#include "test_util.h"

#include <stdlib.h>
#include <string.h>

#include "api/config_json.h"
#include "api/session_json.h"
#include "sim/tanksim.h"
#include "sim/vehicle_channels.h"
#include "preset_config.h"

/* Run preset for duration seconds; rows in *r, the model in *m (caller frees). */
static void run(const char *preset, double duration, ts_model **m, ts_rows *r)
{
    ts_config c = test_preset_config(preset, NULL);
    c.run.duration = duration;
    *m = test_run_rows(&c, r);
}

static double metric(const ts_model *m, const ts_rows *r, const char *name)
{
    ts_metric *mt;
    int n;
    ts_err err;
    assert_int_equal(tsa_model_metrics(m, r->v, r->n, &mt, &n, &err), TS_OK);
    for (int i = 0; i < n; i++)
        if (strcmp(mt[i].name, name) == 0) {
            double v = mt[i].value;
            free(mt);
            return v;
        }
    free(mt);
    fail_msg("no metric %s", name);
    return NAN;
}

/* EVIDENCE: closed form (static equilibrium of a massless chain with free
 * wheels: one tension from the sprocket round the top to the anchor wheel,
 * tau/r_s more from there to the sprocket; the stretches sum to the loop's
 * geometric stretch) against the integrated static-fidelity model on the flat
 * lead-in of the bump course under the constant prescribed torque (t = 2..5 s,
 * the hull squatted, the tension 11 % below static). Tolerance 0.2 % of the
 * static tension (what is left: spin inertia and Kelvin-Voigt damping while
 * accelerating). Nothing calibrated. */
static void quasi_static_tension_matches_static_model_on_flat(void **state)
{
    (void)state;
    ts_model *m;
    ts_rows r;
    run("bump-prescribed-static", 5.0, &m, &r);
    int it = ts_model_channel_index(m, "track.tension.rear_roller");
    int iq = ts_model_channel_index(m, "track.tension.quasi_static");
    assert_true(it >= 0 && iq >= 0);
    int nc = ts_model_nchannel(m);
    double t0 = metric(m, &r, "static_tension");
    double worst = 0, mean_drop = 0;
    int n = 0;
    for (long i = 0; i < r.n; i++) {
        double t = r.v[i * nc];
        if (t < 2.0) continue;
        const double *row = r.v + i * nc;
        worst = fmax(worst, fabs(row[it] - row[iq]));
        mean_drop += t0 - row[iq];
        n++;
    }
    mean_drop /= n;
    printf("# flat lead-in: |T - T_qs| <= %.1f N, T_qs %.0f N below static (%.1f %%)\n", worst,
           mean_drop, 100 * mean_drop / t0);
    assert_true(mean_drop > 0.05 * t0); /* the torque term is exercised */
    assert_true(worst <= 0.002 * t0);
    ts_rows_free(&r);
    ts_model_free(m);
}

/* EVIDENCE: paper Fig. 12 / Section II.D (qualitative): the static track model
 * shows no dynamic amplification of the tension, the dynamic ones do. Run to
 * 9 s (over the first, 1 ft x 25 ft bump). Quantity: max and RMS of
 * (rear-roller tension - quasi-static tension) / static tension. Static: only
 * the Kelvin-Voigt damping of the massless elements separates the two
 * (max <= 0.15, RMS <= 0.01); coupled (31 DOF): the span inertia adds a
 * dynamic part, max >= 0.1 and RMS >= 5x the static model's. The two
 * models' maxima are not compared: the static model's max is its Kelvin-Voigt
 * damping's part (0.105), of the same order as the coupled one's (0.196), so
 * a ratio bound would only restate the measured ratio; the RMS (0.062 vs
 * 0.003, 21x) and the spectrum below carry the separation. The thresholds
 * were set when the test was written (static max 0.063, RMS 0.002; coupled
 * max 0.21, RMS 0.050) with margin: separations between the two models, not
 * fits to the paper. Also: the static model's peak
 * tension (1.88x static here) is the quasi-static peak within 5 %: the suspension geometry, not
 * dynamics, makes it. Nothing calibrated. */
static void static_model_shows_no_dynamic_amplification(void **state)
{
    (void)state;
    ts_model *ms, *mc;
    ts_rows rs, rc;
    run("bump-prescribed-static", 9.0, &ms, &rs);
    run("bump-prescribed-coupled", 9.0, &mc, &rc);
    double s_max = metric(ms, &rs, "dynamic_amplification_max");
    double s_rms = metric(ms, &rs, "dynamic_amplification_rms");
    double c_max = metric(mc, &rc, "dynamic_amplification_max");
    double c_rms = metric(mc, &rc, "dynamic_amplification_rms");
    double s_peak = metric(ms, &rs, "tension_amplification");
    double s_qs = metric(ms, &rs, "quasi_static_peak_tension_lb") /
                  (metric(ms, &rs, "static_tension") / 4.44822);
    double s_f = metric(ms, &rs, "dynamic_tension_peak_2_4.6hz_amp");
    double c_f = metric(mc, &rc, "dynamic_tension_peak_2_4.6hz_amp");
    printf("# first bump: static max %.3f rms %.3f (peak/static %.2f, quasi-static %.2f); "
           "coupled max %.3f rms %.3f; dynamic-part spectrum 2-4.6 Hz: static %.0f N, coupled "
           "%.0f N at %.2f Hz\n",
           s_max, s_rms, s_peak, s_qs, c_max, c_rms, s_f, c_f,
           metric(mc, &rc, "dynamic_tension_peak_2_4.6hz"));
    assert_true(s_max <= 0.15);
    assert_true(s_rms <= 0.01);
    /* the static model's peak is the quasi-static one (geometry, not dynamics) */
    assert_close(s_peak, s_qs, 0.05, 0);
    assert_true(c_max >= 0.1);
    assert_true(c_rms >= 5 * s_rms);
    /* the dynamic part's spectrum (metric dynamic_tension_peak_2_4.6hz, the
     * band of the paper's 3.7-Hz peak, Fig. 13c): measured 7 N static vs 84 N
     * coupled (12x) when added; separation >= 5x */
    assert_true(c_f >= 5 * s_f);
    ts_rows_free(&rs);
    ts_rows_free(&rc);
    ts_model_free(ms);
    ts_model_free(mc);
}

/* EVIDENCE: paper Section II.D, Figs. 13-14, whole 30-s bump-course runs of
 * the three presets. Fig. 13: the tension's peak near 3.7 Hz (the upper
 * circuit's mode, Fig. 5; ours 3.80 Hz at rest) in the coupled model only, the
 * peak near 14 Hz in both dynamic models; Fig. 14b: the rear roller's normal
 * force peaks near 3.7 and 5.5 Hz with the coupled model, null with the static
 * one. What is predicted and what is not: the coupled model's 4.0-Hz peak is
 * there for every train pitch of the course from 6 to 16 ft (README); that the
 * static and longitudinal models have NO peak there follows from the course's
 * 10-ft train pitch, chosen [C Figs. 13a-b] so its passing frequency at the
 * run's ~20-22 mph (2.9-3.2 Hz) is off the mode (with the first estimate, 8 ft,
 * every model peaked at 3.6-3.9 Hz). Measured when written: 2-6 Hz total
 * tension peak 2.26 / 2.04 / 4.02 Hz (static / longitudinal / coupled); 13-20
 * Hz 14.82 / 14.83 Hz (dynamic models); roller force 2-4.6 Hz 47 N static vs
 * 1,008 N coupled at 4.00 Hz, 4.6-7 Hz 40 N vs 995 N at 5.80 Hz. Bands and
 * ratios below are the paper's statements with margins, not fits. */
static void circuit_mode_tension_peak_in_coupled_model_only(void **state)
{
    (void)state;
    static const char *const preset[3] = {"bump-prescribed-static", "bump-prescribed-longitudinal",
                                          "bump-prescribed-coupled"};
    double f26[3], f1320[3], r1amp[3], r2amp[3], r2f[3];
    for (int i = 0; i < 3; i++) {
        ts_model *m;
        ts_rows r;
        run(preset[i], 30.0, &m, &r);
        f26[i] = metric(m, &r, "tension_peak_2_6hz");
        f1320[i] = metric(m, &r, "tension_peak_13_20hz");
        r1amp[i] = metric(m, &r, "roller_force_peak_2_4.6hz_amp");
        r2amp[i] = metric(m, &r, "roller_force_peak_4.6_7hz_amp");
        r2f[i] = metric(m, &r, "roller_force_peak_4.6_7hz");
        printf("# %s: tension peaks %.2f Hz (2-6), %.2f Hz (13-20); roller force %.0f N "
               "(2-4.6 Hz), %.0f N at %.2f Hz (4.6-7)\n",
               preset[i], f26[i], f1320[i], r1amp[i], r2amp[i], r2f[i]);
        ts_rows_free(&r);
        ts_model_free(m);
    }
    /* Fig. 13c: the circuit mode in the coupled model's tension */
    assert_true(f26[2] >= 3.5 && f26[2] <= 4.3);
    /* Fig. 13a-b: not in the static and longitudinal models' */
    for (int i = 0; i < 2; i++)
        assert_true(f26[i] < 3.3 || f26[i] > 4.5);
    /* Fig. 13b-c: the ~14-Hz peak in both dynamic models */
    for (int i = 1; i < 3; i++)
        assert_true(f1320[i] >= 13.5 && f1320[i] <= 15.5);
    /* Fig. 14b: the roller force's two peaks with the coupled model, near 5.5 Hz
     * for the second; the static model's spectrum is null beside them (< 1/10) */
    assert_true(r2f[2] >= 5.0 && r2f[2] <= 6.2);
    assert_true(r1amp[2] >= 10 * r1amp[0] && r2amp[2] >= 10 * r2amp[0]);
}

/* EVIDENCE: definition (vehicle_channels.h): span_tension_min is the least
 * value of the five span.<name>.tension columns over all rows and
 * span_compression_fraction the share of rows in which one is below zero.
 * Synthetic rows with known answers (3 of 8 rows with a negative span, the
 * least -1234.5 N in the last span of row 5), a row of exact zeros (a slack
 * massless element: not compression), the empty run (NAN); then the metric
 * of a real 9-s coupled run against the columns it summarises. */
static void span_metrics_flag_compressed_rows(void **state)
{
    (void)state;
    enum { NR = 8, NC = 1 + VM_NCH };
    double rows[NR * NC];
    for (int i = 0; i < NR; i++)
        for (int j = 0; j < NC; j++) rows[i * NC + j] = 1000.0 + i + j;
    double *span = rows + 1 + VM_CH_SPAN_T0;
    span[1 * NC + 0] = -1.0;
    span[5 * NC + VM_NSPAN - 1] = -1234.5;
    span[5 * NC + 2] = -3.0;
    span[6 * NC + 3] = -0.5;
    for (int k = 0; k < VM_NSPAN; k++) span[7 * NC + k] = 0.0;
    rows[2 * NC + 1 + VM_CH_T_RR] = -9999.0; /* not a span column: ignored */
    ts_metric mt[4];
    int n = vm_channels_span_metrics(rows, NR, NC, 1, mt, 0, 4);
    assert_int_equal(n, 2);
    assert_string_equal(mt[0].name, "span_tension_min");
    assert_string_equal(mt[0].unit, "N");
    assert_close(mt[0].value, -1234.5, 0, 1e-12);
    assert_string_equal(mt[1].name, "span_compression_fraction");
    assert_close(mt[1].value, 3.0 / 8.0, 0, 1e-15);
    n = vm_channels_span_metrics(rows, 0, NC, 1, mt, 0, 4);
    assert_int_equal(n, 2);
    assert_true(isnan(mt[0].value) && isnan(mt[1].value));

    ts_model *m;
    ts_rows r;
    run("bump-prescribed-coupled", 9.0, &m, &r);
    int i0 = ts_model_channel_index(m, "span.sprocket_rear_roller.tension");
    assert_true(i0 >= 0);
    int nc = ts_model_nchannel(m);
    double tmin = INFINITY;
    long neg = 0;
    for (long i = 0; i < r.n; i++) {
        double ri = INFINITY;
        for (int k = 0; k < VM_NSPAN; k++) ri = fmin(ri, r.v[i * nc + i0 + k]);
        tmin = fmin(tmin, ri);
        neg += ri < 0;
    }
    printf("# first 9 s, coupled: least mid-span tension %.0f N, %ld of %ld rows < 0\n", tmin, neg,
           r.n);
    assert_close(metric(m, &r, "span_tension_min"), tmin, 0, 1e-9);
    assert_close(metric(m, &r, "span_compression_fraction"), (double)neg / (double)r.n, 0, 1e-15);
    ts_rows_free(&r);
    ts_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(quasi_static_tension_matches_static_model_on_flat),
        cmocka_unit_test(static_model_shows_no_dynamic_amplification),
        cmocka_unit_test(circuit_mode_tension_peak_in_coupled_model_only),
        cmocka_unit_test(span_metrics_flag_compressed_rows),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
