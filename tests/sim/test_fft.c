/*
 * test_fft.c — amplitude spectra (fft.h) against signals of known content.
 */
#include "test_util.h"

#include <stdlib.h>

#include "sim/fft.h"

#define PI 3.14159265358979323846

/* EVIDENCE: closed form. x = 3 + 0.01 t + 2 sin(2 pi 3.7 t) + 0.5 sin(2 pi 14 t)
 * sampled at 200 Hz for 30 s: after linear detrending and a Hann window the
 * spectrum peaks at 3.7 Hz (amplitude 2) and 14 Hz (0.5). Frequency within
 * half a bin (1/60 Hz), amplitude within 2 % (scalloping of the interpolated
 * Hann peak). */
static void finds_frequencies_and_amplitudes(void **state)
{
    (void)state;
    int n = 6000;
    double fs = 200;
    double *x = malloc(sizeof(double) * (size_t)n);
    int nb = ts_fft_nbins(n);
    double *f = malloc(sizeof(double) * (size_t)nb), *a = malloc(sizeof(double) * (size_t)nb);
    for (int i = 0; i < n; i++) {
        double t = i / fs;
        x[i] = 3 + 0.01 * t + 2 * sin(2 * PI * 3.7 * t) + 0.5 * sin(2 * PI * 14.0 * t);
    }
    ts_err err;
    assert_int_equal(ts_fft_amplitude(x, n, fs, TS_FFT_LINEAR, TS_FFT_HANN, f, a, &err), TS_OK);
    double amp;
    assert_close(ts_fft_peak(f, a, nb, 1, 8, &amp), 3.7, 0, 1.0 / 60);
    assert_close(amp, 2.0, 0.02, 0);
    assert_close(ts_fft_peak(f, a, nb, 10, 20, &amp), 14.0, 0, 1.0 / 60);
    assert_close(amp, 0.5, 0.02, 0);
    assert_true(a[0] < 1e-6); /* mean and trend removed */
    assert_true(isnan(ts_fft_peak(f, a, nb, 200, 300, NULL)));
    assert_int_equal(ts_fft_amplitude(x, 1, fs, TS_FFT_MEAN, TS_FFT_RECT, f, a, &err),
                     TS_ERR_PARAM);
    free(x);
    free(f);
    free(a);
}

/* EVIDENCE: closed form of the single-sided amplitude spectrum's end bins.
 * x_i = c + d (-1)^i (n even, no detrending, rectangular window): the DC bin
 * is the mean c and the Nyquist bin the amplitude d of the alternating
 * component, both NOT doubled (they have no mirror bin); every other bin 0.
 * Session-25 mutation test: end bins doubled like the rest survived. 1e-12. */
static void end_bins_are_not_doubled(void **state)
{
    (void)state;
    int n = 64, nb = ts_fft_nbins(n);
    double x[64], f[33], a[33];
    for (int i = 0; i < n; i++)
        x[i] = 1.5 + 0.25 * (i % 2 ? -1 : 1);
    ts_err err;
    assert_int_equal(ts_fft_amplitude(x, n, 100, TS_FFT_NONE, TS_FFT_RECT, f, a, &err), TS_OK);
    assert_close(a[0], 1.5, 1e-12, 0);
    assert_close(a[nb - 1], 0.25, 1e-12, 0);
    assert_close(f[nb - 1], 50.0, 1e-12, 0);
    for (int k = 1; k < nb - 1; k++)
        assert_close(a[k], 0, 0, 1e-12);
}

/* EVIDENCE: least-squares detrending removes a straight line exactly: the
 * spectrum of x_i = 3 + 0.5 i dt after TS_FFT_LINEAR is zero in every bin (a
 * line left with the wrong slope has a 1/k spectrum). 1e-9 of the line's
 * rise. Session-25 mutation test: a sign error in the slope survived the
 * test above, whose trend is 0.3 of a 1-unit signal. */
static void linear_detrend_removes_a_line(void **state)
{
    (void)state;
    int n = 500, nb = ts_fft_nbins(n);
    double *x = malloc(sizeof(double) * (size_t)n);
    double *f = malloc(sizeof(double) * (size_t)nb), *a = malloc(sizeof(double) * (size_t)nb);
    for (int i = 0; i < n; i++)
        x[i] = 3 + 0.5 * i * 0.01;
    ts_err err;
    assert_int_equal(ts_fft_amplitude(x, n, 100, TS_FFT_LINEAR, TS_FFT_HANN, f, a, &err), TS_OK);
    for (int k = 0; k < nb; k++)
        assert_close(a[k], 0, 0, 1e-9 * 2.5);
    free(x), free(f), free(a);
}

/* EVIDENCE: the peak between two bins. A sine of amplitude 1 at 111.5 / 30 Hz
 * (exactly half-way between bins of a 30-s record at 200 Hz), Hann window: the
 * highest bin reads 0.849 (the Hann window's 1.42-dB scalloping at half a bin)
 * and lies half a bin off; the parabolic interpolation of ts_fft_peak puts the
 * frequency within 0.05 bin and the amplitude at 0.934 (a parabola through
 * the three magnitudes of a Hann main lobe: -6.6 % at half a bin, its worst
 * case), asserted within 7 %, which the bin's own value misses. Session-25
 * mutation test: returning the bin's own value survived (the test above has
 * its sines on bins). */
static void peak_between_bins_is_interpolated(void **state)
{
    (void)state;
    int n = 6000, nb = ts_fft_nbins(n);
    double fs = 200, f0 = 111.5 / 30;
    double *x = malloc(sizeof(double) * (size_t)n);
    double *f = malloc(sizeof(double) * (size_t)nb), *a = malloc(sizeof(double) * (size_t)nb);
    for (int i = 0; i < n; i++)
        x[i] = sin(2 * PI * f0 * i / fs);
    ts_err err;
    assert_int_equal(ts_fft_amplitude(x, n, fs, TS_FFT_MEAN, TS_FFT_HANN, f, a, &err), TS_OK);
    double amp, fp = ts_fft_peak(f, a, nb, 1, 8, &amp);
    print_message("  peak %.5f Hz (true %.5f), amplitude %.4f\n", fp, f0, amp);
    assert_close(fp, f0, 0, 0.05 / 30);
    assert_close(amp, 1.0, 0.07, 0);
    free(x), free(f), free(a);
}

/* EVIDENCE: fft.h ts_fft_peak on a hand-made spectrum — the band is closed
 * (fmin <= f <= fmax), and the parabola through the largest bin and its two
 * neighbours has its vertex at bin + (y0 - y2) / (2 (y0 - 2 y1 + y2)) with
 * height y1 - (y0 - y2) d / 4: for (0, 5, 1) that is +1/18 bin and 5 + 1/72,
 * also at the second-to-last bin. An edge bin has no parabola: it is
 * returned as it is. */
static void peak_band_is_closed_and_the_parabola_exact(void **state)
{
    (void)state;
    const double f[5] = {0, 1, 2, 3, 4};
    const double at2[5] = {0, 0, 5, 1, 0}, at3[5] = {0, 0, 0, 5, 1}, at4[5] = {0, 0, 0, 1, 5};
    double A;
    assert_close(ts_fft_peak(f, at2, 5, 2.0, 4.0, &A), 2.0 + 1.0 / 18, 0, 1e-12);
    assert_close(A, 5.0 + 1.0 / 72, 0, 1e-12);
    assert_close(ts_fft_peak(f, at2, 5, 0.0, 2.0, &A), 2.0 + 1.0 / 18, 0, 1e-12);
    assert_close(ts_fft_peak(f, at3, 5, 0.0, 4.0, &A), 3.0 + 1.0 / 18, 0, 1e-12);
    assert_close(A, 5.0 + 1.0 / 72, 0, 1e-12);
    assert_close(ts_fft_peak(f, at4, 5, 0.0, 4.0, &A), 4.0, 0, 0);
    assert_close(A, 5.0, 0, 0);
    assert_true(isnan(ts_fft_peak(f, at2, 5, 2.1, 2.9, &A)));
    assert_true(isnan(A));
}

/* EVIDENCE: the symmetric Hann window w_i = (1 - cos(2 pi i / (n - 1))) / 2 is
 * 0, 0 for n = 2: no gain to divide by (every amplitude was NaN, and the
 * daemon's /fft answered an empty amplitude list). n = 2 is refused with the
 * Hann window, answered with the rectangular one; n = 3 (window 0, 1, 0) is
 * a spectrum with finite amplitudes (session-32 review). */
static void hann_window_needs_three_samples(void **state)
{
    (void)state;
    const double x[3] = {1.0, 2.0, 0.5};
    double f[2], a[2];
    ts_err err;
    assert_int_equal(ts_fft_amplitude(x, 2, 100, TS_FFT_MEAN, TS_FFT_HANN, f, a, &err),
                     TS_ERR_PARAM);
    assert_int_equal(ts_fft_amplitude(x, 2, 100, TS_FFT_MEAN, TS_FFT_RECT, f, a, &err), TS_OK);
    assert_true(isfinite(a[0]) && isfinite(a[1]));
    assert_int_equal(ts_fft_amplitude(x, 3, 100, TS_FFT_MEAN, TS_FFT_HANN, f, a, &err), TS_OK);
    assert_true(isfinite(a[0]) && isfinite(a[1]));
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(finds_frequencies_and_amplitudes),
                                       cmocka_unit_test(end_bins_are_not_doubled),
                                       cmocka_unit_test(linear_detrend_removes_a_line),
                                       cmocka_unit_test(peak_between_bins_is_interpolated),
                                       cmocka_unit_test(peak_band_is_closed_and_the_parabola_exact),
                                       cmocka_unit_test(hann_window_needs_three_samples)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
