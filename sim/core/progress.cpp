#include "sim/core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>

namespace fovsim {

namespace {

std::mutex g_mutex;
Progress* g_innermost = nullptr;  // the most recently made live Progress

std::string duration_text(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  char b[32];
  const long t = long(std::lround(s));
  if (t >= 3600)
    std::snprintf(b, sizeof b, "%ldh%02ldm", t / 3600, (t % 3600) / 60);
  else if (t >= 60)
    std::snprintf(b, sizeof b, "%ldm%02lds", t / 60, t % 60);
  else
    std::snprintf(b, sizeof b, "%lds", t);
  return b;
}

}  // namespace

ProgressSink stderr_progress_sink() {
  ProgressSink s;
  s.terminal = ::isatty(2) == 1;
  s.now = [] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  };
  s.write = [](const std::string& text) {
    std::fputs(text.c_str(), stderr);
    std::fflush(stderr);
  };
  return s;
}

Progress::Progress(std::string label, size_t total) : Progress(std::move(label), total, {}) {}

Progress::Progress(std::string label, size_t total, ProgressSink sink)
    : label_(std::move(label)), total_(total) {
  std::lock_guard<std::mutex> lock(g_mutex);
  parent_ = g_innermost;
  g_innermost = this;
  if (parent_) {
    parent_->child_ = this;
    return;
  }
  sink_ = sink.now && sink.write ? std::move(sink) : stderr_progress_sink();
  start_ = last_ = sink_.now();
}

void Progress::spans(size_t offset, size_t n) {
  std::lock_guard<std::mutex> lock(g_mutex);
  offset_ = offset;
  span_ = n;
}

Progress::~Progress() {
  done();
}

void Progress::step(size_t n) {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (finished_) return;
  count_ += n;
  Progress* root = this;
  while (root->parent_) root = root->parent_;
  root->render_locked(false);
}

void Progress::phase(const std::string& p) {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (finished_) return;
  phase_ = p;
  Progress* root = this;
  while (root->parent_) root = root->parent_;
  root->render_locked(false);
}

void Progress::done() {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (finished_) return;
  finished_ = true;
  if (parent_ && parent_->child_ == this) parent_->child_ = nullptr;
  if (g_innermost == this) g_innermost = parent_;
  // A child that outlives its parent's done() keeps no dangling pointer into it.
  if (child_) child_->parent_ = nullptr;
  if (!parent_ && sink_.terminal && printed_) sink_.write("\r" + std::string(width_, ' ') + "\r");
}

double Progress::fraction_locked() const {
  if (total_ == 0) return 1.0;
  double f = double(std::min(count_, total_));
  if (child_ && count_ < total_)
    f += double(child_->offset_) +
         double(child_->span_) * std::min(1.0, std::max(0.0, child_->fraction_locked()));
  return std::min(1.0, f / double(total_));
}

std::string Progress::line_locked(double now) const {
  std::string s, phase;
  for (const Progress* p = this; p; p = p->child_) {
    if (!s.empty()) s += " · ";
    s += p->label_ + " " + std::to_string(std::min(p->count_, p->total_)) + "/" +
         std::to_string(p->total_);
    if (!p->phase_.empty()) phase = p->phase_;
  }
  const double f = fraction_locked();
  char pct[16];
  std::snprintf(pct, sizeof pct, " (%.0f%%)", 100.0 * f);
  s += pct;
  if (!phase.empty()) s += " · " + phase;
  const double el = now - start_;
  s += " · " + duration_text(el) + " elapsed";
  if (f > 0 && f < 1) s += ", ETA " + duration_text(el * (1 - f) / f);
  return s;
}

std::string Progress::line() const {
  std::lock_guard<std::mutex> lock(g_mutex);
  const Progress* root = this;
  while (root->parent_) root = root->parent_;
  return root->line_locked(root->sink_.now ? root->sink_.now() : 0.0);
}

void Progress::render_locked(bool force) {
  if (finished_ || !sink_.now) return;
  const double now = sink_.now();
  if (sink_.terminal) {
    if (!force && printed_ && now - last_ < kTerminalInterval) return;
    const std::string l = line_locked(now);
    const size_t pad = width_ > l.size() ? width_ - l.size() : 0;
    sink_.write("\r" + l + std::string(pad, ' '));
    width_ = l.size();
  } else {
    // Logs: nothing in the first minute, then at most one line a minute.
    if (now - start_ < kLogInterval || (printed_ && now - last_ < kLogInterval)) return;
    sink_.write("fovsim: progress: " + line_locked(now) + "\n");
  }
  last_ = now;
  printed_ = true;
}

}  // namespace fovsim
