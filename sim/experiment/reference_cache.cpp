#include "sim/experiment/reference_cache.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/core/error.h"
#include "sim/core/version.h"
#include "sim/experiment/run_config.h"
#include "sim/scene/scene_hash.h"

namespace fovsim {

namespace {

// Exact text of a double (C99 hex float): keys compare bits, not rounded decimals.
std::string exact(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%a", v);
  return b;
}

Json exact3(const glm::dvec3& v) {
  return Json::array({exact(v.x), exact(v.y), exact(v.z)});
}

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

}  // namespace

// The keys and their checks: cache_block_table() (run_config.cpp).
ReferenceCacheSettings ReferenceCacheSettings::from_params(Params& p) {
  return cache_block_table().read(p);
}

void ReferenceCacheSettings::resolve_cap() {
  if (dir.empty()) dir = default_cache_dir();
  if (max_gb > 0 || dir.empty()) return;
  max_gb = std::max(default_cache_cap_gb(dir), 1e-6);
  cap_auto = true;
}

namespace {
ReferenceCacheSettings resolved(ReferenceCacheSettings s) {
  s.resolve_cap();  // a no-op when the engine resolved it (open_reference_cache)
  return s;
}
}  // namespace

ReferenceCache::ReferenceCache(const ReferenceCacheSettings& s, const Scene& scene,
                               const Json& scene_config, const Display& sim_display,
                               const RenderSettings& rs)
    : max_gb_(resolved(s).max_gb),
      cap_auto_(s.cap_auto || s.max_gb <= 0),
      disk_(s.dir.empty() ? default_cache_dir() : s.dir, "references",
            uint64_t(std::min(max_gb_ * kGiB, 9.0e18))) {
  disk_.share_cap_with({"methods"});  // the method memo's entries (method_memo.h) count too
  char h[20];
  std::snprintf(h, sizeof h, "%016llx", static_cast<unsigned long long>(scene_content_hash(scene)));
  base_ = Json{{"what", "fovsim shared frame reference v1"},
               {"code",
                {{"version", version_string()},
                 {"git_commit", git_commit()},
                 {"binary", code_fingerprint()}}},
               {"scene", {{"config", scene_config}, {"content", h}}},
               {"camera",
                {{"width", sim_display.width},
                 {"height", sim_display.height},
                 {"tan_half_h", exact(sim_display.tan_half_h())},
                 {"tan_half_v", exact(sim_display.tan_half_v())}}},
               {"render", {{"spp", rs.spp}, {"shadows", rs.shadows}, {"tile", rs.tile}}}};
}

std::string ReferenceCache::key(int frame, const TraceSample& s, const Camera& cam) const {
  Json k = base_;
  k["frame"] = {{"index", frame},
                {"t", exact(s.t)},
                {"position", exact3(cam.position)},
                {"orientation", Json::array({exact(cam.orientation.w), exact(cam.orientation.x),
                                             exact(cam.orientation.y), exact(cam.orientation.z)})},
                {"gaze_dir", exact3(s.gaze_dir)},
                {"gaze_valid", s.valid}};
  return k.dump();
}

bool ReferenceCache::load(const std::string& key, int width, int height, FrameReference& out) {
  std::optional<CacheItem> item = disk_.get(key);
  if (!item) return false;
  const size_t n = size_t(width) * size_t(height) * 3;
  std::vector<float>* ref = item->array("reference");
  std::vector<float>* dir = item->array("direct");
  std::vector<float>* ind = item->array("all_indirect");
  const Json& c = item->meta.contains("counters") ? item->meta["counters"] : Json();
  // Sizes follow from the key (the camera); checked anyway, so a wrong entry is a miss.
  auto fits = [&](const std::vector<float>* v) { return !v || v->empty() || v->size() == n; };
  if (!ref || ref->size() != n || !fits(dir) || !fits(ind) || !c.is_array()) return false;
  auto image = [&](std::vector<float>* v, Image& im) {
    if (!v || v->empty()) {
      im = Image();
      return;
    }
    im.width = width;
    im.height = height;
    im.channels = 3;
    im.data = std::move(*v);
  };
  image(ref, out.reference);
  image(dir, out.direct);
  image(ind, out.all_indirect);
  out.counters.clear();
  for (auto& kv : c) {
    if (!kv.is_array() || kv.size() != 2 || !kv[0].is_string() || !kv[1].is_string()) return false;
    // Stored as exact hex text: the counters come back bit for bit.
    // A name no counter has any more (an entry of an older build) makes the entry a miss.
    if (!out.counters.set_named(kv[0].get<std::string>(),
                                std::strtod(kv[1].get<std::string>().c_str(), nullptr)))
      return false;
  }
  ++from_cache_;
  return true;
}

void ReferenceCache::store(const std::string& key, const FrameData& fd) {
  ++computed_;
  FrameReference f = frame_reference_of(fd);
  CacheItem item;
  Json counters = Json::array();
  for (auto& [k, v] : f.counters.items()) counters.push_back(Json::array({k, exact(v)}));
  item.meta["counters"] = counters;
  item.arrays.emplace_back("reference", std::move(f.reference.data));
  item.arrays.emplace_back("direct", std::move(f.direct.data));
  item.arrays.emplace_back("all_indirect", std::move(f.all_indirect.data));
  disk_.put(key, item);
}

Json ReferenceCache::manifest() const {
  Json j{{"dir", disk_.dir()},
         {"max_gb", max_gb_},
         {"max_gb_auto", cap_auto_},
         {"frames_from_cache", from_cache_},
         {"frames_computed", computed_}};
  const Json st = disk_.stats().to_json();
  for (auto it = st.begin(); it != st.end(); ++it) j[it.key()] = it.value();
  return j;
}

std::vector<std::string> ReferenceCache::warnings() const {
  std::vector<std::string> w;
  for (auto& s : disk_.warnings()) w.push_back("reference cache: " + s);
  if (disk_.warnings_dropped() > 0)
    w.push_back("reference cache: " + std::to_string(disk_.warnings_dropped()) +
                " more warnings like these");
  return w;
}

}  // namespace fovsim
