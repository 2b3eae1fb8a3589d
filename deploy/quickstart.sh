#!/usr/bin/env bash
# A fresh Debian 12 machine to a running service: installs dependencies, builds Release, starts
# isparsd with the bundled demo scenes on the localhost-only Fast DDS profile, builds an
# Inspection-SPARS roadmap with live progress through the `ispars` client, prints its stats,
# verifies it (exit 1 on an Invariant 1 violation), fetches it, and stops the daemon cleanly
# (SIGTERM, exit 0). Any step that fails fails the script, with the daemon's log. CI runs it first
# (.ci/run), on a clean clone, as a newcomer does.
#
#   deploy/quickstart.sh [SCENE] [SAMPLES]     (default: demo_truss_bridge 60000)
set -euo pipefail
cd "$(dirname "$0")/.."

deploy/install-deps.sh
# The programs and the Python package; deploy/test.sh builds the tests into the same folder.
ISPARS_BUILD_TARGET=ispars_programs deploy/build.sh release

scene="${1:-demo_truss_bridge}"
samples="${2:-60000}"
bin="$PWD/build/bin"
profile="$PWD/deploy/fastdds_localhost.xml"
work="$(mktemp -d /tmp/ispars-quickstart-XXXXXX)"
export ISPARS_DOMAIN="${ISPARS_DOMAIN:-$(( 100 + RANDOM % 120 ))}"   # a private domain for this run
export ISPARS_PROFILE_FILE="$profile"

echo
echo "== isparsd on DDS domain $ISPARS_DOMAIN (localhost only), data in $work/data"
"$bin/isparsd" --data-dir "$work/data" --scene-dir "$PWD/deploy/scenes" --profile-file "$profile" \
  --server-id quickstart --log-level warn > "$work/isparsd.log" 2>&1 &
daemon=$!
stop_daemon() {
  kill -0 "$daemon" 2>/dev/null || { wait "$daemon"; return; }
  kill -TERM "$daemon"
  local code=0
  wait "$daemon" || code=$?
  if [ "$code" -eq 0 ]; then
    echo "== isparsd stopped cleanly (exit 0)"
  else
    echo "== isparsd exited with $code; its log, $work/isparsd.log:" >&2
    tail -n 40 "$work/isparsd.log" >&2
  fi
  return "$code"
}
on_exit() {
  local code=$?
  if [ "$code" -ne 0 ]; then
    echo "== quickstart failed (exit $code); the daemon's log, $work/isparsd.log:" >&2
    tail -n 40 "$work/isparsd.log" >&2 || true
  fi
  stop_daemon || true
}
trap on_exit EXIT

echo "== ispars scenes list"
"$bin/ispars" scenes list
echo
echo "== ispars scenes load $scene"
"$bin/ispars" scenes load "$scene"
echo
echo "== ispars build $scene --method ispars --samples $samples --seed 1 --wait"
"$bin/ispars" build "$scene" --method ispars --samples "$samples" --seed 1 --wait
echo
echo "== ispars stats $scene --json"
"$bin/ispars" stats "$scene" --json
echo
echo "== ispars verify $scene"
"$bin/ispars" verify "$scene"
echo
echo "== ispars snapshot $scene --out $work/roadmap.json"
"$bin/ispars" snapshot "$scene" --out "$work/roadmap.json"
stop_daemon
trap - EXIT
echo
echo "Next: build/bin/ispars --help, build/bin/isparsd --help; docs/service.md has the service's topics and formats."
