// File helpers: atomic writes (temp + rename) so an interrupted run never leaves a
// half-written file that looks complete.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace fovsim {

// The one way fovsim writes an output file (CSV, JSON, images, manifests, plot inputs):
// `write` fills a temporary file in the same folder (".tmp.<pid>.<name>", never the final
// name), `check` (optional) returns "" when that file is complete or why it is not (a
// short write on a full disk, a missing end marker), and only then is it renamed over
// `path` (atomic on POSIX). On any failure the temporary is removed and nothing appears
// under `path`: a process killed at any moment (SIGKILL) leaves either the old file, the
// new one, or a temporary, never a truncated file under the final name. Creates parent
// directories; throws fovsim::Error naming `path`.
// Only a regular file (or nothing) is ever replaced: when `path` exists and is a symbolic
// link (not followed, whatever it points to), a directory, a FIFO, a socket or a device,
// nothing is written and the error says what is there (checked before `write` and again
// just before the rename). `--out /dev/null` is therefore refused, not turned into a file.
void write_atomic(const std::string& path, const std::function<void(const std::string& tmp)>& write,
                  const std::function<std::string(const std::string& tmp)>& check = {});
// The check write_atomic makes on its target (above): returns when `path` is absent or a
// regular file, throws fovsim::Error naming `path` and what is there otherwise.
void check_output_target(const std::string& path);
// True for the temporary names write_atomic (and sweep merge) use, which readers skip.
bool is_temporary_name(const std::string& file_name);
// write_atomic of a byte string; the check compares the written size.
void write_file_atomic(const std::string& path, const std::string& content);
// Read a whole file. Throws fovsim::Error("path", ...) if it cannot, if it is not a regular
// file (a directory, /dev/zero, a FIFO) or if it is larger than max_input_bytes(): both are
// checked before anything is read, so an absurd input never exhausts memory.
std::string read_file(const std::string& path);
// The checks read_file makes, without reading: `path` exists, is a regular file (after
// following symbolic links: a link to /dev/zero is refused) and is at most max_input_bytes().
// Used before a file is handed to a library that reads it itself (assimp, OpenImageIO), so a
// FIFO or device never blocks it. Throws fovsim::Error naming `what` (e.g. "scene.path") and
// `path`.
void check_input_file(const std::string& path, const std::string& what = "");
// Size limit for input files (configs, traces, column maps, sweep specs): 256 MiB, or
// $FOVSIM_MAX_INPUT_MB (an integer in [1, 1048576]; anything else is an error naming it).
uint64_t max_input_bytes();
// Most pixels an image given to `compare` may claim in its header before it is decoded:
// 64 Mpixels (8192 x 8192), or $FOVSIM_MAX_IMAGE_MPIXELS (an integer in [1, 100000]).
double max_image_pixels();
// Strict integer from the environment: nullopt when unset; an error naming the variable
// when set to anything but a decimal integer in [lo, hi] (no "12abc", no "", no overflow).
std::optional<long> env_integer(const char* name, long lo, long hi);
// Strict decimal integer in [lo, hi]; false on anything else.
bool parse_integer(const std::string& s, long lo, long hi, long& out);

// The one way a user-given label or name becomes a file or folder name: every character
// other than [A-Za-z0-9._+-] (separators, control characters, spaces) becomes '_', and a
// leading '.' becomes '_' (so no "..", no hidden files); empty becomes "_"; at most 120
// characters. Whatever the input, the result is a single path component.
std::string safe_file_name(const std::string& name);

// Exclusive advisory lock on DIR/NAME (flock; released when the process ends, even by
// SIGKILL). Throws fovsim::Error naming DIR and `holder` when another process holds it.
class DirLock {
 public:
  DirLock(const std::string& dir, const std::string& name, const std::string& holder);
  ~DirLock();
  DirLock(const DirLock&) = delete;
  DirLock& operator=(const DirLock&) = delete;

 private:
  int fd_ = -1;
};
// While alive, the process's stderr (fd 2) goes to /dev/null. Image decoding is wrapped in it:
// libpng, called through OpenImageIO, prints its own "libpng error: ..." line to stderr before
// OpenImageIO reports the same error, which fovsim then gives in its one error line. Open it
// only on the thread that orchestrates (stderr output of other threads is dropped meanwhile).
class QuietStderr {
 public:
  QuietStderr();
  ~QuietStderr();
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  int saved_ = -1;
};

bool file_exists(const std::string& path);
void make_dirs(const std::string& path);

}  // namespace fovsim
