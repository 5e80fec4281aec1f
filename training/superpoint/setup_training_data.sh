#!/usr/bin/env bash
# Training-only setup (not needed to build or test pllvo): installs the Debian package whose photographs
# the SuperPoint training reads by path (/usr/share/backgrounds/mate/nature, GPL-2+, see
# /usr/share/doc/mate-backgrounds/copyright). Python packages (numpy, torch, opencv) come from
# scripts/setup.sh. Idempotent; run as root or with sudo.
set -euo pipefail
PACKAGES=(mate-backgrounds)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup_training_data: all packages already installed"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
