/*
 * spectrum.h — single-sided amplitude spectrum of a uniformly sampled channel,
 * the quantity plotted in the paper's Figs. 13-14 (spectral content of the
 * hull's vertical motion), computed by sim/fft.h.
 *
 * Definition: X_k = sum_n x_n exp(-2 pi i k n / N) over the N samples (mean
 * removed when detrend = 1); amplitude A_0 = |X_0| / N, A_k = 2 |X_k| / N for
 * 0 < k < N/2, A_{N/2} = |X_{N/2}| / N for even N, at f_k = k fs / N. A sine of
 * amplitude a at a bin frequency gives A_k = a exactly. No window (rectangular).
 *
 * FFTW's planner is not thread-safe: callers running this from several threads
 * must serialise calls (the daemon holds one lock around it).
 */
#ifndef TSA_SPECTRUM_H
#define TSA_SPECTRUM_H

#include "../sim/errors.h"

/* x: n >= 2 samples at rate fs [Hz]. freq and amp receive n/2 + 1 values each
 * (caller allocates). TS_ERR_PARAM for n < 2 or fs <= 0, TS_ERR_NOMEM. */
ts_rc tsa_amplitude_spectrum(const double *x, long n, double fs, int detrend, double *freq,
                             double *amp, ts_err *err);

#endif
