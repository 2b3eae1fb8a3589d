#!/usr/bin/env bash
# A fresh Debian 12 machine to a running service: installs dependencies, builds Release, starts
# isparsd with the bundled demo scenes on the localhost-only Fast DDS profile, builds an
# Inspection-SPARS roadmap with live progress through the `ispars` client, prints its stats,
# verifies it, fetches it, and stops the daemon cleanly (SIGTERM, exit 0).
#
#   deploy/quickstart.sh [SCENE] [SAMPLES]     (default: demo_truss_bridge 60000)
set -euo pipefail
cd "$(dirname "$0")/.."

deploy/install-deps.sh
deploy/build.sh release

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
  if kill -0 "$daemon" 2>/dev/null; then
    kill -TERM "$daemon"
    wait "$daemon" && echo "== isparsd stopped cleanly (exit 0)" || echo "== isparsd exited with $?" >&2
  fi
}
trap stop_daemon EXIT

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
