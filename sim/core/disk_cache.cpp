#include "sim/core/disk_cache.h"

#include <OpenImageIO/hash.h>
#include <dlfcn.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/hash.h"

namespace fovsim {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'F', 'O', 'V', 'S', 'I', 'M', 'C', '1'};
constexpr char kEnd[8] = {'F', 'O', 'V', 'S', 'I', 'M', 'E', 'N'};
constexpr int kFormat = 1;
constexpr size_t kMaxWarnings = 20;
constexpr const char* kExt = ".fce";

// Temporaries of every DiskCache of this process get distinct numbers (two caches on one
// folder in one process never open the same name).
std::atomic<uint64_t> g_tmp_counter{0};

std::string host_name() {
  char h[256] = {0};
  if (::gethostname(h, sizeof h - 1) != 0 || !h[0]) return "host";
  return safe_file_name(h);
}

// Writes all of `n` bytes to fd; false on any error (errno says which).
bool write_all(int fd, const void* p, size_t n) {
  const char* c = static_cast<const char*>(p);
  while (n > 0) {
    ssize_t w = ::write(fd, c, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    c += w;
    n -= size_t(w);
  }
  return true;
}

void fsync_dir(const std::string& dir) {
  int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    (void)::fsync(fd);
    ::close(fd);
  }
}

}  // namespace

uint64_t content_hash(const void* data, size_t bytes, uint64_t seed) {
  return uint64_t(OIIO::xxhash::XXH64(data, bytes, static_cast<unsigned long long>(seed)));
}

std::string code_fingerprint() {
  static const std::string fp = [] {
    std::string path = "/proc/self/exe";
    Dl_info info{};
    if (::dladdr(reinterpret_cast<void*>(&code_fingerprint), &info) && info.dli_fname &&
        info.dli_fname[0] == '/')
      path = info.dli_fname;  // a shared object (or an executable found by absolute path)
    std::ifstream f(path, std::ios::binary);
    if (!f) return std::string("unknown");
    std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (!f.good() && !f.eof()) return std::string("unknown");
    return hex64(content_hash(bytes.data(), bytes.size()));
  }();
  return fp;
}

const std::vector<float>* CacheItem::array(const std::string& name) const {
  for (auto& [n, v] : arrays)
    if (n == name) return &v;
  return nullptr;
}

std::vector<float>* CacheItem::array(const std::string& name) {
  for (auto& [n, v] : arrays)
    if (n == name) return &v;
  return nullptr;
}

uint64_t CacheItem::payload_bytes() const {
  uint64_t b = 0;
  for (auto& a : arrays) b += a.second.size() * sizeof(float);
  return b;
}

Json DiskCacheStats::to_json() const {
  return Json{{"hits", hits},
              {"misses", misses},
              {"ignored", ignored},
              {"writes", writes},
              {"write_failures", write_failures},
              {"evicted", evicted},
              {"bytes_read", bytes_read},
              {"bytes_written", bytes_written},
              {"bytes_evicted", bytes_evicted}};
}

std::string default_cache_dir() {
  const char* d = std::getenv("FOVSIM_CACHE_DIR");
  if (d && *d) return d;
  const char* x = std::getenv("XDG_CACHE_HOME");
  if (x && x[0] == '/') return std::string(x) + "/fovsim";
  const char* h = std::getenv("HOME");
  if (h && *h) return std::string(h) + "/.cache/fovsim";
  return "";
}

bool cache_disabled_by_env() {
  const char* e = std::getenv("FOVSIM_NO_CACHE");
  return e && std::strcmp(e, "0") != 0;
}

DiskCache::DiskCache(std::string dir, std::string kind, uint64_t max_bytes)
    : dir_(std::move(dir)), max_bytes_(max_bytes) {
  kind_dir_ = (fs::path(dir_) / safe_file_name(kind)).string();
}

std::string DiskCache::path_of(const std::string& key) const {
  const std::string h = hex64(content_hash(key.data(), key.size()));
  return (fs::path(kind_dir_) / h.substr(0, 2) / (h + kExt)).string();
}

void DiskCache::warn(const std::string& w) {
  if (warnings_.size() < kMaxWarnings)
    warnings_.push_back(w);
  else
    ++dropped_;
}

std::optional<CacheItem> DiskCache::get(const std::string& key) {
  const std::string path = path_of(key);
  auto ignore = [&](const std::string& why) -> std::optional<CacheItem> {
    ++stats_.ignored;
    ++stats_.misses;
    warn("cache entry " + path + " " + why + ": ignored, recomputed");
    return std::nullopt;
  };
  // O_NONBLOCK: a FIFO (or device) under an entry's name must not block the open; O_NOFOLLOW:
  // an entry is a file the cache wrote, never a link. Both are then refused below.
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOFOLLOW);
  if (fd < 0) {
    if (errno == ELOOP) return ignore("is a symbolic link");
    ++stats_.misses;
    if (errno != ENOENT && errno != ENOTDIR)
      warn("cache entry " + path + ": " + std::strerror(errno));
    return std::nullopt;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return ignore("is not a regular file");
  }
  // No bound from the cap here: a cap lowered since an entry was written still reads it (the
  // next write's trim removes it). The size is the file's, in a folder the cache owns.
  const uint64_t size = uint64_t(st.st_size);
  std::string buf(size, '\0');
  size_t got = 0;
  while (got < size) {
    ssize_t r = ::read(fd, &buf[got], size - got);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break;
    got += size_t(r);
  }
  ::close(fd);
  if (got != size) return ignore("could not be read completely");
  const size_t fixed = sizeof kMagic + 4 + 8 + sizeof kEnd;
  if (size < fixed || std::memcmp(buf.data(), kMagic, sizeof kMagic) != 0)
    return ignore("is truncated or not a cache entry (no header)");
  if (std::memcmp(buf.data() + size - sizeof kEnd, kEnd, sizeof kEnd) != 0)
    return ignore("is truncated (no end marker)");
  uint64_t stored = 0;
  std::memcpy(&stored, buf.data() + size - sizeof kEnd - 8, 8);
  if (content_hash(buf.data(), size - sizeof kEnd - 8) != stored)
    return ignore("is corrupted (checksum mismatch)");
  uint32_t hlen = 0;
  std::memcpy(&hlen, buf.data() + sizeof kMagic, 4);
  if (sizeof kMagic + 4 + uint64_t(hlen) + 8 + sizeof kEnd > size)
    return ignore("has a header longer than the file");
  Json h;
  try {
    h = parse_json_text(buf.substr(sizeof kMagic + 4, hlen), path + " header");
  } catch (const Error&) {  // malformed, or nested deeper than kMaxJsonDepth
    return ignore("has an unreadable header");
  }
  if (!h.is_object() || h.value("format", 0) != kFormat || !h.contains("key") ||
      !h["key"].is_string() || !h.contains("arrays") || !h["arrays"].is_array())
    return ignore("has a header of another format");
  if (h["key"].get<std::string>() != key) {
    // Another key with the same hash: not an error, but not this value either.
    ++stats_.misses;
    return std::nullopt;
  }
  CacheItem item;
  item.meta = h.value("meta", Json::object());
  uint64_t off = sizeof kMagic + 4 + hlen;
  const uint64_t end = size - sizeof kEnd - 8;
  for (auto& a : h["arrays"]) {
    if (!a.is_object() || !a.contains("name") || !a["name"].is_string() || !a.contains("count") ||
        !a["count"].is_number_unsigned())
      return ignore("has a malformed array record");
    const uint64_t n = a["count"].get<uint64_t>();
    if (n > (end - off) / sizeof(float)) return ignore("is shorter than its header says");
    std::vector<float> v(static_cast<size_t>(n));
    if (n) std::memcpy(v.data(), buf.data() + off, size_t(n) * sizeof(float));
    off += n * sizeof(float);
    item.arrays.emplace_back(a["name"].get<std::string>(), std::move(v));
  }
  if (off != end) return ignore("is longer than its header says");
  ++stats_.hits;
  stats_.bytes_read += size;
  // Least recently used = oldest mtime: a read makes it the newest (best effort).
  (void)::utimensat(AT_FDCWD, path.c_str(), nullptr, 0);
  return item;
}

void DiskCache::put(const std::string& key, const CacheItem& item) {
  if (write_disabled_) return;
  Json h{{"format", kFormat},
         {"kind", fs::path(kind_dir_).filename().string()},
         {"key", key},
         {"meta", item.meta},
         {"arrays", Json::array()},
         {"encoding", "float32 little-endian"}};
  for (auto& [n, v] : item.arrays) h["arrays"].push_back(Json{{"name", n}, {"count", v.size()}});
  const std::string head = h.dump();
  const uint64_t total = sizeof kMagic + 4 + head.size() + item.payload_bytes() + 8 + sizeof kEnd;
  if (total > max_bytes_) {
    ++stats_.write_failures;
    warn("cache entry of " + std::to_string(total) +
         " bytes is larger than the cache's size cap (" + std::to_string(max_bytes_) +
         " bytes): not stored");
    return;
  }
  if (!trimmed_) trim();  // the first write of this process: bring the folder under the cap
  const std::string path = path_of(key);
  const fs::path folder = fs::path(path).parent_path();
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) {
    ++stats_.write_failures;
    write_disabled_ = true;
    warn("cache folder " + folder.string() + " cannot be created (" + ec.message() +
         "): nothing is cached in this run");
    return;
  }
  const std::string tmp =
      (folder / (".tmp." + host_name() + "." + std::to_string(::getpid()) + "." +
                 std::to_string(g_tmp_counter++) + "." + fs::path(path).filename().string()))
          .string();
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    ++stats_.write_failures;
    warn("cache entry " + tmp + " cannot be created: " + std::strerror(errno));
    return;
  }
  // Header, payload and checksum are hashed as they are written.
  std::string pre(kMagic, sizeof kMagic);
  const uint32_t hlen = uint32_t(head.size());
  pre.append(reinterpret_cast<const char*>(&hlen), 4);
  pre += head;
  // OIIO's XXH64 has no streaming interface: the file is built in one buffer and hashed.
  std::string all = pre;
  all.reserve(size_t(total));
  for (auto& a : item.arrays)
    all.append(reinterpret_cast<const char*>(a.second.data()), a.second.size() * sizeof(float));
  const uint64_t sum = content_hash(all.data(), all.size());
  all.append(reinterpret_cast<const char*>(&sum), 8);
  all.append(kEnd, sizeof kEnd);
  bool ok = write_all(fd, all.data(), all.size());
  int err = errno;
  if (ok && ::fsync(fd) != 0) {
    ok = false;
    err = errno;
  }
  if (::close(fd) != 0 && ok) {
    ok = false;
    err = errno;
  }
  if (ok && ::rename(tmp.c_str(), path.c_str()) != 0) {
    ok = false;
    err = errno;
  }
  if (!ok) {
    ::unlink(tmp.c_str());
    ++stats_.write_failures;
    warn("cache entry " + path + " could not be written (" + std::strerror(err) + "): not stored");
    return;
  }
  fsync_dir(folder.string());
  ++stats_.writes;
  stats_.bytes_written += all.size();
  since_trim_ += all.size();
  if (since_trim_ > max_bytes_ / 8) trim();
}

void DiskCache::trim() {
  trimmed_ = true;
  since_trim_ = 0;
  struct Entry {
    fs::path path;
    uint64_t size;
    int64_t mtime_ns;
  };
  std::vector<Entry> entries;
  uint64_t total = 0;
  const auto now = std::chrono::system_clock::now();
  std::vector<std::string> dirs{kind_dir_};
  for (auto& k : cap_kinds_) dirs.push_back((fs::path(dir_) / safe_file_name(k)).string());
  for (const std::string& d : dirs) {
    std::error_code ec;
    fs::recursive_directory_iterator it(d, fs::directory_options::skip_permission_denied, ec), end;
    for (; !ec && it != end; it.increment(ec)) {
      std::error_code e2;
      if (!it->is_regular_file(e2)) continue;
      const fs::path p = it->path();
      struct stat st {};
      if (::stat(p.c_str(), &st) != 0) continue;
      const int64_t mt = int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
      const std::string name = p.filename().string();
      if (is_temporary_name(name)) {
        const auto age = std::chrono::duration_cast<std::chrono::seconds>(
                             now.time_since_epoch() - std::chrono::nanoseconds(mt))
                             .count();
        if (age > 3600) fs::remove(p, e2);  // left by a killed writer
        continue;
      }
      if (p.extension() != kExt) continue;
      entries.push_back({p, uint64_t(st.st_size), mt});
      total += uint64_t(st.st_size);
    }
  }
  if (total <= max_bytes_) return;
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.mtime_ns != b.mtime_ns ? a.mtime_ns < b.mtime_ns : a.path < b.path;
  });
  for (auto& e : entries) {
    if (total <= max_bytes_) break;
    std::error_code e2;
    // Another process may have removed it already, or a reader may have it open (POSIX keeps
    // an open file readable after unlink).
    if (fs::remove(e.path, e2)) {
      ++stats_.evicted;
      stats_.bytes_evicted += e.size;
    }
    total -= e.size;
  }
}

}  // namespace fovsim
