/*
 * param.h — the one parameter table that describes every run-config field.
 *
 * Like Redis's command table or Lua's luaL_Reg, a const array of rows drives
 * everything that needs to know about a field: api/ walks it to read JSON into
 * a ts_config (type and range checks, errors naming the field by JSON Pointer),
 * to write a config back to JSON, and to generate the JSON Schema served at
 * /v1/schema; the docs are generated from it too. Default VALUES are not in the
 * table: they live in the data files under sim/data/ (with their sources), so
 * no number is written twice.
 *
 * Columns of ts_param:
 *   pointer     JSON Pointer of the field in a run config ("/track/ea")
 *   type        TS_PT_* below
 *   offset      offsetof(ts_config, ...) of the C field
 *   unit        SI unit ("N", "kg/m", "1" for dimensionless, "" for none)
 *   min, max    inclusive numeric range (numbers, integers, array elements,
 *               array counts use count_min/count_max)
 *   enum_names  NULL-terminated names for TS_PT_ENUM (C value = index)
 *   capacity    TS_PT_DARRAY: max elements; TS_PT_STRING: buffer size
 *   count_offset TS_PT_DARRAY: offsetof the int that holds the element count
 *   description one line for people
 */
#ifndef TS_PARAM_H
#define TS_PARAM_H

#include <stddef.h>

#include "errors.h"

typedef enum ts_param_type {
    TS_PT_DOUBLE, /* double */
    TS_PT_DOUBLE_OFF, /* double in [min, max], or exactly 0 = off (e.g. a step cap) */
    TS_PT_INT,    /* int */
    TS_PT_BOOL,   /* int, 0 or 1 */
    TS_PT_ENUM,   /* int index into enum_names; JSON string */
    TS_PT_STRING, /* char[capacity]; JSON string */
    TS_PT_DARRAY, /* double[capacity] + int count; JSON array of numbers */
    TS_NPT
} ts_param_type;

typedef struct ts_param {
    const char *pointer;
    ts_param_type type;
    size_t offset;
    const char *unit;
    double min, max;
    const char *const *enum_names;
    int capacity;
    size_t count_offset;
    const char *description;
} ts_param;

/* One section of the table (one JSON object under the config root). */
typedef struct ts_param_section {
    const char *name;        /* "track" */
    const char *description; /* one line */
    const ts_param *params;  /* rows */
    int nparams;
} ts_param_section;

/* The whole table, section by section in config order (static data). */
int ts_param_nsections(void);
const ts_param_section *ts_param_section_at(int i); /* NULL when i is out of range */

/* Look a row up by its JSON Pointer; NULL when the pointer names no field. */
const ts_param *ts_param_find(const char *pointer);

/* Name of a param type as JSON Schema spells it ("number", "integer", ...). */
const char *ts_param_type_name(ts_param_type t);

/* Check one numeric value against a row's range; fills err (naming the field)
 * and returns TS_ERR_RANGE when outside [min, max] or not finite. */
TS_MUST_CHECK ts_rc ts_param_check_number(const ts_param *p, double v, ts_err *err);

/* A parameter's unit for a message: ts_param_unit_gap gives " " and
 * ts_param_unit_shown the unit, or both "" for a dimensionless ("1") or
 * unitless parameter, so "[0, 1]%s%s" reads "[0, 1]" or "[0, 10] m". */
const char *ts_param_unit_gap(const ts_param *p);
const char *ts_param_unit_shown(const ts_param *p);

/* Index of name in a TS_PT_ENUM row's names, or -1. */
int ts_param_enum_index(const ts_param *p, const char *name);

/* Field access by table row, for code that walks the table (api/). k indexes
 * TS_PT_DARRAY elements (0 otherwise); INT, BOOL and ENUM fields are ints;
 * the count of a TS_PT_DARRAY is at p->count_offset. */
double ts_param_get_double(const void *cfg, const ts_param *p, int k);
void ts_param_set_double(void *cfg, const ts_param *p, int k, double v);
int ts_param_get_int(const void *cfg, size_t offset);
void ts_param_set_int(void *cfg, size_t offset, int v);

/* Validate a whole config struct against the table (ranges, enum indices,
 * array counts). Used after programmatic edits; JSON input is checked on read. */
TS_MUST_CHECK ts_rc ts_param_validate(const void *cfg, ts_err *err);

#endif
