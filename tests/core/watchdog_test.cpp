// The watchdog reports a step that runs far longer than its slot's previous steps, once,
// naming the step; quick steps never trigger it; a disabled watchdog starts no thread.
#include "sim/core/watchdog.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

using namespace fovsim;

namespace {
struct Captured {
  std::mutex m;
  std::vector<std::string> msgs;
};
Captured& cap() {
  static Captured c;
  return c;
}
void install() {
  Watchdog::set_handler([](const std::string& s) {
    std::lock_guard<std::mutex> l(cap().m);
    cap().msgs.push_back(s);
  });
  std::lock_guard<std::mutex> l(cap().m);
  cap().msgs.clear();
}
size_t count() {
  std::lock_guard<std::mutex> l(cap().m);
  return cap().msgs.size();
}
}  // namespace

TEST(Watchdog, LimitFromMedianOfPreviousSteps) {
  Watchdog w(2, WatchdogLimits{0.5, 10, 60});
  EXPECT_DOUBLE_EQ(w.limit_s(0), 30);  // no neighbours yet
  for (int i = 0; i < 3; ++i) {
    w.begin(0, "quick");
    w.end(0);
  }
  EXPECT_DOUBLE_EQ(w.limit_s(0), 0.5);  // max(min_s, 10 x ~0 s)
  EXPECT_DOUBLE_EQ(w.limit_s(1), 30);   // 60 x 0.5 s   // slots are independent
}

TEST(Watchdog, ReportsAStuckStepOnceNamingIt) {
  install();
  {
    Watchdog w(1, WatchdogLimits{0.2, 10, 1});
    w.begin(0, "frame 7, method \"twfr\"");
    // Wait (bounded) until the watchdog fires; the assertion is on the report, not a time.
    for (int i = 0; i < 400 && count() == 0; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(25));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // it must not repeat
    w.end(0);
  }
  std::lock_guard<std::mutex> l(cap().m);
  ASSERT_EQ(cap().msgs.size(), 1u);
  EXPECT_NE(cap().msgs[0].find("frame 7, method \"twfr\" has run for"), std::string::npos)
      << cap().msgs[0];
  EXPECT_NE(cap().msgs[0].find("--watchdog"), std::string::npos);
}

TEST(Watchdog, QuickStepsAndDisabledNeverFire) {
  install();
  {
    Watchdog w(1, WatchdogLimits{5, 50, 1});
    for (int i = 0; i < 50; ++i) {
      w.begin(0, "step");
      w.end(0);
    }
  }
  {
    Watchdog off(1, WatchdogLimits{0, 50, 0});
    off.begin(0, "never checked");
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    off.end(0);
  }
  EXPECT_EQ(count(), 0u);
}
