/*
 * preset_config.h — test helper: a shipped preset's configuration, optionally
 * with another track fidelity, through the same loader the CLI and the daemon
 * use (api/config_json.c). Shared by the vehicle and coupled tests. Test code
 * only; a preset that does not load fails the test.
 */
#ifndef TS_TEST_PRESET_CONFIG_H
#define TS_TEST_PRESET_CONFIG_H

#include <jansson.h>

#include "api/config_json.h"

/* The configuration of preset; track_fidelity NULL keeps the preset's. */
static inline ts_config test_preset_config(const char *preset, const char *track_fidelity)
{
    ts_config c;
    ts_err err;
    json_t *doc = json_pack("{s:s}", "preset", preset);
    if (track_fidelity)
        json_object_set_new(doc, "track", json_pack("{s:s}", "fidelity", track_fidelity));
    if (tsa_config_load(doc, &c, NULL, NULL, &err) != TS_OK)
        fail_msg("preset %s: %s %s", preset, err.pointer, err.msg);
    json_decref(doc);
    return c;
}

#endif
