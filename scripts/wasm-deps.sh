#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Prepare third-party inputs of the WebAssembly build (idempotent, cached):
#   DEPS/include/       symlinks to header trees (em++ must not see /usr/include)
#   DEPS/openmesh/      OpenMesh core built with Emscripten from the Debian source package
#   DEPS/polyclipping/  Clipper source (clipper.cpp/.hpp) from the Debian source package
# Usage: scripts/wasm-deps.sh [DEPS_DIR]   (default build/deps, relative to the repo root)
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
DEPS="${1:-${DEPS_DIR:-$ROOT/build/deps}}"
mkdir -p "$DEPS"
DEPS="$(cd "$DEPS" && pwd)"
export NODE_PATH="${NODE_PATH:-/usr/share/nodejs}"   # em* tools need Debian's acorn & co (TOOLCHAIN.md)
JOBS="${JOBS:-2}"

log() { printf '[wasm-deps] %s\n' "$*" >&2; }
die() { printf '[wasm-deps] error: %s\n' "$*" >&2; exit 1; }

for tool in emcmake emmake em++ cmake; do
  command -v "$tool" >/dev/null || die "$tool not found (apt-get install emscripten cmake)"
done

# --- (a) staged headers ---------------------------------------------------------------------------
INC="$DEPS/include"
mkdir -p "$INC"
stage() {  # stage NAME TARGET
  local name="$1" target="$2"
  [ -e "$target" ] || die "missing $target (install the Debian package that provides it)"
  if [ "$(readlink "$INC/$name" 2>/dev/null)" != "$target" ]; then
    rm -rf "${INC:?}/$name"
    ln -s "$target" "$INC/$name"
  fi
}
stage Eigen /usr/include/eigen3/Eigen
[ -d /usr/include/eigen3/unsupported ] && stage unsupported /usr/include/eigen3/unsupported
stage CGAL /usr/include/CGAL
stage boost /usr/include/boost
stage glm /usr/include/glm
stage nlohmann /usr/include/nlohmann
stage polyclipping /usr/include/polyclipping

# Fetch a Debian source package into DEPS/src (once). Prints the unpacked source folder.
fetch_source() {  # fetch_source PACKAGE
  local pkg="$1" dir
  mkdir -p "$DEPS/src"
  dir="$(find "$DEPS/src" -mindepth 1 -maxdepth 1 -type d -name "${pkg}-*" | sort | head -n1)"
  if [ -z "$dir" ]; then
    command -v dpkg-source >/dev/null || die "dpkg-source missing (apt-get install dpkg-dev)"
    log "apt-get source $pkg"
    if ! (cd "$DEPS/src" && apt-get source -q "$pkg" >&2); then
      log "apt-get source failed; refreshing package lists (deb-src must be enabled)"
      apt-get update -q >&2 || die "apt-get update failed"
      (cd "$DEPS/src" && apt-get source -q "$pkg" >&2) \
        || die "apt-get source $pkg failed: enable deb-src in /etc/apt/sources.list.d/debian.sources"
    fi
    dir="$(find "$DEPS/src" -mindepth 1 -maxdepth 1 -type d -name "${pkg}-*" | sort | head -n1)"
  fi
  [ -n "$dir" ] || die "no unpacked source for $pkg in $DEPS/src"
  printf '%s\n' "$dir"
}

# --- (c) Clipper source ---------------------------------------------------------------------------
if [ ! -f "$DEPS/polyclipping/clipper.cpp" ] || [ ! -f "$DEPS/polyclipping/clipper.hpp" ]; then
  src="$(fetch_source libpolyclipping)"
  cpp="$(find "$src" -name clipper.cpp -path '*cpp*' | head -n1)"
  hpp="$(find "$src" -name clipper.hpp -path '*cpp*' | head -n1)"
  [ -n "$cpp" ] && [ -n "$hpp" ] || die "clipper.cpp/.hpp not found in $src"
  mkdir -p "$DEPS/polyclipping"
  cp "$cpp" "$hpp" "$DEPS/polyclipping/"
  log "Clipper: $DEPS/polyclipping/clipper.cpp"
fi

# --- (b) OpenMesh core, static, for wasm ----------------------------------------------------------
OM="$DEPS/openmesh"
if [ ! -f "$OM/lib/libOpenMeshCore.a" ] || [ ! -f "$OM/include/OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh" ]; then
  src="$(fetch_source openmesh)"
  bld="$DEPS/openmesh-build"
  log "building OpenMesh core with Emscripten (about 70 s)"
  emcmake cmake -S "$src" -B "$bld" -DCMAKE_BUILD_TYPE=Release -DBUILD_APPS=OFF \
    -DOPENMESH_BUILD_SHARED=OFF -DOPENMESH_DOCS=OFF -Wno-dev -DOPENMESH_BUILD_UNIT_TESTS=OFF \
    -DCMAKE_CXX_FLAGS="-fwasm-exceptions" >&2
  # Upstream names the static target OpenMeshCoreStatic; Debian's patch keeps only OpenMeshCore,
  # which Emscripten's toolchain (no shared libraries) builds as a static archive.
  target=OpenMeshCore
  if (cd "$bld" && make help | grep -q 'OpenMeshCoreStatic'); then target=OpenMeshCoreStatic; fi
  (cd "$bld" && emmake make -j"$JOBS" "$target" >&2)
  lib="$(find "$bld" -name 'libOpenMeshCore*.a' | head -n1)"
  [ -n "$lib" ] || die "OpenMesh build produced no libOpenMeshCore.a"
  mkdir -p "$OM/lib" "$OM/include/OpenMesh"
  cp "$lib" "$OM/lib/libOpenMeshCore.a"
  # Headers: the source tree's Core (headers and the .cc template bodies they include).
  rm -rf "$OM/include/OpenMesh/Core"
  cp -r "$src/src/OpenMesh/Core" "$OM/include/OpenMesh/Core"
  find "$OM/include/OpenMesh/Core" -name CMakeLists.txt -delete
  # Generated config headers, if the build wrote any.
  if [ -d "$bld/src/OpenMesh/Core" ]; then
    (cd "$bld/src/OpenMesh/Core" && find . -name '*.hh' -exec cp --parents {} "$OM/include/OpenMesh/Core/" \;)
  fi
  log "OpenMesh: $OM/lib/libOpenMeshCore.a"
fi

log "deps ready in $DEPS"
