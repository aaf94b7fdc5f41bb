/*
 * cfg_track.c — parameter-table rows of the "track" section (columns in param.h).
 * Defaults and their sources: sim/data/defaults/track.json.
 */
#include <stddef.h>

#include "config.h"

const char *const ts_track_fidelity_names[] = {
    "static", "lumped", "quasi_static", "longitudinal", "transverse", "coupled", NULL};

#define F(field) offsetof(ts_config, track.field)
static const ts_param rows[] = {
    {"/track/fidelity", TS_PT_ENUM, F(fidelity), "", 0, 0, ts_track_fidelity_names, 0, 0,
     "track model: static, lumped, quasi_static, longitudinal, transverse, coupled"},
    {"/track/n_long", TS_PT_INT, F(n_long), "1", 0, 16, NULL, 0, 0,
     "longitudinal modes per free span"},
    {"/track/n_trans", TS_PT_INT, F(n_trans), "1", 0, 16, NULL, 0, 0,
     "transverse modes per free span"},
    {"/track/pitch", TS_PT_DOUBLE, F(pitch), "m", 0.05, 0.5, NULL, 0, 0, "track pitch"},
    {"/track/mass_per_length", TS_PT_DOUBLE, F(mass_per_length), "kg/m", 1, 1000, NULL, 0, 0,
     "track mass per unit length"},
    {"/track/ea", TS_PT_DOUBLE, F(ea), "N", 1e5, 1e10, NULL, 0, 0, "axial stiffness EA"},
    {"/track/tension", TS_PT_DOUBLE, F(tension), "N", 100, 1e6, NULL, 0, 0,
     "static track tension P0, set by the idler's adjusting link on level ground (a start on "
     "uneven ground keeps that setting, so its rest tension differs)"},
    {"/track/damping_ratio", TS_PT_DOUBLE, F(damping_ratio), "1", 0, 1, NULL, 0, 0,
     "modal damping ratio of the span modes"},
    {"/track/translation_terms", TS_PT_BOOL, F(translation_terms), "", 0, 1, NULL, 0, 0,
     "keep the track translation-speed terms of Eqs. 1-2"},
    {"/track/no_compression", TS_PT_BOOL, F(no_compression), "", 0, 1, NULL, 0, 0,
     "modal spans carry no compression (slack law, as the massless elements); off: linear spans"},
    {"/track/modes_speed", TS_PT_DOUBLE, F(modes_speed), "m/s", -100, 100, NULL, 0, 0,
     "track speed for the eigenanalysis when translation_terms is on"},
    {"/track/modes_reported", TS_PT_INT, F(modes_reported), "1", 1, 200, NULL, 0, 0,
     "number of upper-circuit modes reported by tanksim modes"},
    {"/track/span_length", TS_PT_DARRAY, F(span_length), "m", 0.05, 20, NULL, TS_TRACK_MAX_SPANS,
     F(span_n), "single spans to analyse (chord lengths); empty: the layout's five spans"},
    {"/track/span_inclination", TS_PT_DARRAY, F(span_inclination), "rad", -1.6, 1.6, NULL,
     TS_TRACK_MAX_SPANS, F(span_inclination_n),
     "chord angle above horizontal of each /track/span_length span (same count)"},
};
#undef F

const ts_param_section ts_section_track = {"track", "track data and track-model fidelity", rows,
                                           (int)(sizeof rows / sizeof rows[0])};
