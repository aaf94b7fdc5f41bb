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

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(finds_frequencies_and_amplitudes)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
