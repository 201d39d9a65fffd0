#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Install what is missing on a Debian 12 machine: the apt packages the build and tests need,
# Debian source packages enabled (OpenMesh and Clipper are compiled for wasm from them), and the npm
# dependencies. Idempotent: does nothing when everything is there.
set -euo pipefail
cd "$(dirname "$0")/.."

APT_PACKAGES=(
  g++ cmake ninja-build ccache pkg-config dpkg-dev
  libeigen3-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev libglm-dev
  libopenmesh-dev libpolyclipping-dev nlohmann-json3-dev libgtest-dev liborocos-kdl-dev
  emscripten chromium
)

missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

need_src=0
if [ -f /etc/apt/sources.list.d/debian.sources ] &&
   ! grep -q '^Types:.*deb-src' /etc/apt/sources.list.d/debian.sources; then
  need_src=1
fi

if [ ${#missing[@]} -gt 0 ] || [ $need_src -eq 1 ]; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "error: missing packages (${missing[*]:-deb-src}); run 'npm start' or 'npm test' as root once" >&2
    exit 1
  fi
  if [ $need_src -eq 1 ]; then
    echo "bootstrap: enabling Debian source packages (deb-src)"
    sed -i 's/^Types: deb$/Types: deb deb-src/' /etc/apt/sources.list.d/debian.sources
  fi
  echo "bootstrap: apt-get install ${missing[*]:-(none)}"
  apt-get update -q
  if [ ${#missing[@]} -gt 0 ]; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${missing[@]}"
  fi
fi

if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  echo "error: Node.js (>= 18) and npm are needed" >&2
  exit 1
fi

# npm ci when node_modules is missing or older than the lock file.
if [ ! -d node_modules ] || [ package-lock.json -nt node_modules/.package-lock.json ]; then
  echo "bootstrap: npm ci"
  npm ci --no-audit --no-fund
fi
