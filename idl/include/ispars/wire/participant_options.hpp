#pragma once
// How a program joins a DDS domain: a plain struct, so that a client's options need no DDS header.

#include <string>

namespace ispars::wire {

/// How to join a DDS domain.
struct ParticipantOptions {
  int domain = 0;
  /// A Fast DDS XML profiles file. Empty: the built-in localhost-only settings (UDP bound to
  /// 127.0.0.1; nothing leaves the machine).
  std::string profile_file;
  /// The participant profile in profile_file to use.
  std::string profile_name = "ispars";
  /// The participant's name, announced to peers (over a profile's own): "isparsd ID" for a
  /// daemon, which is how peers tell a daemon in their logs and in wire::PeerWatch.
  std::string name = "ispars";
  /// An identity directory made by deploy/security/make-keystore.sh (cert.pem, key.pem,
  /// permissions.p7s, ca.pem, governance.p7s). Empty: no DDS Security, and a secured daemon
  /// neither sees nor hears this participant.
  std::string security;
};

}  // namespace ispars::wire
