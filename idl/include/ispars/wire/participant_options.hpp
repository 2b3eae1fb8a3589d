#pragma once
// How a program joins a DDS domain: a plain struct, so that a client's options need no DDS header.

#include <cstdint>
#include <string>

#include "ispars/params/spec.hpp"
#include "ispars/params/text_spec.hpp"

namespace ispars::wire {

/// The built-in profile's participant lease in seconds (a peer silent this long is dropped).
inline constexpr int kLeaseSeconds = 3;
/// The same under DDS Security, longer (participant.cpp says why).
inline constexpr int kSecureLeaseSeconds = 20;
/// The longest lease a participant may ask for.
inline constexpr std::uint32_t kMaxLeaseSeconds = 600;
/// The lease of a participant with the built-in settings that asked for `configured` seconds
/// (0: the default, kSecureLeaseSeconds when `secure`, else kLeaseSeconds).
[[nodiscard]] inline int lease_seconds(std::uint32_t configured, bool secure) {
  if (configured != 0) return static_cast<int>(configured);
  return secure ? kSecureLeaseSeconds : kLeaseSeconds;
}

/// The participant's settings a user gives (a daemon's config and flags declare theirs by these).
inline constexpr params::Spec<int> kDomain{
    "domain",
    0,
    232,
    "DDS domain id; $ISPARS_DOMAIN when not given (a daemon's config file sets its own)",
    params::Lower::closed,
    true};
inline constexpr params::TextSpec kProfileFile{
    "profile_file", "Fast DDS XML profiles file (default: built-in localhost only)", 4096, true, true};
inline constexpr params::TextSpec kProfileName{"profile_name", "participant profile in the profiles file", 256, false,
                                               true};
inline constexpr params::TextSpec kSecurity{
    "security", "DDS Security identity directory (deploy/security/make-keystore.sh); default: none", 4096, true, true};
inline constexpr params::Spec<std::uint32_t> kLease{
    "lease_s",
    0,
    kMaxLeaseSeconds,
    "seconds a peer waits on this participant's silence before dropping it, with the built-in settings (0: 3, or "
    "20 under DDS Security; a profiles file sets its own)",
    params::Lower::closed,
    true};

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
  /// The participant's lease in seconds with the built-in settings (a peer silent this long
  /// drops it), 1..600; 0: 3 s, or 20 s under DDS Security (lease_seconds). A profiles file
  /// sets its own.
  std::uint32_t lease_seconds = 0;

  /// The settings a user gives, declared once (params/fields.hpp); `name` is the program's.
  static void describe(auto& self, auto&& field) {
    field(kDomain, self.domain);
    field(kProfileFile, self.profile_file);
    field(kProfileName, self.profile_name);
    field(kSecurity, self.security);
    field(kLease, self.lease_seconds);
  }
};

}  // namespace ispars::wire
