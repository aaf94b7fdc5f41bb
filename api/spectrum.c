/*
 * spectrum.c — the API's amplitude spectrum (spectrum.h): sim/fft.h's FFTW
 * transform, so the library and the daemon compute spectra one way.
 */
#include "spectrum.h"

#include <limits.h>

ts_rc tsa_amplitude_spectrum(const double *x, long n, double fs, ts_fft_detrend detrend,
                             ts_fft_window window, double *freq, double *amp, ts_err *err)
{
    if (n < 2) return ts_err_set(err, TS_ERR_PARAM, NULL, "spectrum needs at least 2 samples");
    if (!(fs > 0)) return ts_err_set(err, TS_ERR_PARAM, NULL, "sample rate must be positive");
    if (n > INT_MAX) return ts_err_set(err, TS_ERR_LIMIT, NULL, "spectrum of %ld samples is too long", n);
    return ts_fft_amplitude(x, (int)n, fs, detrend, window, freq, amp, err);
}
