// The on-disk cache (sim/core/disk_cache.h): a stored item comes back bit for bit; a truncated,
// corrupted or foreign file under an entry's name is ignored with a warning (and replaced by
// the next write); the size cap evicts the least recently used entries; concurrent writers of
// one key and a writer killed by SIGKILL at any moment never make a reader see a partial entry.
#include "sim/core/disk_cache.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <thread>

using namespace fovsim;
namespace fs = std::filesystem;

namespace {

std::string fresh_dir(const std::string& name) {
  fs::path d =
      fs::temp_directory_path() / ("fovsim_disk_cache_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d.string();
}

CacheItem item_of(size_t n, float seed) {
  CacheItem it;
  it.meta["counters"] = Json::array({Json::array({"rays", "0x1.8p+3"})});
  std::vector<float> a(n), b(n / 2 + 1);
  for (size_t i = 0; i < n; ++i) a[i] = seed + float(i) * 0.25f;
  for (size_t i = 0; i < b.size(); ++i) b[i] = -seed * float(i);
  a[0] = -0.f;
  if (n > 2) a[1] = std::nextafter(1.f, 2.f);  // odd bits come back as they are
  it.arrays.emplace_back("a", a);
  it.arrays.emplace_back("b", b);
  it.arrays.emplace_back("empty", std::vector<float>());
  return it;
}

bool same(const CacheItem& x, const CacheItem& y) {
  if (x.meta != y.meta || x.arrays.size() != y.arrays.size()) return false;
  for (size_t i = 0; i < x.arrays.size(); ++i) {
    if (x.arrays[i].first != y.arrays[i].first) return false;
    const auto& u = x.arrays[i].second;
    const auto& v = y.arrays[i].second;
    if (u.size() != v.size() || (!u.empty() && std::memcmp(u.data(), v.data(), u.size() * 4) != 0))
      return false;
  }
  return true;
}

void overwrite_byte(const std::string& path, uint64_t at, char c) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(std::streamoff(at));
  f.put(c);
}

}  // namespace

TEST(DiskCache, RoundTripBitForBit) {
  const std::string d = fresh_dir("rt");
  DiskCache c(d, "refs", 1 << 30);
  EXPECT_FALSE(c.get("key one").has_value());  // nothing yet: a miss, no warning
  EXPECT_TRUE(c.warnings().empty());
  const CacheItem it = item_of(1000, 3.5f);
  c.put("key one", it);
  auto back = c.get("key one");
  ASSERT_TRUE(back.has_value());
  EXPECT_TRUE(same(*back, it));
  EXPECT_FALSE(c.get("key two").has_value());
  EXPECT_EQ(c.stats().hits, 1);
  EXPECT_EQ(c.stats().misses, 2);
  EXPECT_EQ(c.stats().writes, 1);
  EXPECT_TRUE(c.warnings().empty());
  // Another process (another DiskCache) on the same folder reads it.
  DiskCache other(d, "refs", 1 << 30);
  ASSERT_TRUE(other.get("key one").has_value());
  EXPECT_NE(c.path_of("key one").find(d + "/refs/"), std::string::npos);
  fs::remove_all(d);
}

TEST(DiskCache, DamagedEntriesAreIgnoredWithAWarningAndRewritten) {
  const std::string d = fresh_dir("damaged");
  DiskCache c(d, "refs", 1 << 30);
  const CacheItem it = item_of(4096, 1.f);
  c.put("k", it);
  const std::string p = c.path_of("k");
  const uint64_t size = fs::file_size(p);
  struct Damage {
    const char* what;
    std::function<void()> apply;
    const char* says;
  };
  const std::vector<Damage> damages = {
      {"truncated (a copy cut short)", [&] { fs::resize_file(p, size - 100); }, "truncated"},
      {"truncated to the header", [&] { fs::resize_file(p, 40); }, "truncated"},
      {"empty", [&] { fs::resize_file(p, 0); }, "truncated"},
      {"one payload byte flipped", [&] { overwrite_byte(p, size / 2, 'x'); }, "checksum"},
      {"garbage",
       [&] { std::ofstream(p, std::ios::binary | std::ios::trunc) << "not a cache entry at all"; },
       "no header"},
  };
  for (auto& dm : damages) {
    SCOPED_TRACE(dm.what);
    c.put("k", it);  // a fresh, complete entry
    ASSERT_TRUE(c.get("k").has_value());
    dm.apply();
    const size_t w0 = c.warnings().size();
    EXPECT_FALSE(c.get("k").has_value());
    ASSERT_EQ(c.warnings().size(), w0 + 1);
    EXPECT_NE(c.warnings().back().find(p), std::string::npos) << c.warnings().back();
    EXPECT_NE(c.warnings().back().find(dm.says), std::string::npos) << c.warnings().back();
    EXPECT_NE(c.warnings().back().find("ignored, recomputed"), std::string::npos);
    c.put("k", it);  // what the engine does after recomputing
    auto back = c.get("k");
    ASSERT_TRUE(back.has_value());
    EXPECT_TRUE(same(*back, it));
  }
  EXPECT_EQ(c.stats().ignored, int(damages.size()));
  fs::remove_all(d);
}

// Two keys whose files collide (the same name) never return each other's value.
TEST(DiskCache, AnotherKeyUnderTheSameNameIsAMiss) {
  const std::string d = fresh_dir("collide");
  DiskCache c(d, "refs", 1 << 30);
  c.put("first", item_of(10, 1.f));
  fs::create_directories(fs::path(c.path_of("second")).parent_path());
  fs::copy_file(c.path_of("first"), c.path_of("second"), fs::copy_options::overwrite_existing);
  EXPECT_FALSE(c.get("second").has_value());
  EXPECT_TRUE(c.get("first").has_value());
  fs::remove_all(d);
}

TEST(DiskCache, SizeCapEvictsLeastRecentlyUsed) {
  const std::string d = fresh_dir("lru");
  const CacheItem it = item_of(25000, 2.f);  // ~150 kB per entry
  uint64_t entry = 0;
  {
    DiskCache probe(d, "refs", 1 << 30);
    probe.put("probe", it);
    entry = fs::file_size(probe.path_of("probe"));
    fs::remove_all(d);
  }
  DiskCache c(d, "refs", entry * 3 + entry / 2);  // room for 3 entries
  c.put("a", it);
  c.put("b", it);
  c.put("c", it);
  // mtimes one second apart whatever the file system's timestamp resolution, "a" read last.
  const auto now = fs::file_time_type::clock::now();
  fs::last_write_time(c.path_of("a"), now - std::chrono::seconds(30));
  fs::last_write_time(c.path_of("b"), now - std::chrono::seconds(20));
  fs::last_write_time(c.path_of("c"), now - std::chrono::seconds(10));
  ASSERT_TRUE(c.get("a").has_value());  // a read makes "a" the most recently used
  // A temporary left by a writer killed long ago is removed; a recent one (a writer at work)
  // is left alone.
  const fs::path old_tmp = fs::path(c.path_of("a")).parent_path() / ".tmp.host.1.0.old.fce";
  const fs::path new_tmp = fs::path(c.path_of("a")).parent_path() / ".tmp.host.1.1.new.fce";
  std::ofstream(old_tmp) << "x";
  std::ofstream(new_tmp) << "x";
  fs::last_write_time(old_tmp, now - std::chrono::hours(2));
  c.trim();
  EXPECT_FALSE(fs::exists(old_tmp));
  EXPECT_TRUE(fs::exists(new_tmp));
  c.put("d", it);  // over the cap: the oldest, "b", goes
  EXPECT_TRUE(fs::exists(c.path_of("a")));
  EXPECT_FALSE(fs::exists(c.path_of("b")));
  EXPECT_TRUE(fs::exists(c.path_of("c")));
  EXPECT_TRUE(fs::exists(c.path_of("d")));
  EXPECT_EQ(c.stats().evicted, 1);
  // An item larger than the whole cap is not stored (a warning, not an error).
  DiskCache tiny(d, "tiny", 1000);
  tiny.put("big", it);
  EXPECT_EQ(tiny.stats().write_failures, 1);
  EXPECT_FALSE(tiny.get("big").has_value());
  fs::remove_all(d);
}

// Kinds that share a cap (share_cap_with: the references and the method memo under cache.max_gb)
// are trimmed together: the least recently used entry of either kind goes first.
TEST(DiskCache, SharedCapCountsEveryKindNamed) {
  const std::string d = fresh_dir("shared_cap");
  const CacheItem it = item_of(25000, 3.f);
  uint64_t entry = 0;
  {
    DiskCache probe(d, "refs", 1 << 30);
    probe.put("probe", it);
    entry = fs::file_size(probe.path_of("probe"));
    fs::remove_all(d);
  }
  const uint64_t cap = entry * 2 + entry / 2;  // room for 2 entries of both kinds together
  DiskCache memo(d, "memo", cap);
  memo.share_cap_with({"refs"});
  memo.put("m", it);
  DiskCache refs(d, "refs", cap);
  refs.share_cap_with({"memo"});
  refs.put("a", it);
  const auto now = fs::file_time_type::clock::now();
  fs::last_write_time(memo.path_of("m"), now - std::chrono::seconds(20));
  fs::last_write_time(refs.path_of("a"), now - std::chrono::seconds(10));
  refs.put("b", it);  // three entries over a cap of two: the memo's older entry goes
  EXPECT_FALSE(fs::exists(memo.path_of("m")));
  EXPECT_TRUE(fs::exists(refs.path_of("a")));
  EXPECT_TRUE(fs::exists(refs.path_of("b")));
  EXPECT_EQ(refs.stats().evicted, 1);
  fs::remove_all(d);
}

TEST(DiskCache, UnwritableFolderIsAWarningNotAnError) {
  const std::string d = fresh_dir("ro");
  fs::create_directories(d);
  std::ofstream(d + "/refs") << "a file where the folder should be";
  DiskCache c(d, "refs", 1 << 30);
  EXPECT_NO_THROW(c.put("k", item_of(10, 1.f)));
  EXPECT_EQ(c.stats().write_failures, 1);
  ASSERT_FALSE(c.warnings().empty());
  EXPECT_FALSE(c.get("k").has_value());
  fs::remove_all(d);
}

// Two processes write one key over and over while a third reads it: every read is a miss or
// the complete value, never a warning.
TEST(DiskCache, ConcurrentWritersOfOneKey) {
  const std::string d = fresh_dir("concurrent");
  const CacheItem it = item_of(200000, 5.f);  // ~1.2 MB: writes take a while
  std::vector<pid_t> kids;
  for (int k = 0; k < 2; ++k) {
    pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      DiskCache w(d, "refs", 1 << 30);
      for (int i = 0; i < 15; ++i) w.put("shared key", it);
      ::_exit(w.stats().writes == 15 ? 0 : 1);
    }
    kids.push_back(pid);
  }
  DiskCache r(d, "refs", 1 << 30);
  int hits = 0;
  for (int i = 0; i < 400; ++i) {
    auto v = r.get("shared key");
    if (v) {
      ++hits;
      ASSERT_TRUE(same(*v, it));
    }
  }
  for (pid_t pid : kids) {
    int st = 0;
    ASSERT_EQ(::waitpid(pid, &st, 0), pid);
    EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0);
  }
  EXPECT_TRUE(r.warnings().empty()) << r.warnings().front();
  auto v = r.get("shared key");
  ASSERT_TRUE(v.has_value());
  EXPECT_TRUE(same(*v, it));
  (void)hits;
  fs::remove_all(d);
}

// A writer killed by SIGKILL at an arbitrary moment leaves the old entry or the new one,
// never a partial one under the entry's name.
TEST(DiskCache, SigkillDuringWritesNeverLeavesAPartialEntry) {
  const std::string d = fresh_dir("sigkill");
  const CacheItem old_v = item_of(300000, 1.f), new_v = item_of(300000, 9.f);
  {
    DiskCache c(d, "refs", 1 << 30);
    c.put("k", old_v);
  }
  for (int round = 0; round < 8; ++round) {
    pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      DiskCache w(d, "refs", 1 << 30);
      for (;;) {
        w.put("k", new_v);
        w.put("k", old_v);
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5 + 7 * round));
    ::kill(pid, SIGKILL);
    int st = 0;
    ::waitpid(pid, &st, 0);
    DiskCache r(d, "refs", 1 << 30);
    auto v = r.get("k");
    ASSERT_TRUE(v.has_value()) << (r.warnings().empty() ? "" : r.warnings().front());
    EXPECT_TRUE(same(*v, old_v) || same(*v, new_v));
    EXPECT_TRUE(r.warnings().empty());
  }
  fs::remove_all(d);
}

TEST(DiskCache, DefaultFolderAndSwitch) {
  const char* saved[] = {std::getenv("FOVSIM_CACHE_DIR"), std::getenv("XDG_CACHE_HOME"),
                         std::getenv("HOME"), std::getenv("FOVSIM_NO_CACHE")};
  const std::string keep[] = {saved[0] ? saved[0] : "", saved[1] ? saved[1] : "",
                              saved[2] ? saved[2] : "", saved[3] ? saved[3] : ""};
  ::setenv("FOVSIM_CACHE_DIR", "/tmp/a", 1);
  ::setenv("XDG_CACHE_HOME", "/tmp/x", 1);
  ::setenv("HOME", "/tmp/h", 1);
  EXPECT_EQ(default_cache_dir(), "/tmp/a");
  ::unsetenv("FOVSIM_CACHE_DIR");
  EXPECT_EQ(default_cache_dir(), "/tmp/x/fovsim");
  ::setenv("XDG_CACHE_HOME", "relative", 1);  // not absolute: ignored (XDG spec)
  EXPECT_EQ(default_cache_dir(), "/tmp/h/.cache/fovsim");
  ::unsetenv("FOVSIM_NO_CACHE");
  EXPECT_FALSE(cache_disabled_by_env());
  ::setenv("FOVSIM_NO_CACHE", "0", 1);
  EXPECT_FALSE(cache_disabled_by_env());
  ::setenv("FOVSIM_NO_CACHE", "1", 1);
  EXPECT_TRUE(cache_disabled_by_env());
  const char* names[] = {"FOVSIM_CACHE_DIR", "XDG_CACHE_HOME", "HOME", "FOVSIM_NO_CACHE"};
  for (int i = 0; i < 4; ++i)
    if (saved[i])
      ::setenv(names[i], keep[i].c_str(), 1);
    else
      ::unsetenv(names[i]);
}

// `fovsim cache info` / `prune` (cache_usage, prune_cache): every kind is counted, and pruning
// removes the least recently used entries of all kinds together down to the size asked for.
TEST(DiskCache, UsageAndPruneAcrossKinds) {
  const std::string d = fresh_dir("prune");
  const CacheItem it = item_of(25000, 2.f);
  DiskCache refs(d, "references", 1ull << 30), memo(d, "methods", 1ull << 30);
  refs.put("a", it);
  refs.put("b", it);
  memo.put("m", it);
  // The headers differ by the key and the kind's name: sizes per file.
  const uint64_t sa = fs::file_size(refs.path_of("a")), sb = fs::file_size(refs.path_of("b")),
                 sm = fs::file_size(memo.path_of("m"));
  const auto now = fs::file_time_type::clock::now();
  fs::last_write_time(refs.path_of("a"), now - std::chrono::seconds(30));
  fs::last_write_time(memo.path_of("m"), now - std::chrono::seconds(20));
  fs::last_write_time(refs.path_of("b"), now - std::chrono::seconds(10));
  CacheUsage u = cache_usage(d);
  EXPECT_TRUE(u.exists);
  EXPECT_EQ(u.entries, 3u);
  EXPECT_EQ(u.bytes, sa + sb + sm);
  ASSERT_EQ(u.kinds.size(), 2u);
  EXPECT_EQ(u.kinds[0].name, "methods");
  EXPECT_EQ(u.kinds[0].entries, 1u);
  EXPECT_EQ(u.kinds[1].name, "references");
  EXPECT_EQ(u.kinds[1].bytes, sa + sb);
  // Down to one and a half entries: the two oldest (a, then the memo's m) go.
  PruneReport r = prune_cache(d, sb + sb / 2);
  EXPECT_EQ(r.removed_entries, 2u);
  EXPECT_EQ(r.removed_bytes, sa + sm);
  EXPECT_EQ(r.before.bytes, sa + sb + sm);
  EXPECT_EQ(r.after.bytes, sb);
  EXPECT_FALSE(fs::exists(refs.path_of("a")));
  EXPECT_FALSE(fs::exists(memo.path_of("m")));
  EXPECT_TRUE(fs::exists(refs.path_of("b")));
  EXPECT_NE(prune_report_text(r, 1.5).find("removed 2 entries"), std::string::npos);
  EXPECT_EQ(prune_cache(d, 0).after.entries, 0u);
  // A folder that does not exist holds nothing and prunes to nothing, without an error.
  EXPECT_FALSE(cache_usage(d + "/none").exists);
  EXPECT_EQ(prune_cache(d + "/none", 0).removed_entries, 0u);
  fs::remove_all(d);
}

// The default cap (cache.max_gb 0): min(20 GB, 10% of free space + what the cache holds).
TEST(DiskCache, DefaultCapFollowsTheFreeSpace) {
  const uint64_t gib = 1ull << 30;
  EXPECT_DOUBLE_EQ(auto_cache_cap_gb(std::nullopt, 0), kCacheCapMaxGb);
  EXPECT_DOUBLE_EQ(auto_cache_cap_gb(10 * gib, 0), 1.0);
  EXPECT_DOUBLE_EQ(auto_cache_cap_gb(9 * gib, 1 * gib), 1.0);  // its own entries count as room
  EXPECT_DOUBLE_EQ(auto_cache_cap_gb(1000 * gib, 0), 20.0);
  EXPECT_DOUBLE_EQ(auto_cache_cap_gb(0, 0), 0.0);
  // A folder not created yet: the free space of its nearest existing parent.
  const std::string d = fresh_dir("free");
  const auto f = free_disk_bytes(d + "/not/yet");
  ASSERT_TRUE(f.has_value());
  EXPECT_GT(*f, 0u);
  EXPECT_LE(default_cache_cap_gb(d + "/not/yet"), kCacheCapMaxGb);
  EXPECT_FALSE(free_disk_bytes("").has_value());
}

// A run that adds more than the threshold says where the cache is and how big it is.
TEST(DiskCache, GrowthNoteAboveTheThresholdOnly) {
  const std::string d = fresh_dir("note");
  DiskCache refs(d, "references", 1ull << 30);
  refs.put("a", item_of(1000, 1.f));
  EXPECT_EQ(cache_growth_note(d, 100, 2.0, 100), "");
  const std::string n = cache_growth_note(d, 101, 2.0, 100);
  EXPECT_NE(n.find("reference cache " + d + ": this run wrote 101 B to it"), std::string::npos)
      << n;
  EXPECT_NE(n.find("in 1 entry (cap cache.max_gb 2 GB)"), std::string::npos) << n;
  EXPECT_NE(n.find("fovsim cache prune --max-gb"), std::string::npos) << n;
  EXPECT_EQ(n.find('\n'), std::string::npos);  // one line
  EXPECT_EQ(cache_size_text(3ull << 30), "3.00 GB");
  EXPECT_EQ(cache_size_text(5ull << 20), "5.0 MB");
  EXPECT_EQ(cache_size_text(1536), "1.5 KB");
  fs::remove_all(d);
}
