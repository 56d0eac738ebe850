#!/usr/bin/env bash
# Installs every Debian 12 package the project builds, tests or runs with.
# Idempotent: packages already present are left alone, so both README commands
# can call it every time. Needs root (or sudo) only when something is missing.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake pkg-config
  # clang + its runtime libraries: the libFuzzer targets and sanitizers
  clang libclang-rt-14-dev
  # compiler front end
  libfast-float-dev libcli11-dev
  # the archive: section compression, checksums, parallel loading
  libzstd-dev libxxhash-dev libtbb-dev
  # mesh tools
  libopenmesh-dev
  # optional lossy mesh compression (Draco sections); the runtime decodes them
  libdraco-dev
  # images decoded at compile time (PNG, TGA, PFM, HDR, EXR); pbrtc only, never the runtime
  libopenimageio-dev
  # the renderer: ray/scene intersection, EXR output, PNG previews
  libembree-dev libopenexr-dev libimath-dev libpng-dev
  # rendering one image across machines (pbrtrun-mpi) and its tests (mpirun)
  openmpi-bin libopenmpi-dev
  # tests and benchmarks; python3 runs the archive reader written from the spec alone
  libgtest-dev libgmock-dev libbenchmark-dev python3
  # real files nobody here wrote, for the first-contact tests (OBJ/MTL with JPEG maps, old PLY)
  assimp-testmodels
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
