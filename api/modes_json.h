/*
 * modes_json.h — eigenanalysis of the track (paper Section II.A, Table 1,
 * Fig. 5) as one JSON document, for `tanksim modes` and POST /v1/modes:
 *   {"spans":[{"name","length_m","inclination_rad","sag_m","lambda2",
 *              "string_f1_hz","kappa_per_m","frequencies_hz":{"longitudinal":[...],
 *              "transverse":[...],"coupled":[...]}}, ...],
 *    "circuit":{"boundary","dof","gyroscopic","speed_m_s","supports":[...],
 *               "frequencies_hz":[...],"mode_shapes":[...]},
 *    "units":{...}, "track":{...}}
 * spans: each free span alone with both ends fixed — the five spans of the
 * /vehicle layout, or the single spans of /track/span_length. Families:
 * longitudinal = the longitudinal sine modes alone (bar), transverse = the
 * transverse modes with quasi-static (uniform-tension, Irvine) stretch,
 * coupled = all modal coordinates (Eqs. 1-2). circuit: the upper track circuit
 * with road wheels 1 and 7 fixed (Fig. 5) and its mode shapes (energy shares
 * per span, sampled deflections). All numbers SI.
 */
#ifndef TSA_MODES_JSON_H
#define TSA_MODES_JSON_H

#include <jansson.h>

#include "../sim/config.h"
#include "../sim/errors.h"

/* The document (new reference), or NULL with err filled; config errors carry
 * the JSON Pointer of the config field (/track/..., /vehicle). */
json_t *tsa_modes_json(const ts_config *cfg, ts_err *err);

#endif
