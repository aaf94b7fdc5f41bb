/*
 * cmd_render.c — "tanksim render": build the model of a config, run it from
 * rest to --t T, take the geometry snapshot (ts_geometry) and draw it into a
 * PNG with the offscreen renderer (render/render.h): the stills behind the
 * paper's animation sequences (II.C.2) and Figs. 9-10.
 *
 * Scenarios without running gear (the point-mass one) have no geometry: the
 * command then says so (TS_ERR_UNSUPPORTED) and writes nothing.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../render/render.h"
#include "cli.h"

/* --view-width M (or its older name --span M, not both): the side view's
 * width in metres into v->span. 0, or -1 after a usage message. */
static int view_width(const char *s, const char *old_s, tsr_view *v)
{
    if (s && old_s) {
        fprintf(stderr, "tanksim: render: --view-width and --span (its older name) both given; "
                        "give one\n");
        return -1;
    }
    const char *name = s ? "--view-width" : "--span";
    if (!s) s = old_s;
    return s ? tsc_number(s, name, 0, 1000, &v->span) : 0;
}

int tsc_cmd_render(int argc, char **argv)
{
    const char *t_s = tsc_option(argc, argv, "--t");
    const char *out = tsc_option(argc, argv, "--out");
    const char *w_s = tsc_option(argc, argv, "--width");
    const char *h_s = tsc_option(argc, argv, "--height");
    const char *view_s = tsc_option(argc, argv, "--view");
    const char *ex_s = tsc_option(argc, argv, "--exaggeration");
    const char *color_s = tsc_option(argc, argv, "--color");
    const char *text_s = tsc_option(argc, argv, "--text");
    const char *span_s = tsc_option(argc, argv, "--view-width");
    const char *old_span_s = tsc_option(argc, argv, "--span"); /* its first name */
    int antialias = tsc_flag(argc, argv, "--antialias");
    int no_overlay = tsc_flag(argc, argv, "--no-overlay");

    tsr_view v;
    tsr_view_default(&v);
    double t = 0;
    long px;
    if (!out) {
        fprintf(stderr, "tanksim: render: --out FILE.png is required\n");
        return TSC_EXIT_USAGE;
    }
    if (w_s) {
        if (tsc_integer(w_s, "--width", TSR_MIN_SIZE, TSR_MAX_SIZE, &px) != 0)
            return TSC_EXIT_USAGE;
        v.width = (int)px;
    }
    if (h_s) {
        if (tsc_integer(h_s, "--height", TSR_MIN_SIZE, TSR_MAX_SIZE, &px) != 0)
            return TSC_EXIT_USAGE;
        v.height = (int)px;
    }
    if (view_s && (v.kind = tsr_view_kind_parse(view_s)) < 0) {
        fprintf(stderr, "tanksim: --view: side or three_quarter, got '%s'\n", view_s);
        return TSC_EXIT_USAGE;
    }
    if (ex_s && tsc_number(ex_s, "--exaggeration", 0, 1000, &v.exaggeration) != 0)
        return TSC_EXIT_USAGE;
    if (view_width(span_s, old_span_s, &v) != 0) return TSC_EXIT_USAGE;
    if (color_s) {
        /* the same words as the daemon's color= (api/openapi.yaml); "none" kept as before */
        if (strcmp(color_s, "tension") == 0) v.color_by_tension = 1;
        else if (strcmp(color_s, "plain") != 0 && strcmp(color_s, "none") != 0) {
            fprintf(stderr, "tanksim: --color: tension or plain, got '%s'\n", color_s);
            return TSC_EXIT_USAGE;
        }
    }
    v.antialias = antialias;
    v.overlay = !no_overlay;
    ts_err err;
    if ((text_s && tsr_view_set_text(&v, text_s, &err) != TS_OK) ||
        tsr_view_check(&v, &err) != TS_OK) {
        /* the view's checks name its field; say the option (only --text can
         * reach them: the numbers are checked above) */
        fprintf(stderr, "tanksim: render: %s: %s\n",
                strcmp(err.pointer, "/text") == 0 ? "--text" : err.pointer, err.msg);
        return TSC_EXIT_USAGE;
    }

    ts_config cfg;
    int rc = tsc_load_config(argc, argv, &cfg, NULL);
    if (rc != TSC_EXIT_OK) return rc;
    if (t_s && tsc_number(t_s, "--t", 0, cfg.run.duration, &t) != 0) return TSC_EXIT_USAGE;
    int status = TSC_EXIT_FAIL;
    ts_model *m = NULL;
    ts_data *d = NULL;
    tsr_ctx *c = NULL;
    unsigned char *png = NULL;
    size_t len = 0;
    tsc_out o = {0};
    ts_geom *g = malloc(sizeof *g);
    if (!g) {
        fprintf(stderr, "tanksim: out of memory\n");
        return TSC_EXIT_FAIL;
    }
    if (tsc_model_start(&cfg, &m, &d) != 0) goto done;
    /* before the run: a model without geometry (the point mass) and a path
     * that cannot be written fail at once, not after simulating to --t */
    if (ts_geometry(m, d, g, &err) != TS_OK) {
        tsc_print_err("geometry", &err);
        goto done;
    }
    if (tsc_out_open(&o, out, "render", 0) != 0) goto done;
    if (t > 0 && ts_advance(m, d, t, NULL, NULL, &err) != TS_OK) {
        tsc_print_err("run", &err);
        goto done;
    }
    if (t > 0 && ts_geometry(m, d, g, &err) != TS_OK) { /* at t = 0: the one above */
        tsc_print_err("geometry", &err);
        goto done;
    }
    c = tsr_ctx_make(&err);
    if (!c) {
        tsc_print_err("render", &err);
        goto done;
    }
    if (tsr_render_png(c, g, &v, NULL, &png, &len, &err) != TS_OK) {
        tsc_print_err("render", &err);
        goto done;
    }
    fwrite(png, 1, len, o.f); /* a short write shows in ferror: tsc_out_close says it */
    if (tsc_out_close(&o, 1) != TSC_EXIT_OK) goto done;
    printf("%s: t = %.3f s, %dx%d %s view -> %s (%zu bytes)\n", ts_model_kind(m), ts_time(d),
           v.width, v.height, tsr_view_kind_name(v.kind), out, len);
    status = TSC_EXIT_OK;
done:
    if (o.f) tsc_out_close(&o, 0);
    free(png);
    free(g);
    tsr_ctx_free(c);
    ts_data_free(d);
    ts_model_free(m);
    return status;
}
