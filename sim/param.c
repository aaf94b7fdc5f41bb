/*
 * param.c — the section registry and the generic checks over the parameter table.
 * The rows themselves live beside their config structs in cfg_*.c.
 */
#include "param.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "config.h"

static const ts_param_section *const sections[] = {
    &ts_section_run,       &ts_section_track,   &ts_section_vehicle,
    &ts_section_terrain,   &ts_section_drive,   &ts_section_engine,
    &ts_section_driveline, &ts_section_control, &ts_section_coupling,
};
#define NSECTIONS ((int)(sizeof sections / sizeof sections[0]))

int ts_param_nsections(void)
{
    return NSECTIONS;
}

const ts_param_section *ts_param_section_at(int i)
{
    return (i >= 0 && i < NSECTIONS) ? sections[i] : NULL;
}

const ts_param *ts_param_find(const char *pointer)
{
    if (!pointer) return NULL;
    for (int s = 0; s < NSECTIONS; s++)
        for (int i = 0; i < sections[s]->nparams; i++)
            if (strcmp(sections[s]->params[i].pointer, pointer) == 0)
                return &sections[s]->params[i];
    return NULL;
}

const char *ts_param_type_name(ts_param_type t)
{
    switch (t) {
    case TS_PT_DOUBLE:
    case TS_PT_DOUBLE_OFF:
        return "number";
    case TS_PT_INT:
        return "integer";
    case TS_PT_BOOL:
        return "boolean";
    case TS_PT_ENUM:
        return "string";
    case TS_PT_STRING:
        return "string";
    case TS_PT_DARRAY:
        return "array";
    default:
        return "unknown";
    }
}

const char *ts_param_unit_gap(const ts_param *p)
{
    return p->unit && p->unit[0] && strcmp(p->unit, "1") != 0 ? " " : "";
}

const char *ts_param_unit_shown(const ts_param *p)
{
    return *ts_param_unit_gap(p) ? p->unit : "";
}

ts_rc ts_param_check_number(const ts_param *p, double v, ts_err *err)
{
    if (!isfinite(v))
        return ts_err_set(err, TS_ERR_RANGE, p->pointer, "%s: must be a finite number", p->pointer);
    if (p->type == TS_PT_DOUBLE_OFF && v == 0) return TS_OK;
    if (v < p->min || v > p->max) {
        if (p->type == TS_PT_DOUBLE_OFF)
            return ts_err_set(err, TS_ERR_RANGE, p->pointer,
                              "%s: 0 (off) or a number in [%g, %g]%s%s, got %g", p->pointer, p->min,
                              p->max, ts_param_unit_gap(p), ts_param_unit_shown(p), v);
        if (p->type == TS_PT_INT)
            return ts_err_set(err, TS_ERR_RANGE, p->pointer, "%s: integer in [%g, %g], got %g",
                              p->pointer, p->min, p->max, v);
        return ts_err_set(err, TS_ERR_RANGE, p->pointer, "%s: number in [%g, %g]%s%s, got %g",
                          p->pointer, p->min, p->max, ts_param_unit_gap(p), ts_param_unit_shown(p),
                          v);
    }
    return TS_OK;
}

int ts_param_enum_index(const ts_param *p, const char *name)
{
    if (p->type != TS_PT_ENUM || !p->enum_names || !name) return -1;
    for (int i = 0; p->enum_names[i]; i++)
        if (strcmp(p->enum_names[i], name) == 0) return i;
    return -1;
}

static int enum_count(const ts_param *p)
{
    int n = 0;
    while (p->enum_names && p->enum_names[n])
        n++;
    return n;
}

/* Fields are read by byte offset into the config struct; memcpy keeps that
 * free of alignment and aliasing questions. */
static double get_double(const char *at, int k)
{
    double v;
    memcpy(&v, at + (size_t)k * sizeof v, sizeof v);
    return v;
}

static int get_int(const char *at)
{
    int v;
    memcpy(&v, at, sizeof v);
    return v;
}

double ts_param_get_double(const void *cfg, const ts_param *p, int k)
{
    return get_double((const char *)cfg + p->offset, k);
}

void ts_param_set_double(void *cfg, const ts_param *p, int k, double v)
{
    memcpy((char *)cfg + p->offset + (size_t)k * sizeof v, &v, sizeof v);
}

int ts_param_get_int(const void *cfg, size_t offset)
{
    return get_int((const char *)cfg + offset);
}

void ts_param_set_int(void *cfg, size_t offset, int v)
{
    memcpy((char *)cfg + offset, &v, sizeof v);
}

ts_rc ts_param_validate(const void *cfg, ts_err *err)
{
    const char *base = cfg;
    for (int s = 0; s < NSECTIONS; s++) {
        for (int i = 0; i < sections[s]->nparams; i++) {
            const ts_param *p = &sections[s]->params[i];
            const char *at = base + p->offset;
            ts_rc rc = TS_OK;
            switch (p->type) {
            case TS_PT_DOUBLE:
            case TS_PT_DOUBLE_OFF:
                rc = ts_param_check_number(p, get_double(at, 0), err);
                break;
            case TS_PT_INT:
                rc = ts_param_check_number(p, get_int(at), err);
                break;
            case TS_PT_BOOL: {
                int v = get_int(at);
                if (v != 0 && v != 1)
                    rc = ts_err_set(err, TS_ERR_RANGE, p->pointer, "%s: boolean, got %d",
                                    p->pointer, v);
                break;
            }
            case TS_PT_ENUM: {
                int v = get_int(at);
                if (v < 0 || v >= enum_count(p))
                    rc = ts_err_set(err, TS_ERR_RANGE, p->pointer, "%s: enum index %d out of range",
                                    p->pointer, v);
                break;
            }
            case TS_PT_STRING:
                if (!memchr(at, '\0', (size_t)p->capacity))
                    rc = ts_err_set(err, TS_ERR_RANGE, p->pointer, "%s: string not terminated",
                                    p->pointer);
                break;
            case TS_PT_DARRAY: {
                int n = get_int(base + p->count_offset);
                if (n < 0 || n > p->capacity) {
                    rc = ts_err_set(err, TS_ERR_RANGE, p->pointer,
                                    "%s: array of at most %d numbers, got %d", p->pointer,
                                    p->capacity, n);
                    break;
                }
                for (int k = 0; k < n && rc == TS_OK; k++) {
                    rc = ts_param_check_number(p, get_double(at, k), err);
                    if (rc != TS_OK && err) {
                        char ptr[TS_ERR_POINTER_LEN];
                        snprintf(ptr, sizeof ptr, "%s/%d", p->pointer, k);
                        memcpy(err->pointer, ptr, sizeof ptr);
                    }
                }
                break;
            }
            default:
                rc = ts_err_set(err, TS_ERR_INTERNAL, p->pointer, "bad param type");
            }
            if (rc != TS_OK) return rc;
        }
    }
    return TS_OK;
}
