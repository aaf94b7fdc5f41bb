/*
 * png_io.h — RGBA8 images to PNG bytes in memory with libpng, tuned for speed
 * (the renderer's frames are served over HTTP and streamed to dashboards).
 *
 * Ownership: tsr_png_encode returns a malloc'd buffer the caller frees.
 */
#ifndef TSR_PNG_IO_H
#define TSR_PNG_IO_H

#include <stddef.h>

#include "../sim/errors.h"

typedef struct tsr_png_opts {
    int compression; /* zlib level 0-9 (default 2: fast, still ~5x smaller than raw) */
    int filter;      /* PNG row filter: 0 none, 1 sub, 2 up, 3 avg, 4 paeth (default 1) */
} tsr_png_opts;

/* Encode width x height RGBA8 pixels, rows top-down, stride bytes apart.
 * opts may be NULL for the defaults. On success *out and *out_len hold the PNG. */
TS_MUST_CHECK ts_rc tsr_png_encode(const unsigned char *rgba, int width, int height, size_t stride,
                                   const tsr_png_opts *opts, unsigned char **out, size_t *out_len,
                                   ts_err *err);

/* As tsr_png_encode, but writes an RGB PNG, dropping every pixel's alpha byte:
 * for opaque frames (the renderer's), a quarter less data to compress. */
TS_MUST_CHECK ts_rc tsr_png_encode_opaque(const unsigned char *rgba, int width, int height,
                                          size_t stride, const tsr_png_opts *opts,
                                          unsigned char **out, size_t *out_len, ts_err *err);

/* Decode a PNG (any colour type) into malloc'd RGBA8 top-down rows; for tests
 * and for re-reading cached frames. */
TS_MUST_CHECK ts_rc tsr_png_decode(const unsigned char *png, size_t len, unsigned char **rgba,
                                   int *width, int *height, ts_err *err);

#endif
