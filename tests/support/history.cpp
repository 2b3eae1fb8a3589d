#include "support/history.hpp"

#include <algorithm>
#include <map>

namespace ispars::test {
namespace {

std::string described_op(const HistoryOp& op) {
  return op.what + " (acknowledged by " + op.server + ": generation " + std::to_string(op.generation) + ", target " +
         std::to_string(op.target) + ")";
}

bool task_listed(const HistoryRead& read, const std::string& task) {
  return std::find(read.tasks.begin(), read.tasks.end(), task) != read.tasks.end();
}

}  // namespace

std::vector<std::string> missing_from(const std::vector<HistoryOp>& history, const HistoryRead& read) {
  std::vector<std::string> missing;
  // The lineage: the latest acknowledged build's generation; the read may serve a later
  // generation only if an acknowledged build made it.
  std::uint64_t latest_build = 0;
  bool read_lineage_acknowledged = false;
  for (const HistoryOp& op : history) {
    if (!op.acknowledged || op.kind != HistoryOp::Kind::build) continue;
    latest_build = std::max(latest_build, op.generation);
    read_lineage_acknowledged = read_lineage_acknowledged || op.generation == read.generation;
  }
  if (read.generation < latest_build) {
    missing.push_back("the read serves generation " + std::to_string(read.generation) +
                      ", older than the latest acknowledged build's " + std::to_string(latest_build));
  } else if (latest_build > 0 && !read_lineage_acknowledged) {
    missing.push_back("the read serves generation " + std::to_string(read.generation) +
                      ", which no acknowledged build made (the latest made " + std::to_string(latest_build) + ")");
  }
  // Within the lineage read: every acknowledged target reached, and each task as its last
  // acknowledged change left it.
  std::map<std::string, const HistoryOp*> last_task_change;
  for (const HistoryOp& op : history) {
    if (!op.acknowledged || op.generation != read.generation) continue;
    if (op.kind == HistoryOp::Kind::build || op.kind == HistoryOp::Kind::extend) {
      if (read.samples < op.target) {
        missing.push_back(described_op(op) + ": the read holds " + std::to_string(read.samples) + " samples");
      }
    } else {
      last_task_change[op.task] = &op;
    }
  }
  for (const auto& [task, op] : last_task_change) {
    const bool added = op->kind == HistoryOp::Kind::add_task;
    if (added != task_listed(read, task)) {
      missing.push_back(described_op(*op) + ": task '" + task + "' is " + (added ? "not listed" : "listed still"));
    }
  }
  return missing;
}

}  // namespace ispars::test
