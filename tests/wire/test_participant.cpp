// Participant options checked at the boundary: a lease out of its range is refused, naming it
// and the range, before any participant is made. (That a lease reaches the peers is what the
// secured stall test relies on: tests/integration/test_service_stall.cpp.)

#include "ispars/wire/participant.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace ispars::wire {
namespace {

TEST(ParticipantOptions, ALeaseOutOfItsRangeIsRefusedByName) {
  ParticipantOptions options;
  options.domain = 231;
  options.lease_seconds = kMaxLeaseSeconds + 1;
  try {
    Participant participant(options);
    FAIL() << "a lease of " << options.lease_seconds << " s was taken";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("participant lease_s: must be a whole number in [0, 600], got 601"),
              std::string::npos)
        << e.what();
  }
}

TEST(ParticipantOptions, TheDefaultLeaseIsLongerUnderSecurity) {
  EXPECT_EQ(lease_seconds(0, false), kLeaseSeconds);
  EXPECT_EQ(lease_seconds(0, true), kSecureLeaseSeconds);
  EXPECT_EQ(lease_seconds(8, true), 8);
  EXPECT_EQ(lease_seconds(8, false), 8);
}

}  // namespace
}  // namespace ispars::wire
