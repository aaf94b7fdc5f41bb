/*
 * test_spectrum.c — the API's amplitude spectrum (spectrum.h): its input
 * checks and the amplitude definition the /fft endpoint documents.
 */
#include "test_util.h"

#include "api/spectrum.h"

/* EVIDENCE: spectrum.h's definition (the paper's Figs. 13-14 quantity): a
 * sine of amplitude a at bin k of N samples, rectangular window, mean
 * removed, gives A_k = a and f_k = k fs / N exactly (closed form, 1e-12); a
 * constant offset is removed (A_0 = 0). Inputs: fewer than 2 samples or a
 * non-positive rate are refused (sim/fft.c refuses them too, so the
 * session-26 mutation pass's "one sample accepted" here is equivalent). */
static void amplitude_of_a_bin_sine_and_bad_inputs(void **state)
{
    (void)state;
    enum { N = 64 };
    double x[N], freq[N / 2 + 1], amp[N / 2 + 1];
    const double fs = 200, a = 1.7, pi = 3.14159265358979323846;
    for (int i = 0; i < N; i++)
        x[i] = 5.0 + a * sin(2 * pi * 5 * i / N);
    ts_err err;
    assert_int_equal(tsa_amplitude_spectrum(x, N, fs, TS_FFT_MEAN, TS_FFT_RECT, freq, amp, &err),
                     TS_OK);
    assert_close(freq[5], 5 * fs / N, 1e-12, 0);
    assert_close(amp[5], a, 1e-12, 0);
    assert_close(amp[0], 0, 0, 1e-12);
    assert_close(amp[6], 0, 0, 1e-12);
    assert_int_equal(tsa_amplitude_spectrum(x, 1, fs, TS_FFT_MEAN, TS_FFT_RECT, freq, amp, &err),
                     TS_ERR_PARAM);
    assert_int_equal(tsa_amplitude_spectrum(x, 0, fs, TS_FFT_NONE, TS_FFT_RECT, freq, amp, &err),
                     TS_ERR_PARAM);
    assert_int_equal(tsa_amplitude_spectrum(x, N, 0, TS_FFT_MEAN, TS_FFT_RECT, freq, amp, &err),
                     TS_ERR_PARAM);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(amplitude_of_a_bin_sine_and_bad_inputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
