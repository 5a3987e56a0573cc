#!/usr/bin/env bash
# Installs the Debian packages chatterlab needs to build, test and render reports.
# Idempotent: prints nothing and changes nothing when every package is present.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config ninja-build lld
  libeigen3-dev libfftw3-dev libceres-dev libyaml-cpp-dev
  nlohmann-json3-dev libkainjow-mustache-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  gnuplot-nox libosmesa6-dev libpng-dev
  libmatio-dev libhdf5-dev zlib1g-dev liblapack-dev libsqlite3-dev
  libssl-dev weasyprint qpdf poppler-utils fonts-dejavu-core
  python3-jsonschema chromium
  clang libclang-rt-dev
  slurm-wlm munge
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "chatterlab: installing missing Debian packages: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
