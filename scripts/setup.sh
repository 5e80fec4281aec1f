#!/usr/bin/env bash
# Installs every build and test dependency of pllvo from Debian 12 packages.
# Idempotent and non-interactive; run as root (or with sudo available).
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git
  libopencv-dev libopencv-contrib-dev
  libeigen3-dev libceres-dev
  libtorch-dev libopenblas0-pthread libopenblas-dev
  libyaml-cpp-dev libcli11-dev libspdlog-dev libfmt-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-numpy python3-torch python3-opencv python3-yaml
  pybind11-dev python3-pybind11 python3-dev python3-pytest python3-matplotlib   # the Python module and its tests
  chromium                                  # headless page rendering in tests/report
)

exec bash "$(dirname "$0")/apt_install.sh" setup "${PACKAGES[@]}"
