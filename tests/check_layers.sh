#!/bin/sh
# check_layers.sh — enforce the layer rules of the Makefile header by grepping
# #include lines: sim/ sees no HTTP, JSON or GL; render/ no HTTP or JSON;
# api/ no GL or HTTP; cli/ no HTTP. Also: no non-const file-scope variables
# in sim/ and render/ (a cheap check for hidden global state).
fail=0
check() { # dir pattern why
  hits=$(grep -nE "^#include[[:space:]]*<($2)" "$1"/*.c "$1"/*.h 2>/dev/null)
  if [ -n "$hits" ]; then echo "layer violation in $1/ ($3):"; echo "$hits"; fail=1; fi
}
check sim 'microhttpd|jansson|GL/|png|sqlite3' 'sim/ is the physics library only'
check render 'microhttpd|jansson|sqlite3' 'render/ knows no HTTP or JSON'
check api 'microhttpd|GL/|sqlite3' 'api/ maps JSON to the model, no GL or HTTP'
check cli 'microhttpd' 'the runner is not a server'
# File-scope mutable variables: lines at column 0 that declare a non-const,
# non-extern, non-function object with static storage.
for f in sim/*.c render/*.c; do
  [ -f "$f" ] || continue
  bad=$(grep -nE '^(static[[:space:]]+)?(double|int|long|float|char|size_t|unsigned|ts_[a-z_]+|tsr_[a-z_]+)[[:space:]*]+[A-Za-z_][A-Za-z0-9_]*(\[[^]]*\])*[[:space:]]*(=|;)' "$f" | grep -v 'const')
  if [ -n "$bad" ]; then echo "file-scope mutable state in $f:"; echo "$bad"; fail=1; fi
done
[ $fail -eq 0 ] && echo "layers ok"
exit $fail
