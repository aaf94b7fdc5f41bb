/*
 * modes_json.c — the track eigenanalysis as one JSON document (modes_json.h),
 * shared by `tanksim modes` (cli/cmd_modes.c) and POST /v1/modes (tanksimd).
 * Moved here from cli/cmd_modes.c unchanged in content, so that the command
 * line and the server print the same numbers from the same code.
 */
#include "modes_json.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../sim/track_circuit.h"

#define NSAMPLE 11 /* deflection samples per span in a mode shape */

/* Map a span-parameter error pointer to the config field behind it. */
static void to_config_pointer(ts_err *err, int override_index)
{
    static const char *const map[][2] = {
        {"/span/tension", "/track/tension"},
        {"/span/rho", "/track/mass_per_length"},
        {"/span/ea", "/track/ea"},
        {"/span/n_long", "/track/n_long"},
        {"/span/n_trans", "/track/n_trans"},
        {"/span/speed", "/track/modes_speed"},
        {"/span/damping_ratio", "/track/damping_ratio"},
        {"/span/g_y", "/track/span_inclination"},
    };
    if (strcmp(err->pointer, "/span/length") == 0) {
        if (override_index >= 0)
            snprintf(err->pointer, sizeof err->pointer, "/track/span_length/%d", override_index);
        else
            snprintf(err->pointer, sizeof err->pointer, "/vehicle");
        return;
    }
    for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
        if (strcmp(err->pointer, map[i][0]) == 0) {
            snprintf(err->pointer, sizeof err->pointer, "%s", map[i][1]);
            return;
        }
}

static json_t *freq_array(const ts_modes *m)
{
    json_t *a = json_array();
    for (int i = 0; m && i < m->n; i++)
        json_array_append_new(a, json_real(m->freq[i]));
    return a;
}

/* One span alone: three families. NULL on error (err filled). */
static json_t *span_json(const char *name, const ts_span_params *p, double inclination,
                         int override_index, ts_err *err)
{
    ts_span_params qs = *p;
    qs.n_long = 0;
    qs.quasi_static_stretch = 1;
    ts_span *sp = ts_span_make(p, err);
    ts_span *sq = sp ? ts_span_make(&qs, err) : NULL;
    ts_modes *ml = NULL, *mt = NULL, *mc = NULL;
    json_t *o = NULL;
    if (!sq) goto done;
    ml = ts_span_modes(sp, 1, TS_SPAN_MAX_MODES, err);
    mt = ml ? ts_span_modes(sq, 2, TS_SPAN_MAX_MODES, err) : NULL;
    mc = mt ? ts_span_modes(sp, 0, 2 * TS_SPAN_MAX_MODES, err) : NULL;
    if (!mc) goto done;
    double L = p->length;
    o = json_pack("{s:s, s:f, s:f, s:f, s:f, s:f, s:f, s:{s:o, s:o, s:o}}", "name", name,
                  "length_m", L, "inclination_rad", inclination, "sag_m", fabs(sp->sag), "lambda2",
                  sp->k2 * L * L / p->tension, "string_f1_hz", sqrt(p->tension / p->rho) / (2 * L),
                  "kappa_per_m", fabs(sp->kappa), "frequencies_hz", "longitudinal", freq_array(ml),
                  "transverse", freq_array(mt), "coupled", freq_array(mc));
done:
    if (!o && err->code != TS_OK) to_config_pointer(err, override_index);
    ts_modes_free(ml);
    ts_modes_free(mt);
    ts_modes_free(mc);
    ts_span_free(sp);
    ts_span_free(sq);
    return o;
}

static json_t *mode_json(const ts_circuit *c, const ts_modes *m, int k)
{
    const double *y = m->shape + k * m->ndof;
    ts_mode_character ch;
    ts_circuit_mode_character(c, y, &ch);
    json_t *shares = json_object(), *defl = json_object();
    double vmax = 0, umax = 0;
    double V[TS_CIRCUIT_NSPANS][NSAMPLE], U[TS_CIRCUIT_NSPANS][NSAMPLE];
    double x[2 + 2 * TS_SPAN_MAX_MODES];
    for (int i = 0; i < TS_CIRCUIT_NSPANS; i++) {
        ts_circuit_span_state(c, i, y, x);
        for (int s = 0; s < NSAMPLE; s++) {
            double at = c->geom[i].length * s / (NSAMPLE - 1);
            ts_span_eval(c->span[i], x, at, &U[i][s], &V[i][s], NULL);
            if (fabs(V[i][s]) > vmax) vmax = fabs(V[i][s]);
            if (fabs(U[i][s]) > umax) umax = fabs(U[i][s]);
        }
    }
    double scale = fmax(vmax, umax);
    if (!(scale > 0)) scale = 1;
    for (int i = 0; i < TS_CIRCUIT_NSPANS; i++) {
        json_object_set_new(
            shares, ts_circuit_span_names[i],
            json_pack("{s:f, s:f}", "transverse", ch.trans[i], "longitudinal", ch.lon[i]));
        json_t *v = json_array(), *u = json_array();
        for (int s = 0; s < NSAMPLE; s++) {
            json_array_append_new(v, json_real(V[i][s] / scale));
            json_array_append_new(u, json_real(U[i][s] / scale));
        }
        json_object_set_new(defl, ts_circuit_span_names[i],
                            json_pack("{s:o, s:o}", "transverse", v, "longitudinal", u));
    }
    json_object_set_new(shares, "wheels", json_real(ch.wheels));
    /* words: which spans move (share >= 10 %), and which motion dominates */
    char desc[512];
    int len = snprintf(desc, sizeof desc, "%s; spans:",
                       ch.transverse ? "transverse" : "longitudinal (track stretch, wheel spin)");
    for (int i = 0; i < TS_CIRCUIT_NSPANS && len < (int)sizeof desc; i++) {
        double e = ch.trans[i] + ch.lon[i];
        if (e >= 0.1)
            len += snprintf(desc + len, sizeof desc - (size_t)len, " %s %.0f%%",
                            ts_circuit_span_names[i], 100 * e);
    }
    if (ch.wheels >= 0.1 && len < (int)sizeof desc)
        snprintf(desc + len, sizeof desc - (size_t)len, " wheels %.0f%%", 100 * ch.wheels);
    return json_pack("{s:i, s:f, s:s, s:s, s:s, s:o, s:o}", "mode", k + 1, "frequency_hz",
                     m->freq[k], "character", ch.transverse ? "transverse" : "longitudinal",
                     "dominant_span", ts_circuit_span_names[ch.dominant_span], "description", desc,
                     "energy_share", shares, "deflection", defl);
}

static json_t *circuit_json(const ts_circuit *c, int nreport, ts_err *err)
{
    ts_modes *m = ts_circuit_modes(c, nreport, err);
    if (!m) return NULL;
    json_t *freqs = freq_array(m), *shapes = json_array(), *sup = json_array();
    for (int k = 0; k < m->n; k++)
        json_array_append_new(shapes, mode_json(c, m, k));
    for (int w = 0; w < TS_CIRCUIT_NSUPPORTS; w++) {
        const ts_span_support *s = &c->p.support[w];
        json_array_append_new(sup, json_pack("{s:s, s:f, s:f, s:f, s:f, s:b}", "name",
                                             ts_circuit_support_names[w], "x_m", s->x, "z_m", s->z,
                                             "pitch_radius_m", s->radius, "wrap_rad", c->wrap[w],
                                             "fixed", w == 0 || w == TS_CIRCUIT_NSUPPORTS - 1));
    }
    ts_modes_free(m);
    return json_pack("{s:s, s:i, s:b, s:f, s:o, s:o, s:o}", "boundary",
                     "road wheels 1 and 7 fixed, hull fixed; idler, rollers, sprocket turn freely",
                     "dof", c->ndof, "gyroscopic", c->gyroscopic, "speed_m_s",
                     c->gyroscopic ? c->p.speed : 0.0, "supports", sup, "frequencies_hz", freqs,
                     "mode_shapes", shapes);
}

json_t *tsa_modes_json(const ts_config *cfg, ts_err *err)
{
    ts_err_clear(err);
    ts_circuit *c = NULL;
    json_t *spans = json_array(), *doc = NULL, *circ = NULL;

    ts_circuit_params cp;
    if (ts_circuit_params_from_config(cfg, &cp, err) != TS_OK) goto fail;
    c = ts_circuit_make(&cp, err);
    if (!c) {
        to_config_pointer(err, -1);
        goto fail;
    }
    if (cfg->track.span_n > 0) {
        for (int i = 0; i < cfg->track.span_n; i++) {
            ts_span_params sp;
            if (ts_span_params_from_config(cfg, i, &sp, err) != TS_OK) goto fail;
            char name[32];
            snprintf(name, sizeof name, "span_%d", i + 1);
            json_t *o = span_json(name, &sp, cfg->track.span_inclination[i], i, err);
            if (!o) goto fail;
            json_array_append_new(spans, o);
        }
    } else {
        for (int i = 0; i < TS_CIRCUIT_NSPANS; i++) {
            ts_span_params sp = c->span[i]->p;
            sp.damping_ratio = cfg->track.damping_ratio;
            double incl = c->geom[i].angle; /* report the angle above horizontal */
            incl = atan2(sin(incl), fabs(cos(incl)));
            json_t *o = span_json(ts_circuit_span_names[i], &sp, incl, -1, err);
            if (!o) goto fail;
            json_array_append_new(spans, o);
        }
    }
    circ = circuit_json(c, cfg->track.modes_reported, err);
    if (!circ) goto fail;
    doc =
        json_pack("{s:o, s:o, s:{s:s, s:s, s:s, s:s, s:s, s:s}, s:{s:i, s:i, s:f, s:f, s:f}}",
                  "spans", spans, "circuit", circ, "units", "frequencies_hz", "Hz", "length_m", "m",
                  "sag_m", "m (static mid-span sag below the chord, every span sags down)",
                  "kappa_per_m", "1/m (curvature of the static sag, its size)", "deflection",
                  "1 (mode shape scaled to max |U|,|V| = 1)", "energy_share",
                  "1 (fraction of the mode's kinetic energy, diagonal mass)", "track", "n_long",
                  cfg->track.n_long, "n_trans", cfg->track.n_trans, "tension_n", cfg->track.tension,
                  "mass_per_length_kg_m", cfg->track.mass_per_length, "ea_n", cfg->track.ea);
    spans = circ = NULL;
    if (!doc) ts_err_set(err, TS_ERR_NOMEM, NULL, "could not build the modes JSON document");
    ts_circuit_free(c);
    return doc;
fail:
    if (err->code == TS_OK) ts_err_set(err, TS_ERR_INTERNAL, NULL, "modes failed");
    json_decref(spans);
    json_decref(circ);
    ts_circuit_free(c);
    return NULL;
}
