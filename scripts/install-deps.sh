#!/usr/bin/env bash
# Installs the Debian packages lambert needs to build, test and benchmark — only those missing.
# Works as root or through sudo; prints what it installs. Safe to run on every `make`.
set -euo pipefail
# Progress goes to stderr, so commands whose stdout is data (make bench) stay clean.
exec 1>&2

packages=(
  build-essential cmake pkg-config python3
  # a fresh clone (CI's) recompiles only what changed (CMakeLists.txt, LAMBERT_CCACHE)
  ccache
  libembree-dev libtbb-dev libeigen3-dev
  libcli11-dev nlohmann-json3-dev libstb-dev libtinyobjloader-dev libtinygltf-dev libtinyexr-dev
  # the lighting report's PDF is drawn with cairo in DejaVu Sans; its test renders the pages
  # (poppler's pdftoppm, pdftotext)
  libcairo2-dev fonts-dejavu-core poppler-utils
  libgtest-dev libgmock-dev libbenchmark-dev
  libglfw3-dev libepoxy-dev libimgui-dev
  # the viewer's test draws in a real window: an X server without a screen, Mesa's software OpenGL
  xvfb xauth libgl1-mesa-dri
  # tests/real_clients_test.cpp draws the lightmapped glb with three.js in headless Chromium
  # (software WebGL; about 390 MB, 15 s to install), and Blender imports it (its glTF importer
  # needs numpy; about 575 MB, 95 s to install)
  chromium blender python3-numpy
  # the Python module (python/, pybind11) and its tests (pytest) and example (matplotlib), for
  # Debian's python3
  python3-dev pybind11-dev python3-pytest python3-matplotlib
  # `lambert solve --distributed` (src/lambert/distributed/) runs on MPI: OpenMPI's library,
  # headers and mpirun (its tests run 1, 2 and 4 ranks on one machine)
  openmpi-bin libopenmpi-dev
)
# `make fuzz` (scripts/install-deps.sh --fuzz) also needs clang and its runtime, which holds
# libFuzzer; the ordinary build does not, so they are installed only then.
if [ "${1:-}" = "--fuzz" ]; then
  packages+=(clang-14 libclang-rt-14-dev)
fi

# The Khronos glTF-Validator (npm, not Debian) checks the .glb export in the tests; optional: the
# test says it is skipped where there is no npm or no registry.
tools="$(cd "$(dirname "$0")/.." && pwd)/.tools"
if command -v npm >/dev/null 2>&1 && [ ! -f "$tools/node_modules/gltf-validator/package.json" ]; then
  echo "install-deps: installing the Khronos glTF-Validator (npm gltf-validator@2.0.0-dev.3.10) into .tools/"
  npm install --silent --no-audit --no-fund --prefix "$tools" gltf-validator@2.0.0-dev.3.10 >/dev/null 2>&1 ||
    echo "install-deps: note: no glTF-Validator (npm failed); its test will be skipped"
fi
# three.js (npm) for the web page of tests/real_clients_test.cpp and examples/web/; optional as above.
if command -v npm >/dev/null 2>&1 && [ ! -f "$tools/node_modules/three/package.json" ]; then
  echo "install-deps: installing three.js (npm three@0.187.0) into .tools/"
  npm install --silent --no-audit --no-fund --prefix "$tools" three@0.187.0 >/dev/null 2>&1 ||
    echo "install-deps: note: no three.js (npm failed); the browser tests will be skipped"
fi
# puppeteer-core (npm; 23.x, the last for Node 18/20) drives Debian's chromium for those tests
# (tests/web-screenshot.js); optional as above.
if command -v npm >/dev/null 2>&1 && [ ! -f "$tools/node_modules/puppeteer-core/package.json" ]; then
  echo "install-deps: installing puppeteer-core (npm puppeteer-core@23.11.1) into .tools/"
  npm install --silent --no-audit --no-fund --prefix "$tools" puppeteer-core@23.11.1 >/dev/null 2>&1 ||
    echo "install-deps: note: no puppeteer-core (npm failed); the browser tests will be skipped"
fi

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
