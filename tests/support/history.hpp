#pragma once
// A history checker in Jepsen's sense for one scene of a fleet: the test records every change a
// client sent and whether it was acknowledged (with the status its reply carried), and, once the
// fleet is connected again, what clients read. check() says what the read is missing: every
// acknowledged change of the lineage served must be in it (an extend's target reached, a task
// added and not removed since present, one removed absent), and the lineage served must be the
// one the latest acknowledged build made, not one nobody acknowledged. Changes that were not
// acknowledged (refused, or no answer) may be in the read or not: their outcome is unknown.
// Pure: no DDS, no daemons (tests/server/test_history.cpp checks it on made-up histories).

#include <cstdint>
#include <string>
#include <vector>

namespace ispars::test {

/// One change a client sent: what it asked, and what its reply said if it was acknowledged.
struct HistoryOp {
  enum class Kind { build, extend, add_task, remove_task };
  Kind kind = Kind::extend;
  std::string task;              ///< add_task, remove_task: the task's name
  bool acknowledged = false;     ///< the daemon answered that it accepted it
  std::uint64_t generation = 0;  ///< from the reply's status: the lineage it changed
  std::uint64_t target = 0;      ///< from the reply's status: the samples accepted to reach
  std::string server;            ///< the daemon that answered
  std::string what;              ///< for messages: e.g. "extend by 300 in round 4"
};

/// What clients read of the scene once the fleet was connected and the scene idle.
struct HistoryRead {
  std::string server;
  std::uint64_t generation = 0;
  std::uint64_t samples = 0;
  std::vector<std::string> tasks;  ///< the names of the tasks listed
};

/// The acknowledged changes a read is missing, one line each (empty: none). Changes of an older
/// lineage that a later acknowledged build replaced are not missing; the lineage the read
/// serves must be the latest acknowledged build's (or a later one's, if it is an acknowledged
/// build's too).
[[nodiscard]] std::vector<std::string> missing_from(const std::vector<HistoryOp>& history, const HistoryRead& read);

}  // namespace ispars::test
