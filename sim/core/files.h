// File helpers: atomic writes (temp + rename) so an interrupted run never leaves a
// half-written file that looks complete.
#pragma once
#include <string>

namespace fovsim {

// Write `content` to `path` atomically; creates parent directories. Throws fovsim::Error.
void write_file_atomic(const std::string& path, const std::string& content);
// Read a whole file. Throws fovsim::Error("path", "cannot read ...") if it cannot.
std::string read_file(const std::string& path);
bool file_exists(const std::string& path);
void make_dirs(const std::string& path);

}  // namespace fovsim
