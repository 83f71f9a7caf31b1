// Progress with ETA on stderr, only when stderr is a terminal (never pollutes logs/CI).
#pragma once
#include <chrono>
#include <cstddef>
#include <string>

namespace fovsim {

class Progress {
 public:
  Progress(std::string label, size_t total);
  ~Progress();
  void step(size_t n = 1);  // thread-compatible when called from one thread
  void done();

 private:
  std::string label_;
  size_t total_, count_ = 0;
  bool enabled_, finished_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace fovsim
