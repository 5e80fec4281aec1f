#!/usr/bin/env bash
# Installs, builds and runs pllvo on its bundled default example: `pllvo eval EST REF` on the
# demo trajectories (examples/trajectories, made by scripts/make_demo_trajectories.py).
# Note the order: estimate first, reference second (evo's commands take REF EST).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
bash scripts/build.sh >/dev/null
exec ./build/bin/pllvo eval examples/trajectories/est.tum examples/trajectories/ref.tum --align se3
