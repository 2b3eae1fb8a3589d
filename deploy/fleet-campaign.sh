#!/usr/bin/env bash
# The fleet's fault campaigns at full length (docs/results/fleet.md): partitions between real
# processes in network namespaces (plain and under DDS Security), and a secured owner stalled past
# its lease, 10 rounds each, and the history campaign (random faults, Jepsen's check) at 100; the
# same tests CI runs with fewer rounds. Needs root (namespaces) and
# a Release build (deploy/build.sh). Usage: deploy/fleet-campaign.sh [ROUNDS]
set -euo pipefail
cd "$(dirname "$0")/.."
rounds="${1:-10}"
tests=build/bin/ispars_service_tests
[ -x "$tests" ] || { echo "fleet-campaign: build first (deploy/build.sh)" >&2; exit 2; }
export ISPARS_PARTITION_ROUNDS="$rounds" ISPARS_STALL_ROUNDS="$rounds" ISPARS_HISTORY_ROUNDS="$((rounds * 10))"
# One process per test, as ctest runs them: Fast DDS keeps the first XML profile of a name it
# loads for the whole process, and these tests load different profiles named "ispars".
status=0
for test in FleetFreshnessTest.ARestartedStaleOwnerNeverReplacesTheFresherRoadmap \
            FleetFreshnessTest.TwoEqualCopiesSettleByWeightAndTheOtherContinuesWithoutRebuilding \
            PartitionTest.CutAndHealTheOwnerPlain PartitionTest.CutAndHealTheOwnerSecured \
            StallTest.AnOwnerStalledPastItsLeaseRejoinsAndTheFleetSettlesOnOneOwner \
            HistoryTest.RandomFaultsLoseNoAcknowledgedChange; do
  "$tests" --gtest_filter="$test" >"/tmp/fleet-campaign-$$.log" 2>&1 || status=1
  grep -E '^\[ *(OK|FAILED) *\]|partition round|stall round|handover:|takeover:|Failure|long-lived replica|rejoined [0-9]+ times|^history' "/tmp/fleet-campaign-$$.log" || true
done
rm -f "/tmp/fleet-campaign-$$.log"
exit "$status"
