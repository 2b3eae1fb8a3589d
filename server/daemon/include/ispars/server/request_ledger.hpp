#pragma once
// The daemon's change requests on disk (ChangeLedger), in wire terms: which operations are kept,
// the answer a retry from before a restart gets, and the records made as a change begins and is
// answered. A retry of a change the daemon answered before it restarted gets that answer; one it
// began and never answered is told it was interrupted; neither runs again.

#include <filesystem>
#include <optional>
#include <string>

#include "ispars.h"
#include "ispars/service/change_ledger.hpp"

namespace ispars::server {

class RequestLedger {
 public:
  /// Opens DATA_DIR/.changes.log; its damage is logged as errors, one line each.
  explicit RequestLedger(const std::filesystem::path& data_dir);

  /// Whether `operation` is kept: a change whose repetition would change stored data again
  /// (build, extend, cancel, drop, task add and remove; not load or unload).
  [[nodiscard]] static bool kept(msg::Operation operation);

  /// The reply to a retry of a change begun before this daemon started (`reply` carries its
  /// header); nullopt when it is new. Its status is left for the caller.
  [[nodiscard]] std::optional<msg::Reply> from_before(const msg::ChangeRequest& request, msg::Reply reply) const;
  /// Records durably that `request` begins (a kept operation). Throws std::runtime_error naming
  /// the file when it cannot: the change is then not made.
  void begin(const msg::ChangeRequest& request);
  /// Records `reply` as the answer of a request begun here (others are ignored).
  void answered(const msg::Reply& reply);

 private:
  service::ChangeLedger ledger_;
};

}  // namespace ispars::server
