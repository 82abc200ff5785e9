#include "app/outputs/http_access.hpp"

#include <gtest/gtest.h>

namespace probeless {
namespace {

HttpAccessConfig basic(std::string user, std::string password) {
  HttpAccessConfig c;
  c.auth = HttpAuth::Basic;
  c.user = std::move(user);
  c.password = std::move(password);
  return c;
}

TEST(HttpAccess, HostNamesLoseTheirPortCaseAndTrailingDot) {
  EXPECT_EQ(host_name_of("Box.Local:8080"), "box.local");
  EXPECT_EQ(host_name_of("localhost."), "localhost");
  EXPECT_EQ(host_name_of("[::1]:8080"), "::1");
  EXPECT_EQ(host_name_of("::1"), "::1");
  EXPECT_EQ(host_name_of("127.0.0.1"), "127.0.0.1");
}

// DNS rebinding: a hostile name resolving to 127.0.0.1 must not reach a loopback server.
TEST(HttpAccess, ALoopbackServerAnswersOnlyToLoopbackNames) {
  const HttpAccessConfig open;
  EXPECT_EQ(check_access(open, "127.0.0.1", "localhost:8080", nullptr), AccessDecision::Allow);
  EXPECT_EQ(check_access(open, "127.0.0.1", "127.0.0.1:8080", nullptr), AccessDecision::Allow);
  EXPECT_EQ(check_access(open, "::1", "[::1]:8080", nullptr), AccessDecision::Allow);
  EXPECT_EQ(check_access(open, "127.0.0.1", "evil.example:8080", nullptr), AccessDecision::BadHost);
  EXPECT_EQ(check_access(open, "127.0.0.1", "localhost.evil.example", nullptr),
            AccessDecision::BadHost);
  // HTTP/1.0 tools send no Host; browsers always do.
  EXPECT_EQ(check_access(open, "127.0.0.1", nullptr, nullptr), AccessDecision::Allow);
  // A server open to the network with no list answers to any name (its address is public).
  EXPECT_EQ(check_access(open, "0.0.0.0", "evil.example", nullptr), AccessDecision::Allow);
}

TEST(HttpAccess, AnAllowedHostsListIsTheOnlyNamesAccepted) {
  HttpAccessConfig c;
  c.allowed_hosts = {"probeless.local", "192.168.1.20"};
  EXPECT_EQ(check_access(c, "0.0.0.0", "PROBELESS.local:8080", nullptr), AccessDecision::Allow);
  EXPECT_EQ(check_access(c, "0.0.0.0", "192.168.1.20", nullptr), AccessDecision::Allow);
  EXPECT_EQ(check_access(c, "0.0.0.0", "localhost", nullptr), AccessDecision::BadHost);
  c.allowed_hosts = {"*"};
  EXPECT_EQ(check_access(c, "127.0.0.1", "anything", nullptr), AccessDecision::Allow);
}

TEST(HttpAccess, BasicAuthNeedsTheExactCredentials) {
  const HttpAccessConfig c = basic("viewer", "s3cret");
  // "viewer:s3cret" in base64.
  EXPECT_EQ(check_access(c, "127.0.0.1", "localhost", "Basic dmlld2VyOnMzY3JldA=="),
            AccessDecision::Allow);
  EXPECT_EQ(check_access(c, "127.0.0.1", "localhost", "basic dmlld2VyOnMzY3JldA=="),
            AccessDecision::Allow);
  EXPECT_EQ(check_access(c, "127.0.0.1", "localhost", nullptr), AccessDecision::Unauthorised);
  // "viewer:s3cre", "viewer:s3cret!" and garbage.
  EXPECT_EQ(check_access(c, "127.0.0.1", "localhost", "Basic dmlld2VyOnMzY3Jl"),
            AccessDecision::Unauthorised);
  EXPECT_EQ(check_access(c, "127.0.0.1", "localhost", "Basic dmlld2VyOnMzY3JldCE="),
            AccessDecision::Unauthorised);
  EXPECT_EQ(check_access(c, "127.0.0.1", "localhost", "Basic !!!!"), AccessDecision::Unauthorised);
  EXPECT_EQ(check_access(c, "127.0.0.1", "localhost", "Basic"), AccessDecision::Unauthorised);
  EXPECT_EQ(check_access(c, "127.0.0.1", "localhost", "Bearer dmlld2VyOnMzY3JldA=="),
            AccessDecision::Unauthorised);
  // The Host check comes first: a rebinding page learns nothing from a 401.
  EXPECT_EQ(check_access(c, "127.0.0.1", "evil.example", "Basic dmlld2VyOnMzY3JldA=="),
            AccessDecision::BadHost);
}

TEST(HttpAccess, BearerTokensCompareWhole) {
  HttpAccessConfig c;
  c.auth = HttpAuth::Bearer;
  c.token = "0123456789abcdef";
  EXPECT_EQ(check_access(c, "127.0.0.1", nullptr, "Bearer 0123456789abcdef"),
            AccessDecision::Allow);
  EXPECT_EQ(check_access(c, "127.0.0.1", nullptr, "Bearer 0123456789abcde"),
            AccessDecision::Unauthorised);
  EXPECT_EQ(check_access(c, "127.0.0.1", nullptr, "Bearer 0123456789abcdef0"),
            AccessDecision::Unauthorised);
  EXPECT_EQ(check_access(c, "127.0.0.1", nullptr, "Bearer "), AccessDecision::Unauthorised);
  EXPECT_EQ(authenticate_challenge(c), "Bearer realm=\"probeless\"");
}

TEST(HttpAccess, AuthNamesParseOrFailClearly) {
  EXPECT_EQ(parse_http_auth("none"), HttpAuth::None);
  EXPECT_EQ(parse_http_auth("basic"), HttpAuth::Basic);
  EXPECT_EQ(parse_http_auth("bearer"), HttpAuth::Bearer);
  try {
    parse_http_auth("digest");
    FAIL() << "digest accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("digest"), std::string::npos);
  }
}

}  // namespace
}  // namespace probeless
