#!/usr/bin/env bash
# Installs the Debian 12 packages lrgc needs, and nothing when all are present.
# Runs apt-get as root, or through sudo when not root.
set -euo pipefail
PACKAGES=(
  build-essential cmake ninja-build git pkg-config
  # MRPT 2.5: the -dev packages of the modules lrgc builds against (CMakeLists.txt's
  # find_package(MRPT COMPONENTS ...); not the libmrpt-dev metapackage, whose other modules
  # bring ROS 1, Boost and ICU headers: 115 packages more), icp-slam & co, the datasets
  libmrpt-slam-dev libmrpt-maps-dev libmrpt-obs-dev libmrpt-graphs-dev libmrpt-graphslam-dev
  libmrpt-io-dev libmrpt-config-dev libmrpt-poses-dev libmrpt-system-dev libmrpt-math-dev
  libmrpt-serialization-dev libmrpt-img-dev libmrpt-opengl-dev libmrpt-hwdrivers-dev
  mrpt-apps mrpt-common
  libeigen3-dev libsuitesparse-dev libopencv-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  socat                                       # pseudo-terminals for the serial-laser tests
  time                                        # /usr/bin/time -v for bench/run
  clang-14 libclang-rt-14-dev                 # libFuzzer and sanitizers for scripts/fuzz
  clang-format-14                             # scripts/check-format (CI)
  universal-ctags                             # scripts/check-function-length (CI)
  lintian                                     # tests/debian/check_packages.sh (the .deb files)
)
missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages present"
  exit 0
fi
echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: not root and no sudo: install ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
