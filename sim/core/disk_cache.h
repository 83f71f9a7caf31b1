// A content-addressed cache of float arrays on disk, shared by every process that points at
// the same folder (runs, sweep shards on a shared file system). What it is for: the shared
// per-frame reference (sim/experiment/reference_cache.h), recomputed only when something it
// depends on changes.
//
// An entry is one file, DIR/KIND/<h0h1>/<h>.fce, where h is the XXH64 of the key text; the file
// records the whole key text, which a read compares, so two keys with one hash never return
// each other's data. Layout (little-endian):
//   "FOVSIMC1"  u32 header bytes  header (JSON: format, kind, key, meta, arrays)
//   payload (the arrays' float32 values, in header order)  u64 XXH64 of everything before it
//   "FOVSIMEN"
// Crash safety: an entry is written to a temporary name in its own folder (".tmp.<host>.<pid>.
// <n>.<name>"; host and pid so writers on several machines of a shared file system never
// collide), flushed with fsync, renamed over the final name (atomic on POSIX file systems and
// NFS) and the folder is fsynced. A reader sees either no file or a complete one; a file that
// is short, has another key, a wrong checksum or no end marker anyway (a disk that lied, a
// copy cut short) is ignored with a warning, and its value is recomputed and written again.
// Two processes writing one key write the same bytes (results are deterministic); the last
// rename wins.
// Size cap (of this kind and the kinds named by share_cap_with): least recently used first (a read
// sets an entry's mtime to now); checked when the cache is opened and whenever this process has
// written past the cap since the last check. Temporaries older than an hour (a writer killed by
// SIGKILL) are removed then too.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/hash.h"
#include "sim/core/params.h"  // Json

namespace fovsim {

// One stored value: named float arrays and a small JSON record (counters, sizes).
struct CacheItem {
  Json meta = Json::object();
  std::vector<std::pair<std::string, std::vector<float>>> arrays;
  // The array called `name`, or nullptr.
  const std::vector<float>* array(const std::string& name) const;
  std::vector<float>* array(const std::string& name);
  uint64_t payload_bytes() const;
};

struct DiskCacheStats {
  int hits = 0;            // entries read and verified
  int misses = 0;          // no entry (or an ignored one)
  int ignored = 0;         // entries found but unusable (truncated, corrupted, another key)
  int writes = 0;          // entries written
  int write_failures = 0;  // could not write (full disk, no permission): the run goes on
  int evicted = 0;         // entries removed by the size cap (by this process)
  uint64_t bytes_read = 0, bytes_written = 0, bytes_evicted = 0;
  Json to_json() const;
};

// The default cache folder: $FOVSIM_CACHE_DIR, else $XDG_CACHE_HOME/fovsim (when absolute, as
// the XDG base directory specification asks), else $HOME/.cache/fovsim; "" when none is set.
std::string default_cache_dir();
// True when the environment sets FOVSIM_NO_CACHE to a value other than "0" (the test suites
// set it, so no test writes to a user's cache unless it asks for one).
bool cache_disabled_by_env();

// XXH64 of the file holding the running code (the executable, or the shared object, such as
// the Python module, that fovsim's library is linked into), as 16 hex digits, computed once per
// process: any rebuild that changes the code gives another value. "unknown" when the file
// cannot be read.
std::string code_fingerprint();

// What a cache folder holds (`fovsim cache info`): the entries (`.fce` files) of every kind
// (subfolder), and the temporaries writers left.
struct CacheUsage {
  std::string dir;
  bool exists = false;  // the folder exists
  uint64_t entries = 0, bytes = 0;
  struct Kind {
    std::string name;
    uint64_t entries = 0, bytes = 0;
  };
  std::vector<Kind> kinds;  // by name
  uint64_t temporaries = 0, temporary_bytes = 0;
};
CacheUsage cache_usage(const std::string& dir);

// `fovsim cache prune`: removes the least recently used entries of every kind together (the
// order DiskCache::trim uses) until the folder's entries take at most `max_bytes`, and
// temporaries older than an hour.
struct PruneReport {
  CacheUsage before, after;
  uint64_t removed_entries = 0, removed_bytes = 0;
};
PruneReport prune_cache(const std::string& dir, uint64_t max_bytes);

// Bytes free for an unprivileged writer on the file system that holds `path` (or its nearest
// existing ancestor: the cache folder may not exist yet); nullopt when statvfs fails.
std::optional<uint64_t> free_disk_bytes(const std::string& path);

// The default size cap of the cache (cache.max_gb = 0), in GB of 2^30 bytes:
// min(kCacheCapMaxGb, kCacheCapFreeShare x (free space + what the cache already holds)), so a
// cache on a small or nearly full disk stays a tenth of what it could use, and one on a large
// disk stops at 20 GB. kCacheCapMaxGb when the free space is unknown.
constexpr double kCacheCapMaxGb = 20;
constexpr double kCacheCapFreeShare = 0.10;
double auto_cache_cap_gb(std::optional<uint64_t> free_bytes, uint64_t cached_bytes);
// auto_cache_cap_gb at `dir`: its free space and its current entries.
double default_cache_cap_gb(const std::string& dir);

// One line for stderr after a run that added more than `threshold` bytes to the cache at `dir`
// (default kCacheGrowthNoteBytes): where it is, what it holds now, its cap, and how to look at
// and shrink it; "" when the run added less.
constexpr uint64_t kCacheGrowthNoteBytes = 100ull * 1000 * 1000;
std::string cache_growth_note(const std::string& dir, uint64_t added_bytes, double cap_gb,
                              uint64_t threshold = kCacheGrowthNoteBytes);

// "1.23 GB" / "45.6 MB" / "7.8 KB" / "789 B" (GB = 2^30 bytes, MB = 2^20, KB = 2^10, as
// cache.max_gb).
std::string cache_size_text(uint64_t bytes);

// `fovsim cache info`: what the folder holds, the free space there and the cap a run with
// cache.max_gb = 0 (the default) would use now.
struct CacheInfo {
  CacheUsage usage;
  std::optional<uint64_t> free_bytes;
  double default_cap_gb = 0;
};
CacheInfo cache_info(const std::string& dir);
// Lines "cache folder: ...", "size: ...", "cap: ...", "free disk space: ...".
std::string cache_info_text(const CacheInfo& info);
// {"dir", "exists", "entries", "bytes", "kinds": [{"name", "entries", "bytes"}],
//  "temporaries", "free_bytes" (null when unknown), "default_max_gb", "cap_rule"}.
Json cache_info_json(const CacheInfo& info);
// "pruned DIR to at most X GB: removed N entries (S); it holds S' in N' entries".
std::string prune_report_text(const PruneReport& r, double max_gb);

class DiskCache {
 public:
  // Entries of `kind` (a folder name) under `dir`, at most `max_bytes` of them together.
  // Creates nothing until the first write.
  DiskCache(std::string dir, std::string kind, uint64_t max_bytes);

  // The entry stored under `key`, verified; nullopt when there is none or it is unusable (then
  // a warning says which file and why). A hit makes the entry the most recently used.
  std::optional<CacheItem> get(const std::string& key);
  // Stores `item` under `key` (crash-safe, see above). A failure (full disk, read-only folder,
  // an item larger than the cap) is a warning, never an error: the caller has its value.
  void put(const std::string& key, const CacheItem& item);
  // Removes the least recently used entries until the entries of this kind take at most the
  // cap, and temporaries older than an hour.
  void trim();

  // Entries of these other kinds (folders next to this one) count against the same cap, and
  // trim() removes the least recently used of all of them together.
  void share_cap_with(std::vector<std::string> kinds) { cap_kinds_ = std::move(kinds); }

  const std::string& dir() const { return dir_; }
  std::string path_of(const std::string& key) const;
  const DiskCacheStats& stats() const { return stats_; }
  // What went wrong, oldest first (at most 20; `warnings_dropped` counts the rest).
  const std::vector<std::string>& warnings() const { return warnings_; }
  int warnings_dropped() const { return dropped_; }

 private:
  void warn(const std::string& w);
  std::string dir_, kind_dir_;
  std::vector<std::string> cap_kinds_;
  uint64_t max_bytes_;
  uint64_t since_trim_ = 0;  // bytes written since the last trim
  bool trimmed_ = false;
  bool write_disabled_ = false;  // after a failure to create the folder
  DiskCacheStats stats_;
  std::vector<std::string> warnings_;
  int dropped_ = 0;
};

}  // namespace fovsim
