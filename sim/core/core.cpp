// Small core utilities: locations, hashes, version, atomic file I/O.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/hash.h"
#include "sim/core/version.h"

namespace fovsim {

namespace fs = std::filesystem;

std::string file_location(const std::string& file, long line, long col) {
  std::string s = file + ":" + std::to_string(line);
  if (col > 0) s += ":" + std::to_string(col);
  return s;
}

void internal_error(const char* file, int line, const std::string& what) {
  std::string f = file ? file : "?";
  // __FILE__ is absolute in out-of-tree builds: keep the part a reader finds in the repository.
  for (const char* top : {"/sim/", "/tests/", "/python/", "/bench/"}) {
    const size_t at = f.rfind(top);
    if (at != std::string::npos) {
      f = f.substr(at + 1);
      break;
    }
  }
  throw InternalError(file_location(f, line), what);
}

std::string escape_control(const std::string& text, size_t max_len) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    if (out.size() >= max_len) {
      out += "...";
      break;
    }
    const unsigned char c = (unsigned char)text[i];
    if (c < 0x20 || c == 0x7F) {
      char b[8];
      std::snprintf(b, sizeof b, "\\x%02X", c);
      out += b;
    } else {
      out += char(c);
    }
  }
  return out;
}

QuietStderr::QuietStderr() {
  std::fflush(stderr);
  const int null_fd = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
  if (null_fd < 0) return;
  saved_ = ::fcntl(2, F_DUPFD_CLOEXEC, 3);
  if (saved_ >= 0 && ::dup2(null_fd, 2) < 0) {
    ::close(saved_);
    saved_ = -1;
  }
  ::close(null_fd);
}

QuietStderr::~QuietStderr() {
  if (saved_ < 0) return;
  std::fflush(stderr);
  ::dup2(saved_, 2);
  ::close(saved_);
}

std::string closest_name(const std::string& word, const std::vector<std::string>& names) {
  // Optimal string alignment distance (Damerau-Levenshtein without repeated edits).
  auto dist = [](const std::string& a, const std::string& b) {
    std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
    for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (size_t i = 1; i <= a.size(); ++i)
      for (size_t j = 1; j <= b.size(); ++j) {
        size_t c = a[i - 1] == b[j - 1] ? 0 : 1;
        d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + c});
        if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
          d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    return d[a.size()][b.size()];
  };
  if (word.size() > 64) return "";
  std::string best;
  size_t best_d = std::max<size_t>(1, word.size() / 2) + 1;
  for (auto& n : names) {
    size_t dd = dist(word, n.substr(0, 64));
    if (dd < best_d) {
      best_d = dd;
      best = n;
    }
  }
  return best;
}

std::string hex64(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::string short_hash(std::string_view s) {
  return hex64(fnv1a64(s)).substr(0, 10);
}

std::string version_string() {
  return FOVSIM_VERSION;
}
namespace detail {
extern const char* const kGitCommit;  // build/generated/git_commit.cpp (cmake/git_commit.cmake)
}
std::string git_commit() {
  return detail::kGitCommit;
}

// A path with an embedded NUL would be cut there by every system call (Python strings can
// carry one): refused wherever fovsim opens or creates a file.
static void check_nul(const std::string& path) {
  if (path.find('\0') != std::string::npos)
    throw Error(path.substr(0, path.find('\0')) + "\\0...",
                "path contains a NUL byte (refused rather than cut at the NUL)");
}

namespace {

// Why a file cannot be opened, as the error line says it.
std::string open_failure(int err) {
  if (err == ELOOP) return "symbolic link loop (too many levels of symbolic links)";
  return std::string("cannot read file (") + std::strerror(err) + ")";
}

std::mutex g_roots_mu;
std::vector<std::string> g_roots;  // OutputRoot folders, absolute and lexically normal

std::string absolute_normal(const std::string& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec);
  if (ec) a = p;
  std::string s = a.lexically_normal().string();
  while (s.size() > 1 && s.back() == '/') s.pop_back();
  return s;
}

// The outermost registered output folder that contains `abs` (or is it); "" when none does.
std::string output_root_of(const std::string& abs) {
  std::lock_guard<std::mutex> lk(g_roots_mu);
  std::string best;
  for (const std::string& r : g_roots) {
    const bool inside = abs == r || (abs.size() > r.size() && abs.compare(0, r.size(), r) == 0 &&
                                     (r == "/" || abs[r.size()] == '/'));
    if (inside && (best.empty() || r.size() < best.size())) best = r;
  }
  return best;
}

const char* kind_of(mode_t m) {
  return S_ISLNK(m)                   ? "a symbolic link"
         : S_ISDIR(m)                 ? "a directory"
         : S_ISFIFO(m)                ? "a FIFO"
         : S_ISSOCK(m)                ? "a socket"
         : (S_ISCHR(m) || S_ISBLK(m)) ? "a device"
         : S_ISREG(m)                 ? "a regular file"
                                      : "not a regular file";
}

// Walks the components of `abs` below `root` (both absolute, normal) with lstat, creating the
// missing ones: a symbolic link or a non-directory there is an error naming it.
void make_dirs_below(const std::string& root, const std::string& abs) {
  std::string cur = root;
  const std::string rest = abs.substr(std::min(abs.size(), root.size() + (root == "/" ? 0 : 1)));
  size_t i = 0;
  while (i < rest.size()) {
    size_t j = rest.find('/', i);
    if (j == std::string::npos) j = rest.size();
    cur += (cur == "/" ? "" : "/") + rest.substr(i, j - i);
    i = j + 1;
    struct stat st {};
    if (::lstat(cur.c_str(), &st) != 0) {
      if (errno != ENOENT)
        throw Error(cur, std::string("cannot create directory: ") + std::strerror(errno));
      if (::mkdir(cur.c_str(), 0777) != 0 && errno != EEXIST)
        throw Error(cur, std::string("cannot create directory: ") + std::strerror(errno));
      if (::lstat(cur.c_str(), &st) != 0)
        throw Error(cur, std::string("cannot create directory: ") + std::strerror(errno));
    }
    if (S_ISLNK(st.st_mode))
      throw Error(cur, "is a symbolic link inside the output folder " + root +
                           "; fovsim writes only into real folders there (remove the link)");
    if (!S_ISDIR(st.st_mode))
      throw Error(cur, std::string("cannot create directory: the path exists and is ") +
                           kind_of(st.st_mode));
  }
}

}  // namespace

OutputRoot::OutputRoot(const std::string& dir) : dir_(absolute_normal(dir)) {
  std::lock_guard<std::mutex> lk(g_roots_mu);
  g_roots.push_back(dir_);
}

OutputRoot::~OutputRoot() {
  std::lock_guard<std::mutex> lk(g_roots_mu);
  auto it = std::find(g_roots.begin(), g_roots.end(), dir_);
  if (it != g_roots.end()) g_roots.erase(it);
}

void make_dirs(const std::string& path) {
  if (path.empty()) return;
  check_nul(path);
  const std::string abs = absolute_normal(path);
  const std::string root = output_root_of(abs);
  std::error_code ec;
  fs::create_directories(root.empty() ? fs::path(path) : fs::path(root), ec);
  if (ec) throw Error(root.empty() ? path : root, "cannot create directory: " + ec.message());
  if (!root.empty()) make_dirs_below(root, abs);
}

PathKind path_kind(const std::string& path, const std::string& what) {
  check_nul(path);
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0)
    return S_ISREG(st.st_mode)   ? PathKind::regular
           : S_ISDIR(st.st_mode) ? PathKind::directory
                                 : PathKind::other;
  const int err = errno;
  if (err == ENOENT || err == ENOTDIR) return PathKind::missing;
  const std::string where = what.empty() ? path : what + ": " + path;
  throw Error(where, open_failure(err));
}

void check_inside(const std::string& root, const std::string& path, const std::string& where,
                  const std::string& what) {
  std::error_code ec;
  const fs::path r = fs::weakly_canonical(root, ec);
  if (ec) throw Error(where, what + " folder " + root + ": " + ec.message());
  fs::path p = fs::weakly_canonical(path, ec);
  if (ec) {
    if (ec.value() == ELOOP)
      throw Error(where,
                  what + " " + path + ": symbolic link loop (too many levels of symbolic links)");
    throw Error(where, what + " " + path + ": " + ec.message());
  }
  const std::string rs = r.string(), ps = p.string();
  const bool inside = ps.size() > rs.size() && ps.compare(0, rs.size(), rs) == 0 &&
                      (rs.back() == '/' || ps[rs.size()] == '/');
  if (!inside)
    throw Error(where, what + " " + path + " resolves to " + ps + ", outside the model's folder " +
                           rs + " (a symbolic link out of the folder is refused like \"..\")");
}

void check_output_target(const std::string& path) {
  if (path.empty()) throw Error("output path", "is empty");
  check_nul(path);
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return;  // nothing there yet (or the rename reports)
  if (S_ISREG(st.st_mode)) return;
  throw Error(path, std::string("output exists and is ") + kind_of(st.st_mode) +
                        "; only a regular file is replaced (remove it or choose another path)");
}

void write_atomic(const std::string& path, const std::function<void(const std::string&)>& write,
                  const std::function<std::string(const std::string&)>& check) {
  // Checked before any work and again just before the rename.
  check_output_target(path);
  fs::path p(path);
  if (p.has_parent_path()) make_dirs(p.parent_path().string());
  // The real extension stays last (image writers pick the format from it).
  std::string tmp =
      (p.parent_path() / (".tmp." + std::to_string(::getpid()) + "." + p.filename().string()))
          .string();
  // The temporary name is fovsim's: whatever is there (a stale file, a planted link or FIFO
  // that the writer would follow) goes first.
  struct stat tst {};
  if (::lstat(tmp.c_str(), &tst) == 0 && !S_ISDIR(tst.st_mode)) ::unlink(tmp.c_str());
  try {
    write(tmp);
    std::string why = check ? check(tmp) : std::string();
    if (!why.empty()) throw Error(path, why + "; nothing written under this name");
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  try {
    check_output_target(path);
    if (p.has_parent_path()) make_dirs(p.parent_path().string());  // no link appeared meanwhile
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw Error(path, "cannot rename temporary file: " + ec.message());
  }
}

bool is_temporary_name(const std::string& name) {
  return name.rfind(".tmp.", 0) == 0 ||
         (name.size() > 10 && name.compare(name.size() - 10, 10, ".merge-tmp") == 0);
}

void write_file_atomic(const std::string& path, const std::string& content) {
  write_atomic(
      path,
      [&](const std::string& tmp) {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f) throw Error(path, "cannot open for writing");
        f.write(content.data(), std::streamsize(content.size()));
        f.close();
        if (!f) throw Error(path, "write failed (disk full?)");
      },
      [&](const std::string& tmp) -> std::string {
        std::error_code ec;
        auto n = fs::file_size(tmp, ec);
        if (ec || n != content.size())
          return "write incomplete (" + std::to_string(ec ? 0 : n) + " of " +
                 std::to_string(content.size()) + " bytes; disk full?)";
        return "";
      });
}

bool parse_integer(const std::string& s, long lo, long hi, long& out) {
  if (s.empty() || s.size() > 19) return false;
  size_t i = s[0] == '-' ? 1 : 0;
  if (i == s.size()) return false;
  for (size_t k = i; k < s.size(); ++k)
    if (s[k] < '0' || s[k] > '9') return false;
  errno = 0;
  char* end = nullptr;
  long v = std::strtol(s.c_str(), &end, 10);
  if (errno != 0 || *end != '\0' || v < lo || v > hi) return false;
  out = v;
  return true;
}

std::optional<long> env_integer(const char* name, long lo, long hi) {
  const char* e = std::getenv(name);
  if (!e) return std::nullopt;
  long v = 0;
  if (!parse_integer(e, lo, hi, v))
    throw Error(std::string("environment ") + name + "=\"" + e + "\"",
                "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

uint64_t max_input_bytes() {
  auto mb = env_integer("FOVSIM_MAX_INPUT_MB", 1, 1048576);
  return uint64_t(mb ? *mb : 256) << 20;
}

double max_image_pixels() {
  auto mp = env_integer("FOVSIM_MAX_IMAGE_MPIXELS", 1, 100000);
  return mp ? double(*mp) * 1048576.0 : 16777216.0;
}

void check_input_file(const std::string& path, const std::string& what) {
  check_nul(path);
  const std::string where = what.empty() ? path : what + ": " + path;
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw Error(where, open_failure(errno));
  if (S_ISDIR(st.st_mode)) throw Error(where, "is a directory, expected a file");
  if (!S_ISREG(st.st_mode))
    throw Error(where, "not a regular file (devices, FIFOs and sockets are refused)");
  const uint64_t limit = max_input_bytes();
  if (uint64_t(st.st_size) > limit)
    throw Error(where, "file is " + std::to_string(uint64_t(st.st_size) >> 20) +
                           " MiB, over the input limit of " + std::to_string(limit >> 20) +
                           " MiB (set FOVSIM_MAX_INPUT_MB to raise it)");
}

std::string read_file(const std::string& path) {
  check_nul(path);
  // Checked on the open descriptor (no race between the check and the read).
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) {
    const int err = errno;
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw Error(path, "is a directory, expected a file");
    throw Error(path, open_failure(err));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    bool dir = S_ISDIR(st.st_mode);
    ::close(fd);
    throw Error(path, dir ? "is a directory, expected a file"
                          : "not a regular file (devices, FIFOs and sockets are refused)");
  }
  const uint64_t limit = max_input_bytes();
  if (uint64_t(st.st_size) > limit)
    throw Error(path, "file is " + std::to_string(uint64_t(st.st_size) >> 20) +
                          " MiB, over the input limit of " + std::to_string(limit >> 20) +
                          " MiB (set FOVSIM_MAX_INPUT_MB to raise it)");
  std::string out;
  out.resize(size_t(st.st_size));
  size_t got = 0;
  while (got < out.size()) {
    ssize_t n = ::read(fd, out.data() + got, out.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      int err = errno;
      ::close(fd);
      throw Error(path, std::string("read failed: ") + std::strerror(err));
    }
    if (n == 0) break;  // shrank while reading
    got += size_t(n);
  }
  ::close(fd);
  out.resize(got);
  return out;
}

std::string safe_file_name(const std::string& name) {
  std::string s;
  for (char c : name) {
    bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
              c == '.' || c == '_' || c == '-' || c == '+';
    s += ok ? c : '_';
  }
  if (s.size() > 120) s.resize(120);
  if (s.empty()) s = "_";
  if (s[0] == '.') s[0] = '_';  // no "..", ".", hidden files
  return s;
}

DirLock::DirLock(const std::string& dir, const std::string& name, const std::string& what) {
  make_dirs(dir);
  std::string p = dir + "/" + name;
  fd_ = ::open(p.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
  if (fd_ < 0) throw Error(p, std::string("cannot create lock file: ") + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    int err = errno;
    ::close(fd_);
    fd_ = -1;
    if (err == EWOULDBLOCK)
      throw Error(dir, what + " is writing to this folder (lock " + p +
                           "); wait for it, or use another --out");
    throw Error(p, std::string("cannot lock: ") + std::strerror(err));
  }
  root_ = std::make_unique<OutputRoot>(dir);
}

DirLock::~DirLock() {
  root_.reset();
  if (fd_ >= 0) ::close(fd_);
}

void clear_run_outputs(const std::string& dir, bool earlier_run) {
  std::error_code ec;
  std::vector<fs::path> gone;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (is_temporary_name(it->path().filename().string())) gone.push_back(it->path());
  if (earlier_run)
    for (const char* f :
         {"frames.csv", "summary.csv", "summary.json", "paired.csv", "images", "plots"})
      gone.push_back(fs::path(dir) / f);
  for (const fs::path& p : gone) {
    std::error_code e2;
    fs::remove_all(p, e2);  // a link itself, not what it points to
    if (e2) throw Error(p.string(), "cannot remove an earlier run's output: " + e2.message());
  }
}

bool file_exists(const std::string& path) {
  std::error_code ec;
  if (fs::exists(path, ec)) return true;
  // A symbolic link loop is there but cannot be followed: "exists", so the reader names why it
  // cannot read it ("Too many levels of symbolic links") instead of the caller's "not found".
  return ec.value() == ELOOP;
}

}  // namespace fovsim
