/*
 * test_apng.c — APNG assembly (apng.h) against the APNG specification (W3C
 * PNG 3rd edition, acTL/fcTL/fdAT): chunk order and sequence numbers, CRCs,
 * the frame count and delays, every frame's data being its own PNG's image
 * data, and the default image being frame 0 for readers that do not know APNG.
 */
#include "test_util.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "render/apng.h"
#include "render/png_io.h"

static uint32_t rd32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* Concatenated IDAT payloads (the zlib stream) of a PNG, in a malloc'd buffer. */
static unsigned char *idat_stream(const unsigned char *png, size_t len, size_t *n)
{
    unsigned char *out = malloc(len);
    *n = 0;
    for (size_t pos = 8; pos + 12 <= len; pos += 12 + rd32(png + pos))
        if (memcmp(png + pos + 4, "IDAT", 4) == 0) {
            memcpy(out + *n, png + pos + 8, rd32(png + pos));
            *n += rd32(png + pos);
        }
    return out;
}

static unsigned char *frame(int w, int h, unsigned char r, size_t *len)
{
    unsigned char *px = malloc((size_t)w * h * 4);
    for (int i = 0; i < w * h; i++) {
        px[4 * i] = r;
        px[4 * i + 1] = (unsigned char)i;
        px[4 * i + 2] = 7;
        px[4 * i + 3] = 255;
    }
    unsigned char *png;
    ts_err err;
    assert_int_equal(tsr_png_encode(px, w, h, (size_t)w * 4, NULL, &png, len, &err), TS_OK);
    free(px);
    return png;
}

static void three_frames_make_a_valid_apng(void **state)
{
    (void)state;
    size_t lens[3];
    unsigned char *f[3] = {frame(16, 8, 10, &lens[0]), frame(16, 8, 120, &lens[1]),
                           frame(16, 8, 250, &lens[2])};
    unsigned char *apng;
    size_t n;
    ts_err err;
    assert_int_equal(tsr_apng_assemble((const unsigned char *const *)f, lens, 3, 1, 25, &apng, &n,
                                       &err),
                     TS_OK);
    /* walk the chunks: order, sequence numbers, CRCs */
    char order[128] = "";
    unsigned char *data_of[3] = {malloc(n), malloc(n), malloc(n)}; /* IDAT / fdAT payloads */
    size_t ndata[3] = {0, 0, 0};
    uint32_t expect_seq = 0;
    int frames = 0;
    size_t pos = 8;
    while (pos < n) {
        uint32_t len = rd32(apng + pos);
        const unsigned char *type = apng + pos + 4, *data = apng + pos + 8;
        uLong crc = crc32(crc32(0L, type, 4), data, len);
        assert_int_equal((uint32_t)crc, rd32(data + len));
        char t[5] = {0};
        memcpy(t, type, 4);
        if (!strcmp(t, "acTL")) {
            assert_int_equal(rd32(data), 3); /* num_frames */
            assert_int_equal(rd32(data + 4), 0); /* loop forever */
        }
        if (!strcmp(t, "fcTL") || !strcmp(t, "fdAT")) assert_int_equal(rd32(data), expect_seq++);
        if (!strcmp(t, "IDAT") || !strcmp(t, "fdAT")) {
            int skip = t[0] == 'f' ? 4 : 0; /* fdAT: sequence number, then the frame data */
            assert_true(frames >= 1 && frames <= 3);
            memcpy(data_of[frames - 1] + ndata[frames - 1], data + skip, len - skip);
            ndata[frames - 1] += len - skip;
        }
        if (!strcmp(t, "fcTL")) {
            frames++;
            assert_int_equal(rd32(data + 4), 16);
            assert_int_equal(rd32(data + 8), 8);
            assert_int_equal(data[20] << 8 | data[21], 1);  /* delay 1/25 s */
            assert_int_equal(data[22] << 8 | data[23], 25);
        }
        if (strlen(order) + 6 < sizeof order) {
            strcat(order, order[0] ? " " : "");
            strcat(order, t);
        }
        pos += 12 + len;
    }
    assert_int_equal(pos, n);
    assert_int_equal(frames, 3);
    assert_string_equal(order, "IHDR acTL fcTL IDAT fcTL fdAT fcTL fdAT IEND");
    /* each frame carries exactly its own PNG's image data */
    for (int i = 0; i < 3; i++) {
        size_t m;
        unsigned char *want = idat_stream(f[i], lens[i], &m);
        assert_int_equal(ndata[i], m);
        assert_memory_equal(data_of[i], want, m);
        free(want);
        free(data_of[i]);
    }
    /* a reader without APNG support sees frame 0 */
    unsigned char *a, *b;
    int w, h;
    assert_int_equal(tsr_png_decode(apng, n, &a, &w, &h, &err), TS_OK);
    assert_int_equal(tsr_png_decode(f[0], lens[0], &b, &w, &h, &err), TS_OK);
    assert_memory_equal(a, b, 16 * 8 * 4);
    free(a);
    free(b);
    free(apng);
    for (int i = 0; i < 3; i++) free(f[i]);
}

static void frames_of_different_size_are_rejected(void **state)
{
    (void)state;
    size_t lens[2];
    unsigned char *f[2] = {frame(16, 8, 1, &lens[0]), frame(8, 8, 1, &lens[1])};
    unsigned char *apng = NULL;
    size_t n;
    ts_err err;
    assert_int_equal(tsr_apng_assemble((const unsigned char *const *)f, lens, 2, 1, 25, &apng, &n,
                                       &err),
                     TS_ERR_PARAM);
    assert_null(apng);
    unsigned char junk[20] = "not a png at all...";
    const unsigned char *pj = junk;
    size_t lj = sizeof junk;
    assert_int_equal(tsr_apng_assemble(&pj, &lj, 1, 1, 25, &apng, &n, &err), TS_ERR_PARAM);
    free(f[0]);
    free(f[1]);
}

/* Assemble n frames (delay 1/den s); the result code. */
static ts_rc assemble(unsigned char **f, size_t *lens, int n, unsigned den)
{
    unsigned char *apng = NULL;
    size_t len;
    ts_err err;
    ts_rc rc =
        tsr_apng_assemble((const unsigned char *const *)f, lens, n, 1, den, &apng, &len, &err);
    if (rc != TS_OK) assert_null(apng);
    free(apng);
    return rc;
}

/* EVIDENCE: APNG spec — every frame shares frame 0's IHDR (not only its width
 * and height: bit depth and colour type too, since fdAT data is decoded with
 * IHDR's format), fcTL's delay fields are 16-bit, and a frame must be a whole
 * PNG (IHDR before IEND; a chunk cannot run past the end of its file). An RGB
 * frame of the same size after an RGBA one, a delay denominator of 65536, a
 * PNG without IHDR and one whose IEND declares 1000 bytes it does not have are
 * refused; before, each was assembled (the survivors of the session-28 pass). */
static void frames_must_share_the_format_and_be_whole(void **state)
{
    (void)state;
    size_t lens[2];
    unsigned char *f[2] = {frame(16, 8, 1, &lens[0]), NULL};
    unsigned char px[16 * 8 * 4] = {0};
    ts_err err;
    assert_int_equal(tsr_png_encode_opaque(px, 16, 8, 16 * 4, NULL, &f[1], &lens[1], &err), TS_OK);
    assert_int_equal(assemble(f, lens, 2, 25), TS_ERR_PARAM); /* RGBA then RGB */
    free(f[1]);
    f[1] = frame(16, 8, 2, &lens[1]);
    assert_int_equal(assemble(f, lens, 2, 25), TS_OK);
    assert_int_equal(assemble(f, lens, 2, 0xffff), TS_OK);
    assert_int_equal(assemble(f, lens, 2, 0x10000), TS_ERR_PARAM);

    /* signature + IEND alone */
    unsigned char no_ihdr[8 + 12];
    memcpy(no_ihdr, f[0], 8);
    memcpy(no_ihdr + 8, "\0\0\0\0IEND\xae\x42\x60\x82", 12);
    unsigned char *g[1] = {no_ihdr};
    size_t glen[1] = {sizeof no_ihdr};
    assert_int_equal(assemble(g, glen, 1, 25), TS_ERR_PARAM);

    /* frame 0's chunks up to its IEND, whose length then claims 1000 bytes */
    size_t iend = lens[0] - 12;
    assert_memory_equal(f[0] + iend + 4, "IEND", 4);
    unsigned char *cut = malloc(lens[0]);
    assert_non_null(cut);
    memcpy(cut, f[0], lens[0]);
    cut[iend + 2] = 0x03, cut[iend + 3] = 0xe8;
    g[0] = cut;
    glen[0] = lens[0];
    assert_int_equal(assemble(g, glen, 1, 25), TS_ERR_PARAM);
    free(cut);
    free(f[0]);
    free(f[1]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(three_frames_make_a_valid_apng),
        cmocka_unit_test(frames_of_different_size_are_rejected),
        cmocka_unit_test(frames_must_share_the_format_and_be_whole),
    };
    return cmocka_run_group_tests_name("render/apng", tests, NULL, NULL);
}
