#!/bin/sh
# install-deps.sh PACKAGE... — install the Debian packages that are missing.
# Silent and fast when everything is present (dpkg-query only, no apt); otherwise
# runs apt-get update once and installs only the missing ones. Needs root (or
# sudo) only when something is missing.
set -eu
missing=""
for p in "$@"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  case "$status" in
    *"install ok installed"*) ;;
    *) missing="$missing $p" ;;
  esac
done
[ -z "$missing" ] && exit 0
echo "make deps: installing missing Debian packages:$missing" >&2
SUDO=""
if [ "$(id -u)" != 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "make deps: run as root (or install sudo) to install:$missing" >&2; exit 1; fi
fi
# DEBIAN_FRONTEND goes through env on each command: sudo's env_reset would drop an export
# Another apt may hold the lists lock for a while: retry the update.
for try in 1 2 3 4 5 6 7 8 9 10; do
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=600 update -qq >&2 && break
  sleep 10
done
# shellcheck disable=SC2086
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=600 install -y -qq \
  --no-install-recommends $missing >&2
