/*
 * spectrum.c — the API's amplitude spectrum (spectrum.h): sim/fft.h's FFTW
 * transform, so the library and the daemon compute spectra one way.
 */
#include "spectrum.h"

#include <limits.h>

ts_rc tsa_amplitude_spectrum(const double *x, long n, double fs, ts_fft_detrend detrend,
                             ts_fft_window window, double *freq, double *amp, ts_err *err)
{
    /* the sample count and rate are ts_fft_amplitude's to refuse; only its int here */
    if (n > INT_MAX) return ts_err_set(err, TS_ERR_LIMIT, NULL, "spectrum of %ld samples is too long", n);
    return ts_fft_amplitude(x, (int)n, fs, detrend, window, freq, amp, err);
}
