#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test with ctest: the Release build with warnings
# as errors, then the AddressSanitizer + UBSan + LeakSanitizer build, then the ThreadSanitizer
# build (skip both sanitizer passes with ISPARS_SKIP_SANITIZE=1).
set -euo pipefail
cd "$(dirname "$0")/.."

deploy/install-deps.sh

start=$(date +%s)
deploy/build.sh release -DISPARS_WERROR=ON
(cd build && ctest --output-on-failure --parallel "$(nproc)" --timeout 900)
fastdds shm clean >/dev/null 2>&1 || true  # segments left by the kill -9 test

if [ "${ISPARS_SKIP_SANITIZE:-0}" != "1" ]; then
  # The sanitizer passes build only the tests and what they run (no benchmarks).
  ISPARS_BUILD_TARGET=ispars_tests deploy/build.sh sanitize -DISPARS_WERROR=ON
  # new_delete_type_mismatch: a known false alarm inside libfastrtps 2.9 at teardown.
  # Leaks are checked, less the third-party ones listed in tests/lsan.supp.
  export ASAN_OPTIONS="new_delete_type_mismatch=0:abort_on_error=1"
  export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
  # The brute-force references run about 10x slower here; the Release pass ran them at full
  # volume, so this pass exercises the same code on a twentieth of the queries.
  export ISPARS_TEST_QUERY_SCALE=0.05
  (cd build-sanitize && ctest --output-on-failure --parallel "$(nproc)" --timeout 1800)
  fastdds shm clean >/dev/null 2>&1 || true  # segments left by the kill -9 test
  unset ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS

  ISPARS_BUILD_TARGET=ispars_tests deploy/build.sh thread -DISPARS_WERROR=ON -DISPARS_SERVICE_TESTS=OFF  # see below
  # Embree builds its BVH on TBB threads, synchronised inside those uninstrumented libraries;
  # tests/tsan.supp hides only races reported inside them.
  export TSAN_OPTIONS="halt_on_error=1 suppressions=$PWD/tests/tsan.supp"
  # The tests labelled `service` drive real isparsd processes over Fast DDS, which is not built
  # for TSan: its synchronisation is invisible and TSan reports races inside its own sample
  # buffers. They run in the Release and ASan passes; the daemon's own concurrent parts (session,
  # store, worker pool, reply cache) are checked here through their unit tests.
  (cd build-thread && ctest --output-on-failure --parallel "$(nproc)" --timeout 1800 -LE service)
fi
echo "test.sh: all tests passed in $(( $(date +%s) - start )) s"
