// File helpers: atomic writes (temp + rename) so an interrupted run never leaves a
// half-written file that looks complete.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
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
// 16 Mpixels (4096 x 4096; a pair takes about 140 bytes per pixel, kCompareBytesPerPixel in
// sim/metrics/compare.h: 2.3 GB at the limit), or $FOVSIM_MAX_IMAGE_MPIXELS (an integer in
// [1, 100000]).
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
// Creates `path` and its missing parents. Below a registered output folder (OutputRoot) every
// component must be a real directory: a symbolic link there (to a folder or not) is refused
// with an error naming it, so nothing is ever written through a link inside --out.
void make_dirs(const std::string& path);

// What is at `path`, symbolic links followed. Missing when nothing is there (ENOENT, or a
// parent that is not a folder); a symbolic-link loop (ELOOP), a name too long or a folder
// that cannot be searched throw fovsim::Error naming `what` and `path` with the reason
// ("symbolic link loop (too many levels of symbolic links)"), so a loop is never reported
// as "not found".
enum class PathKind { missing, regular, directory, other };
PathKind path_kind(const std::string& path, const std::string& what = "");

// Containment for files another file refers to (a model's buffers, textures, material
// libraries): throws fovsim::Error(where, ...) unless `path`, every symbolic link resolved,
// lies inside `root` (resolved the same way). A link that leaves the folder is refused like
// "..": fovsim reads only files inside the folder it was pointed at.
void check_inside(const std::string& root, const std::string& path, const std::string& where,
                  const std::string& what);

// While alive, `dir` is an output folder: make_dirs and write_atomic refuse a symbolic link at
// any component below it (images/, images/frame_N/, a sweep's runs/<cell>/), checked with
// lstat, folder by folder, as they are created or entered. `dir` itself may be a link (a
// results folder on another disk). Registered process-wide (thread-safe); DirLock registers
// the folder it locks, so every locked writer gets this.
class OutputRoot {
 public:
  explicit OutputRoot(const std::string& dir);
  ~OutputRoot();
  OutputRoot(const OutputRoot&) = delete;
  OutputRoot& operator=(const OutputRoot&) = delete;

 private:
  std::string dir_;
};

// Removes what an earlier run left in its output folder `dir` before a new run writes there:
// temporaries of write_atomic (".tmp.*", killed writers) always; the run's result files
// (frames.csv, summary.csv, summary.json, paired.csv) and its images/ and plots/ folders when
// `earlier_run` (the folder held a manifest.json, so they are fovsim's). A symbolic link there
// is removed, never followed. Nothing else in `dir` is touched.
void clear_run_outputs(const std::string& dir, bool earlier_run);

// Exclusive advisory lock on DIR/NAME (flock; released when the process ends, even by
// SIGKILL). Throws fovsim::Error naming DIR and `holder` when another process (or another
// writer of this process) holds it. While held, DIR is an OutputRoot.
class DirLock {
 public:
  DirLock(const std::string& dir, const std::string& name, const std::string& holder);
  ~DirLock();
  DirLock(const DirLock&) = delete;
  DirLock& operator=(const DirLock&) = delete;

 private:
  int fd_ = -1;
  std::unique_ptr<OutputRoot> root_;
};

}  // namespace fovsim
