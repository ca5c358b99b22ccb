#!/usr/bin/env bash
# Configures and builds lrgc in build/ (Release), binaries in build/bin/.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
# A new build/ (a fresh checkout, CI) uses Ninja where it is installed (scripts/setup.sh installs
# it): unlike Make, Ninja starts a target's objects while the libraries it links are still being
# compiled and linked, so both cores stay busy; a build/ configured before keeps its generator.
generator=()
if [ ! -f build/CMakeCache.txt ] && command -v ninja >/dev/null; then generator=(-G Ninja); fi
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$jobs"
