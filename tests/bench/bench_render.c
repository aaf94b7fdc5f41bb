/*
 * bench_render.c — frame time of the renderer at 1280x720 (the dashboard's
 * size), beside a bare OSMesa clear + readback + PNG of the same size in the
 * same run (both encode opaque RGB PNGs with tsr_png_fast, as tsr_render_png
 * does), and the PNG settings behind tsr_png_fast (render.c).
 *
 * Prints medians over N frames; the goal (issue 8) is a full frame, PNG
 * included, within 2x the bare baseline and under 30 ms. Not a timed
 * assertion: the numbers are for the report.
 */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "render/m1_fixture.h"
#include "render/png_io.h"
#include "render/render.h"

#define W 1280
#define H 720
#define N 40

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* A failed call would time garbage (and encode an unset image): stop instead. */
#define CHECK(call)                                                                \
    do {                                                                           \
        if ((call) != TS_OK) {                                                     \
            fprintf(stderr, "bench_render: %s: %s\n", #call, err.msg);            \
            return 1;                                                              \
        }                                                                          \
    } while (0)

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Bare baseline: the same kind of context, an FBO of the same size, clear,
 * glReadPixels, PNG with the same settings. */
typedef struct {
    OSMesaContext ctx;
    unsigned char dummy[16 * 16 * 4];
    GLuint fbo, rb[2];
    unsigned char *px;
} bare;

static int bare_make(bare *b)
{
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                           OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 3,
                           OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    b->ctx = OSMesaCreateContextAttribs(attribs, NULL);
    if (!b->ctx || !OSMesaMakeCurrent(b->ctx, b->dummy, GL_UNSIGNED_BYTE, 16, 16)) return -1;
    glGenFramebuffers(1, &b->fbo);
    glGenRenderbuffers(2, b->rb);
    glBindRenderbuffer(GL_RENDERBUFFER, b->rb[0]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, W, H);
    glBindRenderbuffer(GL_RENDERBUFFER, b->rb[1]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, W, H);
    glBindFramebuffer(GL_FRAMEBUFFER, b->fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, b->rb[0]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, b->rb[1]);
    b->px = malloc((size_t)W * H * 4);
    OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
    return b->px ? 0 : -1;
}

static double bare_frame_ms(bare *b, tsr_png_opts o, size_t *png_len)
{
    double t0 = now();
    OSMesaMakeCurrent(b->ctx, b->dummy, GL_UNSIGNED_BYTE, 16, 16);
    glBindFramebuffer(GL_FRAMEBUFFER, b->fbo);
    glViewport(0, 0, W, H);
    glClearColor(0.8f, 0.85f, 0.9f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, b->px);
    OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
    unsigned char *png;
    ts_err err;
    if (tsr_png_encode_opaque(b->px, W, H, (size_t)W * 4, &o, &png, png_len, &err) != TS_OK) {
        fprintf(stderr, "bench_render: %s\n", err.msg);
        exit(1);
    }
    free(png);
    return (now() - t0) * 1e3;
}

static void bare_free(bare *b)
{
    OSMesaMakeCurrent(b->ctx, b->dummy, GL_UNSIGNED_BYTE, 16, 16);
    glDeleteFramebuffers(1, &b->fbo);
    glDeleteRenderbuffers(2, b->rb);
    OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
    OSMesaDestroyContext(b->ctx);
    free(b->px);
}

int main(void)
{
    static m1_state s;
    m1_set_terrain(&s.g, -60, 100, 10.0, 0.305, 7.62);
    ts_err err;
    tsr_ctx *c = tsr_ctx_make(&err);
    if (!c) {
        fprintf(stderr, "bench_render: %s\n", err.msg);
        return 1;
    }
    printf("renderer: %s, OpenGL %s\n", tsr_ctx_gl_renderer(c), tsr_ctx_gl_version(c));
    tsr_view v;
    tsr_view_default(&v);
    tsr_png_opts fast = tsr_png_fast();

    /* full frame: scene update + render + PNG, the state moving over the bump */
    double t_full[N], t_scene[N], t_draw[N], t_png[N], t_bare[N];
    size_t len = 0, blen = 0;
    static bare b;
    if (bare_make(&b) != 0) {
        fprintf(stderr, "bench_render: bare OSMesa context failed\n");
        return 1;
    }
    tsr_scene *sc = tsr_scene_make(&err);
    if (!sc) {
        fprintf(stderr, "bench_render: %s\n", err.msg);
        return 1;
    }
    for (int i = -3; i < N; i++) {
        m1_pose(&s, 4.0 + 0.1 * (i < 0 ? 0 : i), 0.05 * i, 2.2);
        m1_span_mode(&s, 2, 0.01);
        /* the baseline alternates with the real frame, so both see the same load */
        double tb = bare_frame_ms(&b, fast, &blen);
        double t0 = now();
        CHECK(tsr_scene_update(sc, &s.g, &v, &err));
        double t1 = now();
        tsr_image img;
        CHECK(tsr_render(c, sc, &v, &img, &err));
        double t2 = now();
        unsigned char *png;
        CHECK(tsr_png_encode_opaque(img.rgba, img.width, img.height, img.stride, &fast, &png,
                                    &len, &err));
        double t3 = now();
        free(png);
        if (i < 0) continue; /* warm-up (shader JIT, buffer allocation) */
        t_scene[i] = (t1 - t0) * 1e3;
        t_draw[i] = (t2 - t1) * 1e3;
        t_png[i] = (t3 - t2) * 1e3;
        t_full[i] = (t3 - t0) * 1e3;
        t_bare[i] = tb;
    }
    double full = median(t_full, N);
    printf("frame 1280x720 (scene %.2f + render/readback/overlay %.2f + png %.2f): "
           "median %.2f ms, png %zu bytes\n",
           median(t_scene, N), median(t_draw, N), median(t_png, N), full, len);
    double bare = median(t_bare, N);
    bare_free(&b);
    printf("bare OSMesa clear + readback + png 1280x720: median %.2f ms (%zu bytes)\n",
           bare, blen);
    printf("ratio full / bare: %.2f (goal <= 2), full frame %.2f ms (goal <= 30)\n", full / bare,
           full);

    /* PNG settings on a real frame */
    m1_pose(&s, 12.0, 3.0, 2.2);
    CHECK(tsr_scene_update(sc, &s.g, &v, &err));
    tsr_image img;
    CHECK(tsr_render(c, sc, &v, &img, &err));
    printf("png settings on one M1 frame (fastest of 15, bytes):\n");
    const char *fname[] = {"none", "sub", "up", "avg", "paeth"};
    static const int levels[] = {1, 2, 3, 6};
    for (int opq = 0; opq <= 1; opq++)
        for (int li = 0; li < 4; li++)
            for (int f = 0; f <= 4; f++) {
                if (f == 3) continue; /* avg: never competitive on these frames */
                tsr_png_opts o = {levels[li], f};
                double best = 1e9;
                size_t l = 0;
                for (int k = 0; k < 15; k++) {
                    double t0 = now();
                    unsigned char *png;
                    CHECK((opq ? tsr_png_encode_opaque : tsr_png_encode)(
                        img.rgba, img.width, img.height, img.stride, &o, &png, &l, &err));
                    double t = (now() - t0) * 1e3;
                    if (t < best) best = t;
                    free(png);
                }
                printf("  %s level %d %-5s: %6.2f ms %8zu bytes\n", opq ? "RGB " : "RGBA",
                       levels[li], fname[f], best, l);
            }
    tsr_scene_free(sc);
    tsr_ctx_free(c);
    return 0;
}
