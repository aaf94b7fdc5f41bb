/*
 * test_config_fuzz.c — regression tests for the findings of the adversarial
 * config sweep (tests/fuzz/config_fuzz.py, run under ASan/UBSan): configs the
 * parameter table accepts must either run to the end with finite channels or
 * fail with an error code and the JSON Pointer of the field to change. Each
 * case is one finding: the config that crashed, hung, produced NaN or failed
 * without naming a field, and what it must do now.
 */
#include "test_util.h"

#include <math.h>
#include <string.h>

#include "api/config_json.h"
#include "sim/tanksim.h"

/* Every sample row finite (the rule: no silent NaN). */
static int rows_finite(void *ud, long index, double t, const double *v, int n)
{
    (void)index;
    int *bad = ud;
    if (!isfinite(t)) *bad = 1;
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i])) *bad = 1;
    return 0;
}

/* Load the JSON document, build, reset and advance the model to t_end.
 * Returns the first failing call's code (err filled); *nonfinite set when a row
 * held NaN or Inf. */
static ts_rc run_doc(const char *json, double t_end, ts_err *err, int *nonfinite)
{
    json_error_t je;
    json_t *doc = json_loads(json, 0, &je);
    if (!doc) fail_msg("bad test JSON: %s", je.text);
    ts_config c;
    ts_rc rc = tsa_config_load(doc, &c, NULL, NULL, err);
    json_decref(doc);
    *nonfinite = 0;
    if (rc != TS_OK) return rc;
    ts_model *m = ts_model_make(&c, err);
    if (!m) return err->code;
    ts_data *d = ts_data_make(m, err);
    rc = d ? ts_reset(m, d, err) : err->code;
    if (rc == TS_OK) {
        rows_finite(nonfinite, 0, 0.0, ts_latest(d), ts_model_nchannel(m));
        rc = ts_advance(m, d, t_end, rows_finite, nonfinite, err);
    }
    ts_data_free(d);
    ts_model_free(m);
    return rc;
}

static void expect_ok(const char *json, double t_end)
{
    ts_err err;
    int nonfinite;
    ts_rc rc = run_doc(json, t_end, &err, &nonfinite);
    if (rc != TS_OK) fail_msg("%s: %s: %s (%s)", json, err.pointer, err.msg, ts_rc_name(rc));
    if (nonfinite) fail_msg("%s: NaN/Inf in the samples", json);
}

static void expect_field_error(const char *json, double t_end, const char *pointer)
{
    ts_err err;
    int nonfinite;
    ts_rc rc = run_doc(json, t_end, &err, &nonfinite);
    if (rc == TS_OK) fail_msg("%s: ran (nonfinite=%d), want an error at %s", json, nonfinite, pointer);
    if (strcmp(err.pointer, pointer) != 0)
        fail_msg("%s: error at '%s' (%s), want %s", json, err.pointer, err.msg, pointer);
    assert_true(strlen(err.msg) > 0);
}

/* Finding: /engine/ca_step = 0.1 rad (in range) on the crank-angle powertrain
 * diverged with the pointer of the whole section; the adaptive step cannot go
 * below ca_step / 4, so the error must name ca_step. */
static void coarse_ca_step_names_the_field(void **state)
{
    (void)state;
    expect_field_error("{\"preset\":\"accel-pointmass-conventional\",\"run\":{\"duration\":0.05},"
                       "\"engine\":{\"ca_step\":0.1}}",
                       0.05, "/engine/ca_step");
    /* session 24: the message also says which state left its domain (the same
     * words for an intercooler passage too wide for the step) */
    static const char *const doc[] = {
        "{\"preset\":\"accel-pointmass-conventional\",\"run\":{\"duration\":0.05},"
        "\"engine\":{\"ca_step\":0.1}}",
        "{\"preset\":\"accel-pointmass-conventional\",\"run\":{\"duration\":0.05},"
        "\"engine\":{\"ic_cda\":0.1}}"};
    for (int i = 0; i < 2; i++) {
        ts_err err;
        int nonfinite;
        assert_int_equal(run_doc(doc[i], 0.05, &err, &nonfinite), TS_ERR_DIVERGED);
        if (!strstr(err.msg, "(must be ") ||
            (!strstr(err.msg, ": cylinder ") && !strstr(err.msg, ": bank ")))
            fail_msg("%s: %s", doc[i], err.msg);
    }
}

/* Finding (session 24 probe, fixed in session 25): the mean-value engine's
 * divergence said only "engine state left its domain" at /engine. A wide
 * intercooler passage (in range) empties the intercooler faster than the
 * fidelity's fixed step: the message names the volume and the fields that
 * set how fast it fills and empties. */
static void mean_value_divergence_names_the_volume(void **state)
{
    (void)state;
    /* each volume too small or too open for the fixed step is the one named (the
     * review found a tiny intake manifold reported as the intercooler: by the
     * step's end NaN had spread through every volume; the RK4 stages are read) */
    static const char *const field[] = {"\"ic_cda\":0.1", "\"intake_volume\":1e-4",
                                        "\"exhaust_volume\":1e-4"};
    static const char *const named[] = {": bank 1 intercooler gas mass -",
                                        ": bank 1 intake manifold gas mass -",
                                        ": bank 1 exhaust manifold gas mass -"};
    for (int i = 0; i < 3; i++) {
        char doc[256];
        snprintf(doc, sizeof doc,
                 "{\"preset\":\"accel-pointmass-conventional\",\"run\":{\"duration\":0.05},"
                 "\"engine\":{\"fidelity\":\"mean_value\",%s}}",
                 field[i]);
        ts_err err;
        int nonfinite;
        assert_int_equal(run_doc(doc, 0.05, &err, &nonfinite), TS_ERR_DIVERGED);
        assert_string_equal(err.pointer, "/engine");
        if (!strstr(err.msg, named[i]) || !strstr(err.msg, "/engine/ic_volume") ||
            !strstr(err.msg, "/engine/ic_cda"))
            fail_msg("%s: %s", doc, err.msg);
    }
}

/* Finding: a section given as a scalar ({"run": 3}) replaced the whole section and was
 * reported as "/run/max_step: missing (no default in the data files either)"; the
 * error must name the section and say an object is expected. */
static void section_not_object_names_the_section(void **state)
{
    (void)state;
    const char *docs[] = {"{\"run\": 3}", "{\"preset\":\"m1\",\"track\": [1]}",
                          "{\"engine\": null}", "{\"vehicle\": \"heavy\"}"};
    const char *ptrs[] = {"/run", "/track", "/engine", "/vehicle"};
    for (int i = 0; i < 4; i++) {
        ts_err err;
        int nonfinite;
        assert_int_equal(run_doc(docs[i], 0.0, &err, &nonfinite), TS_ERR_PARAM);
        assert_string_equal(err.pointer, ptrs[i]);
        assert_non_null(strstr(err.msg, "object expected"));
    }
}

/* Finding: /coupling/lead below /coupling/leader_step was refused by data_init, which
 * leaked its 808-byte run record (LeakSanitizer under make asan). */
static void coupled_data_init_failure_does_not_leak(void **state)
{
    (void)state;
    expect_field_error("{\"preset\":\"bump-coupled-rack90\",\"run\":{\"duration\":0.01},"
                       "\"coupling\":{\"lead\":1e-5,\"leader_step\":0.1,\"follower_step\":0.1}}",
                       0.01, "/coupling/lead");
}

/* Finding: /terrain/profile_csv = /dev/zero never returned (the reader grew its buffer
 * until memory ran out); a directory read as an empty profile. Non-regular files are
 * refused with the field's pointer. */
static void profile_csv_must_be_a_regular_file(void **state)
{
    (void)state;
    expect_field_error("{\"preset\":\"bump-prescribed-static\",\"run\":{\"duration\":0.01},"
                       "\"terrain\":{\"kind\":\"profile\",\"profile_csv\":\"/dev/zero\"}}",
                       0.01, "/terrain/profile_csv");
    expect_field_error("{\"preset\":\"bump-prescribed-static\",\"run\":{\"duration\":0.01},"
                       "\"terrain\":{\"kind\":\"profile\",\"profile_csv\":\"/tmp\"}}",
                       0.01, "/terrain/profile_csv");
}

/* Findings: sprocket, rollers and idler all at x = 0 gave element lengths of NaN
 * ("/span/length: span length must be > 0, got -nan", not a config field); seven road
 * wheels at one x sent the static equilibrium into 40 Newton steps on NaN. The layout
 * check names the body's field. */
static void degenerate_layout_names_the_field(void **state)
{
    (void)state;
    expect_field_error("{\"preset\":\"bump-prescribed-coupled\",\"run\":{\"duration\":0.01},"
                       "\"vehicle\":{\"sprocket_x\":0,\"rear_roller_x\":0,"
                       "\"front_roller_x\":0,\"idler_x\":0}}",
                       0.01, "/vehicle/idler_x");
    expect_field_error("{\"preset\":\"bump-prescribed-static\",\"run\":{\"duration\":0.01},"
                       "\"vehicle\":{\"road_wheel_x\":[2,2,2,2,2,2,2]}}",
                       0.01, "/vehicle/road_wheel_x");
    /* the shipped layout still passes */
    expect_ok("{\"preset\":\"bump-prescribed-static\",\"run\":{\"duration\":0.01}}", 0.01);
}

/* Findings (session 24 probe): layouts out of the circuit's order were accepted and
 * ran to nonsense (CG at x = 12 m: hull pitched 100 degrees, 6.5 m underground; sprocket
 * ahead of the idler; road-wheel hubs above the sprocket). Each is refused naming the
 * field (vehicle_layout.c); the shipped layout passes (above), and so do a sprocket or
 * idler as low as the hubs (the model runs them; a review of the first version, which refused
 * them). */
static void circuit_out_of_order_names_the_field(void **state)
{
    (void)state;
    static const struct {
        const char *vehicle, *pointer;
    } cases[] = {
        {"\"cg_x\":12", "/vehicle/cg_x"},
        {"\"cg_x\":-2", "/vehicle/cg_x"},
        {"\"sprocket_x\":12", "/vehicle/sprocket_x"},
        {"\"idler_x\":-2", "/vehicle/idler_x"},
        {"\"road_wheel_z\":2.0", "/vehicle/road_wheel_z"},
        {"\"front_roller_x\":1.0", "/vehicle/front_roller_x"},
        {"\"road_wheel_z\":0.9", "/vehicle/road_wheel_z"},
        {"\"road_wheel_x\":[5.15,4.425,2.975,3.7,2.25,1.525,0.8]", "/vehicle/road_wheel_x"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char json[256];
        snprintf(json, sizeof json,
                 "{\"preset\":\"bump-prescribed-static\",\"run\":{\"duration\":0.01},"
                 "\"terrain\":{\"kind\":\"flat\"},\"vehicle\":{%s}}",
                 cases[i].vehicle);
        expect_field_error(json, 0.01, cases[i].pointer);
    }
    static const char *const low[] = {"\"idler_z\":0.41", "\"sprocket_z\":0.41",
                                      "\"sprocket_z\":0.38,\"sprocket_radius\":0.25"};
    for (size_t i = 0; i < sizeof low / sizeof low[0]; i++) {
        char json[256];
        snprintf(json, sizeof json,
                 "{\"preset\":\"bump-prescribed-static\",\"run\":{\"duration\":0.01},"
                 "\"terrain\":{\"kind\":\"flat\"},\"vehicle\":{%s}}",
                 low[i]);
        expect_ok(json, 0.01);
    }
}

/* Finding (session 24 probe): a foundation of 2e7 N/m and stiffer (range up to 1e10), a
 * track of zero thickness or 0.05-m road wheels (all in range) failed the static
 * equilibrium with "singular Jacobian (check the layout)": Newton's start ignored the
 * wheels' design height over the ground (2.5 mm in the M1 data) and began with every
 * wheel off it. A start on the ground is tried after the first (vehicle_model.c
 * eq_start). */
static void equilibrium_found_for_stiff_ground_and_other_wheels(void **state)
{
    (void)state;
    static const char *const vehicle[] = {"\"foundation_stiffness\":2e7",
                                          "\"foundation_stiffness\":1e9", "\"track_thickness\":0",
                                          "\"road_wheel_radius\":0.05"};
    for (size_t i = 0; i < sizeof vehicle / sizeof vehicle[0]; i++) {
        char json[256];
        snprintf(json, sizeof json,
                 "{\"preset\":\"bump-prescribed-static\",\"run\":{\"duration\":0.01},"
                 "\"terrain\":{\"kind\":\"flat\"},\"vehicle\":{%s}}",
                 vehicle[i]);
        expect_ok(json, 0.01);
    }
}

/* Finding: /run/max_step = 1e-300 (in [0, 1]) made CVODE fail at t = 0 with h = 4e-306
 * and no field named; the row is now TS_PT_DOUBLE_OFF: 0 (no cap) or [1e-6, 1] s. */
static void tiny_max_step_is_refused(void **state)
{
    (void)state;
    expect_field_error("{\"preset\":\"pointmass-prescribed\",\"run\":{\"duration\":0.01,"
                       "\"max_step\":1e-300}}",
                       0.01, "/run/max_step");
    expect_ok("{\"preset\":\"pointmass-prescribed\",\"run\":{\"duration\":0.01,"
              "\"max_step\":1e-6}}",
              0.01);
    expect_ok("{\"preset\":\"pointmass-prescribed\",\"run\":{\"duration\":0.01,"
              "\"max_step\":0}}",
              0.01);
    /* session-24 probe: a cap that cannot reach the next sample within the vehicle
     * integrator's 500,000 steps per sample (1e-6 s at 1 Hz) was accepted and failed
     * with CV_TOO_MUCH_WORK at t = 0.5 s after minutes; it is refused at the field */
    expect_field_error("{\"preset\":\"bump-prescribed-static\",\"run\":{\"duration\":1,"
                       "\"sample_rate\":1,\"max_step\":1e-6}}",
                       1, "/run/max_step");
    expect_ok("{\"preset\":\"bump-prescribed-static\",\"run\":{\"duration\":0.01,"
              "\"max_step\":1e-6}}",
              0.01);
    /* the schema says the same: 0 (off) or [1e-6, 1] s (TS_PT_DOUBLE_OFF) */
    json_t *schema = tsa_config_schema();
    json_t *ms = json_object_get(
        json_object_get(json_object_get(json_object_get(schema, "properties"), "run"),
                        "properties"),
        "max_step");
    json_t *any = json_object_get(ms, "anyOf");
    assert_int_equal(json_array_size(any), 2);
    assert_int_equal(json_integer_value(json_object_get(json_array_get(any, 0), "const")), 0);
    assert_true(json_real_value(json_object_get(json_array_get(any, 1), "minimum")) == 1e-6);
    json_decref(schema);
}

/* Finding (session 24 probe): /driveline/engine_macro_step = 1e-12 (in [0, 0.01]) ran the
 * co-simulation loop ~1e9 times per sample with no sample callback in between, so neither
 * SIGTERM nor Ctrl-C stopped `tanksim run`; below ~1e-16 s it could not advance t at all.
 * The row is TS_PT_DOUBLE_OFF now: 0 (the RK4) or [1e-5, 0.01] s. */
static void tiny_engine_macro_step_is_refused(void **state)
{
    (void)state;
    expect_field_error("{\"preset\":\"accel-pointmass-conventional\",\"run\":{\"duration\":0.01},"
                       "\"driveline\":{\"engine_macro_step\":1e-12}}",
                       0.01, "/driveline/engine_macro_step");
    expect_ok("{\"preset\":\"accel-pointmass-conventional\",\"run\":{\"duration\":0.01},"
              "\"driveline\":{\"engine_macro_step\":1e-5}}",
              0.01);
}

/* Finding (session 24 probe): /driveline/ambient_temperature = 220 K (then in range) failed the
 * crank-angle launch at 0.03 s blaming /engine/ca_step; the gas-property fits start at 300 K
 * and the engine left its domain at 222 K. The range starts at 240 K now, and 240 K runs. */
static void cold_ambient_is_refused_by_its_field(void **state)
{
    (void)state;
    expect_field_error("{\"preset\":\"accel-pointmass-conventional\",\"run\":{\"duration\":0.05},"
                       "\"driveline\":{\"ambient_temperature\":220}}",
                       0.05, "/driveline/ambient_temperature");
    expect_ok("{\"preset\":\"accel-pointmass-conventional\",\"run\":{\"duration\":0.05},"
              "\"driveline\":{\"ambient_temperature\":240}}",
              0.05);
}

/* Finding: fidelity transverse with n_trans = 0 was refused at /track/n_long, a count
 * that fidelity does not read; the error names n_trans now (n_long for the others). */
static void missing_modes_name_the_count_read(void **state)
{
    (void)state;
    expect_field_error("{\"preset\":\"bump-prescribed-static\",\"run\":{\"duration\":0.01},"
                       "\"track\":{\"fidelity\":\"transverse\",\"n_long\":16,\"n_trans\":0}}",
                       0.01, "/track/n_trans");
    expect_field_error("{\"preset\":\"bump-prescribed-static\",\"run\":{\"duration\":0.01},"
                       "\"track\":{\"fidelity\":\"longitudinal\",\"n_long\":0,\"n_trans\":16}}",
                       0.01, "/track/n_long");
}

/* Finding: /engine/cp_air with its four (in-range) coefficients reversed gave cp below
 * the gas constant, so cv < 0, and CVODE failed at t = 0 (h = 8e-17) naming no field.
 * The polynomial is checked for cv > 0 from 200 to 3000 K. */
static void cp_below_gas_constant_names_the_field(void **state)
{
    (void)state;
    expect_field_error("{\"preset\":\"bump-coupled-rack90\",\"run\":{\"duration\":0.01},"
                       "\"engine\":{\"cp_air\":[-7.66,-17.11,228.53,939.43]}}",
                       0.01, "/engine/cp_air");
    expect_field_error("{\"preset\":\"engine-map-conventional\",\"run\":{\"duration\":0.01},"
                       "\"engine\":{\"cp_burned\":[100,0,0,0]}}",
                       0.01, "/engine/cp_burned");
}

/* Finding: /track/tension = 100 N (its minimum) on a dynamic-track vehicle was refused
 * as "/span/tension: shallow-sag condition violated", the pointer of an internal
 * parameter struct; the error names /track/tension now. */
static void span_errors_name_the_track_field(void **state)
{
    (void)state;
    expect_field_error("{\"preset\":\"bump-prescribed-coupled\",\"run\":{\"duration\":0.01},"
                       "\"track\":{\"tension\":100}}",
                       0.01, "/track/tension");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(coarse_ca_step_names_the_field),
        cmocka_unit_test(mean_value_divergence_names_the_volume),
        cmocka_unit_test(section_not_object_names_the_section),
        cmocka_unit_test(coupled_data_init_failure_does_not_leak),
        cmocka_unit_test(profile_csv_must_be_a_regular_file),
        cmocka_unit_test(degenerate_layout_names_the_field),
        cmocka_unit_test(circuit_out_of_order_names_the_field),
        cmocka_unit_test(equilibrium_found_for_stiff_ground_and_other_wheels),
        cmocka_unit_test(tiny_max_step_is_refused),
        cmocka_unit_test(tiny_engine_macro_step_is_refused),
        cmocka_unit_test(cold_ambient_is_refused_by_its_field),
        cmocka_unit_test(missing_modes_name_the_count_read),
        cmocka_unit_test(cp_below_gas_constant_names_the_field),
        cmocka_unit_test(span_errors_name_the_track_field),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
