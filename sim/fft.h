/*
 * fft.h — single-sided amplitude spectrum of a uniformly sampled channel
 * (FFTW3), for the paper's spectra of track tension and roller force
 * (Section II.D, Figs. 13-14).
 *
 * The FFTW planner is not thread-safe: call from one thread at a time (the
 * plan is FFTW_ESTIMATE and made per call).
 */
#ifndef TS_FFT_H
#define TS_FFT_H

#include "errors.h"

typedef enum ts_fft_detrend { TS_FFT_NONE, TS_FFT_MEAN, TS_FFT_LINEAR } ts_fft_detrend;
typedef enum ts_fft_window { TS_FFT_RECT, TS_FFT_HANN } ts_fft_window;

/* Number of spectrum bins for n samples: n/2 + 1. */
int ts_fft_nbins(int n);

/* Fewest samples ts_fft_amplitude takes with this window: 2, or 3 for Hann
 * (its symmetric window over 2 points is 0, 0: no gain to divide by). */
int ts_fft_min_samples(ts_fft_window window);

/* Amplitude spectrum of x[n] sampled at fs [Hz] after detrending and
 * windowing: freq[k] = k fs / n [Hz], amp[k] the amplitude of a sinusoid at
 * that frequency (window gain corrected; a pure A sin(2 pi f t) on a bin gives
 * amp = A). freq and amp hold ts_fft_nbins(n) values. n >= 2. */
TS_MUST_CHECK ts_rc ts_fft_amplitude(const double *x, int n, double fs, ts_fft_detrend detrend,
                                     ts_fft_window window, double *freq, double *amp, ts_err *err);

/* Frequency of the largest amplitude with fmin <= f <= fmax (parabolic
 * interpolation between bins); *peak (may be NULL) gets that amplitude.
 * Returns NAN when no bin lies in the band. */
double ts_fft_peak(const double *freq, const double *amp, int nbins, double fmin, double fmax,
                   double *peak);

#endif
