#!/usr/bin/env bash
# Installs the dependencies (apt, idempotent), builds everything and runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
cd build
ctest --output-on-failure -j "${PLLVO_JOBS:-2}"
