#!/usr/bin/env bash
# Set-up, build, and map the built-in default log (the SENA one-loop rawlog of Debian's
# mrpt-common) into out/. Extra arguments go to lrgc-slam.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
build/bin/lrgc-slam --input "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog" \
  --out out "$@"
ls -l out
