// A watchdog for long runs (issue: nothing hangs silently). Work is reported as steps in
// slots (e.g. slot 0 = the frame's reference, slot 1 + i = cell i's methods); a thread checks
// the open steps twice a second and, when one has run far longer than the completed steps of
// its slot ("its neighbours"), calls the handler once with a message naming the step.
//   limit = first_factor * min_s                    while the slot has no completed step
//   limit = max(min_s, factor * median(last 16))    afterwards
// The library never exits: sim/app installs a handler that prints the message and exits;
// the default handler only writes the message to stderr.
#pragma once
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace fovsim {

struct WatchdogLimits {
  double min_s = 60;         // 0 disables the watchdog
  double factor = 50;        // times the median of the slot's previous steps
  double first_factor = 10;  // a slot's first step (no neighbours yet): first_factor * min_s
};

class Watchdog {
 public:
  using Handler = std::function<void(const std::string& message)>;
  // Process-wide handler (set once by the app before any run).
  static void set_handler(Handler h);

  Watchdog(size_t slots, WatchdogLimits limits);
  ~Watchdog();
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

  void begin(size_t slot, std::string what);  // thread-safe; one open step per slot
  void end(size_t slot);
  // The limit now in force for `slot` (seconds); for tests and messages.
  double limit_s(size_t slot) const;

 private:
  using Clock = std::chrono::steady_clock;
  struct Slot {
    bool open = false, fired = false;
    Clock::time_point start;
    std::string what;
    std::vector<double> history;  // seconds, last 16
  };
  double limit_locked(const Slot& s) const;
  void loop();

  WatchdogLimits lim_;
  mutable std::mutex m_;
  std::condition_variable cv_;
  std::vector<Slot> slots_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace fovsim
