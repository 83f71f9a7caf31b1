#include "sim/core/watchdog.h"

#include <algorithm>
#include <cstdio>

namespace fovsim {

namespace {
std::mutex g_handler_m;
Watchdog::Handler& handler_ref() {
  static Watchdog::Handler h = [](const std::string& msg) {
    std::fprintf(stderr, "fovsim: watchdog: %s\n", msg.c_str());
  };
  return h;
}

std::string seconds(double s) {
  char b[32];
  std::snprintf(b, sizeof b, s < 10 ? "%.2f s" : "%.1f s", s);
  return b;
}
}  // namespace

void Watchdog::set_handler(Handler h) {
  std::lock_guard<std::mutex> l(g_handler_m);
  handler_ref() = std::move(h);
}

Watchdog::Watchdog(size_t slots, WatchdogLimits limits) : lim_(limits), slots_(slots) {
  if (lim_.min_s > 0) thread_ = std::thread([this] { loop(); });
}

Watchdog::~Watchdog() {
  {
    std::lock_guard<std::mutex> l(m_);
    stop_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void Watchdog::begin(size_t slot, std::string what) {
  std::lock_guard<std::mutex> l(m_);
  Slot& s = slots_.at(slot);
  s.open = true;
  s.fired = false;
  s.start = Clock::now();
  s.what = std::move(what);
}

void Watchdog::end(size_t slot) {
  std::lock_guard<std::mutex> l(m_);
  Slot& s = slots_.at(slot);
  if (!s.open) return;
  s.open = false;
  s.history.push_back(std::chrono::duration<double>(Clock::now() - s.start).count());
  if (s.history.size() > 16) s.history.erase(s.history.begin());
}

double Watchdog::limit_locked(const Slot& s) const {
  if (s.history.empty()) return lim_.first_factor * lim_.min_s;
  std::vector<double> h = s.history;
  std::nth_element(h.begin(), h.begin() + long(h.size() / 2), h.end());
  return std::max(lim_.min_s, lim_.factor * h[h.size() / 2]);
}

double Watchdog::limit_s(size_t slot) const {
  std::lock_guard<std::mutex> l(m_);
  return limit_locked(slots_.at(slot));
}

void Watchdog::loop() {
  std::unique_lock<std::mutex> l(m_);
  while (!stop_) {
    cv_.wait_for(l, std::chrono::milliseconds(lim_.min_s < 5 ? 50 : 500));
    if (stop_) break;
    const auto now = Clock::now();
    for (Slot& s : slots_) {
      if (!s.open || s.fired) continue;
      const double t = std::chrono::duration<double>(now - s.start).count(), lim = limit_locked(s);
      if (t <= lim) continue;
      s.fired = true;
      std::string msg =
          s.what + " has run for " + seconds(t) + ", over its limit of " + seconds(lim);
      if (!s.history.empty()) {
        std::vector<double> h = s.history;
        std::nth_element(h.begin(), h.begin() + long(h.size() / 2), h.end());
        msg += " (" + std::to_string(int(lim_.factor)) + "x the median " +
               seconds(h[h.size() / 2]) + " of its previous frames)";
      }
      msg += "; stopped by the watchdog (--watchdog SECONDS raises the limit, 0 disables it)";
      Handler h;
      {
        std::lock_guard<std::mutex> hl(g_handler_m);
        h = handler_ref();
      }
      l.unlock();
      h(msg);
      l.lock();
    }
  }
}

}  // namespace fovsim
