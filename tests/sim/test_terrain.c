/*
 * test_terrain.c — terrain profiles (terrain.h): the shipped apg4-synth course
 * file, inline bump lists, user CSV profiles, and their errors.
 */
#include "test_util.h"

#include <stdlib.h>
#include <string.h>

#include "sim/tanksim.h"
#include "sim/terrain.h"

static ts_terrain_config base(int kind)
{
    ts_terrain_config c;
    memset(&c, 0, sizeof c);
    c.kind = kind;
    snprintf(c.course, sizeof c.course, "apg4-synth");
    snprintf(c.course_dir, sizeof c.course_dir, "sim/data/terrain");
    return c;
}

/* EVIDENCE: paper Fig. 8 / II.D as sim/data/terrain/apg4-synth.txt lays it
 * out: 26 bumps, the first 1 ft x 25 ft at 50 ft [P II.D: the large obstacle], the last
 * 0.25 ft x 2 ft [P II.D: the small obstacle] at 490.5 ft, the train's
 * 10-ft pitch [C Figs. 13a-b] flat between its bumps, course 500 ft.
 * 1-cos shape: full height at the bump middle, zero and flat at its ends.
 * Exact to the file's 4 decimals. */
static void apg4_synth_course_has_the_papers_obstacles(void **state)
{
    (void)state;
    ts_terrain_config c = base(TS_TERRAIN_BUMPS);
    ts_err err;
    ts_terrain *t = ts_terrain_make(&c, &err);
    assert_non_null(t);
    assert_close(ts_terrain_length(t), 152.4, 1e-9, 0);
    double ft = 0.3048, slope;
    assert_close(ts_terrain_height(t, (50 + 12.5) * ft, &slope), 1.0 * ft, 1e-4, 0);
    assert_close(slope, 0, 0, 1e-9);
    assert_close(ts_terrain_height(t, 50 * ft, NULL), 0, 0, 1e-12);
    assert_close(ts_terrain_height(t, 40 * ft, NULL), 0, 0, 0);
    assert_close(ts_terrain_height(t, (490.5 + 1) * ft, NULL), 0.25 * ft, 1e-3, 0);
    assert_close(ts_terrain_height(t, (480.5 + 1) * ft, NULL), 0.25 * ft, 1e-3, 0);
    assert_close(ts_terrain_height(t, (480.5 + 6) * ft, NULL), 0, 0, 0);
    assert_close(ts_terrain_height(t, 495 * ft, NULL), 0, 0, 0);
    /* quarter point of the large bump: h/2, slope pi h / l */
    assert_close(ts_terrain_height(t, (50 + 6.25) * ft, &slope), 0.5 * ft, 1e-4, 0);
    assert_close(slope, 3.14159265 * 1.0 / 25.0, 1e-4, 0);
    /* count the bumps: 26 local maxima */
    int n = 0;
    double prev = 0, prev2 = 0;
    for (double x = 0; x < 152.4; x += 0.005) {
        double z = ts_terrain_height(t, x, NULL);
        if (prev > prev2 && prev >= z && prev > 0.01) n++;
        prev2 = prev;
        prev = z;
    }
    assert_int_equal(n, 26);
    ts_terrain_free(t);
}

/* The profile terrain of a CSV file tests/out/NAME holding text, or NULL
 * (err says why) when ts_terrain_make refuses it. */
static ts_terrain *profile_make(const char *name, const char *text, ts_err *err)
{
    char buf[64];
    const char *path = test_out_path(buf, sizeof buf, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    ts_terrain_config p = base(TS_TERRAIN_PROFILE);
    snprintf(p.profile_csv, sizeof p.profile_csv, "%s", path);
    return ts_terrain_make(&p, err);
}

/* EVIDENCE: the inline list replaces the file; a CSV profile is joined by
 * straight lines and continued flat. Exact. */
static void inline_bumps_and_csv_profile(void **state)
{
    (void)state;
    ts_terrain_config c = base(TS_TERRAIN_BUMPS);
    c.bump_n = c.bump_height_n = c.bump_length_n = 1;
    c.bump_start[0] = 2.0;
    c.bump_height[0] = 0.2;
    c.bump_length[0] = 1.0;
    ts_err err;
    ts_terrain *t = ts_terrain_make(&c, &err);
    assert_non_null(t);
    assert_close(ts_terrain_height(t, 2.5, NULL), 0.2, 1e-12, 0);
    assert_close(ts_terrain_height(t, 15.24 + 3.81, NULL), 0, 0, 0);
    ts_terrain_free(t);

    t = profile_make("terrain_profile.csv", "distance_m,height_m\n0,0\n10,1\n20,0.5\n", &err);
    assert_non_null(t);
    double slope;
    assert_close(ts_terrain_height(t, 5, &slope), 0.5, 1e-12, 0);
    assert_close(slope, 0.1, 1e-12, 0);
    assert_close(ts_terrain_height(t, 15, NULL), 0.75, 1e-12, 0);
    assert_close(ts_terrain_height(t, 30, NULL), 0.5, 1e-12, 0);
    assert_close(ts_terrain_height(t, -3, NULL), 0, 0, 0);
    ts_terrain_free(t);
}

/* EVIDENCE: linear interpolation between CSV points, continued flat at the
 * first and the last point's height on either side (terrain.h), and a
 * point's slope that of the segment starting there (find_le: the last
 * distance <= x); an inline bump list's course ends where its last bump
 * does (start + length), also when that bump abuts the one before. Exact. */
static void profile_edges_and_inline_course_length(void **state)
{
    (void)state;
    ts_err err;
    ts_terrain *t = profile_make("terrain_profile_edges.csv", "5,0.3\n10,0.8\n20,0.3\n", &err);
    assert_non_null(t);
    double slope = -1;
    /* before the first point: its height, flat */
    assert_close(ts_terrain_height(t, 0, &slope), 0.3, 1e-12, 0);
    assert_close(slope, 0, 0, 0);
    /* on the middle point: its height, the slope of the segment 10-20 m */
    assert_close(ts_terrain_height(t, 10, &slope), 0.8, 1e-12, 0);
    assert_close(slope, -0.05, 1e-12, 0);
    assert_close(ts_terrain_height(t, 25, &slope), 0.3, 1e-12, 0);
    assert_close(slope, 0, 0, 0);
    ts_terrain_free(t);

    ts_terrain_config c = base(TS_TERRAIN_BUMPS);
    c.bump_n = c.bump_height_n = c.bump_length_n = 2;
    c.bump_start[0] = 2.0;
    c.bump_height[0] = 0.1;
    c.bump_length[0] = 1.0;
    c.bump_start[1] = 3.0; /* starts where the first ends (allowed) */
    c.bump_height[1] = 0.2;
    c.bump_length[1] = 3.0;
    t = ts_terrain_make(&c, &err);
    assert_non_null(t);
    assert_close(ts_terrain_length(t), 6.0, 1e-12, 0);
    ts_terrain_free(t);
}

static void errors_name_the_field(void **state)
{
    (void)state;
    ts_terrain_config c = base(TS_TERRAIN_BUMPS);
    snprintf(c.course, sizeof c.course, "no-such-course");
    ts_err err;
    assert_null(ts_terrain_make(&c, &err));
    assert_int_equal(err.code, TS_ERR_NOTFOUND);
    assert_string_equal(err.pointer, "/terrain/course");
    ts_terrain_config p = base(TS_TERRAIN_PROFILE);
    assert_null(ts_terrain_make(&p, &err));
    assert_string_equal(err.pointer, "/terrain/profile_csv");
    double s[4], h[4], l[4], len;
    int n;
    assert_int_equal(ts_terrain_parse_course("length 10\n1 0.1\n", s, h, l, 4, &n, &len, &err),
                     TS_ERR_PARAM);
    assert_int_equal(
        ts_terrain_parse_course("# c\nlength 10\n1 0.1 2\n2 0.1 1\n", s, h, l, 4, &n, &len, &err),
        TS_ERR_PARAM); /* overlap */
    assert_int_equal(
        ts_terrain_parse_course("length 10\n1 0.1 2 # a\n4 0.2 1\n", s, h, l, 4, &n, &len, &err),
        TS_OK);
    assert_int_equal(n, 2);
    assert_close(len, 10, 0, 0);
}

/* A profile file holding text: ts_terrain_make's result code; *last: the
 * profile's length (its last distance) [m], 0 when refused. */
static int profile_from(const char *text, int *last, ts_err *err)
{
    ts_terrain *t = profile_make("terrain_profile_check.csv", text, err);
    *last = 0;
    if (!t) return err->code;
    *last = (int)ts_terrain_length(t);
    ts_terrain_free(t);
    return TS_OK;
}

/* EVIDENCE: a file the model cannot use is refused at its line, naming the
 * field (before, "nan", "inf", a third column, trailing text and heights of
 * 1e6 m were read, and the run ended with garbage: wheel loads of 1 MN); CR
 * and CRLF line ends are line ends (a CR-only file was one row: flat ground);
 * hexadecimal ("0x10", which strtod reads as 16) is not a distance (session-24
 * probe: it was read). */
static void terrain_files_are_read_strictly(void **state)
{
    (void)state;
    ts_err err;
    int length_m; /* the profile's last distance [m] */
    const char *bad[] = {"x,z\n0,0\n7,0\n7.5,nan\n200,0\n",
                         "0,inf\n10,0\n",
                         "0,0,5\n10,0.3\n",
                         "0,0\n10,0.3abc\n",
                         "0,0\n10,1e6\n",
                         "0,0\n1e300,0\n",
                         "0x10,0\n20,0\n",
                         "0,0\n20,0x1p-2\n"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal(profile_from(bad[i], &length_m, &err), TS_ERR_PARAM);
        assert_string_equal(err.pointer, "/terrain/profile_csv");
        assert_non_null(strstr(err.msg, "line "));
    }
    assert_int_equal(profile_from("x,z\n0,0\n7,0\n7.5,nan\n", &length_m, &err), TS_ERR_PARAM);
    assert_non_null(strstr(err.msg, "line 4")); /* the line of the nan, not the next */
    assert_int_equal(profile_from("0,0\r10,0.3\r200,0.3\r", &length_m, &err), TS_OK);
    assert_int_equal(length_m, 200);
    assert_int_equal(profile_from("x,z\r\n0,0\r\n10 0.3\r\n150, 0.3 # end\r\n", &length_m, &err),
                     TS_OK);
    assert_int_equal(length_m, 150);

    double s[4], h[4], l[4], len;
    int n;
    const char *bad_course[] = {"length 10\n1 nan 2\n", "length 10\n1 0.1 2 3\n",
                                "length 10\n1 2.5 2\n", "length inf\n", "length 10\n1 0.1 0\n"};
    for (size_t i = 0; i < sizeof bad_course / sizeof bad_course[0]; i++) {
        assert_int_equal(ts_terrain_parse_course(bad_course[i], s, h, l, 4, &n, &len, &err),
                         TS_ERR_PARAM);
        assert_string_equal(err.pointer, "/terrain/course");
    }
    assert_int_equal(
        ts_terrain_parse_course("length 10\r1 0.1 2\r4 0.2 1\r", s, h, l, 4, &n, &len, &err),
        TS_OK);
    assert_int_equal(n, 2);

    /* heights and lengths without starts: refused, not replaced by the course */
    ts_terrain_config c = base(TS_TERRAIN_BUMPS);
    c.bump_height_n = c.bump_length_n = 1;
    c.bump_height[0] = 0.2;
    c.bump_length[0] = 2.0;
    assert_null(ts_terrain_make(&c, &err));
    assert_string_equal(err.pointer, "/terrain/bump_height");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(apg4_synth_course_has_the_papers_obstacles),
        cmocka_unit_test(inline_bumps_and_csv_profile),
        cmocka_unit_test(profile_edges_and_inline_course_length),
        cmocka_unit_test(errors_name_the_field),
        cmocka_unit_test(terrain_files_are_read_strictly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
