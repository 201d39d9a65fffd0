#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Set up (install what is missing), build, and serve the app at http://localhost:${PORT:-8080}.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/bootstrap.sh
bash scripts/build.sh all
exec node scripts/serve.mjs
