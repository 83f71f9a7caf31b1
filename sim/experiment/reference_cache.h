// The reference cache: each frame's shared reference (FrameReference, sim/foveation/frame.h:
// the converged reference image, the 1-spp direct light every full-sampling method and the
// `_fl` reference start from, the indirect light of all VPLs at every pixel that the all_vpls
// strategies add, and the frame's counters) kept on disk across runs, so that a second run that
// changes only what the methods do (a method parameter, a method added, metrics, GPU profiles,
// the latency what-if) renders only the G-buffer and the VPL set of each frame.
//
// Content-addressed (sim/core/disk_cache.h): an entry's key is the text of everything the
// stored values depend on — the code (version, commit and a hash of the binary that computes
// them, so a rebuilt fovsim never reads a stale entry), the scene (its config and a hash of its
// content, files included: sim/scene/scene_hash.h), the simulated camera (resolution, field of
// view), the render settings (render.spp, shadows, tile) and the frame's own inputs (index,
// time, head pose, gaze). Frames, not runs, are the unit: a run of 10 frames reuses the first
// 10 of a run of 90, and the cells of sharded sweeps on a shared file system reuse each other's
// frames. Values are stored as raw float32, so a hit returns the very bits a miss computes.
//
// Run-config keys (configs/README.md "cache"): cache.enabled, cache.dir, cache.max_gb. The
// cache is used when the caller allows it (`fovsim run` and `fovsim sweep` do, unless
// --no-cache or FOVSIM_NO_CACHE) and cache.enabled is true.
#pragma once
#include <memory>
#include <string>

#include "sim/core/disk_cache.h"
#include "sim/core/params.h"
#include "sim/foveation/frame.h"
#include "sim/render/renderer.h"

namespace fovsim {

// The run config's `cache` block.
struct ReferenceCacheSettings {
  bool enabled = true;  // cache.enabled
  std::string dir;      // cache.dir; "" = default_cache_dir()
  // cache.max_gb: size cap of the reference and method memo entries (LRU), GB of 2^30 bytes;
  // 0: default_cache_cap_gb (sim/core/disk_cache.h), resolved by resolve_cap().
  double max_gb = 0;
  bool cap_auto = false;  // max_gb was 0 and resolve_cap() chose it
  // cache.note_mb: a run that adds more than this to the cache says so on stderr, with the
  // cache's size, place and cap (cache_growth_note, sim/core/disk_cache.h); MB of 10^6 bytes.
  double note_mb = 100;
  static ReferenceCacheSettings from_params(Params& p);  // p: the `cache` block
  // Fills `dir` (default_cache_dir() when empty) and, when max_gb is 0, max_gb from the free
  // disk space at dir (cap_auto = true). Idempotent.
  void resolve_cap();
};

class ReferenceCache {
 public:
  // `scene_config`: the resolved `scene` block; `sim_display`: the simulated display.
  ReferenceCache(const ReferenceCacheSettings& s, const Scene& scene, const Json& scene_config,
                 const Display& sim_display, const RenderSettings& rs);

  // The key of frame `frame` (trace sample s, camera cam) as stored in its entry.
  std::string key(int frame, const TraceSample& s, const Camera& cam) const;
  // The frame's stored reference, verified and of the sizes this frame has (W x H).
  bool load(const std::string& key, int width, int height, FrameReference& out);
  void store(const std::string& key, const FrameData& fd);

  // manifest.json "reference_cache": where, the cap, frames from the cache and computed,
  // entries written, and what was ignored or evicted.
  Json manifest() const;
  const DiskCache& disk() const { return disk_; }
  double max_gb() const { return max_gb_; }
  // The entries this run found unusable, and other cache warnings (manifest "warnings").
  std::vector<std::string> warnings() const;

 private:
  Json base_;  // the frame-independent part of every key
  double max_gb_;
  bool cap_auto_;
  DiskCache disk_;
  int from_cache_ = 0, computed_ = 0;
};

}  // namespace fovsim
