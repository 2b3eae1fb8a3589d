#pragma once
// What the DDS endpoints hand the daemon, as an interface: requests addressed to it, and what it
// hears of the fleet. The daemon passes each on to the part whose job it is.

#include "ispars.h"

namespace ispars::server {

/// The daemon as its DDS endpoints see it. Called inside DDS callbacks: quick, no DDS calls.
class DaemonInbox {
 public:
  virtual ~DaemonInbox() = default;
  /// A request addressed to this daemon, its client id the sender's transport identity.
  virtual void receive(msg::QueryRequest request) = 0;
  virtual void receive(msg::ChangeRequest request) = 0;
  /// An announcement arrived (`announcement`, alive) or a daemon left (null).
  virtual void fleet_changed(const msg::DaemonInfo* announcement) = 0;
  /// A status, or a task, another daemon published.
  virtual void status_seen(const msg::SceneStatus& status) = 0;
  virtual void task_seen(const msg::SceneTask& task) = 0;
};

}  // namespace ispars::server
