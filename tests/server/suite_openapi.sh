#!/bin/bash
# suite_openapi.sh — validate api/openapi.yaml as OpenAPI 3.1 with
# @apidevtools/swagger-parser (installed on first use with
# `npm install --no-save` into tests/server/openapi/node_modules, gitignored).
# Ends with "N passed, N failed". If npm cannot reach its registry and the
# package is not installed yet, the suite says so and counts nothing.
cd "$(dirname "$0")/openapi" || exit 1
if [ ! -d node_modules/@apidevtools/swagger-parser ]; then
  if ! timeout 300 npm install --no-save --no-audit --no-fund --loglevel=error \
      @apidevtools/swagger-parser@10 >npm-install.log 2>&1; then
    echo "SKIPPED: npm could not install @apidevtools/swagger-parser (see npm-install.log)"
    echo "0 passed, 0 failed"
    exit 0
  fi
fi
out=$(timeout 120 node validate.js ../../../api/openapi.yaml 2>&1)
echo "$out"
p=$(echo "$out" | grep -c '^ok ')
f=$(echo "$out" | grep -c '^FAIL')
echo "$p passed, $f failed"
[ "$f" -eq 0 ]
