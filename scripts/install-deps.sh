#!/usr/bin/env bash
# Installs the Debian packages lambert needs to build, test and benchmark — only those missing.
# Works as root or through sudo; prints what it installs. Safe to run on every `make`.
set -euo pipefail
# Progress goes to stderr, so commands whose stdout is data (make bench) stay clean.
exec 1>&2

packages=(
  build-essential cmake pkg-config
  libembree-dev libtbb-dev libeigen3-dev
  libcli11-dev nlohmann-json3-dev libstb-dev libtinyobjloader-dev libtinygltf-dev libtinyexr-dev
  libgtest-dev libgmock-dev libbenchmark-dev
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q '^install ok installed$'; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing missing Debian packages: ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then
  as_root=()
elif command -v sudo >/dev/null 2>&1; then
  as_root=(sudo)
else
  echo "install-deps: error: need root or sudo to install: ${missing[*]}" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -qq
"${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
