#include "ispars/web/access_policy.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace ispars::web {
namespace {

std::string lower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

bool starts_with_nocase(std::string_view text, std::string_view prefix) {
  return text.size() >= prefix.size() && lower(text.substr(0, prefix.size())) == prefix;
}

std::string_view trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

// The value of cookie `name` in a Cookie header ("a=b; NAME=VALUE"), or nullopt.
std::optional<std::string_view> cookie_value(std::string_view header, std::string_view name) {
  while (!header.empty()) {
    const auto semi = header.find(';');
    const std::string_view pair = trim(header.substr(0, semi));
    if (pair.size() > name.size() && pair.substr(0, name.size()) == name && pair[name.size()] == '=') {
      return pair.substr(name.size() + 1);
    }
    if (semi == std::string_view::npos) break;
    header.remove_prefix(semi + 1);
  }
  return std::nullopt;
}

// A display of a header's value for a refusal: printable, and not too long.
std::string shown(std::string_view value) {
  std::string out;
  for (const char c : value.substr(0, 100)) out += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
  return value.size() > 100 ? out + "..." : out;
}

}  // namespace

std::string query_value(std::string_view target, std::string_view key) {
  const auto q = target.find('?');
  if (q == std::string_view::npos) return {};
  std::string_view rest = target.substr(q + 1);
  while (!rest.empty()) {
    const auto amp = rest.find('&');
    const std::string_view pair = rest.substr(0, amp);
    if (pair.size() > key.size() && pair.substr(0, key.size()) == key && pair[key.size()] == '=') {
      return std::string(pair.substr(key.size() + 1));
    }
    if (amp == std::string_view::npos) break;
    rest = rest.substr(amp + 1);
  }
  return {};
}

std::string normalize_host(std::string_view host, std::uint16_t default_port) {
  const auto colon = host.find(':');
  const std::string_view name = host.substr(0, colon);
  if (name.empty() || name.size() > 253) return {};
  const bool name_ok = std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.';
  });
  if (!name_ok) return {};
  unsigned long port = default_port;
  if (colon != std::string_view::npos) {
    const std::string_view digits = host.substr(colon + 1);
    if (digits.empty() || digits.size() > 5) return {};
    if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) return {};
    port = std::stoul(std::string(digits));
    if (port > 65535) return {};
  }
  return lower(name) + ":" + std::to_string(port);
}

std::string normalize_origin(std::string_view origin) {
  std::uint16_t port = 0;
  std::string scheme;
  if (starts_with_nocase(origin, "http://")) {
    scheme = "http";
    port = 80;
  } else if (starts_with_nocase(origin, "https://")) {
    scheme = "https";
    port = 443;
  } else {
    return {};
  }
  const std::string host = normalize_host(origin.substr(scheme.size() + 3), port);
  return host.empty() ? std::string() : scheme + "://" + host;
}

bool is_loopback(const std::string& address) { return address.rfind("127.", 0) == 0; }

bool same_secret(std::string_view expected, std::string_view given) {
  unsigned char differ = expected.size() == given.size() ? 0 : 1;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    differ |= static_cast<unsigned char>(expected[i] ^ (i < given.size() ? given[i] : 0));
  }
  return differ == 0;
}

std::string token_problem(std::string_view token) {
  if (token.size() < 16 || token.size() > 256) {
    return fmt::format("the token has {} characters (16 to 256 are accepted)", token.size());
  }
  const bool ok = std::all_of(token.begin(), token.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '~' || c == '-';
  });
  return ok ? std::string() : "the token has characters other than A-Za-z0-9._~-";
}

AccessPolicy::AccessPolicy(AccessOptions options, std::uint16_t port) : options_(std::move(options)), port_(port) {
  hosts_ = {normalize_host("127.0.0.1:" + std::to_string(port)), normalize_host("localhost:" + std::to_string(port))};
  for (const std::string& h : hosts_) origins_.insert("http://" + h);
  for (const std::string& o : options_.allowed_origins) {
    const std::string n = normalize_origin(o);
    if (n.empty()) continue;  // the command line refuses these
    origins_.insert(n);
    const std::string host = n.substr(n.find("://") + 3);
    hosts_.insert(host);
    if (n.starts_with("https://")) https_hosts_.insert(host);
  }
}

std::vector<std::string> AccessPolicy::host_candidates(std::string_view host) {
  // A Host without a port is the default port of whichever scheme the request came by: a TLS
  // proxy that keeps the public name sends "viewer.example" for https://viewer.example.
  if (host.find(':') != std::string_view::npos) return {normalize_host(host)};
  return {normalize_host(host, 80), normalize_host(host, 443)};
}

std::string AccessPolicy::host_problem(const RequestFacts& request) const {
  if (!request.host || request.host->empty()) return "the request has no Host header";
  const std::string own = normalize_host(request.local + ":" + std::to_string(port_));
  for (const std::string& host : host_candidates(*request.host)) {
    if (!host.empty() && (hosts_.count(host) != 0 || host == own)) return {};
  }
  return fmt::format(
      "host {} is not this gateway (name it by 127.0.0.1:{}, localhost:{}, its address, or an "
      "--allow-origin)",
      shown(*request.host), port_, port_);
}

bool AccessPolicy::came_by_https(const RequestFacts& request) const {
  if (lower(trim(request.forwarded_proto)) == "https") return true;
  if (!request.host) return false;
  const auto candidates = host_candidates(*request.host);
  return std::any_of(candidates.begin(), candidates.end(),
                     [&](const std::string& h) { return https_hosts_.count(h) != 0; });
}

std::string AccessPolicy::token_problem_of(const RequestFacts& request, bool& from_query) const {
  from_query = false;
  if (options_.token.empty()) return {};
  std::optional<std::string> given;
  if (starts_with_nocase(request.authorization, "bearer ")) given = std::string(trim(request.authorization.substr(7)));
  if (!given) {
    std::string in_query = query_value(request.target, "token");
    if (!in_query.empty()) {
      given = std::move(in_query);
      from_query = true;
    }
  }
  if (!given) {
    if (auto in_cookie = cookie_value(request.cookie, kTokenCookie)) given = std::string(*in_cookie);
  }
  if (!given) {
    // Loopback too: behind a proxy on the same host every user is a loopback peer.
    return fmt::format(
        "a token is required from {} (an Authorization: Bearer header, or open the page once as "
        "/?token=TOKEN; see --token-file)",
        request.peer);
  }
  if (!same_secret(options_.token, *given)) return "the token is not this gateway's (see --token-file)";
  return {};
}

AccessVerdict AccessPolicy::check(const RequestFacts& request) const {
  if (std::string why = host_problem(request); !why.empty()) return {421, why, {}};
  if (request.origin) {
    const std::string origin = normalize_origin(*request.origin);
    const std::string own = "http://" + normalize_host(request.local + ":" + std::to_string(port_));
    if (origin.empty() || (origins_.count(origin) == 0 && origin != own)) {
      return {403, fmt::format("origin {} is not allowed (see --allow-origin)", shown(*request.origin)), {}};
    }
  }
  bool from_query = false;
  if (std::string why = token_problem_of(request, from_query); !why.empty()) return {401, why, {}};
  AccessVerdict verdict;
  if (from_query) verdict.set_cookie = token_cookie(came_by_https(request));
  return verdict;
}

std::string AccessPolicy::token_cookie(bool secure) const {
  return fmt::format("{}={}; Path=/; HttpOnly; SameSite=Strict{}", kTokenCookie, options_.token,
                     secure ? "; Secure" : "");
}

}  // namespace ispars::web
