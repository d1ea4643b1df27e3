#!/usr/bin/env bash
# Installs every Debian package the project needs (idempotent), then configures and builds into
# build/ with Ninja. Usage: scripts/setup.sh [extra cmake args...]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

packages=$(grep -v '^#' scripts/packages.txt | grep -v '^$' | tr '\n' ' ')
missing=""
for p in $packages; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  echo "setup: installing Debian packages:$missing" >&2
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  # shellcheck disable=SC2086
  $sudo apt-get install -y -qq --no-install-recommends $missing
else
  echo "setup: all Debian packages present" >&2
fi

jobs="${ADUGS_JOBS:-2}"
# ccache keys on paths relative to the checkout, so a fresh clone elsewhere reuses objects.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build build -j"$jobs"
echo "setup: built into $root/build (adugs: build/app/adugs)" >&2
