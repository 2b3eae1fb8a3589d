#!/usr/bin/env bash
# Configures and builds ispars. Usage: deploy/build.sh [release|debug|sanitize|thread] [cmake args]
#   release  (default) build/          optimised, what quickstart and benchmarks use
#   debug              build-debug/
#   sanitize           build-sanitize/  AddressSanitizer + UndefinedBehaviorSanitizer
#   thread             build-thread/    ThreadSanitizer
# ISPARS_BUILD_TARGET=T builds only target T and what it needs (e.g. ispars_tests: every test).
set -euo pipefail
cd "$(dirname "$0")/.."

kind="${1:-release}"
[ $# -gt 0 ] && shift
case "$kind" in
  release)  dir=build;          args=(-DCMAKE_BUILD_TYPE=Release) ;;
  debug)    dir=build-debug;    args=(-DCMAKE_BUILD_TYPE=Debug) ;;
  # -O1 -g1 (line tables): what AddressSanitizer and ThreadSanitizer recommend, and 2-2.5x faster
  # to compile than RelWithDebInfo's -O2 -g on the heaviest files, with file:line in every report.
  sanitize) dir=build-sanitize; args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DISPARS_SANITIZE=ON
                                      "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG") ;;
  thread)   dir=build-thread;   args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DISPARS_SANITIZE_THREAD=ON
                                      "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG") ;;
  *) echo "build.sh: unknown build kind '$kind' (release, debug, sanitize, thread)" >&2; exit 2 ;;
esac

generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
cmake -S . -B "$dir" "${generator[@]}" "${args[@]}" "$@"
target=()
[ -n "${ISPARS_BUILD_TARGET:-}" ] && target=(--target "$ISPARS_BUILD_TARGET")
cmake --build "$dir" --parallel "$(nproc)" "${target[@]}"
echo "build.sh: $kind build in $dir/, executables in $dir/bin/"
