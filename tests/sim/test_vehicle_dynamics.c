/*
 * test_vehicle_dynamics.c — what separates the track fidelities (paper
 * Section II.D, Figs. 12-14), on short runs: the linearised modes about the
 * static equilibrium, and the rear-roller force over two small bumps; and
 * vm_rhs's mass-matrix factor reuse (same q, other rates) against fresh work.
 */
#include "test_util.h"

#include <lapacke.h>
#include <stdlib.h>
#include <string.h>

#include "api/config_json.h"
#include "sim/fft.h"
#include "sim/tanksim.h"
#include "sim/vehicle_model.h"
#include "preset_config.h"
#include "vm_fd.h"

#define PI 3.14159265358979323846

static ts_config config(const char *fidelity)
{
    ts_config c;
    ts_err err;
    json_t *doc =
        json_pack("{s:{s:s,s:f,s:f,s:f,s:f},s:{s:s},s:{s:s,s:f}}", "run", "kind", "vehicle",
                  "duration", 4.0, "sample_rate", 200.0, "rtol", 1e-4, "atol", 1e-6, "track",
                  "fidelity", fidelity, "drive", "kind", "constant", "torque", 0.0);
    assert_int_equal(tsa_config_load(doc, &c, NULL, NULL, &err), TS_OK);
    json_decref(doc);
    return c;
}

/* Undamped natural frequencies [Hz] about the equilibrium: K = -dQ/dq (central
 * differences of the generalised forces), M = M(q_eq), K phi = w^2 M phi. */
static int modes(const ts_config *c, double *freq)
{
    ts_err err;
    vm *v = vm_make(c, &err);
    assert_non_null(v);
    vm_work *w = vm_work_make(v);
    int n = vm_nq(v), ny = vm_ny(v);
    double *y = malloc(sizeof(double) * (size_t)ny);
    double *K = malloc(sizeof(double) * (size_t)(n * n)),
           *M = malloc(sizeof(double) * (size_t)(n * n));
    double *q1 = malloc(sizeof(double) * (size_t)n), *q2 = malloc(sizeof(double) * (size_t)n);
    memcpy(y, vm_equilibrium(v), sizeof(double) * (size_t)ny);
    double *col = malloc(sizeof(double) * (size_t)n);
    for (int j = 0; j < n; j++) {
        vm_fd_stiffness_column(v, w, y, j, 1e-7, q1, q2, col);
        for (int i = 0; i < n; i++)
            K[i * n + j] = col[i];
    }
    free(col);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < i; j++)
            K[i * n + j] = K[j * n + i] = 0.5 * (K[i * n + j] + K[j * n + i]);
    vm_mass(v, w, y, M);
    double *wv = malloc(sizeof(double) * (size_t)n);
    assert_int_equal(LAPACKE_dsygv(LAPACK_ROW_MAJOR, 1, 'N', 'U', n, K, n, M, n, wv), 0);
    for (int i = 0; i < n; i++)
        freq[i] = wv[i] > 0 ? sqrt(wv[i]) / (2 * PI) : 0;
    free(wv), free(y), free(K), free(M), free(q1), free(q2);
    vm_work_free(w);
    vm_free(v);
    return n;
}

static int count_in(const double *f, int n, double lo, double hi, double *first)
{
    int k = 0;
    for (int i = 0; i < n; i++)
        if (f[i] >= lo && f[i] <= hi) {
            if (k == 0 && first) *first = f[i];
            k++;
        }
    return k;
}

/* EVIDENCE: [P Fig. 5] upper-circuit modes 3.7, 5.5, 7.3 Hz and [P Fig. 13,
 * Scholar & Perkins] first longitudinal circuit mode 14.0 Hz. The coupled model
 * (31 DOF, hull and running gear free) must have its lowest track modes within
 * 10 % of 3.7, 5.5 and 7.3 Hz and a longitudinal circuit mode between 13 and
 * 18 Hz; the static (massless-track) model has no mode at all between 2.5 and
 * 25 Hz, so its tension cannot show those peaks (Fig. 13a). Predicted, with
 * one calibration to disclose: the layout's upper span lengths were chosen
 * (vehicle.json, [C Fig. 5]) to put the span fundamentals at the Fig. 5
 * frequencies; EA was estimated for the 14-Hz mode by the formula
 * c_L / (2 x 15 m) (track.json). The assembled model's own longitudinal
 * circuit mode (sprocket, wheel and idler spins with the spans' stretch) is
 * at 16.8 Hz, not 14.0 (review, session 29; README): pinned to +-0.3 Hz here,
 * apart from the 13.2-Hz transverse span mode that also falls in 13-18 Hz.
 * The bump run's 14.8-Hz tension line is the course's (2-ft bumps at ~9 m/s). */
static void coupled_model_has_the_papers_track_modes(void **state)
{
    (void)state;
    double f[64], first = NAN;
    ts_config c = config("coupled");
    int n = modes(&c, f);
    printf("# coupled modes 2-25 Hz:");
    for (int i = 0; i < n; i++)
        if (f[i] > 2 && f[i] < 25) printf(" %.2f", f[i]);
    printf("\n");
    assert_int_equal(count_in(f, n, 3.7 * 0.9, 3.7 * 1.1, &first), 1);
    assert_int_equal(count_in(f, n, 5.5 * 0.9, 5.5 * 1.1, &first), 1);
    assert_int_equal(count_in(f, n, 7.3 * 0.9, 7.3 * 1.1, &first), 1);
    assert_true(count_in(f, n, 13.0, 18.0, &first) >= 1);
    assert_int_equal(count_in(f, n, 16.5, 17.1, &first), 1);
    assert_close(first, 16.8, 0, 0.3);
    ts_config s = config("static");
    n = modes(&s, f);
    assert_int_equal(count_in(f, n, 2.5, 25.0, NULL), 0);
}

static double band_amplitude(const double *x, int n, double fs, double lo, double hi)
{
    int nb = ts_fft_nbins(n);
    double *f = malloc(sizeof(double) * (size_t)nb), *a = malloc(sizeof(double) * (size_t)nb);
    ts_err err;
    assert_int_equal(ts_fft_amplitude(x, n, fs, TS_FFT_LINEAR, TS_FFT_HANN, f, a, &err), TS_OK);
    double s = 0;
    for (int k = 0; k < nb; k++)
        if (f[k] >= lo && f[k] <= hi) s += a[k] * a[k];
    free(f);
    free(a);
    return sqrt(s);
}

typedef struct rec {
    int ch;
    int n;
    double x[1024];
} rec;

static int record(void *ud, long index, double t, const double *v, int n)
{
    (void)index, (void)t, (void)n;
    rec *r = ud;
    if (r->n < 1024) r->x[r->n++] = v[r->ch];
    return 0;
}

static double roller_force_band(const char *fidelity)
{
    ts_config c = config(fidelity);
    c.drive.torque = 8000;
    c.terrain.kind = TS_TERRAIN_BUMPS;
    c.terrain.bump_n = c.terrain.bump_height_n = c.terrain.bump_length_n = 2;
    double s0[2] = {5.6, 7.0}; /* two 0.25 ft x 2 ft bumps [P II.D] under road wheel 1 */
    for (int i = 0; i < 2; i++) {
        c.terrain.bump_start[i] = s0[i];
        c.terrain.bump_height[i] = 0.0762;
        c.terrain.bump_length[i] = 0.6096;
    }
    ts_err err;
    ts_model *m = ts_model_make(&c, &err);
    assert_non_null(m);
    ts_data *d = ts_data_make(m, &err);
    assert_int_equal(ts_reset(m, d, &err), TS_OK);
    static rec r;
    r.n = 0;
    r.ch = ts_model_channel_index(m, "roller.rear.normal_force");
    assert_int_equal(ts_advance(m, d, 4.0, record, &r, &err), TS_OK);
    double a = band_amplitude(r.x, r.n, 200.0, 3.0, 8.0);
    ts_data_free(d);
    ts_model_free(m);
    return a;
}

/* EVIDENCE: [P Fig. 14] the rear-roller normal force has its dynamic content at
 * 3.7 and 5.5 Hz in the coupled model and is "null" in the static model.
 * Measured as the RMS spectral amplitude in 3-8 Hz over 4 s that carry the
 * vehicle from rest over two small bumps; the coupled model must exceed the
 * static one fivefold (measured 612 N vs 76 N: the static model's force is not
 * quite null, the hull's pitch turns the two massless spans' resultant a
 * little). Predicted; nothing calibrated to it. */
static void roller_force_dynamics_need_the_transverse_modes(void **state)
{
    (void)state;
    double s = roller_force_band("static"), c = roller_force_band("coupled");
    printf("# rear-roller force, 3-8 Hz RMS amplitude: static %.1f N, coupled %.1f N\n", s, c);
    assert_true(c > 5 * s);
}

/* EVIDENCE: exact algebra, no tolerance. vm_rhs reuses the mass matrix's
 * factor when q is bit for bit that of its previous call (M depends on q
 * alone): at a perturbed state, rates changed with q held (the velocity
 * columns of a difference-quotient Jacobian) give the same ydot, to the bit,
 * as a fresh vm_work that assembles and factors M; after a call at another
 * q the cache is not used (the same again), nor after vm_rhs_torque factored
 * its own M (with the powertrain's sprocket inertia) at the same q. */
static void rhs_factor_reuse_is_exact(void **state)
{
    (void)state;
    ts_config c = config("coupled");
    vm *v = test_vm(&c);
    int nq = vm_nq(v), ny = vm_ny(v);
    vm_work *w = vm_work_make(v);
    double *y = malloc(sizeof(double) * (size_t)ny), *a = malloc(sizeof(double) * (size_t)ny),
           *b = malloc(sizeof(double) * (size_t)ny);
    memcpy(y, vm_equilibrium(v), sizeof(double) * (size_t)ny);
    for (int i = 0; i < ny; i++) /* off the equilibrium, moving */
        y[i] += (i < nq ? 1e-3 : 0.1) * (double)((i * 7) % 5 - 2);
    assert_int_equal(vm_rhs(v, w, 0.1, y, a, NULL), 0);
    for (int j = nq; j < ny; j += 5) {
        y[j] += 0.05;
        assert_int_equal(vm_rhs(v, w, 0.1, y, a, NULL), 0); /* cached factor */
        vm_work *fresh = vm_work_make(v);
        assert_int_equal(vm_rhs(v, fresh, 0.1, y, b, NULL), 0);
        vm_work_free(fresh);
        assert_memory_equal(a, b, sizeof(double) * (size_t)ny);
    }
    y[0] += 1e-3; /* new q: factored again */
    assert_int_equal(vm_rhs(v, w, 0.1, y, a, NULL), 0);
    vm_work *fresh = vm_work_make(v);
    assert_int_equal(vm_rhs(v, fresh, 0.1, y, b, NULL), 0);
    vm_work_free(fresh);
    assert_memory_equal(a, b, sizeof(double) * (size_t)ny);
    /* a factorisation by vm_rhs_torque (sprocket inertia added to M) at the
     * same q must clear the cache: vm_rhs then factors its own M again */
    assert_int_equal(vm_rhs_torque(v, w, 0.1, y, 1000.0, 50.0, a, NULL), 0);
    assert_int_equal(vm_rhs(v, w, 0.1, y, a, NULL), 0);
    assert_memory_equal(a, b, sizeof(double) * (size_t)ny);
    free(y), free(a), free(b);
    vm_work_free(w);
    vm_free(v);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(coupled_model_has_the_papers_track_modes),
        cmocka_unit_test(roller_force_dynamics_need_the_transverse_modes),
        cmocka_unit_test(rhs_factor_reuse_is_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
