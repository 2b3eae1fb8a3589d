#pragma once
// Who may use the gateway (client/web/README.md, "Who may use the gateway"): a request's Host must
// name the gateway (against DNS rebinding), its Origin, when it has one, must be the gateway's own
// or one allowed by --allow-origin (against other pages in the user's browser), and, when the
// gateway has a token (--token-file), every peer must present it, loopback included (behind a
// proxy on the same host every user is loopback). Knows nothing of sockets or Beast.

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace ispars::web {

/// The name of the cookie that carries the token for a page and its WebSocket.
inline constexpr std::string_view kTokenCookie = "ispars_token";

/// What the gateway lets in beyond its own origin. Every bound is checked by the command line.
struct AccessOptions {
  std::vector<std::string> allowed_origins;  ///< scheme://host[:port] (--allow-origin; at most 32).
  std::string token;                         ///< Empty: none; else 16-256 of A-Za-z0-9._~- .
};

/// What a request says about itself, as the policy needs it.
struct RequestFacts {
  std::optional<std::string_view> host;    ///< The Host header, when there is one.
  std::optional<std::string_view> origin;  ///< The Origin header, when there is one.
  std::string_view authorization;          ///< The Authorization header (may be empty).
  std::string_view cookie;                 ///< The Cookie header (may be empty).
  std::string_view target;                 ///< The request target, with its query.
  std::string peer;                        ///< The TCP peer's IPv4 address.
  std::string local;                       ///< The IPv4 address the connection came in on.
  std::string_view forwarded_proto;        ///< X-Forwarded-Proto (a TLS proxy's "https"), may be empty.
};

/// A request let in (`status` 0), or refused: the HTTP status and a one-line reason.
struct AccessVerdict {
  unsigned status = 0;
  std::string reason;
  std::string set_cookie;  ///< Let in by ?token=: the Set-Cookie that keeps the token (Secure over https).
};

/// "scheme://host[:port]" in lower case with its port made explicit (http 80, https 443); empty
/// when `origin` is not an http or https origin (a path, user info or "null" make it none).
[[nodiscard]] std::string normalize_origin(std::string_view origin);
/// "host[:port]" in lower case with its port made explicit (`default_port` when none); empty
/// when it is not a host name or IPv4 address with an optional port.
[[nodiscard]] std::string normalize_host(std::string_view host, std::uint16_t default_port = 80);
/// The value of `key` in a target's query string ("/ws?scene=s0"), undecoded: names and tokens
/// need no escapes.
[[nodiscard]] std::string query_value(std::string_view target, std::string_view key);
/// Whether `address` (dotted IPv4) is in 127.0.0.0/8.
[[nodiscard]] bool is_loopback(const std::string& address);
/// Equal, in a time that does not depend on where they first differ.
[[nodiscard]] bool same_secret(std::string_view expected, std::string_view given);
/// Why `token` is not a valid token (empty when it is one).
[[nodiscard]] std::string token_problem(std::string_view token);

class AccessPolicy {
 public:
  /// The gateway's own origins are http://127.0.0.1:PORT, http://localhost:PORT and
  /// http://ADDRESS:PORT for the address each connection came in on.
  AccessPolicy(AccessOptions options, std::uint16_t port);

  [[nodiscard]] AccessVerdict check(const RequestFacts& request) const;
  [[nodiscard]] bool has_token() const { return !options_.token.empty(); }
  /// The Set-Cookie value that keeps the token for a page let in by ?token= (`secure`: it came by
  /// https, through a TLS proxy, so the browser must send it back only over https).
  [[nodiscard]] std::string token_cookie(bool secure) const;

 private:
  /// The normalized forms a Host header may stand for (both default ports when it has none).
  [[nodiscard]] static std::vector<std::string> host_candidates(std::string_view host);
  [[nodiscard]] std::string host_problem(const RequestFacts& request) const;
  /// Whether the request came through TLS: X-Forwarded-Proto says so, or its Host names an
  /// https --allow-origin.
  [[nodiscard]] bool came_by_https(const RequestFacts& request) const;
  [[nodiscard]] std::string token_problem_of(const RequestFacts& request, bool& from_query) const;
  AccessOptions options_;
  std::uint16_t port_;
  std::set<std::string> hosts_;        // normalized Host values that name this gateway
  std::set<std::string> origins_;      // normalized origins let in
  std::set<std::string> https_hosts_;  // hosts of the https origins let in
};

}  // namespace ispars::web
