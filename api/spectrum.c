/*
 * spectrum.c — amplitude spectrum by FFTW's real-to-complex transform
 * (spectrum.h). FFTW_ESTIMATE plans: no timing runs, deterministic, and the
 * transform is a one-off per request.
 */
#include "spectrum.h"

#include <fftw3.h>
#include <math.h>
#include <string.h>

ts_rc tsa_amplitude_spectrum(const double *x, long n, double fs, int detrend, double *freq,
                             double *amp, ts_err *err)
{
    if (n < 2) return ts_err_set(err, TS_ERR_PARAM, NULL, "spectrum needs at least 2 samples");
    if (!(fs > 0)) return ts_err_set(err, TS_ERR_PARAM, NULL, "sample rate must be positive");
    const long nf = n / 2 + 1;
    double *in = fftw_malloc(sizeof(double) * (size_t)n);
    fftw_complex *out = fftw_malloc(sizeof(fftw_complex) * (size_t)nf);
    fftw_plan plan = NULL;
    if (!in || !out) goto nomem;
    plan = fftw_plan_dft_r2c_1d((int)n, in, out, FFTW_ESTIMATE);
    if (!plan) goto nomem;
    double mean = 0.0;
    if (detrend) {
        for (long i = 0; i < n; i++)
            mean += x[i];
        mean /= (double)n;
    }
    for (long i = 0; i < n; i++)
        in[i] = x[i] - mean;
    fftw_execute(plan);
    for (long k = 0; k < nf; k++) {
        double mag = hypot(out[k][0], out[k][1]) / (double)n;
        int edge = k == 0 || (n % 2 == 0 && k == n / 2);
        amp[k] = edge ? mag : 2.0 * mag;
        freq[k] = (double)k * fs / (double)n;
    }
    fftw_destroy_plan(plan);
    fftw_free(in);
    fftw_free(out);
    return TS_OK;
nomem:
    fftw_free(in);
    fftw_free(out);
    return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory for a %ld-point spectrum", n);
}
