/*
 * render.c — the OpenGL side of render.h: an OSMesa core-profile context per
 * tsr_ctx, one shader pair (flat-lit triangles, or flat part colours for the
 * id images), framebuffer objects (a 4x multisampled one, resolved into the
 * single-sample one, when tsr_view.antialias asks for it), glReadPixels
 * readback in top-down rows (the projection flips y, so the rows arrive in
 * image order without a copy), the text overlay drawn on the CPU with the
 * built-in font, and PNG through png_io.
 *
 * Why these choices: OSMesa/llvmpipe needs no display or GPU (Paper II.C.2
 * "animation sequences" for the API, dashboard and CI); rendering into FBOs
 * lets one context serve every image size without re-creating it; the core
 * profile keeps us off fixed-function paths.
 *
 * PNG settings (tsr_png_fast): opaque RGB, zlib level 3, filter "none".
 * Measured by tests/bench/bench_render.c on a 1280x720 M1 frame (fastest of
 * 15, a quiet moment on the 2-core machine): RGB level 3 none 4.6 ms / 36 KB,
 * level 2 none 4.5 ms / 39 KB, level 1 none 5.6 ms / 40 KB; "sub" and "up"
 * cost 1-4 ms more ("up" gives 28-31 KB), "paeth" 3-4 ms more, level 6 three
 * times the time; RGBA instead of RGB adds ~15-25 % for a quarter more data.
 * Timings on the shared machine vary by 2x with load; the bench prints them.
 *
 * Leaves out: shadows, textures, anti-aliased id images (ids must be exact).
 */
#define GL_GLEXT_PROTOTYPES 1
#include "render.h"

#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../sim/constants.h"
#include "font.h"
#include "scene.h"

#define MSAA_SAMPLES 4

struct tsr_ctx {
    OSMesaContext osm;
    unsigned char dummy[16 * 16 * 4]; /* OSMesa's window buffer; we draw into FBOs */
    GLuint prog, vao, vbo;
    GLint u_mvp, u_ids, u_idcol, u_light;
    size_t vbo_bytes;
    GLuint fbo_ms, rb_ms_color, rb_ms_depth; /* multisampled target */
    GLuint fbo, rb_color, rb_depth;          /* single-sample target / resolve */
    int fb_w, fb_h, samples;
    unsigned char *pixels; /* fb_w * fb_h * 4, top-down */
    size_t pixels_cap;
    tsr_scene *scene; /* for tsr_render_png */
    char gl_renderer[128], gl_version[128];
};

/* Part colours of TSR_SHADE_IDS images: distinct, saturated, easy to count. */
static const unsigned char PART_COLORS[TSR_NPART][3] = {
    [TSR_PART_BACKGROUND] = {0, 0, 0},      [TSR_PART_TERRAIN] = {0, 160, 0},
    [TSR_PART_HULL] = {255, 0, 0},          [TSR_PART_TURRET] = {255, 128, 0},
    [TSR_PART_GUN] = {255, 255, 0},         [TSR_PART_ROAD_ARM] = {128, 0, 255},
    [TSR_PART_ROAD_WHEEL] = {0, 0, 255},    [TSR_PART_SPROCKET] = {0, 255, 255},
    [TSR_PART_IDLER] = {255, 0, 255},       [TSR_PART_ROLLER] = {0, 128, 128},
    [TSR_PART_TRACK] = {255, 255, 255},
};

static const unsigned char SKY[3] = {206, 218, 228};

static const char *VS =
    "#version 330 core\n"
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 1) in vec3 a_nrm;\n"
    "layout(location = 2) in vec4 a_col;\n"
    "uniform mat4 u_mvp;\n"
    "uniform int u_ids;\n"
    "uniform vec3 u_idcol[16];\n"
    "uniform vec3 u_light;\n"
    "flat out vec3 v_col;\n"
    "void main() {\n"
    "  gl_Position = u_mvp * vec4(a_pos, 1.0);\n"
    "  if (u_ids != 0) {\n"
    "    v_col = u_idcol[clamp(int(a_col.a * 255.0 + 0.5), 0, 15)];\n"
    "  } else {\n"
    "    float d = max(dot(a_nrm, u_light), 0.0);\n"
    "    float sky = 0.5 + 0.5 * a_nrm.z;\n" /* hemisphere ambient */
    "    v_col = min(a_col.rgb * (0.38 + 0.16 * sky + 0.62 * d), vec3(1.0));\n"
    "  }\n"
    "}\n";

static const char *FS = "#version 330 core\n"
                        "flat in vec3 v_col;\n"
                        "out vec4 o_col;\n"
                        "void main() { o_col = vec4(v_col, 1.0); }\n";

/* ---- view ------------------------------------------------------------------ */

void tsr_view_default(tsr_view *v)
{
    memset(v, 0, sizeof *v);
    v->width = 1280;
    v->height = 720;
    v->kind = TSR_VIEW_SIDE;
    v->exaggeration = 1.0;
    v->color_by_tension = 0;
    v->overlay = 1;
    v->span = 0.0;
    v->shading = TSR_SHADE_LIT;
    v->antialias = 0;
}

ts_rc tsr_view_check(const tsr_view *v, ts_err *err)
{
    if (v->width < TSR_MIN_SIZE || v->width > TSR_MAX_SIZE)
        return ts_err_set(err, TS_ERR_RANGE, "/width", "integer in [%d, %d], got %d",
                          TSR_MIN_SIZE, TSR_MAX_SIZE, v->width);
    if (v->height < TSR_MIN_SIZE || v->height > TSR_MAX_SIZE)
        return ts_err_set(err, TS_ERR_RANGE, "/height", "integer in [%d, %d], got %d",
                          TSR_MIN_SIZE, TSR_MAX_SIZE, v->height);
    if (v->kind < 0 || v->kind >= TSR_NVIEW)
        return ts_err_set(err, TS_ERR_RANGE, "/view", "one of side, three_quarter");
    if (!isfinite(v->exaggeration) || v->exaggeration < 0 || v->exaggeration > 1000)
        return ts_err_set(err, TS_ERR_RANGE, "/exaggeration", "number in [0, 1000], got %g",
                          v->exaggeration);
    if (v->color_by_tension != 0 && v->color_by_tension != 1)
        return ts_err_set(err, TS_ERR_RANGE, "/color_by_tension", "0 or 1");
    if (v->overlay != 0 && v->overlay != 1)
        return ts_err_set(err, TS_ERR_RANGE, "/overlay", "0 or 1");
    if (!isfinite(v->span) || v->span < 0 || v->span > 1000)
        return ts_err_set(err, TS_ERR_RANGE, "/span", "number in [0, 1000] m, got %g", v->span);
    if (v->antialias != 0 && v->antialias != 1)
        return ts_err_set(err, TS_ERR_RANGE, "/antialias", "0 or 1");
    if (v->shading < 0 || v->shading >= TSR_NSHADE)
        return ts_err_set(err, TS_ERR_RANGE, "/shading", "lit or ids");
    size_t n = strnlen(v->text, TSR_TEXT_LEN);
    if (n == TSR_TEXT_LEN)
        return ts_err_set(err, TS_ERR_RANGE, "/text", "at most %d characters", TSR_TEXT_LEN - 1);
    for (size_t i = 0; i < n; i++)
        if (v->text[i] < 32 || v->text[i] > 126)
            return ts_err_set(err, TS_ERR_PARAM, "/text", "printable ASCII only (codes 32-126)");
    return TS_OK;
}

ts_rc tsr_view_set_text(tsr_view *v, const char *text, ts_err *err)
{
    size_t n = strlen(text);
    if (n >= TSR_TEXT_LEN)
        return ts_err_set(err, TS_ERR_RANGE, "/text", "at most %d characters, got %zu",
                          TSR_TEXT_LEN - 1, n);
    memcpy(v->text, text, n + 1);
    return TS_OK;
}

int tsr_view_kind_parse(const char *name)
{
    if (!name) return -1;
    if (strcmp(name, "side") == 0) return TSR_VIEW_SIDE;
    if (strcmp(name, "three_quarter") == 0) return TSR_VIEW_THREE_QUARTER;
    return -1;
}

const char *tsr_view_kind_name(int kind)
{
    switch (kind) {
    case TSR_VIEW_SIDE: return "side";
    case TSR_VIEW_THREE_QUARTER: return "three_quarter";
    default: return "unknown";
    }
}

void tsr_part_color(int part, unsigned char rgb[3])
{
    if (part < 0 || part >= TSR_NPART) part = TSR_PART_BACKGROUND;
    memcpy(rgb, PART_COLORS[part], 3);
}

tsr_png_opts tsr_png_fast(void)
{
    tsr_png_opts o = {3, 0};
    return o;
}

/* ---- context ----------------------------------------------------------------- */

static int make_current(tsr_ctx *c)
{
    return OSMesaMakeCurrent(c->osm, c->dummy, GL_UNSIGNED_BYTE, 16, 16) ? 0 : -1;
}

static void release_current(void) { OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0); }

static GLuint compile(GLenum type, const char *src, char *log, size_t loglen)
{
    GLuint sh = glCreateShader(type);
    glShaderSource(sh, 1, &src, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        glGetShaderInfoLog(sh, (GLsizei)loglen, NULL, log);
        glDeleteShader(sh);
        return 0;
    }
    return sh;
}

static void delete_targets(tsr_ctx *c)
{
    if (c->fbo_ms) glDeleteFramebuffers(1, &c->fbo_ms);
    if (c->fbo) glDeleteFramebuffers(1, &c->fbo);
    GLuint rbs[4] = {c->rb_ms_color, c->rb_ms_depth, c->rb_color, c->rb_depth};
    for (int i = 0; i < 4; i++)
        if (rbs[i]) glDeleteRenderbuffers(1, &rbs[i]);
    c->fbo_ms = c->fbo = c->rb_ms_color = c->rb_ms_depth = c->rb_color = c->rb_depth = 0;
    c->fb_w = c->fb_h = 0;
}

static ts_rc make_targets(tsr_ctx *c, int w, int h, int want_ms, ts_err *err)
{
    if (c->fb_w == w && c->fb_h == h && (!want_ms || c->fbo_ms)) return TS_OK;
    delete_targets(c);
    glGenFramebuffers(1, &c->fbo);
    glGenRenderbuffers(1, &c->rb_color);
    glGenRenderbuffers(1, &c->rb_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, c->rb_color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, c->rb_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, c->fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, c->rb_color);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, c->rb_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        delete_targets(c);
        return ts_err_set(err, TS_ERR_INTERNAL, NULL, "render: framebuffer %dx%d incomplete", w,
                          h);
    }
    if (c->samples > 1 && want_ms) {
        glGenFramebuffers(1, &c->fbo_ms);
        glGenRenderbuffers(1, &c->rb_ms_color);
        glGenRenderbuffers(1, &c->rb_ms_depth);
        glBindRenderbuffer(GL_RENDERBUFFER, c->rb_ms_color);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, c->samples, GL_RGBA8, w, h);
        glBindRenderbuffer(GL_RENDERBUFFER, c->rb_ms_depth);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, c->samples, GL_DEPTH_COMPONENT24, w, h);
        glBindFramebuffer(GL_FRAMEBUFFER, c->fbo_ms);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                  c->rb_ms_color);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                  c->rb_ms_depth);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            delete_targets(c);
            return ts_err_set(err, TS_ERR_INTERNAL, NULL,
                              "render: multisampled framebuffer %dx%d incomplete", w, h);
        }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    size_t need = (size_t)w * (size_t)h * 4;
    if (need > c->pixels_cap) {
        unsigned char *p = realloc(c->pixels, need);
        if (!p) {
            delete_targets(c);
            return ts_err_set(err, TS_ERR_NOMEM, NULL, "render: out of memory");
        }
        c->pixels = p;
        c->pixels_cap = need;
    }
    c->fb_w = w;
    c->fb_h = h;
    return TS_OK;
}

tsr_ctx *tsr_ctx_make(ts_err *err)
{
    tsr_ctx *c = calloc(1, sizeof *c);
    if (!c) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "render: out of memory");
        return NULL;
    }
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                           OSMESA_STENCIL_BITS, 0, OSMESA_ACCUM_BITS, 0,
                           OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    c->osm = OSMesaCreateContextAttribs(attribs, NULL);
    if (!c->osm) {
        free(c);
        ts_err_set(err, TS_ERR_UNSUPPORTED, NULL,
                   "render: OSMesa could not create an OpenGL 3.3 core context");
        return NULL;
    }
    if (make_current(c) != 0) {
        OSMesaDestroyContext(c->osm);
        free(c);
        ts_err_set(err, TS_ERR_UNSUPPORTED, NULL, "render: OSMesaMakeCurrent failed");
        return NULL;
    }
    const char *renderer = (const char *)glGetString(GL_RENDERER);
    const char *version = (const char *)glGetString(GL_VERSION);
    snprintf(c->gl_renderer, sizeof c->gl_renderer, "%s", renderer ? renderer : "unknown");
    snprintf(c->gl_version, sizeof c->gl_version, "%s", version ? version : "unknown");
    char log[1024] = "";
    GLuint vs = compile(GL_VERTEX_SHADER, VS, log, sizeof log);
    GLuint fs = vs ? compile(GL_FRAGMENT_SHADER, FS, log, sizeof log) : 0;
    if (!vs || !fs) {
        if (vs) glDeleteShader(vs);
        tsr_ctx_free(c);
        ts_err_set(err, TS_ERR_INTERNAL, NULL, "render: shader: %s", log);
        return NULL;
    }
    c->prog = glCreateProgram();
    glAttachShader(c->prog, vs);
    glAttachShader(c->prog, fs);
    glLinkProgram(c->prog);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(c->prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        glGetProgramInfoLog(c->prog, sizeof log, NULL, log);
        tsr_ctx_free(c);
        ts_err_set(err, TS_ERR_INTERNAL, NULL, "render: link: %s", log);
        return NULL;
    }
    c->u_mvp = glGetUniformLocation(c->prog, "u_mvp");
    c->u_ids = glGetUniformLocation(c->prog, "u_ids");
    c->u_idcol = glGetUniformLocation(c->prog, "u_idcol");
    c->u_light = glGetUniformLocation(c->prog, "u_light");
    glGenVertexArrays(1, &c->vao);
    glGenBuffers(1, &c->vbo);
    glBindVertexArray(c->vao);
    glBindBuffer(GL_ARRAY_BUFFER, c->vbo);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(tsr_vertex),
                          (const void *)offsetof(tsr_vertex, pos));
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(tsr_vertex),
                          (const void *)offsetof(tsr_vertex, normal));
    glVertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(tsr_vertex),
                          (const void *)offsetof(tsr_vertex, rgba));
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);
    glEnableVertexAttribArray(2);
    GLint max_samples = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    c->samples = max_samples >= MSAA_SAMPLES ? MSAA_SAMPLES : 1;
    GLenum glerr = glGetError();
    release_current();
    if (glerr != GL_NO_ERROR) {
        tsr_ctx_free(c);
        ts_err_set(err, TS_ERR_INTERNAL, NULL, "render: GL error 0x%x while setting up", glerr);
        return NULL;
    }
    return c;
}

void tsr_ctx_free(tsr_ctx *c)
{
    if (!c) return;
    if (make_current(c) == 0) {
        delete_targets(c);
        if (c->vbo) glDeleteBuffers(1, &c->vbo);
        if (c->vao) glDeleteVertexArrays(1, &c->vao);
        if (c->prog) glDeleteProgram(c->prog);
        release_current();
    }
    OSMesaDestroyContext(c->osm);
    tsr_scene_free(c->scene);
    free(c->pixels);
    free(c);
}

const char *tsr_ctx_gl_renderer(const tsr_ctx *c) { return c->gl_renderer; }
const char *tsr_ctx_gl_version(const tsr_ctx *c) { return c->gl_version; }

/* ---- overlay --------------------------------------------------------------- */

static void draw_overlay(const tsr_scene *s, const tsr_view *v, unsigned char *px, size_t stride)
{
    int W = v->width, H = v->height;
    int scale = H >= 1400 ? 4 : H >= 700 ? 2 : 1;
    int lh = (TSR_GLYPH_H + 4) * scale, pad = 4 * scale;
    static const unsigned char white[3] = {255, 255, 255}, dark[3] = {20, 24, 28};
    char line[2][160];
    int nl = 0;
    if (v->overlay) {
        int n = snprintf(line[0], sizeof line[0], "t %.2f s   v %.1f km/h (%.1f mph)", s->t,
                         s->speed * 3.6, s->speed / TS_MPH);
        if (s->gear != 0 && n >= 0 && (size_t)n < sizeof line[0]) /* not truncated already */
            snprintf(line[0] + n, sizeof line[0] - (size_t)n, "   gear %d", s->gear);
        nl = 1;
        if (v->text[0]) snprintf(line[nl++], sizeof line[0], "%s", v->text);
    }
    if (nl) {
        int bw = 0;
        for (int i = 0; i < nl; i++) {
            int tw = tsr_text_width(line[i], scale);
            if (tw > bw) bw = tw;
        }
        tsr_fill_rect(px, W, H, stride, pad, pad, bw + 2 * pad, nl * lh + pad, dark, 0.6);
        for (int i = 0; i < nl; i++)
            tsr_text_draw(px, W, H, stride, 2 * pad, 2 * pad + i * lh, scale, line[i], white);
    }
    if (s->color_by_tension && s->tension_ref > 0) {
        /* legend: ramp from 0 to 2 x reference tension, bottom-left */
        int bw = 100 * scale, bh = 5 * scale, x0 = 2 * pad, y0 = H - 2 * pad - bh - lh;
        char lab[3][32], title[64];
        snprintf(title, sizeof title, "track tension [kN]");
        snprintf(lab[0], sizeof lab[0], "0");
        snprintf(lab[1], sizeof lab[1], "%.0f", s->tension_ref / 1000);
        snprintf(lab[2], sizeof lab[2], "%.0f", 2 * s->tension_ref / 1000);
        tsr_fill_rect(px, W, H, stride, x0 - pad, y0 - lh - pad, bw + 2 * pad + 4 * scale * 6,
                      bh + 2 * lh + 2 * pad, dark, 0.6);
        tsr_text_draw(px, W, H, stride, x0, y0 - lh + scale, scale, title, white);
        for (int i = 0; i < bw; i++) {
            unsigned char rgb[3];
            tsr_tension_color(2.0 * i / (bw - 1), rgb);
            tsr_fill_rect(px, W, H, stride, x0 + i, y0, 1, bh, rgb, 1.0);
        }
        for (int k = 0; k < 3; k++) {
            int tx = x0 + k * (bw - 1) / 2 - tsr_text_width(lab[k], scale) / 2;
            tsr_text_draw(px, W, H, stride, tx < 0 ? 0 : tx, y0 + bh + 2 * scale, scale, lab[k],
                          white);
        }
    }
}

/* ---- rendering ----------------------------------------------------------------- */

ts_rc tsr_render(tsr_ctx *c, const tsr_scene *s, const tsr_view *v, tsr_image *out, ts_err *err)
{
    ts_rc rc = tsr_view_check(v, err);
    if (rc != TS_OK) return rc;
    if (make_current(c) != 0)
        return ts_err_set(err, TS_ERR_INTERNAL, NULL, "render: OSMesaMakeCurrent failed");
    int W = v->width, H = v->height;
    int ids = v->shading == TSR_SHADE_IDS;
    int ms = !ids && v->antialias && c->samples > 1;
    rc = make_targets(c, W, H, ms, err);
    if (rc != TS_OK) {
        release_current();
        return rc;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, ms ? c->fbo_ms : c->fbo);
    glViewport(0, 0, W, H);
    if (ids) glClearColor(0, 0, 0, 1);
    else glClearColor(SKY[0] / 255.f, SKY[1] / 255.f, SKY[2] / 255.f, 1);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    if (s->nv > 0) {
        glUseProgram(c->prog);
        float mvp[16], idcol[16 * 3] = {0};
        tsr_scene_mvp(s, v, mvp);
        /* Flip clip-space y so that GL's bottom-up rows read back top-down: the
         * readback needs no row swap. */
        for (int k = 0; k < 4; k++) mvp[k * 4 + 1] = -mvp[k * 4 + 1];
        for (int p = 0; p < TSR_NPART; p++)
            for (int k = 0; k < 3; k++) idcol[p * 3 + k] = PART_COLORS[p][k] / 255.f;
        const float light[3] = {0.36f, -0.62f, 0.70f}; /* unit: from front-right, above */
        glUniformMatrix4fv(c->u_mvp, 1, GL_FALSE, mvp);
        glUniform1i(c->u_ids, ids);
        glUniform3fv(c->u_idcol, 16, idcol);
        glUniform3fv(c->u_light, 1, light);
        glBindVertexArray(c->vao);
        glBindBuffer(GL_ARRAY_BUFFER, c->vbo);
        size_t bytes = (size_t)s->nv * sizeof(tsr_vertex);
        if (bytes > c->vbo_bytes) {
            glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)bytes, s->v, GL_STREAM_DRAW);
            c->vbo_bytes = bytes;
        } else {
            glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)bytes, s->v);
        }
        glDrawArrays(GL_TRIANGLES, 0, s->nv);
    }
    if (ms) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, c->fbo_ms);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, c->fbo);
        glBlitFramebuffer(0, 0, W, H, 0, 0, W, H, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, c->fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, c->pixels);
    GLenum glerr = glGetError();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    release_current();
    if (glerr != GL_NO_ERROR)
        return ts_err_set(err, TS_ERR_INTERNAL, NULL, "render: GL error 0x%x", glerr);
    size_t stride = (size_t)W * 4;
    if (!ids) draw_overlay(s, v, c->pixels, stride);
    out->width = W;
    out->height = H;
    out->stride = stride;
    out->rgba = c->pixels;
    return TS_OK;
}

ts_rc tsr_render_png(tsr_ctx *c, const ts_geom *g, const tsr_view *v, const tsr_png_opts *png,
                     unsigned char **out, size_t *out_len, ts_err *err)
{
    if (!c->scene) {
        c->scene = tsr_scene_make(err);
        if (!c->scene) return TS_ERR_NOMEM;
    }
    ts_rc rc = tsr_scene_update(c->scene, g, v, err);
    if (rc != TS_OK) return rc;
    tsr_image img;
    rc = tsr_render(c, c->scene, v, &img, err);
    if (rc != TS_OK) return rc;
    tsr_png_opts fast = tsr_png_fast();
    return tsr_png_encode_opaque(img.rgba, img.width, img.height, img.stride, png ? png : &fast,
                                 out, out_len, err);
}
