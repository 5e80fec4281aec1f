#!/usr/bin/env bash
# Training-only setup (not needed to build or test pllvo): installs the Debian package whose photographs
# the SuperPoint training reads by path (/usr/share/backgrounds/mate/nature, GPL-2+, see
# /usr/share/doc/mate-backgrounds/copyright). Python packages (numpy, torch, opencv) come from
# scripts/setup.sh. Idempotent; run as root or with sudo.
set -euo pipefail
exec bash "$(dirname "$0")/../../scripts/apt_install.sh" setup_training_data mate-backgrounds
