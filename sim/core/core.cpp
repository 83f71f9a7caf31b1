// Small core utilities: locations, hashes, version, atomic file I/O, progress.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/hash.h"
#include "sim/core/progress.h"
#include "sim/core/version.h"

namespace fovsim {

namespace fs = std::filesystem;

std::string file_location(const std::string& file, long line, long col) {
  std::string s = file + ":" + std::to_string(line);
  if (col > 0) s += ":" + std::to_string(col);
  return s;
}

std::string hex64(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::string short_hash(std::string_view s) { return hex64(fnv1a64(s)).substr(0, 10); }

std::string version_string() { return FOVSIM_VERSION; }
std::string git_commit() { return FOVSIM_GIT_COMMIT; }

void make_dirs(const std::string& path) {
  if (path.empty()) return;
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec) throw Error(path, "cannot create directory: " + ec.message());
}

void write_file_atomic(const std::string& path, const std::string& content) {
  fs::path p(path);
  if (p.has_parent_path()) make_dirs(p.parent_path().string());
  std::string tmp = path + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw Error(path, "cannot open for writing");
    f.write(content.data(), std::streamsize(content.size()));
    f.flush();
    if (!f) {
      std::remove(tmp.c_str());
      throw Error(path, "write failed (disk full?)");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw Error(path, "cannot rename temporary file: " + ec.message());
  }
}

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error(path, "is a directory, expected a file");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error(path, "cannot read file (missing or unreadable)");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

bool file_exists(const std::string& path) {
  std::error_code ec;
  return fs::exists(path, ec);
}

Progress::Progress(std::string label, size_t total)
    : label_(std::move(label)), total_(total), enabled_(::isatty(2) == 1) {
  start_ = last_ = std::chrono::steady_clock::now();
}

Progress::~Progress() { done(); }

void Progress::step(size_t n) {
  count_ += n;
  if (!enabled_) return;
  auto now = std::chrono::steady_clock::now();
  if (count_ < total_ && now - last_ < std::chrono::milliseconds(200)) return;
  last_ = now;
  double el = std::chrono::duration<double>(now - start_).count();
  double eta = count_ ? el * double(total_ - std::min(count_, total_)) / double(count_) : 0.0;
  std::fprintf(stderr, "\r%s %zu/%zu (%3.0f%%) elapsed %.1fs ETA %.1fs   ", label_.c_str(), count_,
               total_, total_ ? 100.0 * double(count_) / double(total_) : 100.0, el, eta);
  std::fflush(stderr);
}

void Progress::done() {
  if (finished_) return;
  finished_ = true;
  if (enabled_) {
    std::fprintf(stderr, "\r%*s\r", 80, "");
    std::fflush(stderr);
  }
}

}  // namespace fovsim
