// AccessPolicy, the gateway's door (client/web/README.md, "Who may use the gateway"): Host against
// DNS rebinding, Origin against other pages, the token from every peer (loopback too: behind a
// proxy on the same host every user is loopback), and the token's cookie, Secure behind TLS.
// Before this library these rules were reached only through a browser (WebGatewayTest,
// WebProxyTest).

#include <gtest/gtest.h>

#include <string>

#include "ispars/web/access_policy.hpp"

namespace ispars::web {
namespace {

constexpr std::uint16_t kPort = 8080;
const std::string kToken = "0123456789abcdef-token";

RequestFacts request(std::string_view host, std::string peer = "127.0.0.1") {
  RequestFacts r;
  r.host = host;
  r.target = "/";
  r.peer = std::move(peer);
  r.local = "127.0.0.1";
  return r;
}

AccessPolicy with_token(std::vector<std::string> origins = {}) {
  return AccessPolicy({std::move(origins), kToken}, kPort);
}

TEST(AccessPolicy, AHostThatDoesNotNameTheGatewayIsMisdirected) {
  const AccessPolicy open({}, kPort);
  EXPECT_EQ(open.check(request("127.0.0.1:8080")).status, 0u);
  EXPECT_EQ(open.check(request("LOCALHOST:8080")).status, 0u);
  const AccessVerdict rebound = open.check(request("rebind.example:8080"));
  EXPECT_EQ(rebound.status, 421u);
  EXPECT_NE(rebound.reason.find("host rebind.example:8080 is not this gateway"), std::string::npos) << rebound.reason;
  RequestFacts none = request("");
  none.host.reset();
  EXPECT_EQ(open.check(none).status, 421u);
  // The address the connection came in on names it too.
  RequestFacts lan = request("10.0.0.5:8080", "10.0.0.9");
  lan.local = "10.0.0.5";
  EXPECT_EQ(open.check(lan).status, 0u);
}

// A TLS proxy that keeps the public name sends Host without a port: https's 443, not 80.
TEST(AccessPolicy, AHostWithoutAPortIsTheDefaultPortOfEitherScheme) {
  const AccessPolicy behind_tls({{"https://viewer.example"}, {}}, kPort);
  EXPECT_EQ(behind_tls.check(request("viewer.example")).status, 0u);
  EXPECT_EQ(behind_tls.check(request("viewer.example:443")).status, 0u);
  EXPECT_EQ(behind_tls.check(request("viewer.example:80")).status, 421u);
  EXPECT_EQ(normalize_host("Viewer.Example", 443), "viewer.example:443");
  EXPECT_EQ(normalize_origin("HTTPS://Viewer.Example"), "https://viewer.example:443");
  EXPECT_EQ(normalize_origin("https://viewer.example/path"), "");
  EXPECT_EQ(normalize_origin("null"), "");
}

TEST(AccessPolicy, AnOriginOtherThanTheGatewaysOrAnAllowedOneIsForbidden) {
  const AccessPolicy policy({{"https://viewer.example"}, {}}, kPort);
  RequestFacts r = request("127.0.0.1:8080");
  r.origin = "http://127.0.0.1:8080";
  EXPECT_EQ(policy.check(r).status, 0u);
  r.origin = "https://viewer.example";
  EXPECT_EQ(policy.check(r).status, 0u);
  r.origin = "https://evil.example";
  const AccessVerdict v = policy.check(r);
  EXPECT_EQ(v.status, 403u);
  EXPECT_NE(v.reason.find("origin https://evil.example is not allowed"), std::string::npos) << v.reason;
  r.origin = "null";
  EXPECT_EQ(policy.check(r).status, 403u);
}

TEST(AccessPolicy, WithATokenEveryPeerNeedsItLoopbackIncluded) {
  const AccessPolicy policy = with_token();
  const AccessVerdict loopback = policy.check(request("127.0.0.1:8080"));
  EXPECT_EQ(loopback.status, 401u);
  EXPECT_NE(loopback.reason.find("a token is required from 127.0.0.1"), std::string::npos) << loopback.reason;
  RequestFacts bearer = request("127.0.0.1:8080");
  const std::string header = "Bearer " + kToken;
  bearer.authorization = header;
  EXPECT_EQ(policy.check(bearer).status, 0u);
  RequestFacts cookie = request("127.0.0.1:8080");
  const std::string cookies = "a=b; ispars_token=" + kToken;
  cookie.cookie = cookies;
  EXPECT_EQ(policy.check(cookie).status, 0u);
  RequestFacts wrong = request("127.0.0.1:8080");
  const std::string bad = "Bearer " + kToken + "x";
  wrong.authorization = bad;
  const AccessVerdict refused = policy.check(wrong);
  EXPECT_EQ(refused.status, 401u);
  EXPECT_NE(refused.reason.find("not this gateway's"), std::string::npos) << refused.reason;
}

TEST(AccessPolicy, ATokenInTheQueryIsKeptInACookieSecureOnlyBehindTls) {
  const AccessPolicy policy = with_token({"https://viewer.example"});
  RequestFacts plain = request("127.0.0.1:8080");
  const std::string target = "/?token=" + kToken;
  plain.target = target;
  AccessVerdict v = policy.check(plain);
  ASSERT_EQ(v.status, 0u);
  EXPECT_EQ(v.set_cookie, "ispars_token=" + kToken + "; Path=/; HttpOnly; SameSite=Strict");
  RequestFacts proxied = plain;
  proxied.forwarded_proto = "https";
  EXPECT_NE(policy.check(proxied).set_cookie.find("; Secure"), std::string::npos);
  RequestFacts named = plain;
  named.host = "viewer.example";  // an https --allow-origin's host
  EXPECT_NE(policy.check(named).set_cookie.find("; Secure"), std::string::npos);
  RequestFacts by_header = request("127.0.0.1:8080");
  const std::string header = "Bearer " + kToken;
  by_header.authorization = header;
  EXPECT_EQ(policy.check(by_header).set_cookie, "") << "only a token in the query is kept";
}

TEST(AccessPolicy, TokensAndQueriesAreCheckedByTheirRules) {
  EXPECT_EQ(token_problem(kToken), "");
  EXPECT_NE(token_problem("short").find("5 characters"), std::string::npos);
  EXPECT_NE(token_problem(std::string(16, '!')).find("other than"), std::string::npos);
  EXPECT_EQ(token_problem(std::string(257, 'a')).find("257 characters") != std::string::npos, true);
  EXPECT_TRUE(same_secret("abc", "abc"));
  EXPECT_FALSE(same_secret("abc", "abd"));
  EXPECT_FALSE(same_secret("abc", "abcd"));
  EXPECT_FALSE(same_secret("abc", ""));
  EXPECT_EQ(query_value("/ws?scene=s0&token=t", "scene"), "s0");
  EXPECT_EQ(query_value("/ws?scene=s0&token=t", "token"), "t");
  EXPECT_EQ(query_value("/ws", "scene"), "");
  EXPECT_TRUE(is_loopback("127.0.0.2"));
  EXPECT_FALSE(is_loopback("10.0.0.1"));
}

}  // namespace
}  // namespace ispars::web
