#!/usr/bin/env bash
# Set-up, build, and run every test (CTest). Tests needing ../shared data skip when absent.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
jobs=$(nproc 2>/dev/null || echo 2)
cd build && ctest --output-on-failure -j"$jobs"
