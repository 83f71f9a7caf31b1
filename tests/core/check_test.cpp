// FOVSIM_CHECK: a broken invariant is an InternalError naming the source file:line (sim/app
// exits 3 with it), never a fovsim::Error that would read as the user's bad input (exit 2).
#include <gtest/gtest.h>

#include <string>

#include "sim/core/error.h"

namespace {
int checked_half(int even) {
  FOVSIM_CHECK(even % 2 == 0, "expected an even number, got " + std::to_string(even));
  return even / 2;
}
}  // namespace

TEST(Check, PassesSilently) {
  EXPECT_EQ(checked_half(4), 2);
}

TEST(Check, ThrowsInternalErrorWithSourceLocation) {
  try {
    checked_half(3);
    FAIL() << "no exception";
  } catch (const fovsim::Error&) {
    FAIL() << "an internal bug must not be a fovsim::Error (bad input, exit 2)";
  } catch (const fovsim::InternalError& e) {
    // Relative to the repository, whatever the build directory: "tests/core/check_test.cpp:11".
    EXPECT_EQ(e.where().rfind("tests/core/check_test.cpp:", 0), 0u) << e.where();
    EXPECT_EQ(e.message(), "expected an even number, got 3");
    EXPECT_NE(std::string(e.what()).find("check_test.cpp:11: expected an even"), std::string::npos)
        << e.what();
  }
}
