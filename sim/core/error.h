// The one error type of fovsim for bad input (docs/architecture.md "Errors and conventions").
// Library code throws it with a location (JSON path, file:line:column, parameter); only sim/app
// catches, prints one line, exits 2. A broken invariant of the code itself is an InternalError
// (FOVSIM_CHECK): exit 3 with the source file:line, so a bug is never reported as the user's
// mistake.
#pragma once
#include <new>
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

// A bug in fovsim, not in its input: thrown by FOVSIM_CHECK with the source location
// ("sim/experiment/engine.cpp:744"). Deliberately not a fovsim::Error, so code that recovers
// from bad input (catch (const Error&)) never swallows it; sim/app prints
// "fovsim: internal error: <where>: <what>" and exits 3.
class InternalError : public std::logic_error {
 public:
  InternalError(const std::string& where, const std::string& what)
      : std::logic_error(where + ": " + what), where_(where), what_(what) {}
  const std::string& where() const { return where_; }
  const std::string& message() const { return what_; }

 private:
  std::string where_;
  std::string what_;
};

// Throws InternalError at `file` (shortened to the path from the repository's sim/, tests/ or
// python/ folder) and `line`.
[[noreturn]] void internal_error(const char* file, int line, const std::string& what);

// User text as it may appear in a message, a CSV cell or the terminal: control bytes (C0,
// DEL) become \xNN, so no NUL, ESC sequence or line break from a label, path or value reaches
// an output raw; longer than `max_len` bytes is cut and ends in "...".
std::string escape_control(const std::string& text, size_t max_len = std::string::npos);

// Runs f(); a std::bad_alloc inside becomes fovsim::Error(where, "out of memory while <what>
// (<advice>)"), so the one out-of-memory message names what was being allocated and the key
// or flag that sizes it. Wrapped around the phases that hold large buffers (scene, trace,
// frames of a run or a sweep's cells).
template <class F>
decltype(auto) with_memory_context(const std::string& where, const std::string& what,
                                   const std::string& advice, F&& f) {
  try {
    return f();
  } catch (const std::bad_alloc&) {
    throw Error(where, "out of memory while " + what + " (" + advice + ")");
  }
}

}  // namespace fovsim

// FOVSIM_CHECK(cond, msg): an invariant the code guarantees whatever the input (input is checked
// with located fovsim::Errors before it gets here). Always on, also in release builds: the checks
// sit outside per-pixel loops. `msg` is a std::string or a string literal.
#define FOVSIM_CHECK(cond, msg)                                       \
  do {                                                                \
    if (!(cond)) ::fovsim::internal_error(__FILE__, __LINE__, (msg)); \
  } while (0)

namespace fovsim {}  // namespace fovsim
