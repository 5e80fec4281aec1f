#!/usr/bin/env bash
# Configures and builds pllvo in ./build (Release, -j2 by default: PLLVO_JOBS overrides).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release ${PLLVO_CMAKE_ARGS:-} >/dev/null
cmake --build build -j "${PLLVO_JOBS:-2}"
