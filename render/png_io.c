/*
 * png_io.c — in-memory PNG encode/decode over libpng (png_io.h). libpng reports
 * errors by longjmp; each call keeps its own jmp_buf, so this is thread-safe.
 */
#include "png_io.h"

#include "bytebuf.h"

#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>

static void write_cb(png_structp p, png_bytep data, png_size_t n)
{
    tsr_bytebuf_put(png_get_io_ptr(p), data, n);
}

static void flush_cb(png_structp p) { (void)p; }

static ts_rc encode(const unsigned char *rgba, int width, int height, size_t stride,
                    const tsr_png_opts *opts, int opaque, unsigned char **out, size_t *out_len,
                    ts_err *err)
{
    static const int filters[] = {PNG_FILTER_NONE, PNG_FILTER_SUB, PNG_FILTER_UP, PNG_FILTER_AVG,
                                  PNG_FILTER_PAETH};
    int level = opts ? opts->compression : 2;
    int filter = opts ? opts->filter : 1;
    if (width <= 0 || height <= 0 || level < 0 || level > 9 || filter < 0 || filter > 4)
        return ts_err_set(err, TS_ERR_PARAM, NULL, "png: bad size or options");
    /* The sink lives on the heap: libpng writes into it between setjmp and a
     * possible longjmp, and an automatic object modified there would be
     * indeterminate after the jump (C11 7.13.2.1); the pointer itself is not. */
    tsr_bytebuf *m = calloc(1, sizeof *m);
    png_structp p = m ? png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL) : NULL;
    png_infop info = p ? png_create_info_struct(p) : NULL;
    if (!p || !info) {
        png_destroy_write_struct(&p, NULL);
        free(m);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "png: out of memory");
    }
    if (setjmp(png_jmpbuf(p))) {
        png_destroy_write_struct(&p, &info);
        free(m->p);
        free(m);
        return ts_err_set(err, TS_ERR_INTERNAL, NULL, "png: libpng failed while encoding");
    }
    png_set_write_fn(p, m, write_cb, flush_cb);
    png_set_IHDR(p, info, (png_uint_32)width, (png_uint_32)height, 8,
                 opaque ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGBA,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(p, level);
    png_set_filter(p, PNG_FILTER_TYPE_BASE, filters[filter]);
    png_write_info(p, info);
    if (opaque) png_set_filler(p, 0, PNG_FILLER_AFTER); /* input keeps 4 bytes a pixel */
    for (int y = 0; y < height; y++) png_write_row(p, (png_const_bytep)(rgba + (size_t)y * stride));
    png_write_end(p, NULL);
    png_destroy_write_struct(&p, &info);
    int oom = m->oom;
    *out = oom ? NULL : m->p;
    *out_len = oom ? 0 : m->n;
    if (oom) free(m->p);
    free(m);
    if (oom) return ts_err_set(err, TS_ERR_NOMEM, NULL, "png: out of memory");
    return TS_OK;
}

ts_rc tsr_png_encode(const unsigned char *rgba, int width, int height, size_t stride,
                     const tsr_png_opts *opts, unsigned char **out, size_t *out_len, ts_err *err)
{
    return encode(rgba, width, height, stride, opts, 0, out, out_len, err);
}

ts_rc tsr_png_encode_opaque(const unsigned char *rgba, int width, int height, size_t stride,
                            const tsr_png_opts *opts, unsigned char **out, size_t *out_len,
                            ts_err *err)
{
    return encode(rgba, width, height, stride, opts, 1, out, out_len, err);
}

ts_rc tsr_png_decode(const unsigned char *png, size_t len, unsigned char **rgba, int *width,
                     int *height, ts_err *err)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&img, png, len))
        return ts_err_set(err, TS_ERR_PARAM, NULL, "png: not a PNG (%s)", img.message);
    img.format = PNG_FORMAT_RGBA;
    unsigned char *buf = malloc(PNG_IMAGE_SIZE(img));
    if (!buf) {
        png_image_free(&img);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "png: out of memory");
    }
    if (!png_image_finish_read(&img, NULL, buf, 0, NULL)) {
        free(buf);
        return ts_err_set(err, TS_ERR_PARAM, NULL, "png: decode failed (%s)", img.message);
    }
    *rgba = buf;
    *width = (int)img.width;
    *height = (int)img.height;
    return TS_OK;
}
