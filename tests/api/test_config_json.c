/*
 * test_config_json.c — JSON configs through the parameter table: defaults
 * cover every field, presets and overrides merge, and every kind of bad input
 * is reported with the JSON Pointer of the field (config_json.h contract).
 */
#include "test_util.h"

#include <string.h>

#include "api/config_json.h"
#include "api/problem.h"
#include "sim/tanksim.h"

static void defaults_cover_every_field(void **state)
{
    (void)state;
    ts_config c;
    ts_err err;
    json_t *errors = json_array();
    ts_rc rc = tsa_config_load(NULL, &c, NULL, errors, &err);
    if (rc != TS_OK) fail_msg("defaults incomplete: %s", err.msg);
    assert_int_equal(json_array_size(errors), 0);
    assert_int_equal(ts_param_validate(&c, &err), TS_OK);
    assert_close(c.track.tension, 66700, 0, 0);
    assert_int_equal(c.driveline.gear_ratio_n, 4);
    json_decref(errors);
}

static void preset_then_overrides(void **state)
{
    (void)state;
    ts_config c;
    ts_err err;
    json_t *doc = json_pack("{s:s,s:{s:f}}", "preset", "pointmass-prescribed", "drive", "torque",
                            1234.5);
    json_t *resolved = NULL;
    assert_int_equal(tsa_config_load(doc, &c, &resolved, NULL, &err), TS_OK);
    assert_int_equal(c.run.kind, TS_RUN_POINTMASS);
    assert_close(c.run.duration, 30, 0, 0);      /* from the preset */
    assert_close(c.drive.torque, 1234.5, 0, 0);  /* from the override */
    assert_close(c.vehicle.mass, 58967, 0, 0);   /* from the defaults */
    assert_null(json_object_get(resolved, "preset"));
    /* round trip: config -> JSON -> config */
    json_t *back = tsa_config_to_json(&c);
    ts_config c2;
    assert_int_equal(tsa_config_read(back, &c2, NULL, &err), TS_OK);
    assert_memory_equal(&c.drive, &c2.drive, sizeof c.drive);
    json_decref(back);
    json_decref(resolved);
    json_decref(doc);
}

static void expect_error(const char *json, const char *pointer, const char *words)
{
    json_error_t je;
    json_t *doc = json_loads(json, 0, &je);
    assert_non_null(doc);
    ts_config c;
    ts_err err;
    json_t *errors = json_array();
    ts_rc rc = tsa_config_load(doc, &c, NULL, errors, &err);
    assert_int_not_equal(rc, TS_OK);
    int found = 0;
    size_t i;
    json_t *e;
    json_array_foreach(errors, i, e)
    {
        const char *p = json_string_value(json_object_get(e, "pointer"));
        const char *msg = json_string_value(json_object_get(e, "message"));
        if (strcmp(p, pointer) == 0 && strstr(msg, words)) found = 1;
    }
    if (!found) fail_msg("%s: no error at %s mentioning '%s' (first: %s)", json, pointer, words,
                         err.msg);
    json_decref(errors);
    json_decref(doc);
}

static void bad_input_names_the_field(void **state)
{
    (void)state;
    expect_error("{\"track\":{\"ea\":\"stiff\"}}", "/track/ea", "number expected, got string");
    expect_error("{\"track\":{\"n_trans\":99}}", "/track/n_trans", "got 99");
    expect_error("{\"track\":{\"n_trans\":1.5}}", "/track/n_trans", "integer expected");
    expect_error("{\"track\":{\"eaa\":1}}", "/track/eaa", "unknown field");
    expect_error("{\"trak\":{}}", "/trak", "unknown section");
    /* "commands" is skipped inside presets only (an api/ mutation survivor
     * dropped it from a user's document too) */
    expect_error("{\"commands\":[\"run\"]}", "/commands", "unknown section");
    expect_error("{\"track\":{\"fidelity\":\"wobbly\"}}", "/track/fidelity", "coupled");
    expect_error("{\"preset\":\"no-such-preset\"}", "/preset", "no preset");
    expect_error("{\"preset\":7}", "/preset", "string expected");
    expect_error("{\"driveline\":{\"gear_ratio\":[3,\"x\"]}}", "/driveline/gear_ratio/1",
                 "number expected");
    expect_error("{\"vehicle\":{\"mass\":-5}}", "/vehicle/mass", "got -5");
    expect_error("{\"track\":{\"translation_terms\":1}}", "/track/translation_terms", "boolean");
    /* RFC 6901: a key's '/' is ~1 and '~' is ~0 ("/run/a/b" named a field b of a section a) */
    expect_error("{\"run\":{\"a/b\":1}}", "/run/a~1b", "unknown field");
    expect_error("{\"x~y\":{}}", "/x~0y", "unknown section");
    char ptr[8];
    assert_string_equal(tsa_pointer_join(ptr, sizeof ptr, "/ab", "c/d"), "/ab/c~1");
    assert_string_equal(tsa_pointer_join(ptr, sizeof ptr, "", "~/"), "/~0~1");
    /* several errors at once */
    json_t *doc = json_loads("{\"track\":{\"ea\":-1,\"tension\":-1}}", 0, NULL);
    json_t *errors = json_array();
    ts_config c;
    ts_err err;
    assert_int_not_equal(tsa_config_load(doc, &c, NULL, errors, &err), TS_OK);
    assert_int_equal(json_array_size(errors), 2);
    json_decref(errors);
    json_decref(doc);
}

static void schema_comes_from_the_table(void **state)
{
    (void)state;
    json_t *s = tsa_config_schema();
    json_t *ea = json_object_get(
        json_object_get(json_object_get(json_object_get(s, "properties"), "track"), "properties"),
        "ea");
    assert_non_null(ea);
    assert_string_equal(json_string_value(json_object_get(ea, "x-unit")), "N");
    /* comment keys ("_...") are allowed at every level, as tsa_config_load reads them */
    assert_non_null(json_object_get(json_object_get(s, "patternProperties"), "^_"));
    assert_non_null(json_object_get(
        json_object_get(json_object_get(json_object_get(s, "properties"), "run"),
                        "patternProperties"),
        "^_"));
    assert_close(json_number_value(json_object_get(ea, "default")), 3e7, 0, 0);
    assert_close(json_number_value(json_object_get(ea, "minimum")),
                 ts_param_find("/track/ea")->min, 0, 0);
    /* a string's maxLength is what the loader takes: its buffer less the NUL */
    json_t *course = json_object_get(
        json_object_get(json_object_get(json_object_get(s, "properties"), "terrain"), "properties"),
        "course");
    assert_int_equal(json_integer_value(json_object_get(course, "maxLength")),
                     ts_param_find("/terrain/course")->capacity - 1);
    /* in bytes: maxLength counts characters, exact for ASCII only (session 32) */
    assert_int_equal(json_integer_value(json_object_get(course, "x-max-bytes")),
                     ts_param_find("/terrain/course")->capacity - 1);
    /* the shipped courses as examples (the dashboard offers them), not an enum */
    json_t *ex = json_object_get(course, "examples");
    assert_true(json_array_size(ex) >= 1);
    assert_string_equal(json_string_value(json_array_get(ex, 0)), "apg4-synth");
    assert_null(json_object_get(course, "enum"));
    json_decref(s);
    /* a number below the double range is refused, not read as 0 */
    double x = -1;
    assert_int_equal(tsa_parse_number("1e-400", 0, 1, &x), -1);
    assert_int_equal(tsa_parse_number("1e-300", 0, 1, &x), 0);
    json_t *list = tsa_preset_list();
    assert_true(json_array_size(list) >= 1);
    json_decref(list);
}

static void problem_mapping(void **state)
{
    (void)state;
    assert_int_equal(tsa_http_status(TS_ERR_PARAM), 400);
    assert_int_equal(tsa_http_status(TS_ERR_NOTFOUND), 404);
    assert_int_equal(tsa_http_status(TS_ERR_LIMIT), 429);
    /* a config the model cannot solve is the request's content, not a server fault */
    assert_int_equal(tsa_http_status(TS_ERR_SOLVER), 422);
    assert_int_equal(tsa_http_status(TS_ERR_DIVERGED), 422);
    /* every code's status and type (only server tests saw most of them) */
    static const struct {
        ts_rc rc;
        int status;
        const char *type;
    } table[] = {
        {TS_ERR_RANGE, 400, "/problems/invalid-config"},
        {TS_ERR_NOMEM, 503, "/problems/out-of-memory"},
        {TS_ERR_IO, 500, "/problems/io"},
        {TS_ERR_STATE, 409, "/problems/conflict"},
        {TS_ERR_UNSUPPORTED, 422, "/problems/unsupported"},
        {TS_ERR_CANCELLED, 409, "/problems/cancelled"},
        {TS_ERR_INTERNAL, 500, "/problems/internal"},
    };
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
        assert_int_equal(tsa_http_status(table[i].rc), table[i].status);
        assert_string_equal(tsa_problem_type(table[i].rc), table[i].type);
    }
    /* request bytes that are not UTF-8 become U+FFFD, so the answer is built:
     * lead bytes past F4, overlongs (of 2, 3 and 4 bytes: a mutation survivor
     * passed E0 80 AF through), surrogates, code points past U+10FFFF */
    static const char *const bad[] = {"\xF5\x80\x80\x80", "\xF8\x80",         "\xC0\x80",
                                      "\xED\xA0\x80",     "\xF4\x90\x80\x80", "\xE0\x80\xAF",
                                      "\xF0\x80\x80\xAF"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char detail[64];
        snprintf(detail, sizeof detail, "no preset named '%s'", bad[i]);
        json_t *q = tsa_problem(404, "/problems/not-found", "Not found", detail, NULL);
        assert_non_null(q);
        const char *d = json_string_value(json_object_get(q, "detail"));
        assert_non_null(strstr(d, "\xEF\xBF\xBD")); /* U+FFFD */
        assert_null(strchr(d, bad[i][0]));
        json_decref(q);
    }
    ts_err err;
    ts_err_set(&err, TS_ERR_RANGE, "/track/ea", "/track/ea: too small");
    json_t *p = tsa_problem_from_err(&err, NULL);
    assert_int_equal(json_integer_value(json_object_get(p, "status")), 400);
    json_t *e0 = json_array_get(json_object_get(p, "errors"), 0);
    assert_string_equal(json_string_value(json_object_get(e0, "pointer")), "/track/ea");
    json_decref(p);
}

/* The shipped course comes from the embedded store, not the working directory
 * (parameters: apg4-synth, 26 bumps, the first 1 ft x 25 ft at 50 ft), with
 * the default /terrain/course_dir (a relative path that need not exist where
 * the program runs); a course_dir of the user's own is left for the disk, even
 * for a shipped name (session 20: it was silently replaced). */
static void shipped_course_comes_from_the_store(void **state)
{
    (void)state;
    ts_config c;
    ts_err err;
    json_t *doc = json_pack("{s:{s:s,s:s}}", "terrain", "kind", "bumps", "course", "apg4-synth");
    assert_int_equal(tsa_config_load(doc, &c, NULL, NULL, &err), TS_OK);
    assert_string_equal(c.terrain.course_dir, "sim/data/terrain");
    assert_int_equal(c.terrain.bump_n, 26);
    assert_close(c.terrain.bump_start[0], 50 * 0.3048, 1e-3, 0);
    assert_close(c.terrain.bump_height[0], 0.3048, 1e-2, 0);
    assert_close(c.terrain.bump_length[0], 25 * 0.3048, 1e-3, 0);
    json_decref(doc);
    doc = json_pack("{s:{s:s,s:s,s:s}}", "terrain", "kind", "bumps", "course", "apg4-synth",
                    "course_dir", "/nonexistent");
    assert_int_equal(tsa_config_load(doc, &c, NULL, NULL, &err), TS_OK);
    assert_int_equal(c.terrain.bump_n, 0); /* read (and refused) when the model is built */
    json_decref(doc);
}

/* Load {"SECTION": {"FIELD": v}} (v stolen) through the table: the result
 * code, the config in *c, the first error's pointer in ptr (may be "").
 * section/field split the pointer "/SECTION/FIELD". */
static ts_rc load_one(const char *pointer, json_t *v, ts_config *c, char *ptr, size_t n)
{
    char sec[64];
    const char *slash = strchr(pointer + 1, '/');
    snprintf(sec, sizeof sec, "%.*s", (int)(slash - pointer - 1), pointer + 1);
    json_t *doc = json_pack("{s:{s:o}}", sec, slash + 1, v);
    json_t *errors = json_array();
    ts_err err;
    ts_rc rc = tsa_config_load(doc, c, NULL, errors, &err);
    json_t *e0 = json_array_get(errors, 0);
    snprintf(ptr, n, "%s", e0 ? json_string_value(json_object_get(e0, "pointer")) : "");
    json_decref(errors);
    json_decref(doc);
    return rc;
}

/* Every field of the table read the way its row says (session-26 mutation
 * pass over api/: each of these survived): a boolean set to the opposite of
 * its default is read as set (false is not true); a number beyond its max is
 * refused naming it, also for the 0-means-off fields; a string of its whole
 * buffer size (no room for the NUL) is refused naming it. */
static void every_field_reads_as_its_row_says(void **state)
{
    (void)state;
    ts_config def, c;
    ts_err err;
    assert_int_equal(tsa_config_load(NULL, &def, NULL, NULL, &err), TS_OK);
    char ptr[128];
    int nbool = 0, nnum = 0, nstr = 0;
    for (int s = 0; s < ts_param_nsections(); s++) {
        const ts_param_section *sec = ts_param_section_at(s);
        for (int i = 0; i < sec->nparams; i++) {
            const ts_param *p = &sec->params[i];
            if (p->type == TS_PT_BOOL) {
                int want = !ts_param_get_int(&def, p->offset);
                ts_rc rc = load_one(p->pointer, json_boolean(want), &c, ptr, sizeof ptr);
                if (rc != TS_OK) continue; /* a combination the config refuses */
                if (ts_param_get_int(&c, p->offset) != want)
                    fail_msg("%s set to %s read as %d", p->pointer, want ? "true" : "false",
                             ts_param_get_int(&c, p->offset));
                nbool++;
            } else if ((p->type == TS_PT_DOUBLE || p->type == TS_PT_DOUBLE_OFF) && p->max > 0) {
                double over = p->max * 2 + 1;
                if (load_one(p->pointer, json_real(over), &c, ptr, sizeof ptr) == TS_OK ||
                    strcmp(ptr, p->pointer) != 0)
                    fail_msg("%s = %g (max %g) not refused at its pointer (got '%s')", p->pointer,
                             over, p->max, ptr);
                nnum++;
            } else if (p->type == TS_PT_STRING && !p->enum_names) {
                char text[4096];
                assert_true(p->capacity < (int)sizeof text);
                memset(text, 'a', (size_t)p->capacity);
                text[p->capacity] = '\0';
                if (load_one(p->pointer, json_string(text), &c, ptr, sizeof ptr) == TS_OK ||
                    strcmp(ptr, p->pointer) != 0)
                    fail_msg("%s: %d characters (the whole buffer) accepted", p->pointer,
                             p->capacity);
                nstr++;
            }
        }
    }
    printf("# %d booleans, %d ranged numbers, %d strings\n", nbool, nnum, nstr);
    assert_true(nbool >= 5 && nnum >= 100 && nstr >= 3);
}

/* An inline bump list is the course, even when a shipped course is named
 * too (fill_course: a survivor of the session-26 mutation pass let the
 * shipped course replace it). */
static void inline_bumps_win_over_a_named_course(void **state)
{
    (void)state;
    ts_config c;
    ts_err err;
    json_t *doc =
        json_pack("{s:{s:s,s:s,s:[f],s:[f],s:[f]}}", "terrain", "kind", "bumps", "course",
                  "apg4-synth", "bump_start", 20.0, "bump_height", 0.1, "bump_length", 2.0);
    assert_int_equal(tsa_config_load(doc, &c, NULL, NULL, &err), TS_OK);
    assert_int_equal(c.terrain.bump_n, 1);
    assert_close(c.terrain.bump_start[0], 20.0, 0, 0);
    assert_close(c.terrain.bump_height[0], 0.1, 0, 0);
    json_decref(doc);
}

/* Survivors of a mutation pass over api/ and the daemon's routing, below. */

/* A section sent as a scalar or an array is one error naming the section
 * (merge_document), not that error followed by a "missing" for every field
 * of the section the scalar replaced (a survivor listed 20-odd bogus errors). */
static void section_not_object_is_one_error(void **state)
{
    (void)state;
    const char *docs[] = {"{\"vehicle\": 5}", "{\"preset\":\"m1\",\"track\":[1]}"};
    const char *ptrs[] = {"/vehicle", "/track"};
    for (int i = 0; i < 2; i++) {
        json_t *doc = json_loads(docs[i], 0, NULL);
        json_t *errors = json_array();
        ts_config c;
        ts_err err;
        assert_int_equal(tsa_config_load(doc, &c, NULL, errors, &err), TS_ERR_PARAM);
        assert_string_equal(err.pointer, ptrs[i]);
        if (json_array_size(errors) != 1)
            fail_msg("%s: %zu errors, want 1 (the section's)", docs[i], json_array_size(errors));
        json_t *e0 = json_array_get(errors, 0);
        assert_string_equal(json_string_value(json_object_get(e0, "pointer")), ptrs[i]);
        json_decref(errors);
        json_decref(doc);
    }
}

/* A value outside its allowed set is TS_ERR_RANGE (problem title "Value out
 * of range") alike for a scalar, an array's element and an enum's unknown
 * word; a wrong type stays TS_ERR_PARAM ("Invalid request"). */
static void range_errors_say_out_of_range(void **state)
{
    (void)state;
    static const struct {
        const char *json, *pointer;
        ts_rc code;
    } cases[] = {
        {"{\"vehicle\":{\"mass\":-5}}", "/vehicle/mass", TS_ERR_RANGE},
        {"{\"driveline\":{\"gear_ratio\":[3,-1]}}", "/driveline/gear_ratio/1", TS_ERR_RANGE},
        {"{\"track\":{\"fidelity\":\"wobbly\"}}", "/track/fidelity", TS_ERR_RANGE},
        {"{\"track\":{\"fidelity\":3}}", "/track/fidelity", TS_ERR_PARAM},
        {"{\"driveline\":{\"gear_ratio\":[3,\"x\"]}}", "/driveline/gear_ratio/1", TS_ERR_PARAM},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        json_t *doc = json_loads(cases[i].json, 0, NULL);
        ts_config c;
        ts_err err;
        ts_rc rc = tsa_config_load(doc, &c, NULL, NULL, &err);
        if (rc != cases[i].code || strcmp(err.pointer, cases[i].pointer) != 0)
            fail_msg("%s: code %d at '%s', want %d at %s", cases[i].json, rc, err.pointer,
                     cases[i].code, cases[i].pointer);
        json_t *p = tsa_problem_from_err(&err, NULL);
        assert_string_equal(json_string_value(json_object_get(p, "title")),
                            cases[i].code == TS_ERR_RANGE ? "Value out of range"
                                                          : "Invalid request");
        json_decref(p);
        json_decref(doc);
    }
}

/* A partial inline bump list (starts only) is the user's and is left for
 * ts_terrain_make to refuse, not replaced by the named shipped course (a
 * survivor that tested the heights and lengths only took the 26 bumps). */
static void partial_inline_bumps_are_not_replaced_by_the_course(void **state)
{
    (void)state;
    ts_config c;
    ts_err err;
    json_t *doc = json_pack("{s:{s:s,s:s,s:[f,f]}}", "terrain", "kind", "bumps", "course",
                            "apg4-synth", "bump_start", 20.0, 40.0);
    assert_int_equal(tsa_config_load(doc, &c, NULL, NULL, &err), TS_OK);
    assert_int_equal(c.terrain.bump_n, 2);
    assert_int_equal(c.terrain.bump_height_n, 0);
    assert_int_equal(c.terrain.bump_length_n, 0);
    assert_close(c.terrain.bump_start[1], 40.0, 0, 0);
    json_decref(doc);
}

/* Comment keys inside a section of the request are dropped from the resolved
 * config (the one a session keeps and shows as "config"), as the data files'
 * are: a survivor merged {"vehicle": {"_why": ...}} into it. */
static void comment_keys_stay_out_of_the_resolved_config(void **state)
{
    (void)state;
    json_t *doc = json_loads("{\"preset\":\"m1\",\"_note\":\"x\","
                             "\"vehicle\":{\"_why\":\"heavier\",\"mass\":60000}}",
                             0, NULL);
    ts_err err;
    json_t *res = tsa_config_resolve(doc, &err);
    assert_non_null(res);
    json_t *veh = json_object_get(res, "vehicle");
    assert_close(json_number_value(json_object_get(veh, "mass")), 60000, 0, 0);
    assert_null(json_object_get(veh, "_why"));
    assert_null(json_object_get(res, "_note"));
    json_decref(res);
    json_decref(doc);
}

/* Query numbers and integers (tsa_parse_number/_integer: the daemon's
 * ?page_size=, ?every=, the CLI's --width) take both ends of their range: a
 * survivor refused GET /v1/sessions?page_size=1000, its documented maximum. */
static void query_ranges_are_closed(void **state)
{
    (void)state;
    long k = -1;
    assert_int_equal(tsa_parse_integer("1000", 1, 1000, &k), 0);
    assert_int_equal(k, 1000);
    assert_int_equal(tsa_parse_integer("1", 1, 1000, &k), 0);
    assert_int_equal(k, 1);
    assert_int_equal(tsa_parse_integer("1001", 1, 1000, &k), -1);
    assert_int_equal(tsa_parse_integer("0", 1, 1000, &k), -1);
    double x = -1;
    assert_int_equal(tsa_parse_number("1000", 0, 1000, &x), 0);
    assert_close(x, 1000, 0, 0);
    assert_int_equal(tsa_parse_number("0", 0, 1000, &x), 0);
    assert_int_equal(tsa_parse_number("1000.001", 0, 1000, &x), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(defaults_cover_every_field),
        cmocka_unit_test(preset_then_overrides),
        cmocka_unit_test(bad_input_names_the_field),
        cmocka_unit_test(schema_comes_from_the_table),
        cmocka_unit_test(problem_mapping),
        cmocka_unit_test(shipped_course_comes_from_the_store),
        cmocka_unit_test(every_field_reads_as_its_row_says),
        cmocka_unit_test(inline_bumps_win_over_a_named_course),
        cmocka_unit_test(section_not_object_is_one_error),
        cmocka_unit_test(range_errors_say_out_of_range),
        cmocka_unit_test(partial_inline_bumps_are_not_replaced_by_the_course),
        cmocka_unit_test(comment_keys_stay_out_of_the_resolved_config),
        cmocka_unit_test(query_ranges_are_closed),
    };
    return cmocka_run_group_tests_name("api/config_json", tests, NULL, NULL);
}
