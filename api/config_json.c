/*
 * config_json.c — resolving and reading JSON run configs (config_json.h).
 */
#include "config_json.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../sim/file_read.h"
#include "../sim/terrain.h"
#include "json_error.h"
#include "problem.h"
#include "store.h"

#define PRESET_DIR       "sim/data/presets/"
#define DEFAULTS_DIR     "sim/data/defaults/"
#define MAX_PRESET_DEPTH 8

json_t *tsa_store_json(const char *path, ts_err *err)
{
    const tsa_file *f = tsa_store_find(path);
    if (!f) {
        ts_err_set(err, TS_ERR_NOTFOUND, NULL, "no file '%s' in the store", path);
        return NULL;
    }
    json_error_t je;
    json_t *j = json_loadb((const char *)f->data, f->size, JSON_REJECT_DUPLICATES, &je);
    if (!j) ts_err_set(err, TS_ERR_INTERNAL, NULL, "%s:%d: %s", path, je.line, je.text);
    return j;
}

/* The schema's word for comment keys: any value, ignored (tsa_strip_comments). */
static json_t *comment_keys(void)
{
    return json_pack("{s:{s:s}}", "^_", "description", "a comment: read and ignored");
}

/* Remove comment keys ("_...") recursively, arrays' elements included. */
void tsa_strip_comments(json_t *j)
{
    size_t i;
    json_t *v;
    if (json_is_array(j)) {
        json_array_foreach(j, i, v) tsa_strip_comments(v);
        return;
    }
    if (!json_is_object(j)) return;
    const char *key;
    void *tmp;
    json_object_foreach_safe(j, tmp, key, v)
    {
        if (key[0] == '_')
            json_object_del(j, key);
        else
            tsa_strip_comments(v);
    }
}

/* dst <- src, objects merged key by key, everything else replaced. */
static void deep_merge(json_t *dst, const json_t *src)
{
    const char *key;
    json_t *val;
    json_object_foreach((json_t *)src, key, val)
    {
        if (key[0] == '_') continue;
        json_t *cur = json_object_get(dst, key);
        if (json_is_object(cur) && json_is_object(val))
            deep_merge(cur, val);
        else
            json_object_set_new(dst, key, json_deep_copy(val));
    }
}

json_t *tsa_config_defaults(ts_err *err)
{
    json_t *root = json_object();
    if (!root) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        return NULL;
    }
    for (int s = 0; s < ts_param_nsections(); s++) {
        const ts_param_section *sec = ts_param_section_at(s);
        char path[256];
        snprintf(path, sizeof path, DEFAULTS_DIR "%s.json", sec->name);
        json_t *j = tsa_store_json(path, err);
        if (!j) {
            json_decref(root);
            return NULL;
        }
        tsa_strip_comments(j);
        json_object_set_new(root, sec->name, j);
    }
    return root;
}

json_t *tsa_preset_get(const char *name, ts_err *err)
{
    char path[256];
    for (const char *c = name; *c; c++)
        if (!(*c == '-' || *c == '_' || (*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9'))) {
            ts_err_set(err, TS_ERR_NOTFOUND, "/preset", "/preset: no preset named '%s'", name);
            return NULL;
        }
    snprintf(path, sizeof path, PRESET_DIR "%s.json", name);
    if (!tsa_store_find(path)) {
        ts_err_set(err, TS_ERR_NOTFOUND, "/preset", "/preset: no preset named '%s'", name);
        return NULL;
    }
    return tsa_store_json(path, err);
}

static const char *json_type_word(const json_t *j)
{
    switch (json_typeof(j)) {
    case JSON_OBJECT:
        return "object";
    case JSON_ARRAY:
        return "array";
    case JSON_STRING:
        return "string";
    case JSON_INTEGER:
        return "integer";
    case JSON_REAL:
        return "number";
    case JSON_TRUE:
    case JSON_FALSE:
        return "boolean";
    default:
        return "null";
    }
}

/* Merge a document (and, first, the preset chain it names) into merged. */
static ts_rc merge_document(json_t *merged, const json_t *doc, int depth, ts_err *err)
{
    json_t *preset = json_object_get(doc, "preset");
    if (preset) {
        if (!json_is_string(preset))
            return ts_err_set(err, TS_ERR_PARAM, "/preset", "/preset: string expected, got %s",
                              json_type_word(preset));
        if (depth >= MAX_PRESET_DEPTH)
            return ts_err_set(err, TS_ERR_PARAM, "/preset", "/preset: presets nest too deep");
        json_t *p = tsa_preset_get(json_string_value(preset), err);
        if (!p) {
            /* a name in a body is a bad value (400), not a missing route (404) */
            if (err && err->code == TS_ERR_NOTFOUND) err->code = TS_ERR_PARAM;
            return err ? err->code : TS_ERR_PARAM;
        }
        ts_rc rc = merge_document(merged, p, depth + 1, err);
        json_decref(p);
        if (rc != TS_OK) return rc;
    }
    const char *key;
    json_t *val;
    json_object_foreach((json_t *)doc, key, val)
    {
        if (strcmp(key, "description") == 0 && !json_is_string(val))
            return ts_err_set(err, TS_ERR_PARAM, "/description",
                              "/description: a string expected"); /* it was dropped unseen */
        if (strcmp(key, "preset") == 0 || strcmp(key, "description") == 0) continue;
        if (key[0] == '_') continue;
        if (depth > 0 && strcmp(key, "commands") == 0) continue; /* preset metadata */
        json_t *cur = json_object_get(merged, key);
        if (json_is_object(cur) && !json_is_object(val)) {
            /* a section given as a scalar or array would replace the whole section and
             * every one of its fields would then be reported missing: name the section */
            char ptr[TS_ERR_POINTER_LEN];
            tsa_pointer_join(ptr, sizeof ptr, "", key);
            return ts_err_set(err, TS_ERR_PARAM, ptr, "%s: object expected, got %s", ptr,
                              json_type_word(val));
        }
        if (json_is_object(cur) && json_is_object(val))
            deep_merge(cur, val);
        else
            json_object_set_new(merged, key, json_deep_copy(val));
    }
    return TS_OK;
}

json_t *tsa_config_resolve(const json_t *doc, ts_err *err)
{
    if (doc && !json_is_object(doc)) {
        tsa_root_err(err, TS_ERR_PARAM, "the config must be a JSON object");
        return NULL;
    }
    json_t *merged = tsa_config_defaults(err);
    if (!merged) return NULL;
    if (doc && merge_document(merged, doc, 0, err) != TS_OK) {
        json_decref(merged);
        return NULL;
    }
    return merged;
}

/* Append {pointer, message} to errors and keep the first in err. */
static void add_error(json_t *errors, ts_err *first, int *count, ts_rc code, const char *pointer,
                      const char *fmt, ...) __attribute__((format(printf, 6, 7)));
static void add_error(json_t *errors, ts_err *first, int *count, ts_rc code, const char *pointer,
                      const char *fmt, ...)
{
    char msg[TS_ERR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (*count == 0) ts_err_set(first, code, pointer, "%s", msg);
    tsa_errors_add(errors, *count, pointer, msg);
    (*count)++;
}

/* Read one field; returns 0 on success or after recording an error. */
static void read_field(const ts_param *p, const json_t *v, char *base, json_t *errors,
                       ts_err *first, int *count)
{
    char *at = base + p->offset;
    ts_err e;
    ts_err_clear(&e);
    switch (p->type) {
    case TS_PT_DOUBLE:
    case TS_PT_DOUBLE_OFF:
    case TS_PT_INT: {
        if (!json_is_number(v)) {
            add_error(errors, first, count, TS_ERR_PARAM, p->pointer, "%s: %s expected, got %s",
                      p->pointer, p->type == TS_PT_INT ? "integer" : "number", json_type_word(v));
            return;
        }
        double x = json_number_value(v);
        if (p->type == TS_PT_INT && x != floor(x)) {
            add_error(errors, first, count, TS_ERR_PARAM, p->pointer,
                      "%s: integer expected, got %g", p->pointer, x);
            return;
        }
        if (ts_param_check_number(p, x, &e) != TS_OK) {
            add_error(errors, first, count, e.code, p->pointer, "%s", e.msg);
            return;
        }
        if (p->type == TS_PT_INT)
            ts_param_set_int(base, p->offset, (int)x);
        else
            ts_param_set_double(base, p, 0, x);
        return;
    }
    case TS_PT_BOOL:
        if (!json_is_boolean(v)) {
            add_error(errors, first, count, TS_ERR_PARAM, p->pointer,
                      "%s: boolean expected, got %s", p->pointer, json_type_word(v));
            return;
        }
        ts_param_set_int(base, p->offset, json_is_true(v));
        return;
    case TS_PT_ENUM: {
        int idx = json_is_string(v) ? ts_param_enum_index(p, json_string_value(v)) : -1;
        if (idx < 0) {
            char names[256] = "";
            for (int i = 0; p->enum_names[i]; i++) {
                strncat(names, i ? ", " : "", sizeof names - strlen(names) - 1);
                strncat(names, p->enum_names[i], sizeof names - strlen(names) - 1);
            }
            if (json_is_string(v))
                add_error(errors, first, count, TS_ERR_RANGE, p->pointer,
                          "%s: one of [%s], got '%s'", p->pointer, names, json_string_value(v));
            else
                add_error(errors, first, count, TS_ERR_PARAM, p->pointer, "%s: one of [%s], got %s",
                          p->pointer, names, json_type_word(v));
            return;
        }
        ts_param_set_int(base, p->offset, idx);
        return;
    }
    case TS_PT_STRING: {
        if (!json_is_string(v)) {
            add_error(errors, first, count, TS_ERR_PARAM, p->pointer, "%s: string expected, got %s",
                      p->pointer, json_type_word(v));
            return;
        }
        size_t n = json_string_length(v);
        if (n + 1 > (size_t)p->capacity) {
            add_error(errors, first, count, TS_ERR_RANGE, p->pointer,
                      "%s: at most %d bytes of UTF-8, got %zu", p->pointer, p->capacity - 1, n);
            return;
        }
        memcpy(at, json_string_value(v), n + 1);
        return;
    }
    case TS_PT_DARRAY: {
        if (!json_is_array(v)) {
            add_error(errors, first, count, TS_ERR_PARAM, p->pointer,
                      "%s: array of numbers expected, got %s", p->pointer, json_type_word(v));
            return;
        }
        size_t n = json_array_size(v);
        if (n > (size_t)p->capacity) {
            add_error(errors, first, count, TS_ERR_RANGE, p->pointer,
                      "%s: at most %d values, got %zu", p->pointer, p->capacity, n);
            return;
        }
        for (size_t k = 0; k < n; k++) {
            json_t *el = json_array_get(v, k);
            char ptr[TS_ERR_POINTER_LEN];
            snprintf(ptr, sizeof ptr, "%s/%zu", p->pointer, k);
            if (!json_is_number(el)) {
                add_error(errors, first, count, TS_ERR_PARAM, ptr, "%s: number expected, got %s",
                          ptr, json_type_word(el));
                return;
            }
            double x = json_number_value(el);
            if (ts_param_check_number(p, x, &e) != TS_OK) {
                add_error(errors, first, count, TS_ERR_RANGE, ptr,
                          "%s: number in [%g, %g]%s%s, got %g", ptr, p->min, p->max,
                          ts_param_unit_gap(p), ts_param_unit_shown(p), x);
                return;
            }
            ts_param_set_double(base, p, (int)k, x);
        }
        ts_param_set_int(base, p->count_offset, (int)n);
        return;
    }
    default:
        add_error(errors, first, count, TS_ERR_INTERNAL, p->pointer, "bad param type");
    }
}

/* A shipped bump course named by /terrain/course is taken from the embedded
 * store (so a daemon or runner started anywhere finds it) and written into
 * the inline bump arrays; a course not in the store, or any course when
 * /terrain/course_dir names another directory than the shipped one, is left
 * for sim/terrain.c to read from /terrain/course_dir (user courses on disk:
 * a user's own apg4-synth.txt there was silently replaced by the shipped
 * one; CLI review, session 20). */
#define SHIPPED_COURSE_DIR "sim/data/terrain" /* terrain.json's default, the store's prefix */

int tsa_course_dir_is_shipped(const ts_terrain_config *t)
{
    return strcmp(t->course_dir, SHIPPED_COURSE_DIR) == 0;
}

static ts_rc fill_course(ts_config *cfg, json_t *errors, ts_err *err)
{
    ts_terrain_config *tc = &cfg->terrain;
    /* an inline list, even a partial one (ts_terrain_make refuses that), is not overridden */
    if (tc->kind != TS_TERRAIN_BUMPS || tc->bump_n > 0 || tc->bump_height_n > 0 ||
        tc->bump_length_n > 0 || !tc->course[0])
        return TS_OK;
    if (!tsa_course_dir_is_shipped(tc)) return TS_OK; /* the user's directory */
    char path[TS_NAME_LEN + 64];
    snprintf(path, sizeof path, SHIPPED_COURSE_DIR "/%s.txt", tc->course);
    const tsa_file *f = tsa_store_find(path);
    if (!f) return TS_OK;
    double length;
    int n = 0;
    ts_rc rc = ts_terrain_parse_course((const char *)f->data, tc->bump_start, tc->bump_height,
                                       tc->bump_length, TS_TERRAIN_BUMPS_MAX, &n, &length, err);
    if (rc != TS_OK) {
        if (errors && err)
            json_array_append_new(errors, json_pack("{s:s,s:s}", "pointer", "/terrain/course",
                                                    "message", err->msg));
        return rc;
    }
    tc->bump_n = tc->bump_height_n = tc->bump_length_n = n;
    return TS_OK;
}

ts_rc tsa_config_read(const json_t *resolved, ts_config *cfg, json_t *errors, ts_err *err)
{
    ts_err_clear(err);
    int count = 0;
    memset(cfg, 0, sizeof *cfg);
    char *base = (char *)cfg;
    if (!json_is_object(resolved)) {
        add_error(errors, err, &count, TS_ERR_PARAM, "", "the config must be a JSON object");
        return TS_ERR_PARAM;
    }
    /* Unknown sections and fields first, so a typo is named as such. */
    const char *skey;
    json_t *sval;
    json_object_foreach((json_t *)resolved, skey, sval)
    {
        if (skey[0] == '_') continue;
        const ts_param_section *sec = NULL;
        for (int s = 0; s < ts_param_nsections(); s++)
            if (strcmp(ts_param_section_at(s)->name, skey) == 0) sec = ts_param_section_at(s);
        char ptr[TS_ERR_POINTER_LEN];
        tsa_pointer_join(ptr, sizeof ptr, "", skey);
        if (!sec) {
            add_error(errors, err, &count, TS_ERR_PARAM, ptr, "%s: unknown section", ptr);
            continue;
        }
        if (!json_is_object(sval)) {
            add_error(errors, err, &count, TS_ERR_PARAM, ptr, "%s: object expected, got %s", ptr,
                      json_type_word(sval));
            continue;
        }
        const char *fkey;
        json_t *fval;
        json_object_foreach(sval, fkey, fval)
        {
            if (fkey[0] == '_') continue;
            char fptr[TS_ERR_POINTER_LEN];
            tsa_pointer_join(fptr, sizeof fptr, ptr, fkey);
            if (!ts_param_find(fptr))
                add_error(errors, err, &count, TS_ERR_PARAM, fptr, "%s: unknown field", fptr);
        }
    }
    for (int s = 0; s < ts_param_nsections(); s++) {
        const ts_param_section *sec = ts_param_section_at(s);
        json_t *sobj = json_object_get(resolved, sec->name);
        for (int i = 0; i < sec->nparams; i++) {
            const ts_param *p = &sec->params[i];
            const char *field = strrchr(p->pointer, '/') + 1;
            json_t *v = json_is_object(sobj) ? json_object_get(sobj, field) : NULL;
            if (!v) {
                add_error(errors, err, &count, TS_ERR_PARAM, p->pointer,
                          "%s: missing (no default in the data files either)", p->pointer);
                continue;
            }
            read_field(p, v, base, errors, err, &count);
        }
    }
    if (count) return err && err->code ? err->code : TS_ERR_PARAM;
    return fill_course(cfg, errors, err);
}

ts_rc tsa_config_load(const json_t *doc, ts_config *cfg, json_t **resolved_out, json_t *errors,
                      ts_err *err)
{
    ts_err_clear(err);
    json_t *resolved = tsa_config_resolve(doc, err);
    if (!resolved) {
        if (errors && err)
            json_array_append_new(
                errors, json_pack("{s:s,s:s}", "pointer", err->pointer, "message", err->msg));
        return err ? err->code : TS_ERR_PARAM;
    }
    ts_rc rc = tsa_config_read(resolved, cfg, errors, err);
    if (rc == TS_OK && resolved_out)
        *resolved_out = resolved;
    else
        json_decref(resolved);
    return rc;
}

ts_rc tsa_config_runnable(const json_t *doc, const char *command, ts_err *err)
{
    json_t *owned = NULL;
    ts_rc rc = TS_OK;
    for (int depth = 0; depth <= MAX_PRESET_DEPTH && doc; depth++) {
        if (json_object_get(json_object_get(doc, "run"), "kind")) break; /* says what to run */
        json_t *name = json_object_get(doc, "preset");
        if (!json_is_string(name)) break;
        ts_err perr;
        json_t *p = tsa_preset_get(json_string_value(name), &perr);
        if (!p) break; /* the config load reports an unknown preset */
        json_t *cmds = json_object_get(p, "commands");
        int serves = !json_is_array(cmds);
        size_t i;
        json_t *c;
        json_array_foreach(cmds, i, c)
        {
            if (json_is_string(c) && strcmp(json_string_value(c), command) == 0) serves = 1;
        }
        if (!serves) {
            char list[128] = "";
            json_array_foreach(cmds, i, c)
            {
                if (!json_is_string(c)) continue;
                size_t k = strlen(list);
                snprintf(list + k, sizeof list - k, "%s%s", k ? ", " : "", json_string_value(c));
            }
            rc = ts_err_set(err, TS_ERR_PARAM, "/preset",
                            "/preset: '%s' is a preset for %s only (it sets no /run/kind); "
                            "start from another preset or give /run/kind",
                            json_string_value(name), list);
            json_decref(p);
            break;
        }
        json_decref(owned);
        owned = p;
        doc = p;
    }
    json_decref(owned);
    return rc;
}

/* A config file is read once, whole, and parsed from memory: a parse error's
 * member is then named from the same bytes jansson saw, and a file that can be
 * read only once (a pipe, `<(...)`, /dev/stdin) works. Bounded: a config is a
 * few kB, so anything past TSA_CONFIG_FILE_MAX is refused, not buffered. */
#define TSA_CONFIG_FILE_MAX ((size_t)16 << 20)

ts_rc tsa_config_load_path(const char *path, ts_config *cfg, json_t **resolved_out, json_t *errors,
                           ts_err *err)
{
    struct stat st; /* a directory read as an empty document: say what it is */
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
        return ts_err_set(err, TS_ERR_IO, NULL, "%s: a directory, not a config file", path);
    size_t len = 0;
    char *text = ts_file_read(path, TSA_CONFIG_FILE_MAX, TS_READ_ANY, &len, err);
    if (!text) return err ? err->code : TS_ERR_IO;
    ts_rc rc;
    json_error_t je;
    json_t *doc = json_loadb(text, len, JSON_REJECT_DUPLICATES, &je);
    if (!doc) {
        char lead[TS_ERR_MSG_LEN / 2];
        snprintf(lead, sizeof lead, "%s:%d:%d", path, je.line, je.column);
        size_t upto = je.position > 0 ? (size_t)je.position : 0;
        rc = tsa_json_parse_err(text, upto < len ? upto : len, &je, lead, err);
        free(text);
        return rc;
    }
    free(text);
    rc = tsa_config_load(doc, cfg, resolved_out, errors, err);
    json_decref(doc);
    return rc;
}

static json_t *field_to_json(const ts_param *p, const char *base)
{
    const char *at = base + p->offset;
    switch (p->type) {
    case TS_PT_DOUBLE:
    case TS_PT_DOUBLE_OFF:
        return json_real(ts_param_get_double(base, p, 0));
    case TS_PT_INT:
        return json_integer(ts_param_get_int(base, p->offset));
    case TS_PT_BOOL:
        return json_boolean(ts_param_get_int(base, p->offset));
    case TS_PT_ENUM:
        return json_string(p->enum_names[ts_param_get_int(base, p->offset)]);
    case TS_PT_STRING:
        return json_string(at);
    case TS_PT_DARRAY: {
        json_t *a = json_array();
        int n = ts_param_get_int(base, p->count_offset);
        for (int k = 0; k < n; k++)
            json_array_append_new(a, json_real(ts_param_get_double(base, p, k)));
        return a;
    }
    default:
        return json_null();
    }
}

json_t *tsa_config_to_json(const ts_config *cfg)
{
    json_t *root = json_object();
    const char *base = (const char *)cfg;
    for (int s = 0; s < ts_param_nsections(); s++) {
        const ts_param_section *sec = ts_param_section_at(s);
        json_t *o = json_object();
        for (int i = 0; i < sec->nparams; i++) {
            const ts_param *p = &sec->params[i];
            json_object_set_new(o, strrchr(p->pointer, '/') + 1, field_to_json(p, base));
        }
        json_object_set_new(root, sec->name, o);
    }
    return root;
}

/* NAME of each SHIPPED_COURSE_DIR/NAME.txt in the store. The schema gives
 * them as /terrain/course's "examples" (the dashboard offers them: a user
 * typed a name blind until the daemon's 400 listed them). */
json_t *tsa_shipped_courses(void)
{
    json_t *names = json_array();
    const tsa_file *f;
    for (int i = 0; names && (f = tsa_store_nth(SHIPPED_COURSE_DIR "/", ".txt", i)); i++) {
        const char *base = f->path + strlen(SHIPPED_COURSE_DIR "/");
        json_array_append_new(names, json_stringn(base, strlen(base) - strlen(".txt")));
    }
    return names;
}

json_t *tsa_config_schema(void)
{
    ts_err e;
    json_t *defaults = tsa_config_defaults(&e);
    json_t *props = json_object();
    json_object_set_new(props, "preset",
                        json_pack("{s:s,s:s}", "type", "string", "description",
                                  "name of a shipped preset to start from (GET /v1/presets)"));
    json_object_set_new(props, "description",
                        json_pack("{s:s,s:s}", "type", "string", "description", "free text"));
    for (int s = 0; s < ts_param_nsections(); s++) {
        const ts_param_section *sec = ts_param_section_at(s);
        json_t *sprops = json_object();
        json_t *sdef = json_object_get(defaults, sec->name);
        for (int i = 0; i < sec->nparams; i++) {
            const ts_param *p = &sec->params[i];
            const char *field = strrchr(p->pointer, '/') + 1;
            json_t *f = json_pack("{s:s,s:s}", "type", ts_param_type_name(p->type), "description",
                                  p->description);
            if (p->unit && p->unit[0]) json_object_set_new(f, "x-unit", json_string(p->unit));
            switch (p->type) {
            case TS_PT_DOUBLE:
            case TS_PT_INT:
                json_object_set_new(f, "minimum", json_real(p->min));
                json_object_set_new(f, "maximum", json_real(p->max));
                break;
            case TS_PT_DOUBLE_OFF: /* 0 (off), or in [min, max] */
                json_object_set_new(f, "anyOf",
                                    json_pack("[{s:i},{s:f,s:f}]", "const", 0, "minimum", p->min,
                                              "maximum", p->max));
                break;
            case TS_PT_ENUM: {
                json_t *en = json_array();
                for (int k = 0; p->enum_names[k]; k++)
                    json_array_append_new(en, json_string(p->enum_names[k]));
                json_object_set_new(f, "enum", en);
                break;
            }
            case TS_PT_STRING:
                /* the limit is in bytes (the C field's size): maxLength, which counts
                 * characters, is exact for ASCII; x-max-bytes holds for any text */
                json_object_set_new(f, "maxLength", json_integer(p->capacity - 1));
                json_object_set_new(f, "x-max-bytes", json_integer(p->capacity - 1));
                /* not an enum: with --client-files yes a daemon reads other courses */
                if (strcmp(p->pointer, "/terrain/course") == 0)
                    json_object_set_new(f, "examples", tsa_shipped_courses());
                break;
            case TS_PT_DARRAY:
                json_object_set_new(f, "maxItems", json_integer(p->capacity));
                json_object_set_new(f, "items",
                                    json_pack("{s:s,s:f,s:f}", "type", "number", "minimum", p->min,
                                              "maximum", p->max));
                break;
            default:
                break;
            }
            json_t *dv = json_object_get(sdef, field);
            if (dv) json_object_set(f, "default", dv);
            json_object_set_new(sprops, field, f);
        }
        json_object_set_new(props, sec->name,
                            json_pack("{s:s,s:s,s:o,s:o,s:b}", "type", "object", "description",
                                      sec->description, "properties", sprops, "patternProperties",
                                      comment_keys(), "additionalProperties", 0));
    }
    json_decref(defaults);
    return json_pack("{s:s,s:s,s:s,s:o,s:o,s:b}", "$schema",
                     "https://json-schema.org/draft/2020-12/schema", "title", "tanksim run config",
                     "type", "object", "properties", props, "patternProperties", comment_keys(),
                     "additionalProperties", 0);
}

static int cmp_name(const void *a, const void *b)
{
    return strcmp(json_string_value(json_object_get(*(json_t *const *)a, "name")),
                  json_string_value(json_object_get(*(json_t *const *)b, "name")));
}

json_t *tsa_preset_list(void)
{
    json_t *items[256] = {0};
    int n = 0;
    const tsa_file *f;
    for (int i = 0; n < 256 && (f = tsa_store_nth(PRESET_DIR, ".json", i)); i++) {
        const char *base = f->path + strlen(PRESET_DIR);
        char name[128];
        snprintf(name, sizeof name, "%.*s", (int)(strlen(base) - 5), base);
        json_error_t je;
        json_t *doc = json_loadb((const char *)f->data, f->size, 0, &je);
        json_t *desc = doc ? json_object_get(doc, "description") : NULL;
        items[n] = json_pack("{s:s,s:s}", "name", name, "description",
                             json_is_string(desc) ? json_string_value(desc) : "");
        json_t *cmds = doc ? json_object_get(doc, "commands") : NULL;
        if (json_is_array(cmds)) json_object_set(items[n], "commands", cmds);
        n++;
        json_decref(doc);
    }
    qsort(items, (size_t)n, sizeof items[0], cmp_name);
    json_t *arr = json_array();
    for (int i = 0; i < n; i++)
        json_array_append_new(arr, items[i]);
    return arr;
}

/* (config_json.h) moved from server/routes.c: the daemon's query numbers,
 * the CLI's options and the tuning schedules read text numbers alike */
int tsa_is_decimal(const char *v, int integer)
{
    const char *s = v;
    if (*s == '+' || *s == '-') s++;
    int digits = 0;
    while (isdigit((unsigned char)*s)) s++, digits++;
    if (!integer && *s == '.')
        for (s++; isdigit((unsigned char)*s); s++) digits++;
    if (!digits) return 0;
    if (!integer && (*s == 'e' || *s == 'E')) {
        s++;
        if (*s == '+' || *s == '-') s++;
        if (!isdigit((unsigned char)*s)) return 0;
        while (isdigit((unsigned char)*s)) s++;
    }
    return *s == '\0';
}

int tsa_parse_number(const char *v, double lo, double hi, double *out)
{
    if (!tsa_is_decimal(v, 0)) return -1;
    errno = 0; /* ERANGE: beyond a double, or below its normal range */
    double x = strtod(v, NULL);
    if (errno || !isfinite(x) || x < lo || x > hi) return -1;
    *out = x;
    return 0;
}

int tsa_parse_integer(const char *v, long lo, long hi, long *out)
{
    if (!tsa_is_decimal(v, 1)) return -1;
    errno = 0; /* ERANGE: beyond a long */
    long x = strtol(v, NULL, 10);
    if (errno || x < lo || x > hi) return -1;
    *out = x;
    return 0;
}
