#include "sim/experiment/cell_memo.h"

#include <algorithm>
#include <filesystem>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/hash.h"
#include "sim/experiment/cell.h"
#include "sim/experiment/reference_cache.h"

namespace fovsim {

namespace fs = std::filesystem;

void Cell::memo_images(const FrameIn& in) {
  if (!images.memo_files.empty()) make_dirs(in.img_dir);
  for (auto& [path, bytes] : images.memo_files) write_file_atomic(path, *bytes);
  images.memo_files.clear();
  for (auto& m : methods)
    if (m.memo.rec && !m.memo.rec->frames.empty() && m.memo.rec->frames.back().fi == in.fi)
      for (auto& [name, bytes] : m.memo.rec->frames.back().images)
        if (bytes.empty()) bytes = read_file(in.img_dir + "/" + name);
}

void Cell::record_frame(const FrameIn& in, MethodRun& m, const Step& st,
                        const MetricValues& metrics, size_t queued) {
  MemoFrame f;
  f.fi = in.fi;
  f.record = in.record;
  f.cost_method = st.cost_method;
  f.sim_ms = st.sim_ms;
  f.counters = m.fo.counters.items();
  f.metrics = metrics.items();
  f.flags = m.fo.flags;
  const size_t dir_len = in.img_dir.size() + 1;
  for (size_t i = queued; i < images.jobs.jobs.size(); ++i)  // read back once written
    f.images.emplace_back(images.jobs.jobs[i].first.substr(dir_len), std::string());
  m.memo.rec->frames.push_back(std::move(f));
}

void Cell::replay_method(const FrameIn& in, size_t mi, FrameContext& ctx) {
  MethodRun& m = methods[mi];
  FOVSIM_CHECK(m.memo.replay_next < m.memo.replay->frames.size() &&
                   m.memo.replay->frames[m.memo.replay_next].fi == in.fi &&
                   m.memo.replay->frames[m.memo.replay_next].record == in.record,
               "method memo of \"" + m.label + "\" is out of step with the frame order");
  const MemoFrame& f = m.memo.replay->frames[m.memo.replay_next++];
  Step st;
  st.lat_ms = gaze->gaze_for(mi, in.fd, ctx);
  st.cost_method = f.cost_method;
  st.sim_ms = f.sim_ms;
  st.impl = m.impl.get();
  if (f.cost_method != m.method)  // rendered as `full` while tracking was lost
    st.impl = &m.tracking.full_method();
  m.fo.counters.clear();
  for (auto& [n, v] : f.counters) m.fo.counters.set_named(n, v);
  m.fo.flags = f.flags;
  MetricValues metrics;
  for (auto& [k, v] : f.metrics) metrics.set(k, v);
  for (auto& fl : m.fo.flags) flags_seen.insert(m.label + ":" + fl);
  latency.note(metrics);
  for (auto& [name, bytes] : f.images)
    images.memo_files.emplace_back(in.img_dir + "/" + name, &bytes);
  build_rows(in, mi, st, ctx, metrics);
}

std::vector<std::pair<int, bool>> memo_frame_list(const Shared& sh) {
  std::vector<std::pair<int, bool>> v;
  for (int k = -sh.warmup; k < sh.count; ++k) v.emplace_back(sh.start + k * sh.stride, k >= 0);
  return v;
}

namespace {

// Hash of every file of the models folder (displays, GPU profiles, workloads, metric data):
// 35 small files, read once per run.
std::string models_hash(const std::string& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec)) files.push_back(it->path());
  std::sort(files.begin(), files.end());
  ContentHasher h;
  for (auto& f : files) {
    h.str(fs::relative(f, dir, ec).string());
    h.str(read_file(f.string()));
  }
  return hex64(h.value());
}

// Everything of cell `c` the key of each of its method entries holds besides the entry itself
// (method_memo.h).
Json memo_cell_base(const Cell& c, const Shared& sh, const ReferenceCache& rc,
                    const std::vector<std::pair<int, bool>>& frames, const std::string& models) {
  const Json& res = c.manifest["resolved_config"];
  auto get = [&](const char* k) { return res.contains(k) ? res[k] : Json(); };
  Json shared = res;
  for (auto& k : per_cell_keys()) shared.erase(k);
  shared.erase("cache");
  shared.erase("run");
  shared.erase("sweep");
  Json outputs = get("outputs");
  if (outputs.is_object()) outputs.erase("print_summary");
  ContentHasher fk;  // every frame's reference key: code, scene content, camera, pose, gaze
  for (auto& f : frames) {
    const TraceSample& s = sh.trace.samples[size_t(f.first)];
    fk.str(rc.key(f.first, s, Camera::from_pose(sh.sim_display, s.head_pos, s.head_rot)));
  }
  ContentHasher th;  // the trace as resampled and as read (latency what-if, tracking loss)
  for (const Trace* t : {&sh.raw_trace, &sh.trace}) {
    th.pod(uint64_t(t->samples.size()));
    for (const TraceSample& s : t->samples) {
      th.pod(s.t).pod(s.head_pos).pod(s.head_rot).pod(s.gaze_dir);
      th.pod(uint8_t(s.valid ? 1 : 0));
    }
  }
  Json fl = Json::array();
  for (auto& f : frames) fl.push_back(Json::array({f.first, f.second}));
  Json j{{"shared", shared},
         {"display", sh.display.to_json()},
         {"models", models},
         {"frames", fl},
         {"frame_keys", hex64(fk.value())},
         {"trace", hex64(th.value())},
         {"metrics", get("metrics")},
         {"latency", get("latency")},
         {"outputs", outputs}};
  if (c.latency.config.render_from_estimate) {  // the gaze follows the first GPU's cost estimate
    j["gpus"] = get("gpus");
    j["workload"] = get("workload");
  }
  return j;
}

}  // namespace

std::unique_ptr<MethodMemo> open_method_memo(const Shared& sh, const ReferenceCache* rc,
                                             std::vector<std::unique_ptr<Cell>>& cells,
                                             bool sampled) {
  if (!rc || sampled) return nullptr;
  auto memo = std::make_unique<MethodMemo>(sh.cache);
  const std::vector<std::pair<int, bool>> frames = memo_frame_list(sh);
  const std::string models = models_hash(sh.models);
  for (auto& c : cells) {
    const Json& ms = c->manifest["resolved_config"]["methods"];
    Json memoised = Json::array();
    if (ms.is_array() && ms.size() == c->methods.size()) {
      const Json base = memo_cell_base(*c, sh, *rc, frames, models);
      for (size_t mi = 0; mi < c->methods.size(); ++mi) {
        MethodRun& m = c->methods[mi];
        m.memo.key = MethodMemo::key(base, ms[mi]);
        m.memo.replay = memo->load(m.memo.key, frames);
        if (m.memo.replay)
          memoised.push_back(m.label);
        else
          m.memo.rec = std::make_unique<MemoEntry>();
      }
    }
    c->manifest["memoised_methods"] = memoised;
  }
  return memo;
}

}  // namespace fovsim
