/*
 * config_json.h — JSON run configs <-> ts_config, through the parameter table.
 *
 * A run config document is {"preset": NAME?, "<section>": {...}, ...}. It is
 * resolved by deep-merging, in order: the defaults (sim/data/defaults/SECTION.json),
 * the named preset (sim/data/presets/NAME.json, which may itself name a base
 * preset), then the document's own fields. Objects merge key by key; numbers,
 * strings and arrays replace. Keys starting with '_' are comments and ignored.
 * The resolved document is then read field by field through the table:
 * unknown fields, wrong types and out-of-range values are reported with the
 * JSON Pointer of the field, every violation at once in an errors array of
 * {"pointer", "message"} (RFC 9457 style), the first also in ts_err.
 *
 * Ownership: functions returning json_t* return a NEW reference the caller
 * must json_decref; NULL on failure with err filled.
 */
#ifndef TSA_CONFIG_JSON_H
#define TSA_CONFIG_JSON_H

#include <jansson.h>

#include "../sim/config.h"
#include "../sim/errors.h"

/* Parse a JSON file of the embedded store ("sim/data/presets/x.json"). */
json_t *tsa_store_json(const char *path, ts_err *err);

/* Remove comment keys ("_...", read and ignored by the loader) from j in
 * place, in objects at any depth, arrays' elements included. The daemon
 * keeps a request without them (a comment may be most of a body). */
void tsa_strip_comments(json_t *j);

/* The defaults document {section: {field: value}} with comment keys removed. */
json_t *tsa_config_defaults(ts_err *err);

/* Resolve a document (see above); doc may be NULL for plain defaults. */
json_t *tsa_config_resolve(const json_t *doc, ts_err *err);

/* Read a resolved document into cfg. errors (may be NULL) is a JSON array that
 * receives every violation; returns the first one's code. */
TS_MUST_CHECK ts_rc tsa_config_read(const json_t *resolved, ts_config *cfg, json_t *errors,
                                    ts_err *err);

/* Resolve + read in one call; *resolved_out (if non-NULL) gets the resolved
 * document (new reference) on success. */
TS_MUST_CHECK ts_rc tsa_config_load(const json_t *doc, ts_config *cfg, json_t **resolved_out,
                                    json_t *errors, ts_err *err);

/* Write a config back as a document {section: {field: value}}. */
json_t *tsa_config_to_json(const ts_config *cfg);

/* JSON Schema (draft 2020-12) of a run-config document, generated from the
 * parameter table with defaults from the data files. */
json_t *tsa_config_schema(void);

/* [{"name", "description"[, "commands"]}] of every shipped preset, sorted by
 * name; "commands" is there when the preset serves only those commands. */
json_t *tsa_preset_list(void);

/* The preset document as shipped (not resolved). TS_ERR_NOTFOUND if unknown. */
json_t *tsa_preset_get(const char *name, ts_err *err);

/* May doc be used by command ("run", "render", "tune", "engine-map", "session")?
 * No (TS_ERR_PARAM, pointer /preset) when its preset chain reaches a preset
 * whose "commands" list leaves command out (m1 and table1-span are for
 * "modes" only) before any document of the chain sets /run/kind itself. */
TS_MUST_CHECK ts_rc tsa_config_runnable(const json_t *doc, const char *command, ts_err *err);

/* 1 when v is a plain decimal numeral: [+-] digits [. digits] [(e|E) [+-]
 * digits], a digit before or after the point, no point or exponent when
 * integer. What strtod also takes (blanks, "0x10", "inf", "nan") is refused:
 * a number typed as text (query value, CLI option) means what it reads in
 * decimal. */
int tsa_is_decimal(const char *v, int integer);
/* v as an integer in [lo, hi] into *out: 0, or -1 when v is not a plain
 * decimal integer (tsa_is_decimal with integer: "640.5", "6.4e2", " 640",
 * "640px" are refused, not cut) or is outside [lo, hi]. The daemon's query
 * integers and the CLI's integer options. */
TS_MUST_CHECK int tsa_parse_integer(const char *v, long lo, long hi, long *out);
/* v as a number in [lo, hi] into *out: 0, or -1 when v is not a plain decimal
 * numeral (tsa_is_decimal), is beyond a double or below its normal range
 * (ERANGE), or is outside [lo, hi]. The daemon's query numbers and flags, the
 * CLI's number options, the tune schedule lists. */
TS_MUST_CHECK int tsa_parse_number(const char *v, double lo, double hi, double *out);

/* Read a config from a file path (a JSON document as above). */
TS_MUST_CHECK ts_rc tsa_config_load_path(const char *path, ts_config *cfg, json_t **resolved_out,
                                         json_t *errors, ts_err *err);

/* 1 when /terrain/course_dir is the shipped courses' directory (whose courses
 * come from the embedded store), 0 for a directory of the user's, read from
 * disk. */
int tsa_course_dir_is_shipped(const ts_terrain_config *t);

/* The shipped bump courses' names, in store order (a new JSON array of
 * strings; NULL only when out of memory): the schema's /terrain/course
 * examples and the daemon's unknown-course message. */
json_t *tsa_shipped_courses(void);

#endif
