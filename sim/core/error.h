// The one error type of fovsim (docs/architecture.md §10). Library code throws it with a location
// (JSON path, file:line:column, parameter); only sim/app catches, prints one line, exits 2.
#pragma once
#include <stdexcept>
#include <string>

namespace fovsim {

class Error : public std::runtime_error {
 public:
  // `where` is a location such as "configs/run.json: methods[0].sigma" or "trace.csv:12:4".
  Error(const std::string& where, const std::string& what)
      : std::runtime_error(where.empty() ? what : where + ": " + what),
        where_(where),
        what_(what) {}
  const std::string& where() const { return where_; }
  const std::string& message() const { return what_; }

 private:
  std::string where_;
  std::string what_;
};

// Formats "file:line" or "file:line:col" (col <= 0 omitted).
std::string file_location(const std::string& file, long line, long col = 0);

}  // namespace fovsim
