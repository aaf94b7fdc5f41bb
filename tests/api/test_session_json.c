/*
 * test_session_json.c — the daemon's JSON/text shapes (api/session_json.h) and
 * the amplitude spectrum (api/spectrum.h) without HTTP.
 */
#include "test_util.h"

#include <stdlib.h>
#include <string.h>

#include "api/config_json.h"
#include "api/session_json.h"
#include "api/spectrum.h"
#include "sim/tanksim.h"

#define PI 3.14159265358979323846

/* EVIDENCE: closed form — a sine of amplitude a at a bin frequency f_k = k fs/N
 * has single-sided DFT amplitude exactly a at bin k and ~0 elsewhere; the mean
 * is removed. Tolerance 1e-9 (round-off only); nothing calibrated. */
static void spectrum_of_two_sines(void **state)
{
    (void)state;
    const long n = 1000;
    const double fs = 500.0; /* df = 0.5 Hz */
    double *x = malloc(sizeof(double) * (size_t)n);
    double *f = malloc(sizeof(double) * (size_t)(n / 2 + 1));
    double *a = malloc(sizeof(double) * (size_t)(n / 2 + 1));
    for (long i = 0; i < n; i++) {
        double t = (double)i / fs;
        x[i] = 7.0 + 2.0 * sin(2 * PI * 5.0 * t) + 0.5 * cos(2 * PI * 42.5 * t);
    }
    ts_err err;
    assert_int_equal(tsa_amplitude_spectrum(x, n, fs, 1, f, a, &err), TS_OK);
    assert_close(f[1], 0.5, 1e-12, 0);
    assert_close(f[n / 2], 250.0, 1e-12, 0);
    assert_close(a[0], 0.0, 0, 1e-9);  /* mean removed */
    assert_close(a[10], 2.0, 1e-9, 0); /* 5 Hz */
    assert_close(a[85], 0.5, 1e-9, 0); /* 42.5 Hz */
    for (long k = 1; k <= n / 2; k++)
        if (k != 10 && k != 85) assert_close(a[k], 0.0, 0, 1e-9);
    /* without detrending the mean shows at DC */
    assert_int_equal(tsa_amplitude_spectrum(x, n, fs, 0, f, a, &err), TS_OK);
    assert_close(a[0], 7.0, 1e-9, 0);
    assert_int_equal(tsa_amplitude_spectrum(x, 1, fs, 1, f, a, &err), TS_ERR_PARAM);
    free(x);
    free(f);
    free(a);
}

static void numbers_report_every_field(void **state)
{
    (void)state;
    ts_err err;
    const char *body = "{\"duration\": \"1\", \"until\": -2, \"extra\": 1}";
    json_t *doc = tsa_parse_object(body, strlen(body), &err);
    assert_non_null(doc);
    double d = 0, u = 0;
    tsa_num_field f[] = {{"duration", 1, 0, 10, &d, NULL},
                         {"until", 0, 0, 10, &u, NULL},
                         {"rate", 1, 0, 1, &u, NULL}};
    json_t *errors = json_array();
    assert_int_not_equal(tsa_read_numbers(doc, f, 3, errors, &err), TS_OK);
    assert_int_equal(json_array_size(errors), 4);
    const char *want[] = {"/extra", "/duration", "/until", "/rate"};
    for (int i = 0; i < 4; i++)
        assert_string_equal(
            json_string_value(json_object_get(json_array_get(errors, (size_t)i), "pointer")),
            want[i]);
    assert_string_equal(err.pointer, "/extra");
    json_decref(errors);
    json_decref(doc);
    assert_null(tsa_parse_object("{\"a\": ", 6, &err));
    assert_int_equal(err.code, TS_ERR_PARAM);
    assert_non_null(strstr(err.msg, "malformed JSON"));
    assert_null(tsa_parse_object("[1]", 3, &err));
    assert_null(tsa_parse_object("{\"a\":1,\"a\":2}", 13, &err)); /* duplicate keys */
}

static ts_model *pointmass(void)
{
    ts_config c;
    ts_err err;
    json_t *doc = json_pack("{s:s}", "preset", "pointmass-prescribed");
    assert_int_equal(tsa_config_load(doc, &c, NULL, NULL, &err), TS_OK);
    json_decref(doc);
    ts_model *m = ts_model_make(&c, &err);
    assert_non_null(m);
    return m;
}

static void channels_rows_and_series(void **state)
{
    (void)state;
    ts_model *m = pointmass();
    ts_err err;
    int idx[16], n;
    assert_int_equal(tsa_channel_select(m, "vehicle.speed,t,vehicle.speed", idx, 16, &n, &err),
                     TS_OK);
    assert_int_equal(n, 2);
    assert_int_equal(idx[0], 0);
    assert_int_equal(idx[1], ts_model_channel_index(m, "vehicle.speed"));
    assert_int_equal(tsa_channel_select(m, "nope", idx, 16, &n, &err), TS_ERR_NOTFOUND);
    assert_string_equal(err.pointer, "/channels");
    assert_int_equal(tsa_channel_select(m, NULL, idx, 16, &n, &err), TS_OK);
    assert_int_equal(n, ts_model_nchannel(m));

    const int nch = ts_model_nchannel(m);
    double rows[3 * 16];
    long index[3] = {4, 6, 8};
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < nch; c++)
            rows[r * nch + c] = r * 100 + c + 0.25;
    tsa_buf b = {0};
    int sel[2] = {0, 2};
    tsa_series_json(&b, "s1", m, sel, 2, index, rows, 3, 2, "10");
    json_error_t je;
    json_t *j = json_loads(b.p, 0, &je);
    assert_non_null(j);
    assert_int_equal(json_integer_value(json_object_get(j, "count")), 3);
    assert_string_equal(json_string_value(json_object_get(j, "next_page_token")), "10");
    json_t *ch = json_array_get(json_object_get(j, "channels"), 1);
    assert_string_equal(json_string_value(json_object_get(ch, "name")),
                        ts_model_channel(m, 2)->name);
    assert_string_equal(json_string_value(json_object_get(ch, "unit")),
                        ts_model_channel(m, 2)->unit);
    assert_close(json_number_value(json_array_get(json_object_get(ch, "values"), 2)), 202.25, 0, 0);
    json_decref(j);
    tsa_buf_free(&b);

    tsa_csv_header(&b, m, sel, 2);
    tsa_csv_row(&b, rows + nch, sel, 2);
    char want[256];
    snprintf(want, sizeof want, "t [s],%s [%s]\n100.25,102.25\n", ts_model_channel(m, 2)->name,
             ts_model_channel(m, 2)->unit);
    assert_string_equal(b.p, want);
    tsa_buf_free(&b);

    tsa_row_json(&b, m, 6, rows + nch, sel, 2);
    j = json_loads(b.p, 0, &je);
    assert_non_null(j);
    assert_int_equal(json_integer_value(json_object_get(j, "index")), 6);
    assert_close(json_number_value(json_object_get(j, "t")), 100.25, 0, 0);
    assert_int_equal(json_object_size(json_object_get(j, "values")), 1);
    json_decref(j);
    tsa_buf_free(&b);
    ts_model_free(m);
}

static void buffer_grows_past_first_block(void **state)
{
    (void)state;
    tsa_buf b = {0};
    for (int i = 0; i < 10000; i++)
        tsa_buf_printf(&b, "%05d,", i);
    assert_int_equal(b.n, 60000);
    assert_memory_equal(b.p + 6 * 9999, "09999,", 6);
    size_t len;
    char *p = tsa_buf_take(&b, &len);
    assert_int_equal(len, 60000);
    assert_null(b.p);
    free(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(spectrum_of_two_sines),
        cmocka_unit_test(numbers_report_every_field),
        cmocka_unit_test(channels_rows_and_series),
        cmocka_unit_test(buffer_grows_past_first_block),
    };
    return cmocka_run_group_tests_name("api/session_json", tests, NULL, NULL);
}
