#!/usr/bin/env bash
# test.sh: sets up, builds and runs the whole test suite (ctest), then builds Core and its
# unit tests with AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/) and runs them.
# Usage: scripts/test.sh [ctest options, e.g. -L core]
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS=${DDG_JOBS:-$(nproc)}
bash scripts/setup.sh
bash scripts/build.sh
# A failed test gets one more run (a real failure fails both). X tests run under
# scripts/with-xvfb.sh, which fixed the "bad X server connection" seen with xvfb-run -a.
# The kind check's references kept between sessions (Core's kindCacheDirectory): every test
# keeps them in the build tree (Testing/CMakeLists.txt), emptied at each run.
rm -rf build/Testing/kind-cache
(cd build && ctest --output-on-failure -j "$JOBS" --repeat until-pass:2 "$@")

echo "test: sanitizer build of Core and its tests (ASan + UBSan)"
rm -rf build-asan/Testing/kind-cache
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DDDG_SANITIZE=ON -DDDG_BUILD_PLUGIN=OFF \
  -DDDG_BUILD_BENCHMARKS=OFF > build-asan.log 2>&1 || { cat build-asan.log; exit 1; }
cmake --build build-asan -j "$JOBS"
(cd build-asan && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --output-on-failure -j "$JOBS" -L core)
echo "test: all passed"
