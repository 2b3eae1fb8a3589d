#include "ispars/service/memory_budget.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "ispars/params/input_error.hpp"
#include "request_input.hpp"

namespace ispars::service {
namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
constexpr double kMiB = 1024.0 * 1024.0;

}  // namespace

MemoryLease::~MemoryLease() { budget_->give_back(bytes_); }

void MemoryLease::shrink_to(double bytes) {
  if (!(bytes < bytes_)) return;
  budget_->give_back(bytes_ - std::max(0.0, bytes));
  bytes_ = std::max(0.0, bytes);
}

double MemoryBudget::reserved_locked() const {
  double sum = 0.0;
  for (const auto& [name, bytes] : reserved_) sum += bytes;
  return sum;
}

double MemoryBudget::reserved() const {
  std::lock_guard lock(mutex_);
  return reserved_locked();
}

double MemoryBudget::leased() const {
  std::lock_guard lock(mutex_);
  return leased_;
}

std::string MemoryBudget::admission_problem(const std::string& scene, const planning::BuildCost& cost,
                                            bool count_leases) const {
  const auto own = reserved_.find(scene);
  const double others = reserved_locked() - (own == reserved_.end() ? 0.0 : own->second);
  // A scene reserves its peak (its roadmap and one compaction fold of it), not its steady state:
  // every scene may fold at once.
  if (others + cost.peak_bytes > total_) {
    return fmt::format(
        "the roadmap would hold about {:.2f} GiB ({:.3g} vertices, {:.3g} edges expected) and {:.2f} GiB "
        "while its store compacts, more than this daemon's memory budget leaves: {:.2f} of {:.2f} GiB "
        "(other scenes hold {:.2f}); ask for fewer samples or a smaller dense_delta",
        cost.bytes / kGiB, cost.vertices, cost.edges, cost.peak_bytes / kGiB, std::max(0.0, total_ - others) / kGiB,
        total_ / kGiB, others / kGiB);
  }
  if (count_leases && others + leased_ + cost.peak_bytes > total_) {
    return fmt::format(
        "busy: the roadmap would hold {:.1f} MiB at its peak, and this daemon's memory budget leaves "
        "{:.1f} of {:.1f} MiB now (other scenes reserve {:.1f}, running tours and snapshot encodings "
        "hold {:.1f} until they end); retry later",
        cost.peak_bytes / kMiB, std::max(0.0, total_ - others - leased_) / kMiB, total_ / kMiB, others / kMiB,
        leased_ / kMiB);
  }
  return "";
}

void MemoryBudget::admit(const std::string& scene, const planning::BuildCost& cost) {
  for (int attempt = 0;; ++attempt) {
    std::unique_lock lock(mutex_);
    std::string problem = admission_problem(scene, cost, true);
    if (!problem.empty()) {
      const bool busy = problem.starts_with("busy:");
      if (busy && attempt == 0 && reclaim_) {
        lock.unlock();
        reclaim_();  // caches give their leases back; then the check again
        continue;
      }
      throw params::InputError(kRequest, busy ? "kind" : "samples", std::move(problem));
    }
    const double others = reserved_locked() - (reserved_.count(scene) ? reserved_.at(scene) : 0.0);
    reserved_[scene] = cost.peak_bytes;
    spdlog::info(
        "scene '{}': admitted: about {:.1f} MiB held, {:.1f} MiB at its peak ({:.3g} vertices, {:.3g} edges "
        "expected); other scenes reserve {:.1f} MiB of the budget's {:.1f}, leases {:.1f}",
        scene, cost.bytes / kMiB, cost.peak_bytes / kMiB, cost.vertices, cost.edges, others / kMiB, total_ / kMiB,
        leased_ / kMiB);
    return;
  }
}

void MemoryBudget::set_reserved(const std::string& scene, double bytes) {
  std::lock_guard lock(mutex_);
  if (bytes > 0.0) {
    reserved_[scene] = bytes;
  } else {
    reserved_.erase(scene);
  }
}

std::string MemoryBudget::lease_problem(double bytes, const std::string& what) const {
  const double reserved = reserved_locked();
  if (reserved + leased_ + bytes <= total_) return "";
  return fmt::format(
      "busy: {} would need about {:.1f} MiB of memory, and this daemon's memory budget leaves {:.1f} of "
      "{:.1f} MiB now (the loaded roadmaps reserve {:.1f}, running work holds {:.1f}); retry later",
      what, bytes / kMiB, std::max(0.0, total_ - reserved - leased_) / kMiB, total_ / kMiB, reserved / kMiB,
      leased_ / kMiB);
}

std::shared_ptr<MemoryLease> MemoryBudget::lease(double bytes, const std::string& what) {
  bytes = std::max(0.0, bytes);
  for (int attempt = 0;; ++attempt) {
    std::unique_lock lock(mutex_);
    if (std::string problem = lease_problem(bytes, what); !problem.empty()) {
      if (attempt == 0 && reclaim_) {
        lock.unlock();
        reclaim_();
        continue;
      }
      throw params::InputError(kRequest, "kind", std::move(problem));
    }
    leased_ += bytes;
    break;
  }
  return std::shared_ptr<MemoryLease>(new MemoryLease(shared_from_this(), bytes));
}

void MemoryBudget::give_back(double bytes) {
  std::lock_guard lock(mutex_);
  leased_ = std::max(0.0, leased_ - bytes);
}

}  // namespace ispars::service
