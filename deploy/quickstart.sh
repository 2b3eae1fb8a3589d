#!/usr/bin/env bash
# A fresh Debian 12 machine to a first result: installs dependencies, builds Release, and
# reports on the water tower scene (what it holds, what a sensor sees, what queries cost).
set -euo pipefail
cd "$(dirname "$0")/.."

deploy/install-deps.sh
deploy/build.sh release

scene="${1:-deploy/scenes/water_tower.yaml}"
echo
echo "== ispars-lab scene info $scene"
build/bin/ispars-lab scene info "$scene"
echo
echo "== ispars-lab bench geometry $scene"
build/bin/ispars-lab bench geometry "$scene" --queries 5000 --reference-queries 50
echo
echo "Next: build/bin/ispars-lab --help; the other scenes are in deploy/scenes/."
