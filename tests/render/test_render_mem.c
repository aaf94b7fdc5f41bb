/*
 * test_render_mem.c — the renderer's memory behaviour over many frames: 100
 * frames through every path (lit / ids, side / three-quarter, antialias,
 * size changes, PNG) run clean under `make asan` (AddressSanitizer and
 * LeakSanitizer fail the program on any error or leak of ours), and 1000
 * frames leave the resident set size flat in the normal build.
 */
#include "test_util.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "render/m1_fixture.h"
#include "render/render.h"

#if defined(__SANITIZE_ADDRESS__)
#define UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define UNDER_ASAN 1
#endif
#endif
#ifndef UNDER_ASAN
#define UNDER_ASAN 0
#endif
#if defined(__SANITIZE_THREAD__)
#define UNDER_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define UNDER_TSAN 1
#endif
#endif
#ifndef UNDER_TSAN
#define UNDER_TSAN 0
#endif

static long rss_bytes(void)
{
    long pages_total = 0, pages_rss = 0;
    FILE *f = fopen("/proc/self/statm", "r");
    if (!f) return -1;
    if (fscanf(f, "%ld %ld", &pages_total, &pages_rss) != 2) pages_rss = -1;
    fclose(f);
    return pages_rss < 0 ? -1 : pages_rss * sysconf(_SC_PAGESIZE);
}

/* Frame i of a run over the bump, cycling through the view options. */
static ts_rc frame(tsr_ctx *c, m1_state *s, int i, int small, size_t *bytes)
{
    m1_pose(s, 4.0 + 0.05 * (i % 200), 0.01 * i, 2.0);
    m1_span_mode(s, 1 + i % 3, 0.01);
    tsr_view v;
    tsr_view_default(&v);
    v.width = small ? 160 + 16 * (i % 3) : 320 + 32 * (i % 3); /* size changes too */
    v.height = small ? 90 : 180;
    v.kind = i % 4 == 3 ? TSR_VIEW_THREE_QUARTER : TSR_VIEW_SIDE;
    v.shading = i % 5 == 4 ? TSR_SHADE_IDS : TSR_SHADE_LIT;
    v.antialias = i % 7 == 6;
    v.color_by_tension = i % 2;
    v.exaggeration = 1 + i % 10;
    snprintf(v.text, sizeof v.text, "frame %d", i);
    unsigned char *png = NULL;
    size_t len = 0;
    ts_err err;
    ts_rc rc = tsr_render_png(c, &s->g, &v, NULL, &png, &len, &err);
    free(png);
    *bytes += len;
    return rc;
}

/* EVIDENCE: ASan/LSan report (make asan) — 100 frames and two context
 * lifetimes without an invalid access or a leak; every frame succeeds. */
static void hundred_frames_clean(void **state)
{
    (void)state;
    static m1_state s;
    m1_set_terrain(&s.g, -60, 100, 10.0, 0.3048, 7.62);
    size_t bytes = 0;
    for (int round = 0; round < 2; round++) {
        ts_err err;
        tsr_ctx *c = tsr_ctx_make(&err);
        assert_non_null(c);
        for (int i = 0; i < 50; i++) assert_int_equal(frame(c, &s, 50 * round + i, 0, &bytes), TS_OK);
        tsr_ctx_free(c);
    }
    assert_true(bytes > 100 * 1000);
}

/* EVIDENCE: /proc/self/statm — after a 50-frame warm-up, 1000 more frames
 * grow the resident set by less than 4 MiB (a leak of one small PNG per frame,
 * ~10 kB, would add ~10 MiB). Skipped under ASan, whose quarantine holds freed
 * memory on purpose, and under TSan, whose shadow memory and access history
 * grow with the run (make tsan measured 194 -> 226 MiB here; 1000 frames
 * passed once and failed once there). */
static void rss_flat_over_1000_frames(void **state)
{
    (void)state;
    if (UNDER_ASAN) {
        print_message("skipped under AddressSanitizer (quarantine grows the RSS)\n");
        skip();
    }
    if (UNDER_TSAN) {
        print_message("skipped under ThreadSanitizer (shadow memory grows the RSS)\n");
        skip();
    }
    static m1_state s;
    m1_set_terrain(&s.g, -60, 100, 10.0, 0.3048, 7.62);
    ts_err err;
    tsr_ctx *c = tsr_ctx_make(&err);
    assert_non_null(c);
    size_t bytes = 0;
    for (int i = 0; i < 50; i++) assert_int_equal(frame(c, &s, i, 1, &bytes), TS_OK);
    long before = rss_bytes();
    for (int i = 50; i < 1050; i++) assert_int_equal(frame(c, &s, i, 1, &bytes), TS_OK);
    long after = rss_bytes();
    print_message("RSS %.1f MiB -> %.1f MiB over 1000 frames\n", before / 1048576.0,
                  after / 1048576.0);
    assert_true(before > 0 && after > 0);
    assert_true(after - before < 4L * 1024 * 1024);
    tsr_ctx_free(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(hundred_frames_clean),
        cmocka_unit_test(rss_flat_over_1000_frames),
    };
    return cmocka_run_group_tests_name("render/render_mem", tests, NULL, NULL);
}
