#!/usr/bin/env bash
# Installs, builds and runs pllvo on its bundled default example.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
bash scripts/build.sh >/dev/null
exec ./build/bin/pllvo eval examples/trajectories/ref.tum examples/trajectories/est.tum --align se3
