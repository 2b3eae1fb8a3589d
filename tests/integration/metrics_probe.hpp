#pragma once
// Reading a daemon's metrics endpoint from an integration test.

// Eigen first: httplib.h defines a macro Eigen's headers use, so Eigen must be read before it.
#include <Eigen/Core>

#include <string>

#include <httplib.h>

namespace ispars::test {

/// The value of the unlabelled series `name` on the metrics endpoint at `port` of `address`; -1
/// when unreadable.
inline double metric_on(int port, const std::string& name, const std::string& address = "127.0.0.1") {
  httplib::Client http(address, port);
  http.set_read_timeout(5, 0);
  const auto res = http.Get("/metrics");
  if (!res || res->status != 200) return -1;
  const std::string text = "\n" + res->body;
  const std::string series = "\n" + name + " ";
  const auto at = text.find(series);
  if (at == std::string::npos) return -1;
  return std::stod(text.substr(at + series.size()));
}

/// How many other live daemons the daemon serving metrics on `port` of `address` counts (the
/// fleet view its takeovers are decided on); -1 when unreadable.
inline double other_daemons_counted_on(int port, const std::string& address = "127.0.0.1") {
  return metric_on(port, "ispars_other_daemons", address);
}

}  // namespace ispars::test
