#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# CuraEngine 4.13 for the benchmark's fixed-direction comparison (issue 7; `npm run bench` only,
# never `npm test`). Installs Debian's cura-engine with apt and extracts the machine definitions
# (fdmprinter.def.json, fdmextruder.def.json) from Debian's `cura` package without installing it
# (it would pull the whole Python/Qt stack): `apt-get download cura`, then `dpkg-deb -x` into
# build/deps/cura. Only Debian's apt repositories are used. Idempotent: does nothing when both
# are there. Prints the definitions folder on stdout; exit code 1 (with a message on stderr) when
# it cannot install, so callers can skip the comparison.
set -euo pipefail
cd "$(dirname "$0")/.."

DEST=build/deps/cura
DEFS="$DEST/usr/share/cura/resources/definitions"

# Already installed (or a system-wide cura package provides the definitions).
for d in "$DEFS" /usr/share/cura/resources/definitions; do
  if command -v CuraEngine >/dev/null && [ -f "$d/fdmprinter.def.json" ] && [ -f "$d/fdmextruder.def.json" ]; then
    echo "$(cd "$d" && pwd)"
    exit 0
  fi
done

if [ "$(id -u)" -ne 0 ] && ! command -v CuraEngine >/dev/null; then
  echo "install-cura: cura-engine is missing; run scripts/install-cura.sh as root once" >&2
  exit 1
fi

updated=0
apt_update() {
  if [ $updated -eq 0 ]; then
    apt-get update -q >&2
    updated=1
  fi
}

if ! command -v CuraEngine >/dev/null; then
  echo "install-cura: apt-get install cura-engine" >&2
  apt_update
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q cura-engine >&2
fi

if [ ! -f "$DEFS/fdmprinter.def.json" ] || [ ! -f "$DEFS/fdmextruder.def.json" ]; then
  command -v dpkg-deb >/dev/null || { echo "install-cura: dpkg-deb is missing" >&2; exit 1; }
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  chown _apt "$work" 2>/dev/null || true  # apt-get download fetches as the _apt user
  echo "install-cura: apt-get download cura (definitions only, not installed)" >&2
  if ! (cd "$work" && apt-get download -q cura >&2); then
    # The package lists may be stale or missing (fresh container): refresh once and retry.
    apt_update
    (cd "$work" && apt-get download -q cura >&2)
  fi
  deb=$(ls "$work"/cura_*.deb)
  dpkg-deb -x "$deb" "$work/x"
  rm -rf "$DEST.tmp"
  mkdir -p "$DEST.tmp/usr/share/cura/resources"
  cp -r "$work/x/usr/share/cura/resources/definitions" "$DEST.tmp/usr/share/cura/resources/"
  dpkg-deb -f "$deb" Version > "$DEST.tmp/VERSION"
  rm -rf "$DEST"
  mv "$DEST.tmp" "$DEST"
fi

for f in fdmprinter.def.json fdmextruder.def.json; do
  [ -f "$DEFS/$f" ] || { echo "install-cura: $f not found in the cura package" >&2; exit 1; }
done
echo "$(cd "$DEFS" && pwd)"
