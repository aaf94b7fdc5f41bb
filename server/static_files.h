/*
 * static_files.h — tanksimd serves the browser dashboard (web_static/, built
 * by `make web`) at "/" and its assets at "/static/NAME".
 *
 * Only flat file names of [A-Za-z0-9._-] (1-100 characters) not starting with
 * '.' and with a known type (the last extension: .html .js .mjs .css .map
 * .json .svg .png .ico .txt) are served, with Cache-Control: no-cache and
 * X-Content-Type-Options: nosniff, from
 * the one --web-root directory, opened with O_NOFOLLOW and required to be
 * regular files: no directory traversal, no symlink escapes, no listings.
 */
#ifndef TSD_STATIC_FILES_H
#define TSD_STATIC_FILES_H

#include <stddef.h>

#include "server.h"

/* The default --web-root: "<dir of the executable>/../web_static" when that
 * holds index.html (build/tanksimd in a checkout), else "./web_static". */
void tsd_static_default_root(char *out, size_t n);

/* GET / -> WEB_ROOT/index.html (404 problem naming `make web` when missing). */
enum MHD_Result tsd_static_index(tsd_request *r);

/* GET /static/{file} -> WEB_ROOT/{file} with a content type from its extension. */
enum MHD_Result tsd_static_file(tsd_request *r);

#endif
