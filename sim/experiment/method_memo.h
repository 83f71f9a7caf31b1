// The method memo: one method entry's results over one cell's whole frame sequence, kept in the
// cache folder of the reference cache (reference_cache.h, kind "methods"), so that a run which
// changes one method's parameters recomputes that method only; the other entries' per-frame
// outputs (counters, metric values including `_fl` and sequence-metric columns, flags, the
// cost method, sim_ms as recorded) and the images they write on saved frames come from the
// cache, and their rows are built as in a computed run (cost model, GPUs), byte for byte.
//
// The unit is the whole sequence, not a frame: methods, sequence metrics, temporal metrics and
// the latency feedback carry state from frame to frame, so a per-frame entry would need that
// history in its key; a whole sequence starts from the same empty state every time. The key
// (MethodMemo::key) holds everything a method's outputs depend on: the code (version, commit,
// hash of the binary), the resolved shared config (scene, display, render, trace, frames,
// tone map, seed, ...) with the scene's content hash, the trace's samples (resampled and raw)
// and every frame's reference key, the resolved method entry, the cell's metrics, latency and
// outputs blocks, its GPU list and workload when the gaze depends on the cost
// (latency.render_from_estimate), and the ordered list of frames with the warm-up frames.
// Written only when the cell completes (atomically: disk_cache.h); a missing, unusable or
// mismatching entry is recomputed. Not used under --target (its frame order depends on the
// other methods' results).
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/disk_cache.h"
#include "sim/core/params.h"

namespace fovsim {

struct ReferenceCacheSettings;

// One frame of a method: what build_rows needs, and the files queued on saved frames.
struct MemoFrame {
  int fi = 0;
  bool record = true;  // false: a warm-up frame
  std::string cost_method;
  double sim_ms = 0;
  std::vector<std::pair<std::string, double>> counters;
  std::vector<std::pair<std::string, double>> metrics;
  std::vector<std::string> flags;
  // The files written on a saved frame: name in the frame's image folder, the file's bytes
  // (PNG or EXR as encoded when computed; written back as they are).
  std::vector<std::pair<std::string, std::string>> images;
};

struct MemoEntry {
  std::vector<MemoFrame> frames;
};

class MethodMemo {
 public:
  explicit MethodMemo(const ReferenceCacheSettings& s);

  // The key text of method entry `method` (its resolved JSON) of a cell whose other inputs are
  // `cell_base` (everything else the key holds, see above).
  static std::string key(const Json& cell_base, const Json& method);
  // The stored sequence, verified: its frames are `frames` ((index, recorded) in evaluation
  // order) and every counter name is known; nullopt otherwise.
  std::optional<MemoEntry> load(const std::string& key,
                                const std::vector<std::pair<int, bool>>& frames);
  void store(const std::string& key, const MemoEntry& e);

  // manifest.json "method_memo": the cache's statistics for this kind.
  Json manifest() const;
  const DiskCache& disk() const { return disk_; }
  std::vector<std::string> warnings() const;

 private:
  DiskCache disk_;
  double max_gb_;
};

}  // namespace fovsim
