// Progress of long work on stderr (docs/architecture.md "Where each concept lives"): on a terminal
// one line, updated in place at most 5 times a second; when stderr is not a terminal (logs, CI,
// Slurm) a short line at most once a minute, the first after a minute, so short commands write
// nothing.
//
// Progress objects nest: one made while another is alive (a sweep's cells, each cell group's
// frames inside it; the fidelity ladder's rungs around a sweep) reports to the outer one, and
// the outermost prints one line for all of them, e.g.
//   sweep: cells 3/12 · frames 40/90 · phase reference · 1m02s elapsed, ETA 4m10s
// The ETA extrapolates the elapsed time over the fraction done (the inner levels' fractions
// count within the current outer step). Thread-compatible: every call takes one global lock.
#pragma once
#include <cstddef>
#include <functional>
#include <string>

namespace fovsim {

// Where a root Progress writes, and its clock (injected by tests; no timing assertions).
struct ProgressSink {
  bool terminal = false;
  std::function<double()> now;                    // seconds, monotonic
  std::function<void(const std::string&)> write;  // raw text
};
// stderr, terminal when isatty(2), steady_clock.
ProgressSink stderr_progress_sink();

class Progress {
 public:
  static constexpr double kTerminalInterval = 0.2;  // seconds between terminal updates
  static constexpr double kLogInterval = 60.0;  // seconds between log lines (and before the first)

  // `label`: what is counted ("frames", "cells", "rungs"); `total` steps expected.
  Progress(std::string label, size_t total);
  Progress(std::string label, size_t total, ProgressSink sink);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void step(size_t n = 1);
  void phase(const std::string& p);  // the current phase ("reference", "outputs", ...)
  // What this nested progress stands for in its parent: its 0..1 covers the parent's steps
  // [offset, offset + n) counted from the parent's steps already done (default 0, 1: one parent
  // step). A sweep's cell group runs several cells' frames at once, so its frames progress
  // spans those cells; a later memory pass of the group starts at the cells of the passes before.
  void spans(size_t offset, size_t n);
  void done();  // clears the terminal line (idempotent; the destructor calls it)

  // The line as the outermost Progress would print it now (for tests).
  std::string line() const;
  bool nested() const { return parent_ != nullptr; }

 private:
  void render_locked(bool force);
  std::string line_locked(double now) const;
  double fraction_locked() const;

  std::string label_;
  size_t total_ = 0, count_ = 0;
  size_t offset_ = 0, span_ = 1;  // in the parent's steps (spans())
  std::string phase_;
  Progress* parent_ = nullptr;
  Progress* child_ = nullptr;
  ProgressSink sink_;
  bool finished_ = false, printed_ = false;
  double start_ = 0, last_ = 0;
  size_t width_ = 0;  // of the last terminal line (to clear it)
};

}  // namespace fovsim
