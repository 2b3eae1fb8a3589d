#pragma once
// The daemon's memory budget, in two kinds of share. Each loaded scene *reserves* its roadmap's
// peak (what it holds, plus one compaction fold or recovery of its store; build_cost.hpp), from
// the build or extend that makes it until it is unloaded or dropped: a build whose peak does not
// fit beside the other scenes' reservations is refused before it starts. Work that holds memory
// for a while and then gives it back (a tour's distance rows, a snapshot's encoding) takes a
// *lease* of its worst case from what the reservations and the other leases leave, and is refused
// as busy when that is too little; a build is admitted only beside the leases held too. All estimates, not measurements
// of the heap: ispars-bench peak measures how they compare (docs/results/service.md). Safe from many threads.

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "ispars/planning/builders/build_cost.hpp"

namespace ispars::service {

class MemoryBudget;

/// A share of the budget held until destroyed (then given back). Made by MemoryBudget::lease.
class MemoryLease {
 public:
  ~MemoryLease();
  MemoryLease(const MemoryLease&) = delete;
  MemoryLease& operator=(const MemoryLease&) = delete;
  [[nodiscard]] double bytes() const { return bytes_; }
  /// Gives back all but `bytes` (no-op when it holds no more).
  void shrink_to(double bytes);

 private:
  friend class MemoryBudget;
  MemoryLease(std::shared_ptr<MemoryBudget> budget, double bytes) : budget_(std::move(budget)), bytes_(bytes) {}
  std::shared_ptr<MemoryBudget> budget_;  // kept alive by its leases
  double bytes_;
};

/// See the file comment. Made shared (leases keep it alive).
class MemoryBudget : public std::enable_shared_from_this<MemoryBudget> {
 public:
  /// `bytes`: the whole budget (infinity: none).
  static std::shared_ptr<MemoryBudget> make(double bytes) {
    return std::shared_ptr<MemoryBudget>(new MemoryBudget(bytes));
  }

  /// Reserves `cost.peak_bytes` for `scene` in place of what it reserved before. Throws InputError
  /// ("request: samples: ...", naming the sizes and what the budget leaves) when that does not fit
  /// beside the other scenes' reservations; and ("request: kind: busy: ...") when it fits beside
  /// them but not beside the leases held now too (tours, snapshot encodings), after the reclaimer
  /// gave back what it could: a build does not take memory that running work holds.
  void admit(const std::string& scene, const planning::BuildCost& cost);
  /// Called, with no lock held, when an admission or a lease does not fit beside the leases held:
  /// it drops what holds a lease only as a cache (kept snapshot encodings), then the check is made
  /// again. Set once, before the budget is shared.
  void set_reclaimer(std::function<void()> reclaim) { reclaim_ = std::move(reclaim); }
  /// Sets `scene`'s reservation without a check (a stored roadmap is held whatever the budget);
  /// 0 removes it.
  void set_reserved(const std::string& scene, double bytes);
  /// A lease of `bytes` for `what` ("a snapshot of scene 'S'"), or InputError ("request: kind:
  /// busy: ...") when the reservations and the leases held now leave less (after the reclaimer).
  [[nodiscard]] std::shared_ptr<MemoryLease> lease(double bytes, const std::string& what);

  [[nodiscard]] double total() const { return total_; }
  [[nodiscard]] double reserved() const;
  [[nodiscard]] double leased() const;

 private:
  explicit MemoryBudget(double bytes) : total_(bytes) {}
  friend class MemoryLease;
  void give_back(double bytes);
  double reserved_locked() const;
  // The refusal of `scene`'s admission under mutex_, or "" when it fits (leases counted or not).
  std::string admission_problem(const std::string& scene, const planning::BuildCost& cost, bool count_leases) const;
  std::string lease_problem(double bytes, const std::string& what) const;  // the same for a lease

  const double total_;
  mutable std::mutex mutex_;
  std::map<std::string, double> reserved_;
  double leased_ = 0.0;
  std::function<void()> reclaim_;
};

}  // namespace ispars::service
