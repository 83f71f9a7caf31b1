// Per-phase timing of a run (serial fraction and scaling): wall time, CPU time of the whole process
// and CPU time of the thread that drives the frame loop, summed per named phase (setup, reference,
// methods, tonemap, metrics, images, rows). Written to manifest.json as "phases" by the engine.
//
// Serial-work estimate at T > 1 threads: a phase whose work S runs on the driving thread alone
// and whose work P is spread evenly over T threads takes main = S + P / T of the driving
// thread's CPU and cpu = S + P of the process's, so S = (T main - cpu) / (T - 1), clamped to
// [0, cpu]. serial_fraction = sum S / sum cpu. It reads CPU time, not wall time, so a machine
// loaded by other processes does not inflate it; it assumes one cell (`fovsim run`), since with
// parallel sweep cells the process CPU time of a phase includes the other cells' work.
#pragma once
#include <time.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <string>

#include "sim/core/params.h"

namespace fovsim {

// Wall milliseconds since `t0` (the engine's per-frame and per-cell timings).
inline double elapsed_ms(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

struct PhaseClock {
  double wall_ms = 0, cpu_ms = 0, main_cpu_ms = 0;
  static PhaseClock now() {
    auto ms = [](clockid_t id) {
      timespec t{};
      clock_gettime(id, &t);
      return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
    };
    PhaseClock c;
    c.wall_ms = std::chrono::duration<double, std::milli>(
                    std::chrono::steady_clock::now().time_since_epoch())
                    .count();
    c.cpu_ms = ms(CLOCK_PROCESS_CPUTIME_ID);
    c.main_cpu_ms = ms(CLOCK_THREAD_CPUTIME_ID);
    return c;
  }
};

class PhaseTimes {
 public:
  // Adds the time from `from` to now to `name`; returns now (the start of the next phase).
  PhaseClock lap(const std::string& name, const PhaseClock& from) {
    const PhaseClock to = PhaseClock::now();
    PhaseClock& a = acc_[name];
    a.wall_ms += to.wall_ms - from.wall_ms;
    a.cpu_ms += to.cpu_ms - from.cpu_ms;
    a.main_cpu_ms += to.main_cpu_ms - from.main_cpu_ms;
    return to;
  }
  void merge(const PhaseTimes& o) {
    for (auto& [k, v] : o.acc_) add(k, v);
  }
  const std::map<std::string, PhaseClock>& items() const { return acc_; }
  // Serial CPU work of a phase from its frame-loop thread CPU `main` and process CPU `cpu` at
  // `threads` > 1 (header comment), clamped to [0, cpu]; 0 at one thread.
  static double serial_cpu_ms(int threads, double main, double cpu) {
    if (threads <= 1) return 0.0;
    return std::clamp((threads * main - cpu) / (threads - 1), 0.0, std::max(cpu, 0.0));
  }
  // Adds a measured phase directly (tests; merging timings taken elsewhere).
  void add(const std::string& name, const PhaseClock& d) {
    PhaseClock& a = acc_[name];
    a.wall_ms += d.wall_ms;
    a.cpu_ms += d.cpu_ms;
    a.main_cpu_ms += d.main_cpu_ms;
  }
  // {"threads", "phases": {name: {wall_ms, cpu_ms, main_cpu_ms, serial_cpu_ms}}, "wall_ms",
  //  "cpu_ms", "serial_cpu_ms", "serial_fraction"} (serial_* only for threads > 1).
  Json to_json(int threads) const {
    Json ph = Json::object();
    double wall = 0, cpu = 0, serial = 0;
    for (auto& [k, v] : acc_) {
      Json o{{"wall_ms", v.wall_ms}, {"cpu_ms", v.cpu_ms}, {"main_cpu_ms", v.main_cpu_ms}};
      wall += v.wall_ms;
      cpu += v.cpu_ms;
      if (threads > 1) {
        const double s = serial_cpu_ms(threads, v.main_cpu_ms, v.cpu_ms);
        o["serial_cpu_ms"] = s;
        serial += s;
      }
      ph[k] = o;
    }
    Json j{{"threads", threads}, {"phases", ph}, {"wall_ms", wall}, {"cpu_ms", cpu}};
    if (threads > 1) {
      j["serial_cpu_ms"] = serial;
      j["serial_fraction"] = cpu > 0 ? serial / cpu : 0.0;
    }
    return j;
  }

 private:
  std::map<std::string, PhaseClock> acc_;
};

}  // namespace fovsim
