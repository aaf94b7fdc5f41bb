/*
 * spectrum.h — single-sided amplitude spectrum of a uniformly sampled channel,
 * the quantity plotted in the paper's Figs. 13-14 (spectral content of the
 * hull's vertical motion), computed by sim/fft.h.
 *
 * Definition: X_k = sum_n w_n x_n exp(-2 pi i k n / N) over the N samples
 * after detrending (none, mean or least-squares line removed); amplitude
 * A_0 = |X_0| / N, A_k = 2 |X_k| / N for 0 < k < N/2, A_{N/2} = |X_{N/2}| / N
 * for even N, at f_k = k fs / N, with the window's coherent gain divided out
 * (sim/fft.h). Rectangular window: a sine of amplitude a at a bin frequency
 * gives A_k = a exactly. Hann window with a linear detrend: what the run
 * summaries' spectral peaks use (sim/scenario_vehicle.c), so a client can
 * reproduce them.
 *
 * FFTW's planner is not thread-safe: callers running this from several threads
 * must serialise calls (the daemon holds one lock around it).
 */
#ifndef TSA_SPECTRUM_H
#define TSA_SPECTRUM_H

#include "../sim/errors.h"
#include "../sim/fft.h"

/* x: n >= 2 samples at rate fs [Hz]. freq and amp receive n/2 + 1 values each
 * (caller allocates). TS_ERR_PARAM for n < 2 or fs <= 0, TS_ERR_NOMEM. */
TS_MUST_CHECK ts_rc tsa_amplitude_spectrum(const double *x, long n, double fs,
                                           ts_fft_detrend detrend, ts_fft_window window,
                                           double *freq, double *amp, ts_err *err);

#endif
