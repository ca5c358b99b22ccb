#!/usr/bin/env bash
# The Debian packages of a built tree (cmake/DebianPackages.cmake), checked as Debian would:
# cpack -G DEB into a temporary folder, then per package its contents (dpkg-deb -c), its
# dependencies (no -dev package in lrgc's), lintian (no error; skipped if not installed), the
# programs of lrgc run from the unpacked package (--help, --version), the development files
# unpacked the very files `cmake --install` installs (those consumer_find_package builds
# against), and a find_package(lrgc) project (tests/consumer) configured against them.
# Usage: check_packages.sh BUILD_DIR WORK_DIR. Prints "SKIP: ..." where dpkg-deb is absent.
set -euo pipefail
build=$(cd "$1" && pwd)
work=$2
command -v dpkg-deb >/dev/null || { echo "SKIP: dpkg-deb not installed"; exit 0; }
fail() { echo "FAIL: $*" >&2; exit 1; }

rm -rf "$work" && mkdir -p "$work"
work=$(cd "$work" && pwd)
(cd "$work" && cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work" >cpack.log 2>&1) ||
  fail "cpack failed: $(tail -5 "$work/cpack.log")"
run=$(ls "$work"/lrgc_*_*.deb) || fail "no lrgc_*.deb"
dev=$(ls "$work"/liblrgc-dev_*_*.deb) || fail "no liblrgc-dev_*.deb"
arch=$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || gcc -print-multiarch)

# Each package's file list, read once (dpkg-deb -c unpacks the whole xz archive each time).
for deb in "$run" "$dev"; do
  dpkg-deb -c "$deb" | awk '{print $6}' | sed 's|^\./|/|' >"$deb.contents"
done
contents() { cat "$1.contents"; }
has() { grep -qx "$2" <(contents "$1") || fail "$(basename "$1") lacks $2"; }
hasnot() { ! grep -qE "$2" <(contents "$1") || fail "$(basename "$1") holds $2: $(contents "$1" | grep -E "$2" | head -3)"; }

for f in /usr/bin/lrgc-slam /usr/bin/lrgc-eval /usr/bin/lrgc-plot /usr/bin/calibrate-sweep-time \
         /usr/share/lrgc/lrgc-default.ini /usr/share/lrgc/python/bench_runs.py \
         /usr/share/doc/lrgc/copyright /usr/share/doc/lrgc/changelog.Debian.gz \
         /usr/share/man/man1/lrgc-slam.1.gz /usr/share/man/man1/lrgc-eval.1.gz \
         /usr/share/man/man1/lrgc-plot.1.gz /usr/share/man/man1/calibrate-sweep-time.1.gz; do
  has "$run" "$f"
done
hasnot "$run" '^/usr/include|\.a$|/cmake/'
# --live runs in lrgc-slam-live, which lrgc-slam execs (LiveProgram.h): lrgc-slam itself loads
# no sensor driver.
has "$run" /usr/libexec/lrgc/lrgc-slam-live
for f in /usr/include/lrgc/map_builder/CMetricMapBuilderLRGC.h \
         "/usr/lib/$arch/liblrgc.a" "/usr/lib/$arch/liblrgc_apps.a" \
         "/usr/lib/$arch/cmake/lrgc/lrgcConfig.cmake" /usr/share/doc/liblrgc-dev/copyright; do
  has "$dev" "$f"
done
hasnot "$dev" '^/usr/bin/|^/usr/lib/[^/]*\.a$'
grep -q "License: BSD-3-Clause" <(dpkg-deb --fsys-tarfile "$run" | tar -xO ./usr/share/doc/lrgc/copyright) ||
  fail "lrgc's copyright names no BSD-3-Clause licence"

depends=$(dpkg-deb -f "$run" Depends)
! grep -q -- '-dev' <<<"$depends" || fail "lrgc depends on development packages: $depends"
grep -q 'libmrpt-slam2.5' <<<"$depends" || fail "lrgc's dependencies lack MRPT's runtime: $depends"
devdeps=$(dpkg-deb -f "$dev" Depends)
for d in "lrgc (= " libmrpt-dev; do
  grep -qF "$d" <<<"$devdeps" || fail "liblrgc-dev does not depend on $d: $devdeps"
done

if command -v lintian >/dev/null; then
  lintian "$run" "$dev" >"$work/lintian.txt" 2>&1 || true
  ! grep -q '^E:' "$work/lintian.txt" || fail "lintian errors: $(grep '^E:' "$work/lintian.txt")"
  echo "lintian: $(grep -c '^W:' "$work/lintian.txt" || true) warnings, no error"
else
  echo "lintian not installed: not run"
fi

mkdir -p "$work/root"
dpkg-deb -x "$run" "$work/root"
"$work/root/usr/bin/lrgc-slam" --help </dev/null | grep -q "Usage:" || fail "installed lrgc-slam --help"
for p in lrgc-slam lrgc-eval lrgc-plot; do
  "$work/root/usr/bin/$p" --version </dev/null | grep -q "^$p " || fail "installed $p --version"
done
! readelf -d "$work/root/usr/bin/lrgc-slam" | grep -q 'libmrpt-hwdrivers' ||
  fail "installed lrgc-slam links mrpt::hwdrivers (only lrgc-slam-live should)"
# The installed lrgc-slam finds the installed lrgc-slam-live: it answers for the sensors file.
live_err=$("$work/root/usr/bin/lrgc-slam" --live "$work/no-sensors.ini" --out "$work/live-out" \
  </dev/null 2>&1 || true)
grep -q "sensors file '$work/no-sensors.ini' does not exist" <<<"$live_err" ||
  fail "installed lrgc-slam --live did not reach lrgc-slam-live: $live_err"
grep -q 'libmrpt-hwdrivers2.5' <<<"$depends" || fail "lrgc's dependencies lack MRPT's hwdrivers: $depends"
"$work/root/usr/bin/calibrate-sweep-time" --help </dev/null | grep -q "scan_sweep_time_s" ||
  fail "installed calibrate-sweep-time --help"
# liblrgc-dev as shipped: the two packages unpacked (as apt would install both) hold, byte for
# byte, every file `cmake --install` puts under a prefix but the programs (stripped in the
# package, run above): headers, static libraries, CMake package files, the default .ini; and
# find_package(lrgc) resolves there (lrgcTargets.cmake fails if a library it names is absent).
# consumer_find_package builds tests/consumer against such an install, every header alone, and
# maps SENA with it: building it here again compiled the same source against the same files
# (doc/architecture.md, "CI cost", session 57).
dpkg-deb -x "$dev" "$work/root"
cmake --install "$build" --prefix "$work/install" >"$work/install.log" 2>&1 ||
  fail "cmake --install: $(tail -5 "$work/install.log")"
compared=0
while IFS= read -r -d '' f; do
  rel=${f#"$work/install/"}
  case "$rel" in bin/* | libexec/*) continue ;; esac
  cmp -s "$f" "$work/root/usr/$rel" || fail "the packages' /usr/$rel is not what cmake --install installs"
  compared=$((compared + 1))
done < <(find "$work/install" -type f -print0)
[ "$compared" -gt 50 ] || fail "only $compared installed files compared"
cmake -S "$(dirname "$0")/../consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/root/usr" \
  -DCMAKE_BUILD_TYPE=Release >"$work/consumer.log" 2>&1 ||
  fail "find_package(lrgc) in the unpacked packages: $(tail -5 "$work/consumer.log")"
grep -q "^lrgc_DIR:PATH=$work/root/usr/lib/$arch/cmake/lrgc$" "$work/consumer/CMakeCache.txt" ||
  fail "find_package(lrgc) did not find the unpacked packages' lrgc: $(grep '^lrgc_DIR' "$work/consumer/CMakeCache.txt")"
echo "OK: $(basename "$run") and $(basename "$dev")"
