/*
 * test_png_io.c — PNG encoding is lossless and compresses (png_io.h contract).
 */
#include "test_util.h"

#include <stdlib.h>
#include <string.h>

#include "render/png_io.h"

static void round_trip_is_lossless(void **state)
{
    (void)state;
    int w = 97, h = 61;
    unsigned char *img = malloc((size_t)w * h * 4);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            unsigned char *p = img + ((size_t)y * w + x) * 4;
            p[0] = (unsigned char)(x * 2);
            p[1] = (unsigned char)(y * 4);
            p[2] = (unsigned char)((x + y) & 0xff);
            p[3] = 255;
        }
    for (int f = 0; f <= 4; f++) {
        tsr_png_opts o = {2, f};
        unsigned char *png = NULL, *back = NULL;
        size_t len = 0;
        int bw, bh;
        ts_err err;
        assert_int_equal(tsr_png_encode(img, w, h, (size_t)w * 4, &o, &png, &len, &err), TS_OK);
        assert_true(len > 8 && memcmp(png, "\x89PNG\r\n\x1a\n", 8) == 0);
        assert_true(len < (size_t)w * h * 4); /* smooth gradients compress */
        assert_int_equal(tsr_png_decode(png, len, &back, &bw, &bh, &err), TS_OK);
        assert_int_equal(bw, w);
        assert_int_equal(bh, h);
        assert_memory_equal(back, img, (size_t)w * h * 4);
        free(png);
        free(back);
    }
    free(img);
}

static void bad_arguments_are_errors(void **state)
{
    (void)state;
    unsigned char px[4] = {0};
    unsigned char *png = NULL;
    size_t len;
    ts_err err;
    tsr_png_opts o = {12, 0};
    assert_int_equal(tsr_png_encode(px, 1, 1, 4, &o, &png, &len, &err), TS_ERR_PARAM);
    assert_int_equal(tsr_png_encode(px, 0, 1, 4, NULL, &png, &len, &err), TS_ERR_PARAM);
    unsigned char *rgba;
    int w, h;
    assert_int_equal(tsr_png_decode((const unsigned char *)"not a png", 9, &rgba, &w, &h, &err),
                     TS_ERR_PARAM);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(round_trip_is_lossless),
        cmocka_unit_test(bad_arguments_are_errors),
    };
    return cmocka_run_group_tests_name("render/png_io", tests, NULL, NULL);
}
