#include "sim/experiment/method_memo.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "sim/core/counters.h"
#include "sim/experiment/reference_cache.h"

namespace fovsim {

namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

// Exact text of a double (C99 hex float; "nan", "inf" and signs round-trip through strtod).
std::string exact(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%a", v);
  return b;
}

bool parse_exact(const Json& j, double& v) {
  if (!j.is_string()) return false;
  const std::string s = j.get<std::string>();
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end && *end == '\0' && !s.empty();
}

Json pairs_json(const std::vector<std::pair<std::string, double>>& v) {
  Json a = Json::array();
  for (auto& [k, x] : v) a.push_back(Json::array({k, exact(x)}));
  return a;
}

bool pairs_from(const Json& a, std::vector<std::pair<std::string, double>>& out) {
  if (!a.is_array()) return false;
  for (auto& e : a) {
    double v = 0;
    if (!e.is_array() || e.size() != 2 || !e[0].is_string() || !parse_exact(e[1], v)) return false;
    out.emplace_back(e[0].get<std::string>(), v);
  }
  return true;
}

}  // namespace

namespace {
double resolved_cap_gb(ReferenceCacheSettings s) {
  s.resolve_cap();  // a no-op when the engine resolved it (open_reference_cache)
  return s.max_gb;
}
}  // namespace

MethodMemo::MethodMemo(const ReferenceCacheSettings& s)
    : disk_(s.dir.empty() ? default_cache_dir() : s.dir, "methods",
            uint64_t(std::min(resolved_cap_gb(s) * kGiB, 9.0e18))),
      max_gb_(resolved_cap_gb(s)) {
  disk_.share_cap_with({"references"});  // one cap, cache.max_gb, for both kinds
}

std::string MethodMemo::key(const Json& cell_base, const Json& method) {
  Json k = cell_base;
  k["what"] = "fovsim method memo v1";
  k["method"] = method;
  return k.dump();
}

std::optional<MemoEntry> MethodMemo::load(const std::string& key,
                                          const std::vector<std::pair<int, bool>>& frames) {
  std::optional<CacheItem> item = disk_.get(key);
  if (!item) return std::nullopt;
  const Json& fj = item->meta.contains("frames") ? item->meta["frames"] : Json();
  if (!fj.is_array() || fj.size() != frames.size()) return std::nullopt;
  MemoEntry e;
  e.frames.resize(frames.size());
  try {
    for (size_t i = 0; i < frames.size(); ++i) {
      const Json& j = fj[i];
      MemoFrame& f = e.frames[i];
      f.fi = j.at("fi").get<int>();
      f.record = j.at("record").get<bool>();
      if (f.fi != frames[i].first || f.record != frames[i].second) return std::nullopt;
      f.cost_method = j.at("cost_method").get<std::string>();
      if (!parse_exact(j.at("sim_ms"), f.sim_ms)) return std::nullopt;
      if (!pairs_from(j.at("counters"), f.counters) || !pairs_from(j.at("metrics"), f.metrics))
        return std::nullopt;
      Counters probe;  // a counter this build does not know: an entry of another build
      for (auto& [n, v] : f.counters)
        if (!probe.set_named(n, v)) return std::nullopt;
      for (auto& fl : j.at("flags")) f.flags.push_back(fl.get<std::string>());
      for (auto& ij : j.at("images")) {
        const size_t n = ij.at("bytes").get<size_t>();
        std::vector<float>* a = item->array(ij.at("array").get<std::string>());
        if (!a || a->size() != (n + 3) / 4) return std::nullopt;
        std::string bytes(n, '\0');
        if (n > 0) std::memcpy(bytes.data(), a->data(), n);
        f.images.emplace_back(ij.at("name").get<std::string>(), std::move(bytes));
      }
    }
  } catch (const std::exception&) {  // a field missing or of another type: recompute
    return std::nullopt;
  }
  return e;
}

void MethodMemo::store(const std::string& key, const MemoEntry& e) {
  CacheItem item;
  Json frames = Json::array();
  for (const MemoFrame& f : e.frames) {
    Json images = Json::array();
    for (auto& [name, bytes] : f.images) {  // file bytes as float32 words (bits kept)
      const std::string a = "file" + std::to_string(item.arrays.size());
      images.push_back(Json{{"name", name}, {"bytes", bytes.size()}, {"array", a}});
      std::vector<float> words((bytes.size() + 3) / 4, 0.f);
      if (!bytes.empty()) std::memcpy(words.data(), bytes.data(), bytes.size());
      item.arrays.emplace_back(a, std::move(words));
    }
    frames.push_back(Json{{"fi", f.fi},
                          {"record", f.record},
                          {"cost_method", f.cost_method},
                          {"sim_ms", exact(f.sim_ms)},
                          {"counters", pairs_json(f.counters)},
                          {"metrics", pairs_json(f.metrics)},
                          {"flags", f.flags},
                          {"images", images}});
  }
  item.meta["frames"] = frames;
  disk_.put(key, item);
}

Json MethodMemo::manifest() const {
  Json j{{"dir", disk_.dir()}, {"max_gb", max_gb_}};
  const Json st = disk_.stats().to_json();
  for (auto it = st.begin(); it != st.end(); ++it) j[it.key()] = it.value();
  return j;
}

std::vector<std::string> MethodMemo::warnings() const {
  std::vector<std::string> w;
  for (auto& s : disk_.warnings()) w.push_back("method memo: " + s);
  if (disk_.warnings_dropped() > 0)
    w.push_back("method memo: " + std::to_string(disk_.warnings_dropped()) +
                " more warnings like these");
  return w;
}

}  // namespace fovsim
