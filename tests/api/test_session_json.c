/*
 * test_session_json.c — the daemon's JSON/text shapes (api/session_json.h) and
 * the amplitude spectrum (api/spectrum.h) without HTTP.
 */
#include "test_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "api/config_json.h"
#include "api/problem.h"
#include "api/session_json.h"
#include "api/spectrum.h"
#include "sim/tanksim.h"
#include "tests/sim/preset_config.h"

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
    assert_int_equal(tsa_amplitude_spectrum(x, n, fs, TS_FFT_MEAN, TS_FFT_RECT, f, a, &err), TS_OK);
    assert_close(f[1], 0.5, 1e-12, 0);
    assert_close(f[n / 2], 250.0, 1e-12, 0);
    assert_close(a[0], 0.0, 0, 1e-9);  /* mean removed */
    assert_close(a[10], 2.0, 1e-9, 0); /* 5 Hz */
    assert_close(a[85], 0.5, 1e-9, 0); /* 42.5 Hz */
    for (long k = 1; k <= n / 2; k++)
        if (k != 10 && k != 85) assert_close(a[k], 0.0, 0, 1e-9);
    /* without detrending the mean shows at DC */
    assert_int_equal(tsa_amplitude_spectrum(x, n, fs, TS_FFT_NONE, TS_FFT_RECT, f, a, &err), TS_OK);
    assert_close(a[0], 7.0, 1e-9, 0);
    assert_int_equal(tsa_amplitude_spectrum(x, 1, fs, TS_FFT_MEAN, TS_FFT_RECT, f, a, &err),
                     TS_ERR_PARAM);
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
    tsa_num_field f[] = {{"duration", 1, 0, 10, &d, NULL, "s"},
                         {"until", 0, 0, 10, &u, NULL, "s"},
                         {"rate", 1, 0, 1, &u, NULL, NULL}};
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
    /* the range is closed at both ends (a survivor of the session-26 mutation
     * pass excluded the max) */
    const char *edges = "{\"duration\": 10, \"until\": 0}";
    doc = tsa_parse_object(edges, strlen(edges), &err);
    assert_non_null(doc);
    assert_int_equal(tsa_read_numbers(doc, f, 2, NULL, &err), TS_OK);
    assert_close(d, 10, 0, 0);
    assert_close(u, 0, 0, 0);
    json_decref(doc);
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
    ts_channel store[16];
    tsa_channels cv;
    assert_int_equal(tsa_channels_from_model(&cv, store, 16, m, &err), TS_OK);
    assert_int_equal(cv.n, ts_model_nchannel(m));
    assert_close(cv.period, ts_model_sample_period(m), 0, 0);
    int idx[16], n;
    assert_int_equal(
        tsa_channel_select(&cv, "channels", "vehicle.speed,t,vehicle.speed", idx, 16, &n, &err),
        TS_OK);
    assert_int_equal(n, 2);
    assert_int_equal(idx[0], 0);
    assert_int_equal(idx[1], ts_model_channel_index(m, "vehicle.speed"));
    assert_int_equal(tsa_channel_select(&cv, "channels", "nope", idx, 16, &n, &err),
                     TS_ERR_NOTFOUND);
    assert_string_equal(err.pointer, "/channels");
    /* the error names the parameter the list came from (fft's single "channel") */
    assert_int_equal(tsa_channel_select(&cv, "channel", "nope", idx, 16, &n, &err),
                     TS_ERR_NOTFOUND);
    assert_string_equal(err.pointer, "/channel");
    assert_non_null(strstr(err.msg, "channel: no channel named 'nope'"));
    assert_int_equal(tsa_channel_select(&cv, "channels", NULL, idx, 16, &n, &err), TS_OK);
    assert_int_equal(n, ts_model_nchannel(m));

    const int nch = ts_model_nchannel(m);
    double rows[3 * 16];
    long index[3] = {4, 6, 8};
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < nch; c++)
            rows[r * nch + c] = r * 100 + c + 0.25;
    tsa_buf b = {0};
    int sel[2] = {0, 2};
    tsa_series_json(&b, "s1", &cv, sel, 2, index, rows, 3, 2, "10");
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

    tsa_csv_header(&b, &cv, sel, 2);
    tsa_csv_row(&b, rows + nch, sel, 2);
    char want[256];
    snprintf(want, sizeof want, "t [s],%s [%s]\n100.25,102.25\n", ts_model_channel(m, 2)->name,
             ts_model_channel(m, 2)->unit);
    assert_string_equal(b.p, want);
    tsa_buf_free(&b);

    tsa_row_json(&b, &cv, 6, rows + nch, sel, 2);
    j = json_loads(b.p, 0, &je);
    assert_non_null(j);
    assert_int_equal(json_integer_value(json_object_get(j, "index")), 6);
    assert_close(json_number_value(json_object_get(j, "t")), 100.25, 0, 0);
    assert_int_equal(json_object_size(json_object_get(j, "values")), 1);
    json_decref(j);
    tsa_buf_free(&b);
    ts_model_free(m);
}

/* A table that is not a model's (the daemon's stored channel list, channels.h):
 * every shape is built from the plain array alone, byte for byte as written
 * out here by hand (%.12g for time, %.9g otherwise, null or an empty CSV
 * field when not finite, names escaped as JSON strings). */
static void shapes_from_a_plain_channel_array(void **state)
{
    (void)state;
    const ts_channel v[] = {{"t", "s", "simulated time"},
                            {"hull.pitch", "rad", "nose-down positive"},
                            {"odd\"name\\", "1", ""}};
    const tsa_channels c = {v, 3, 0.01};
    ts_err err;
    int idx[8], n;
    assert_int_equal(tsa_channel_index(&c, "hull.pitch"), 1);
    assert_int_equal(tsa_channel_index(&c, "nope"), -1);
    assert_int_equal(
        tsa_channel_select(&c, "channels", "odd\"name\\,,hull.pitch", idx, 8, &n, &err), TS_OK);
    assert_int_equal(n, 3);
    assert_int_equal(idx[0], 0);
    assert_int_equal(idx[1], 2);
    assert_int_equal(idx[2], 1);
    assert_int_equal(tsa_channel_select(&c, "channels", "t,vehicle.speed", idx, 8, &n, &err),
                     TS_ERR_NOTFOUND);
    assert_string_equal(err.pointer, "/channels");
    assert_int_equal(tsa_channel_select(&c, "channels", "hull.pitch", idx, 1, &n, &err),
                     TS_ERR_LIMIT);
    assert_int_equal(tsa_channel_select(&c, "channels", "", idx, 8, &n, &err), TS_OK);
    assert_int_equal(n, 3);

    const double rows[] = {0.0, 0.125, 1.0 / 3.0, 0.01, NAN, -2.5e-7};
    const long index[] = {0, 1};
    const int sel[] = {0, 2, 1};
    tsa_buf b = {0};
    tsa_series_json(&b, "s\"1", &c, sel, 3, index, rows, 2, 1, NULL);
    assert_string_equal(b.p,
                        "{\"session\":\"s\\\"1\",\"sample_rate\":100,\"every\":1,\"count\":2,"
                        "\"index\":[0,1],\"channels\":["
                        "{\"name\":\"t\",\"unit\":\"s\",\"values\":[0,0.01]},"
                        "{\"name\":\"odd\\\"name\\\\\",\"unit\":\"1\",\"values\":[0.333333333,"
                        "-2.5e-07]},"
                        "{\"name\":\"hull.pitch\",\"unit\":\"rad\",\"values\":[0.125,null]}]}");
    tsa_buf_free(&b);

    tsa_csv_header(&b, &c, sel, 3);
    tsa_csv_row(&b, rows + 3, sel, 3);
    assert_string_equal(b.p, "t [s],odd\"name\\ [1],hull.pitch [rad]\n0.01,-2.5e-07,\n");
    tsa_buf_free(&b);

    tsa_row_json(&b, &c, 1, rows + 3, sel, 3);
    assert_string_equal(b.p, "{\"index\":1,\"t\":0.01,\"values\":{\"odd\\\"name\\\\\":-2.5e-07,"
                             "\"hull.pitch\":null}}");
    tsa_buf_free(&b);
    /* time to 12 digits in rows and series (a sample rate of 7 Hz: t = 1/7;
     * %.9g survived the session-26 mutation pass), other channels to 9 */
    const double row7[] = {1.0 / 7.0, 0.125, 1.0 / 3.0};
    tsa_row_json(&b, &c, 1, row7, sel, 1);
    assert_string_equal(b.p, "{\"index\":1,\"t\":0.142857142857,\"values\":{}}");
    tsa_buf_free(&b);
    tsa_series_json(&b, "s", &c, sel, 1, index, row7, 1, 1, NULL);
    assert_non_null(strstr(b.p, "\"values\":[0.142857142857]"));
    tsa_buf_free(&b);

    /* the session object of rows without a model: channels, latest and
     * sample_rate from the table, no kind or duration */
    tsa_session_view sv = {.id = "s1",
                           .status = "failed",
                           .ch = &c,
                           .latest = rows + 3,
                           .persisted = 2,
                           .index = 1,
                           .t = 0.01};
    json_t *o = tsa_session_json(&sv, 0);
    assert_non_null(o);
    assert_null(json_object_get(o, "kind"));
    assert_null(json_object_get(o, "duration"));
    assert_close(json_number_value(json_object_get(o, "sample_rate")), 100.0, 1e-15, 0);
    json_t *chs = json_object_get(o, "channels");
    assert_int_equal(json_array_size(chs), 3);
    json_t *c1 = json_array_get(chs, 1);
    assert_string_equal(json_string_value(json_object_get(c1, "name")), "hull.pitch");
    assert_string_equal(json_string_value(json_object_get(c1, "unit")), "rad");
    assert_string_equal(json_string_value(json_object_get(c1, "description")),
                        "nose-down positive");
    json_t *latest = json_object_get(o, "latest");
    assert_int_equal(json_object_size(latest), 3);
    assert_true(json_is_null(json_object_get(latest, "hull.pitch")));
    assert_close(json_number_value(json_object_get(latest, "odd\"name\\")), -2.5e-7, 0, 0);
    json_decref(o);
    sv.ch = NULL; /* rows that cannot be labelled: neither channels nor latest */
    o = tsa_session_json(&sv, 0);
    assert_null(json_object_get(o, "channels"));
    assert_null(json_object_get(o, "latest"));
    assert_null(json_object_get(o, "sample_rate"));
    json_decref(o);
}

/* A model's table that does not fit the caller's store is refused, not cut. */
static void model_table_larger_than_store_is_refused(void **state)
{
    (void)state;
    ts_model *m = pointmass();
    ts_err err;
    ts_channel store[2];
    tsa_channels cv = {store, 5, 1.0};
    assert_true(ts_model_nchannel(m) > 2);
    assert_int_equal(tsa_channels_from_model(&cv, store, 2, m, &err), TS_ERR_LIMIT);
    assert_null(cv.v);
    assert_int_equal(cv.n, 0);
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

/* The run figures of 2 s of the 21-DOF vehicle over the bump course (25
 * figures: more than the 4 given below). */
static ts_model *vehicle_rows(ts_rows *r)
{
    ts_config c = test_preset_config("bump-prescribed-static", NULL);
    c.run.duration = 2.0;
    return test_run_rows(&c, r);
}

/* No figure is dropped: ts_model_metrics says how many there are when out is
 * too small (the first max are the same), and tsa_model_metrics returns them
 * all whatever its first guess; no text fills its field (a description cut
 * at 159 characters went unseen); a figure the run did not reach is null. */
static void every_figure_is_kept(void **state)
{
    (void)state;
    ts_rows r;
    ts_model *m = vehicle_rows(&r);
    ts_metric few[4], all[64];
    int n = ts_model_metrics(m, r.v, r.n, all, 64);
    assert_true(n > 4 && n < 64);
    assert_int_equal(ts_model_metrics(m, r.v, r.n, few, 4), n);
    assert_int_equal(ts_model_metrics(m, r.v, r.n, NULL, 0), n);
    for (int i = 0; i < 4; i++) {
        assert_string_equal(few[i].name, all[i].name);
        assert_memory_equal(&few[i].value, &all[i].value, sizeof all[i].value);
    }
    ts_metric *mt;
    int k;
    ts_err err;
    assert_int_equal(tsa_model_metrics(m, r.v, r.n, &mt, &k, &err), TS_OK);
    assert_int_equal(k, n);
    for (int i = 0; i < n; i++) {
        assert_string_equal(mt[i].name, all[i].name);
        assert_string_equal(mt[i].description, all[i].description);
        assert_memory_equal(&mt[i].value, &all[i].value, sizeof all[i].value);
        assert_true(strlen(mt[i].name) < sizeof mt[i].name - 1);
        assert_true(strlen(mt[i].unit) < sizeof mt[i].unit - 1);
        assert_true(strlen(mt[i].description) < sizeof mt[i].description - 1);
    }
    mt[1].value = NAN;
    json_t *a = tsa_metrics_json(mt, k);
    assert_int_equal(json_array_size(a), (size_t)n);
    json_t *o = json_array_get(a, 1);
    assert_string_equal(json_string_value(json_object_get(o, "name")), all[1].name);
    assert_true(json_is_null(json_object_get(o, "value")));
    assert_true(json_real_value(json_object_get(json_array_get(a, 0), "value")) == all[0].value);
    json_decref(a);
    free(mt);
    /* no rows: no figures, and an array to free all the same */
    assert_int_equal(tsa_model_metrics(m, r.v, 0, &mt, &k, &err), TS_OK);
    assert_int_equal(k, 0);
    free(mt);
    ts_rows_free(&r);
    ts_model_free(m);
}

/* Survivors of a mutation pass over api/ and the daemon's routing. A body
 * number out of its range is TS_ERR_RANGE ("Value out of range"), a wrong
 * type TS_ERR_PARAM, as the config's fields are. A channel name of 128 bytes
 * (the buffer's size) is "too long" (400), not looked up past the buffer and
 * answered 404. The time column of a CSV row has the JSON series' 12 digits,
 * so that t = index / sample_rate round-trips (1/3 s at 3 Hz). */
static void ranges_names_and_time_digits(void **state)
{
    (void)state;
    ts_err err;
    double d = 0;
    tsa_num_field f[] = {{"duration", 1, 0, 10, &d, NULL, "s"}};
    json_t *doc = json_loads("{\"duration\": 11}", 0, NULL);
    assert_int_equal(tsa_read_numbers(doc, f, 1, NULL, &err), TS_ERR_RANGE);
    assert_string_equal(err.pointer, "/duration");
    assert_non_null(strstr(err.msg, "[0, 10] s expected, got 11")); /* the unit (review) */
    json_t *p = tsa_problem_from_err(&err, NULL);
    assert_string_equal(json_string_value(json_object_get(p, "title")), "Value out of range");
    json_decref(p);
    json_decref(doc);
    doc = json_loads("{\"duration\": \"1\"}", 0, NULL);
    assert_int_equal(tsa_read_numbers(doc, f, 1, NULL, &err), TS_ERR_PARAM);
    json_decref(doc);

    ts_model *m = pointmass();
    ts_channel store[16];
    tsa_channels cv;
    assert_int_equal(tsa_channels_from_model(&cv, store, 16, m, &err), TS_OK);
    int idx[16], n;
    char name[200];
    memset(name, 'a', 127);
    name[127] = '\0';
    assert_int_equal(tsa_channel_select(&cv, "channels", name, idx, 16, &n, &err), TS_ERR_NOTFOUND);
    memset(name, 'a', 128);
    name[128] = '\0';
    assert_int_equal(tsa_channel_select(&cv, "channels", name, idx, 16, &n, &err), TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/channels");
    assert_non_null(strstr(err.msg, "too long"));

    double row[16] = {1.0 / 3, 1.0 / 3};
    int sel[2] = {0, 1};
    tsa_buf b = {0};
    tsa_csv_row(&b, row, sel, 2);
    assert_string_equal(b.p, "0.333333333333,0.333333333\n");
    tsa_buf_free(&b);
    ts_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(spectrum_of_two_sines),
        cmocka_unit_test(numbers_report_every_field),
        cmocka_unit_test(channels_rows_and_series),
        cmocka_unit_test(shapes_from_a_plain_channel_array),
        cmocka_unit_test(model_table_larger_than_store_is_refused),
        cmocka_unit_test(buffer_grows_past_first_block),
        cmocka_unit_test(every_figure_is_kept),
        cmocka_unit_test(ranges_names_and_time_digits),
    };
    return cmocka_run_group_tests_name("api/session_json", tests, NULL, NULL);
}
