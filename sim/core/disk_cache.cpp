#include "sim/core/disk_cache.h"

#include <OpenImageIO/hash.h>
#include <dlfcn.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
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

namespace {

struct Entry {
  fs::path path;
  uint64_t size;
  int64_t mtime_ns;
};

// The entries (.fce) under `dirs`; temporaries older than an hour (left by a killed writer) are
// removed, younger ones counted in `tmp` / `tmp_bytes` when given.
std::vector<Entry> scan_entries(const std::vector<std::string>& dirs, uint64_t* tmp = nullptr,
                                uint64_t* tmp_bytes = nullptr) {
  std::vector<Entry> entries;
  const auto now = std::chrono::system_clock::now();
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
        if (age > 3600) {
          fs::remove(p, e2);  // left by a killed writer
        } else {
          if (tmp) ++*tmp;
          if (tmp_bytes) *tmp_bytes += uint64_t(st.st_size);
        }
        continue;
      }
      if (p.extension() != kExt) continue;
      entries.push_back({p, uint64_t(st.st_size), mt});
    }
  }
  return entries;
}

// Removes the least recently used of `entries` (oldest mtime first, then by path) until they
// take at most `max_bytes`; returns {entries removed, bytes removed}.
std::pair<uint64_t, uint64_t> evict_lru(std::vector<Entry> entries, uint64_t max_bytes) {
  uint64_t total = 0;
  for (auto& e : entries) total += e.size;
  if (total <= max_bytes) return {0, 0};
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.mtime_ns != b.mtime_ns ? a.mtime_ns < b.mtime_ns : a.path < b.path;
  });
  uint64_t n = 0, bytes = 0;
  for (auto& e : entries) {
    if (total <= max_bytes) break;
    std::error_code e2;
    // Another process may have removed it already, or a reader may have it open (POSIX keeps
    // an open file readable after unlink).
    if (fs::remove(e.path, e2)) {
      ++n;
      bytes += e.size;
    }
    total -= e.size;
  }
  return {n, bytes};
}

// The kind folders of a cache folder, by name.
std::vector<std::string> kind_dirs(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code e2;
    if (it->is_directory(e2) && !it->is_symlink(e2)) out.push_back(it->path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

void DiskCache::trim() {
  trimmed_ = true;
  since_trim_ = 0;
  std::vector<std::string> dirs{kind_dir_};
  for (auto& k : cap_kinds_) dirs.push_back((fs::path(dir_) / safe_file_name(k)).string());
  const auto [n, bytes] = evict_lru(scan_entries(dirs), max_bytes_);
  stats_.evicted += int(n);
  stats_.bytes_evicted += bytes;
}

CacheUsage cache_usage(const std::string& dir) {
  CacheUsage u;
  u.dir = dir;
  std::error_code ec;
  u.exists = fs::is_directory(dir, ec);
  if (!u.exists) return u;
  for (const std::string& k : kind_dirs(dir)) {
    CacheUsage::Kind kind;
    kind.name = fs::path(k).filename().string();
    for (auto& e : scan_entries({k}, &u.temporaries, &u.temporary_bytes)) {
      ++kind.entries;
      kind.bytes += e.size;
    }
    u.entries += kind.entries;
    u.bytes += kind.bytes;
    u.kinds.push_back(kind);
  }
  return u;
}

PruneReport prune_cache(const std::string& dir, uint64_t max_bytes) {
  PruneReport r;
  r.before = cache_usage(dir);
  if (r.before.exists) {
    const auto [n, bytes] = evict_lru(scan_entries(kind_dirs(dir)), max_bytes);
    r.removed_entries = n;
    r.removed_bytes = bytes;
  }
  r.after = cache_usage(dir);
  return r;
}

std::optional<uint64_t> free_disk_bytes(const std::string& path) {
  if (path.empty()) return std::nullopt;
  std::error_code ec;
  fs::path p = fs::absolute(path, ec);
  if (ec) return std::nullopt;
  // The nearest existing ancestor (the cache folder is created on the first write).
  while (!p.empty() && !fs::exists(p, ec) && p != p.root_path()) p = p.parent_path();
  struct statvfs st {};
  if (::statvfs(p.c_str(), &st) != 0) return std::nullopt;
  return uint64_t(st.f_bavail) * uint64_t(st.f_frsize);
}

double auto_cache_cap_gb(std::optional<uint64_t> free_bytes, uint64_t cached_bytes) {
  if (!free_bytes) return kCacheCapMaxGb;
  const double gib = 1024.0 * 1024.0 * 1024.0;
  return std::min(kCacheCapMaxGb,
                  kCacheCapFreeShare * (double(*free_bytes) + double(cached_bytes)) / gib);
}

double default_cache_cap_gb(const std::string& dir) {
  return auto_cache_cap_gb(free_disk_bytes(dir), cache_usage(dir).bytes);
}

std::string cache_size_text(uint64_t bytes) {
  char b[40];
  const double kib = 1024.0, mib = kib * 1024, gib = mib * 1024;
  if (double(bytes) >= gib)
    std::snprintf(b, sizeof b, "%.2f GB", double(bytes) / gib);
  else if (double(bytes) >= mib)
    std::snprintf(b, sizeof b, "%.1f MB", double(bytes) / mib);
  else if (double(bytes) >= kib)
    std::snprintf(b, sizeof b, "%.1f KB", double(bytes) / kib);
  else
    std::snprintf(b, sizeof b, "%llu B", static_cast<unsigned long long>(bytes));
  return b;
}

CacheInfo cache_info(const std::string& dir) {
  CacheInfo i;
  i.usage = cache_usage(dir);
  i.free_bytes = free_disk_bytes(dir);
  i.default_cap_gb = auto_cache_cap_gb(i.free_bytes, i.usage.bytes);
  return i;
}

namespace {
constexpr const char* kCapRule =
    "cache.max_gb 0 (the default): min(20 GB, 10% of the free space + what the cache holds)";
std::string gb_text(double gb) {
  char b[40];
  std::snprintf(b, sizeof b, "%.3g GB", gb);
  return b;
}
}  // namespace

std::string cache_info_text(const CacheInfo& i) {
  const CacheUsage& u = i.usage;
  std::string s = "cache folder: " + u.dir + (u.exists ? "" : " (does not exist yet)") + "\n";
  s += "size: " + cache_size_text(u.bytes) + " in " + std::to_string(u.entries) + " entr" +
       (u.entries == 1 ? "y" : "ies");
  if (!u.kinds.empty()) {
    s += " (";
    for (size_t k = 0; k < u.kinds.size(); ++k)
      s += (k ? ", " : "") + u.kinds[k].name + ": " + std::to_string(u.kinds[k].entries) + ", " +
           cache_size_text(u.kinds[k].bytes);
    s += ")";
  }
  if (u.temporaries)
    s += "; " + std::to_string(u.temporaries) + " temporaries of writers (" +
         cache_size_text(u.temporary_bytes) + ")";
  s += "\ncap: " + gb_text(i.default_cap_gb) + " (" + kCapRule +
       "; a config's cache.max_gb > 0 sets it)\n";
  s += "free disk space: " + (i.free_bytes ? cache_size_text(*i.free_bytes) : "unknown") + "\n";
  return s;
}

Json cache_info_json(const CacheInfo& i) {
  Json kinds = Json::array();
  for (auto& k : i.usage.kinds)
    kinds.push_back(Json{{"name", k.name}, {"entries", k.entries}, {"bytes", k.bytes}});
  return Json{{"dir", i.usage.dir},
              {"exists", i.usage.exists},
              {"entries", i.usage.entries},
              {"bytes", i.usage.bytes},
              {"kinds", kinds},
              {"temporaries", i.usage.temporaries},
              {"free_bytes", i.free_bytes ? Json(*i.free_bytes) : Json()},
              {"default_max_gb", i.default_cap_gb},
              {"cap_rule", kCapRule}};
}

std::string prune_report_text(const PruneReport& r, double max_gb) {
  return "pruned " + r.after.dir + " to at most " + gb_text(max_gb) + ": removed " +
         std::to_string(r.removed_entries) + " entr" + (r.removed_entries == 1 ? "y" : "ies") +
         " (" + cache_size_text(r.removed_bytes) + "); it holds " + cache_size_text(r.after.bytes) +
         " in " + std::to_string(r.after.entries) + " entr" + (r.after.entries == 1 ? "y" : "ies") +
         "\n";
}

std::string cache_growth_note(const std::string& dir, uint64_t added_bytes, double cap_gb,
                              uint64_t threshold) {
  if (added_bytes <= threshold) return "";
  const CacheUsage u = cache_usage(dir);
  char cap[40];
  std::snprintf(cap, sizeof cap, "%.3g GB", cap_gb);
  return "reference cache " + dir + ": this run wrote " + cache_size_text(added_bytes) + " to it" +
         ", it holds " + cache_size_text(u.bytes) + " in " + std::to_string(u.entries) +
         (u.entries == 1 ? " entry" : " entries") + " (cap cache.max_gb " + cap +
         "); `fovsim cache info` shows it, `fovsim cache prune --max-gb N` shrinks it";
}

}  // namespace fovsim
