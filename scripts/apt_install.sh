#!/usr/bin/env bash
# Installs the named Debian packages that are not installed yet (idempotent, non-interactive;
# root, or sudo). Shared by scripts/setup.sh and training/superpoint/setup_training_data.sh.
#   usage: scripts/apt_install.sh NAME-FOR-MESSAGES PACKAGE...
set -euo pipefail
name=$1
shift
missing=()
for p in "$@"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "$name: all $# packages already installed"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "$name: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
