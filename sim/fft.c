/*
 * fft.c — amplitude spectra with FFTW3 (fft.h), as used for the paper's
 * Figs. 13-14 (FFT of dynamic track tension and roller normal force).
 */
#include "fft.h"

#include <fftw3.h>
#include <math.h>
#include <stdlib.h>

#include "constants.h"
#define PI TS_PI

int ts_fft_nbins(int n)
{
    return n / 2 + 1;
}

int ts_fft_min_samples(ts_fft_window window)
{
    return window == TS_FFT_HANN ? 3 : 2;
}

ts_rc ts_fft_amplitude(const double *x, int n, double fs, ts_fft_detrend detrend,
                       ts_fft_window window, double *freq, double *amp, ts_err *err)
{
    if (n < ts_fft_min_samples(window) || !(fs > 0))
        return ts_err_set(
            err, TS_ERR_PARAM, NULL, "fft: need n >= %d samples (%s window) and fs > 0",
            ts_fft_min_samples(window), window == TS_FFT_HANN ? "Hann" : "rectangular");
    int nb = ts_fft_nbins(n);
    double *in = fftw_malloc(sizeof(double) * (size_t)n);
    fftw_complex *out = fftw_malloc(sizeof(fftw_complex) * (size_t)nb);
    if (!in || !out) {
        fftw_free(in);
        fftw_free(out);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "fft: out of memory");
    }
    /* detrend: least-squares line (or mean) */
    double a = 0, b = 0;
    if (detrend != TS_FFT_NONE) {
        double sx = 0, sy = 0, sxx = 0, sxy = 0;
        for (int i = 0; i < n; i++) {
            sx += i, sy += x[i], sxx += (double)i * i, sxy += i * x[i];
        }
        if (detrend == TS_FFT_LINEAR) {
            double den = n * sxx - sx * sx;
            b = den != 0 ? (n * sxy - sx * sy) / den : 0;
        }
        a = (sy - b * sx) / n;
    }
    double gain = 0;
    for (int i = 0; i < n; i++) {
        double wv = window == TS_FFT_HANN ? 0.5 * (1 - cos(2 * PI * i / (n - 1))) : 1.0;
        gain += wv;
        in[i] = (x[i] - a - b * i) * wv;
    }
    fftw_plan p = fftw_plan_dft_r2c_1d(n, in, out, FFTW_ESTIMATE);
    if (!p) {
        fftw_free(in);
        fftw_free(out);
        return ts_err_set(err, TS_ERR_INTERNAL, NULL, "fft: no FFTW plan");
    }
    fftw_execute(p);
    fftw_destroy_plan(p);
    for (int k = 0; k < nb; k++) {
        double mag = hypot(out[k][0], out[k][1]);
        int edge = k == 0 || (n % 2 == 0 && k == n / 2);
        amp[k] = (edge ? 1.0 : 2.0) * mag / gain;
        freq[k] = k * fs / n;
    }
    fftw_free(in);
    fftw_free(out);
    return TS_OK;
}

double ts_fft_peak(const double *freq, const double *amp, int nbins, double fmin, double fmax,
                   double *peak)
{
    int best = -1;
    for (int k = 0; k < nbins; k++)
        if (freq[k] >= fmin && freq[k] <= fmax && (best < 0 || amp[k] > amp[best])) best = k;
    if (best < 0) {
        if (peak) *peak = NAN;
        return NAN;
    }
    double f = freq[best], A = amp[best];
    if (best > 0 && best < nbins - 1) {
        double y0 = amp[best - 1], y1 = amp[best], y2 = amp[best + 1];
        double den = y0 - 2 * y1 + y2;
        if (den < 0) {
            double d = 0.5 * (y0 - y2) / den;
            f += d * (freq[1] - freq[0]);
            A = y1 - 0.25 * (y0 - y2) * d;
        }
    }
    if (peak) *peak = A;
    return f;
}
