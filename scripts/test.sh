#!/usr/bin/env bash
# Installs the dependencies (apt, idempotent), builds everything and runs every test (ctest, which
# includes the Python module's pytest suite), then the install: a temporary prefix, the C++ example
# built against it and run on a fixture.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
(cd build && ctest --output-on-failure -j "${PLLVO_JOBS:-2}")
bash scripts/test_install.sh build
