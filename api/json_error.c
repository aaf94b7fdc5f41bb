/*
 * json_error.c — the JSON Pointer of a parse error (json_error.h).
 *
 * A scanner reads the text up to the parser's stop token by token, as
 * jansson's lexer cuts it, and follows the grammar with a stack of open
 * containers: for each its state, the index of the element being read (an
 * array) and where its pointer ends in `ptr` (the pointer of the innermost
 * open container). The key being read in the innermost object is kept,
 * already escaped for a pointer (~ as ~0, / as ~1), in `key`. The last token
 * (the one the parser stopped on) is not fed to the grammar but asked where
 * it stands (culprit_pointer); so is the first token the grammar refuses.
 */
#include "json_error.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "session_json.h"

enum tok {
    T_END,    /* nothing before the stop */
    T_LBRACE, /* { */
    T_RBRACE, /* } */
    T_LBRACK, /* [ */
    T_RBRACK, /* ] */
    T_COLON,
    T_COMMA,
    T_STRING, /* a string closed before the stop */
    T_OPEN,   /* a string the stop cuts */
    T_SCALAR, /* a number, true, false, null or another word */
    T_OTHER,  /* any other byte */
};

enum state {
    S_OBJ_FIRST, /* after {: a key or } */
    S_OBJ_KEY,   /* after ,: a key */
    S_OBJ_COLON, /* after a key: : */
    S_OBJ_VALUE, /* after :: the member's value */
    S_OBJ_NEXT,  /* after a member: , or } */
    S_ARR_FIRST, /* after [: a value or ] */
    S_ARR_VALUE, /* after ,: a value */
    S_ARR_NEXT,  /* after a value: , or ] */
};

typedef struct frame {
    enum state state;
    size_t index; /* array: the element being read */
    size_t len;   /* length of this container's pointer in ptr */
} frame;

typedef struct scan {
    const char *s;
    size_t pos; /* the stop: bytes [0, pos) are read */
    frame *st;
    size_t depth, cap;
    int done;   /* the root value is complete */
    int key_ok; /* key holds the innermost object's current key */
    tsa_buf ptr, key;
} scan;

typedef struct token {
    enum tok kind;
    size_t start, end;
} token;

static int is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

static int is_digit(char c)
{
    return c >= '0' && c <= '9';
}

static int is_alpha(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}

static size_t skip_blanks(const scan *sc, size_t i)
{
    while (i < sc->pos && is_blank(sc->s[i]))
        i++;
    return i;
}

static size_t skip_digits(const scan *sc, size_t i)
{
    while (i < sc->pos && is_digit(sc->s[i]))
        i++;
    return i;
}

/* End of the number at i, cut where jansson's lexer cuts it: "-", "0" before
 * a digit, "1.", "1e" and "1e+" end a (bad) token ("1.e5" at "1.", "01" at
 * "0", "-01" at "-0"). */
static size_t number_end(const scan *sc, size_t i)
{
    if (i < sc->pos && sc->s[i] == '-') i++;
    if (i < sc->pos && sc->s[i] == '0')
        i++;
    else
        i = skip_digits(sc, i);
    if (i < sc->pos && sc->s[i] == '.') {
        if (i + 1 >= sc->pos || !is_digit(sc->s[i + 1])) return i + 1;
        i = skip_digits(sc, i + 1);
    }
    if (i < sc->pos && (sc->s[i] == 'e' || sc->s[i] == 'E')) {
        i++;
        if (i < sc->pos && (sc->s[i] == '+' || sc->s[i] == '-')) i++;
        i = skip_digits(sc, i);
    }
    return i;
}

/* End of the string whose quote is at i: past its closing quote, or pos
 * (then *open = 1) when the stop comes first. */
static size_t string_end(const scan *sc, size_t i, int *open)
{
    for (i++; i < sc->pos; i++) {
        if (sc->s[i] == '"') {
            *open = 0;
            return i + 1;
        }
        if (sc->s[i] == '\\') i++; /* the escaped byte */
    }
    *open = 1;
    return sc->pos;
}

/* The token at or after *i (blanks skipped); *i moves past it. */
static token next_token(const scan *sc, size_t *i)
{
    token t = {T_END, 0, 0};
    size_t at = skip_blanks(sc, *i);
    t.start = t.end = at;
    if (at >= sc->pos) {
        *i = at;
        return t;
    }
    char c = sc->s[at];
    int open = 0;
    t.end = at + 1;
    switch (c) {
    case '{':
        t.kind = T_LBRACE;
        break;
    case '}':
        t.kind = T_RBRACE;
        break;
    case '[':
        t.kind = T_LBRACK;
        break;
    case ']':
        t.kind = T_RBRACK;
        break;
    case ':':
        t.kind = T_COLON;
        break;
    case ',':
        t.kind = T_COMMA;
        break;
    case '"':
        t.end = string_end(sc, at, &open);
        t.kind = open ? T_OPEN : T_STRING;
        break;
    default:
        if (c == '-' || is_digit(c)) {
            t.kind = T_SCALAR;
            t.end = number_end(sc, at);
        } else if (is_alpha(c)) {
            t.kind = T_SCALAR;
            while (t.end < sc->pos && is_alpha(sc->s[t.end]))
                t.end++;
        } else {
            t.kind = T_OTHER;
        }
    }
    *i = t.end;
    return t;
}

/* One decoded byte of a key, escaped for a pointer (RFC 6901: ~0, ~1). */
static void put_key_byte(tsa_buf *b, char c)
{
    if (c == '~')
        tsa_buf_put(b, "~0", 2);
    else if (c == '/')
        tsa_buf_put(b, "~1", 2);
    else
        tsa_buf_put(b, &c, 1);
}

/* The key of string token t, decoded (by jansson: the token alone is a JSON
 * string) and escaped, into b (emptied first). -1 when it names no member a
 * pointer can: an invalid escape, a lone surrogate, U+0000 (not in a C
 * string). */
static int decode_key(const scan *sc, token t, tsa_buf *b)
{
    b->n = 0;
    if (b->p) b->p[0] = '\0';
    json_error_t je;
    json_t *k = json_loadb(sc->s + t.start, t.end - t.start, JSON_DECODE_ANY, &je);
    if (!json_is_string(k)) {
        json_decref(k);
        return -1;
    }
    const char *v = json_string_value(k);
    for (size_t i = 0, n = json_string_length(k); i < n; i++)
        put_key_byte(b, v[i]);
    json_decref(k);
    return b->oom ? -1 : 0;
}

static frame *top(scan *sc)
{
    return sc->depth ? &sc->st[sc->depth - 1] : NULL;
}

/* Cut ptr back to n bytes. */
static void ptr_cut(scan *sc, size_t n)
{
    sc->ptr.n = n;
    if (sc->ptr.p) sc->ptr.p[n] = '\0';
}

/* Append the segment of the value being read in f ("/key" or "/index") to b. */
static void put_segment(const scan *sc, const frame *f, tsa_buf *b)
{
    if (f->state == S_ARR_FIRST || f->state == S_ARR_VALUE)
        tsa_buf_printf(b, "/%zu", f->index);
    else if (sc->key_ok)
        tsa_buf_printf(b, "/%s", sc->key.p ? sc->key.p : "");
}

/* Open a container as the value being read; -1 when out of memory. */
static int push(scan *sc, enum tok kind)
{
    frame *f = top(sc);
    if (f) put_segment(sc, f, &sc->ptr);
    if (sc->depth == sc->cap) {
        size_t cap = sc->cap ? 2 * sc->cap : 16;
        frame *st = realloc(sc->st, cap * sizeof *st);
        if (!st) return -1;
        sc->st = st;
        sc->cap = cap;
    }
    frame nf = {kind == T_LBRACE ? S_OBJ_FIRST : S_ARR_FIRST, 0, sc->ptr.n};
    sc->st[sc->depth++] = nf;
    sc->key_ok = 0;
    return sc->ptr.oom ? -1 : 0;
}

/* A value in the innermost container (or the root) is complete. */
static void value_done(scan *sc)
{
    frame *f = top(sc);
    if (!f)
        sc->done = 1;
    else
        f->state = f->state == S_OBJ_VALUE ? S_OBJ_NEXT : S_ARR_NEXT;
}

static void pop(scan *sc)
{
    sc->depth--;
    frame *f = top(sc);
    ptr_cut(sc, f ? f->len : 0);
    sc->key_ok = 0; /* the parent object's key is not needed after its value */
    value_done(sc);
}

static int is_value_start(enum tok k)
{
    return k == T_LBRACE || k == T_LBRACK || k == T_STRING || k == T_SCALAR;
}

/* Feed token t to the grammar: 0, 1 when it does not fit there (it is the
 * culprit), -1 when out of memory. */
static int feed(scan *sc, token t)
{
    frame *f = top(sc);
    if (sc->done) return 1;
    enum state st = f ? f->state : S_ARR_VALUE; /* the root: a value */
    switch (st) {
    case S_OBJ_FIRST:
    case S_OBJ_KEY:
        if (t.kind == T_RBRACE && st == S_OBJ_FIRST) {
            pop(sc);
            return 0;
        }
        if (t.kind != T_STRING || decode_key(sc, t, &sc->key) != 0) return 1;
        sc->key_ok = 1;
        f->state = S_OBJ_COLON;
        return 0;
    case S_OBJ_COLON:
        if (t.kind != T_COLON) return 1;
        f->state = S_OBJ_VALUE;
        return 0;
    case S_OBJ_NEXT:
    case S_ARR_NEXT:
        if (t.kind == (st == S_OBJ_NEXT ? T_RBRACE : T_RBRACK)) {
            pop(sc);
            return 0;
        }
        if (t.kind != T_COMMA) return 1;
        if (st == S_ARR_NEXT) f->index++;
        f->state = st == S_OBJ_NEXT ? S_OBJ_KEY : S_ARR_VALUE;
        return 0;
    case S_OBJ_VALUE:
    case S_ARR_FIRST:
    case S_ARR_VALUE:
        if (t.kind == T_RBRACK && st == S_ARR_FIRST) {
            pop(sc);
            return 0;
        }
        if (!is_value_start(t.kind)) return 1;
        if (t.kind == T_LBRACE || t.kind == T_LBRACK) return push(sc, t.kind);
        value_done(sc);
        return 0;
    }
    return 1;
}

/* Pointer of the place culprit t stands in, into b. */
static void culprit_pointer(scan *sc, token t, tsa_buf *b)
{
    frame *f = top(sc);
    tsa_buf_put(b, "", 0);
    if (!f) return; /* the root value, or text after it */
    tsa_buf_put(b, sc->ptr.p ? sc->ptr.p : "", sc->ptr.n);
    switch (f->state) {
    case S_OBJ_FIRST:
    case S_OBJ_KEY: /* a key that is whole names its member; else the object */
        if (t.kind == T_STRING && decode_key(sc, t, &sc->key) == 0) {
            sc->key_ok = 1;
            put_segment(sc, f, b);
        }
        return;
    case S_OBJ_COLON:
    case S_OBJ_VALUE:
    case S_ARR_FIRST:
    case S_ARR_VALUE: /* the member or element being read */
        put_segment(sc, f, b);
        return;
    case S_OBJ_NEXT:
    case S_ARR_NEXT: /* between members: the container */
        return;
    }
}

/* b into out (n bytes), cut at a segment boundary when it does not fit. */
static void copy_whole_segments(const tsa_buf *b, char *out, size_t n)
{
    size_t k = b->n;
    if (k >= n) {
        k = n - 1;
        while (k > 0 && b->p[k] != '/')
            k--;
    }
    memcpy(out, b->p, k);
    out[k] = '\0';
}

int tsa_json_pointer_at(const char *text, size_t pos, tsa_stop stop, char *out, size_t n)
{
    if (n == 0) return 0;
    out[0] = '\0';
    scan sc = {.s = text ? text : "", .pos = text ? pos : 0};
    token culprit = {T_END, pos, pos};
    int rc = 0;
    for (size_t i = 0;;) {
        token t = next_token(&sc, &i);
        if (t.kind == T_END) break; /* the culprit is what begins at pos */
        int last = skip_blanks(&sc, i) >= pos;
        if (t.kind == T_OPEN || (last && stop == TSA_STOP_ON_TOKEN)) {
            culprit = t;
            break;
        }
        rc = feed(&sc, t);
        if (rc != 0) {
            culprit = t;
            break;
        }
    }
    tsa_buf res = {0};
    if (rc >= 0) culprit_pointer(&sc, culprit, &res);
    if (rc < 0 || sc.ptr.oom || sc.key.oom || res.oom || !res.p)
        rc = -1;
    else
        copy_whole_segments(&res, out, n);
    tsa_buf_free(&res);
    tsa_buf_free(&sc.ptr);
    tsa_buf_free(&sc.key);
    free(sc.st);
    return rc < 0 ? -1 : 0;
}

ts_rc tsa_json_parse_err(const char *text, size_t len, const json_error_t *je, const char *lead,
                         ts_err *err)
{
    enum json_error_code code = json_error_code(je);
    if (code == json_error_out_of_memory || !je->text[0])
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "%s: out of memory while parsing", lead);
    size_t pos = je->position < 0 ? 0 : (size_t)je->position;
    if (pos > len) pos = len;
    tsa_stop stop = code == json_error_premature_end_of_input || code == json_error_invalid_utf8
                        ? TSA_STOP_AT_POS
                        : TSA_STOP_ON_TOKEN;
    char ptr[TS_ERR_POINTER_LEN];
    tsa_json_pointer_at(text, pos, stop, ptr, sizeof ptr); /* "" (the root) if out of memory */
    ts_err_set(err, TS_ERR_PARAM, ptr, "%s%s%s: %s", ptr, ptr[0] ? ": " : "", lead, je->text);
    if (err) err->at_root = ptr[0] == '\0';
    return TS_ERR_PARAM;
}
