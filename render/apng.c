/*
 * apng.c — APNG assembly from encoded PNG frames (apng.h). The chunk layout is
 * length (4, big endian), type (4), data, CRC-32 over type and data (zlib's
 * crc32, the PNG CRC).
 */
#include "apng.h"

#include "bytebuf.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

static const unsigned char png_sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

static void be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

static uint32_t rd32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* One chunk; data2 (may be NULL) is appended after data (for fdAT's payload). */
static void chunk(tsr_bytebuf *b, const char *type, const unsigned char *data, size_t n,
                  const unsigned char *data2, size_t n2)
{
    unsigned char hdr[8];
    be32(hdr, (uint32_t)(n + n2));
    memcpy(hdr + 4, type, 4);
    tsr_bytebuf_put(b, hdr, 8);
    tsr_bytebuf_put(b, data, n);
    if (data2) tsr_bytebuf_put(b, data2, n2);
    uLong crc = crc32(0L, (const Bytef *)type, 4);
    if (n) crc = crc32(crc, data, (uInt)n); /* crc32(c, NULL, 0) would reset c */
    if (data2 && n2) crc = crc32(crc, data2, (uInt)n2);
    unsigned char c[4];
    be32(c, (uint32_t)crc);
    tsr_bytebuf_put(b, c, 4);
}

/* Walk the chunks of one PNG: *ihdr gets its IHDR data (13 bytes); every IDAT
 * payload is handed to emit. 0 on success, -1 when the PNG is malformed. */
typedef void (*idat_fn)(void *ud, const unsigned char *data, size_t n);
static int walk(const unsigned char *png, size_t len, const unsigned char **ihdr, idat_fn emit,
                void *ud)
{
    if (len < 8 || memcmp(png, png_sig, 8) != 0) return -1;
    size_t pos = 8;
    *ihdr = NULL;
    while (pos + 12 <= len) {
        uint32_t n = rd32(png + pos);
        const unsigned char *type = png + pos + 4, *data = png + pos + 8;
        if (n > len - pos - 12) return -1;
        if (memcmp(type, "IHDR", 4) == 0 && n == 13) *ihdr = data;
        else if (memcmp(type, "IDAT", 4) == 0) emit(ud, data, n);
        else if (memcmp(type, "IEND", 4) == 0) return *ihdr ? 0 : -1;
        pos += 12 + (size_t)n;
    }
    return -1;
}

typedef struct {
    tsr_bytebuf *b;
    uint32_t *seq;
    int as_fdat;
} frame_sink;

static void emit_data(void *ud, const unsigned char *data, size_t n)
{
    frame_sink *s = ud;
    if (!s->as_fdat) {
        chunk(s->b, "IDAT", data, n, NULL, 0);
        return;
    }
    unsigned char seq[4];
    be32(seq, (*s->seq)++);
    chunk(s->b, "fdAT", seq, 4, data, n);
}

static void count_only(void *ud, const unsigned char *data, size_t n)
{
    (void)ud;
    (void)data;
    (void)n;
}

ts_rc tsr_apng_assemble(const unsigned char *const *pngs, const size_t *lens, int n,
                        unsigned delay_num, unsigned delay_den, unsigned char **out,
                        size_t *out_len, ts_err *err)
{
    if (n < 1 || delay_num > 0xffff || delay_den > 0xffff)
        return ts_err_set(err, TS_ERR_PARAM, NULL, "apng: need >= 1 frame and 16-bit delays");
    const unsigned char *ihdr0;
    if (walk(pngs[0], lens[0], &ihdr0, count_only, NULL) != 0)
        return ts_err_set(err, TS_ERR_PARAM, NULL, "apng: frame 0 is not a PNG");
    for (int i = 1; i < n; i++) {
        const unsigned char *ih;
        if (walk(pngs[i], lens[i], &ih, count_only, NULL) != 0)
            return ts_err_set(err, TS_ERR_PARAM, NULL, "apng: frame %d is not a PNG", i);
        if (memcmp(ih, ihdr0, 13) != 0)
            return ts_err_set(err, TS_ERR_PARAM, NULL,
                              "apng: frame %d differs from frame 0 in size or format", i);
    }
    tsr_bytebuf b = {0};
    uint32_t seq = 0;
    tsr_bytebuf_put(&b, png_sig, 8);
    chunk(&b, "IHDR", ihdr0, 13, NULL, 0);
    unsigned char actl[8];
    be32(actl, (uint32_t)n); /* num_frames */
    be32(actl + 4, 0);       /* num_plays: 0 = loop forever */
    chunk(&b, "acTL", actl, 8, NULL, 0);
    for (int i = 0; i < n; i++) {
        unsigned char fctl[26];
        be32(fctl, seq++);
        memcpy(fctl + 4, ihdr0, 8); /* width, height: the whole canvas */
        be32(fctl + 12, 0);         /* x offset */
        be32(fctl + 16, 0);         /* y offset */
        fctl[20] = (unsigned char)(delay_num >> 8);
        fctl[21] = (unsigned char)delay_num;
        fctl[22] = (unsigned char)(delay_den >> 8);
        fctl[23] = (unsigned char)delay_den;
        fctl[24] = 0; /* dispose: none (every frame covers the canvas) */
        fctl[25] = 0; /* blend: source */
        chunk(&b, "fcTL", fctl, 26, NULL, 0);
        frame_sink s = {&b, &seq, i > 0};
        const unsigned char *ih;
        walk(pngs[i], lens[i], &ih, emit_data, &s);
    }
    chunk(&b, "IEND", NULL, 0, NULL, 0);
    if (b.oom) {
        free(b.p);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "apng: out of memory");
    }
    *out = b.p;
    *out_len = b.n;
    return TS_OK;
}
