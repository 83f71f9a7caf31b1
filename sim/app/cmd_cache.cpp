// `fovsim cache info [--dir DIR] [--json]` and `fovsim cache prune [--max-gb X] [--dir DIR]`:
// the reference cache's folder, size, entries and cap, and shrinking it now (least recently used
// entries first). Parsing and printing only; the logic is sim/core/disk_cache.cpp.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <memory>

#include "sim/app/commands.h"
#include "sim/app/flags.h"
#include "sim/core/disk_cache.h"
#include "sim/core/error.h"

namespace fovsim::app {

namespace {
struct CacheArgs {
  std::string dir;
  bool json = false;
  double max_gb = -1;  // prune: unset -> the default cap (cache_info)
};

std::string cache_dir_of(const CacheArgs& a) {
  if (!a.dir.empty()) return a.dir;
  const std::string d = default_cache_dir();
  if (d.empty())
    throw Error("fovsim cache",
                "no cache folder: FOVSIM_CACHE_DIR, XDG_CACHE_HOME and HOME are unset; give --dir");
  return d;
}

void add_dir_flag(CLI::App* c, CacheArgs& a) {
  c->add_option("--dir", a.dir,
                "Cache folder (default: the runs' default: $FOVSIM_CACHE_DIR, else "
                "$XDG_CACHE_HOME/fovsim, else ~/.cache/fovsim; a config's cache.dir may name "
                "another)");
}
}  // namespace

void register_cache(CLI::App& app, Action& action) {
  CLI::App* cache = app.add_subcommand(
      "cache", "The reference cache (configs/README.md \"cache\"): its size and cap, prune it");
  cache->require_subcommand(1);
  cache->footer(
      "A run prints one line on stderr when it adds more than cache.note_mb (100 MB) to the "
      "cache.\nThe cap of a run is its config's cache.max_gb; 0 (the default) means min(20 GB, "
      "10% of the\nfree disk space at the folder plus what the cache holds).");

  auto ia = std::make_shared<CacheArgs>();
  CLI::App* info = cache->add_subcommand(
      "info", "Print the cache folder, its size and entries per kind, the cap and free space");
  add_dir_flag(info, *ia);
  info->add_flag("--json", ia->json, "Print one JSON object instead of text");
  info->callback([ia, &action] {
    action = [ia] {
      const CacheInfo i = cache_info(cache_dir_of(*ia));
      if (ia->json)
        std::printf("%s\n", cache_info_json(i).dump().c_str());
      else
        std::fputs(cache_info_text(i).c_str(), stdout);
      return 0;
    };
  });

  auto pa = std::make_shared<CacheArgs>();
  CLI::App* prune = cache->add_subcommand(
      "prune", "Remove the least recently used entries until the cache holds at most --max-gb");
  add_dir_flag(prune, *pa);
  add_number(prune, "--max-gb", pa->max_gb,
             "Size to prune to, GB of 2^30 bytes (default: the cap `fovsim cache info` shows; "
             "0 empties the cache)",
             {Range::closed(0, 1e6), "GB"});
  prune->callback([pa, &action] {
    action = [pa] {
      const std::string dir = cache_dir_of(*pa);
      const double gb = pa->max_gb >= 0 ? pa->max_gb : cache_info(dir).default_cap_gb;
      const PruneReport r =
          prune_cache(dir, uint64_t(std::min(gb * 1024.0 * 1024.0 * 1024.0, 9.0e18)));
      std::fputs(prune_report_text(r, gb).c_str(), stdout);
      return 0;
    };
  });
}

}  // namespace fovsim::app
