#!/usr/bin/env bash
# Installs the dependencies, builds pllvo and runs `pllvo demo`: renders a 12 s synthetic stereo
# sequence (easy_normal, 752x480, exact ground truth), runs the visual odometry on it and prints
# the ATE RMSE (metres and % of the path), frames per second and the per-module timing split.
# With no SuperPoint weights installed (models/, $PLLVO_MODELS) it runs the ORB front end and
# says so. Extra arguments go to `pllvo demo` (e.g. --preset medium_normal --duration 20 --out DIR).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
bash scripts/build.sh >/dev/null
exec ./build/bin/pllvo demo "$@"
