#include "sim/experiment/fidelity.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/stats.h"
#include "sim/core/version.h"
#include "sim/cost/analytic.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/workload.h"
#include "sim/display/display.h"
#include "sim/experiment/intervals.h"
#include "sim/experiment/runner.h"
#include "sim/experiment/sweep_runner.h"
#include "sim/experiment/sweep_spec.h"
#include "sim/metrics/registry.h"
#include "sim/render/renderer.h"
#include "sim/scene/scene.h"

namespace fovsim {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

std::string trim(const std::string& s) {
  size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// One rung from its token ("analytic" or overrides separated by ',').
FidelityRung parse_rung(const std::string& token, const std::string& flag) {
  FidelityRung r;
  r.name = trim(token);
  const std::string where = flag + " " + (r.name.empty() ? "\"\"" : r.name);
  if (r.name.empty())
    throw Error(where,
                "empty rung (rungs are separated by ';', e.g. analytic;scale=0.25;stride=2)");
  if (r.name == "analytic") {
    r.analytic = true;
    return r;
  }
  std::set<std::string> knobs;
  for (auto& part : split(r.name, ',')) {
    std::string p = trim(part);
    size_t eq = p.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 >= p.size())
      throw Error(where, "expected analytic, scale=X, stride=N, spp=N or key.path=value, got \"" +
                             p + "\"");
    std::string key = p.substr(0, eq), val = p.substr(eq + 1);
    // Each knob once per rung ("scale" and "render.scale" are one knob): a repeat would
    // silently keep only the last value.
    const std::string knob = key == "scale" ? "render.scale" : key == "spp" ? "render.spp" : key;
    if (!knobs.insert(knob).second)
      throw Error(where, "\"" + knob + "\" is given twice in one rung (each knob once)");
    auto number = [&](double lo, double hi, bool integer) {
      char* end = nullptr;
      double v = std::strtod(val.c_str(), &end);
      if (end == val.c_str() || *end != 0 || !std::isfinite(v) || v <= lo || v > hi ||
          (integer && v != std::floor(v)))
        throw Error(where, key + " must be " + (integer ? "an integer" : "a number") + " in (" +
                               format_number(lo) + ", " + format_number(hi) + "], got \"" + val +
                               "\"");
      return v;
    };
    if (key == "scale") {
      number(0, 4, false);
      r.overrides.push_back("render.scale=" + val);
    } else if (key == "stride") {
      r.stride = int(number(0, 1e6, true));
    } else if (key == "spp") {
      number(0, 1e6, true);
      r.overrides.push_back("render.spp=" + val);
      if (!render_spp_known())
        r.skipped = "render.spp is not a key of this build's render settings";
    } else if (key.find('.') != std::string::npos || key.find('[') != std::string::npos ||
               key == "seed" || key == "workload") {
      r.overrides.push_back(p);  // a raw override, checked when the rung's config is loaded
    } else {
      throw Error(where, "unknown knob \"" + key +
                             "\" (scale, stride, spp, or a config key.path such as render.scale)");
    }
  }
  return r;
}

double num_or_nan(const ResultRow& r, const std::string& k) {
  return r.get(k, NAN);
}

std::map<std::string, const ResultRow*> by_config(const ResultTable& t) {
  std::map<std::string, const ResultRow*> m;
  for (auto& r : t.rows()) {
    const std::string* id = r.text_of("config_id");
    if (id) m[*id] = &r;
  }
  return m;
}

// Per config_id: value of `col` by frame index.
std::map<std::string, std::map<double, double>> per_frame(const ResultTable& frames,
                                                          const std::string& col) {
  std::map<std::string, std::map<double, double>> m;
  for (auto& r : frames.rows()) {
    const std::string* id = r.text_of("config_id");
    if (id) m[*id][r.get("frame", NAN)] = r.get(col, NAN);
  }
  return m;
}

// Config ids of one GPU ordered by `output` (descending mean, ties by id).
std::map<std::string, std::vector<std::string>> rankings(const ResultTable& t,
                                                         const std::string& output) {
  std::map<std::string, std::vector<std::pair<double, std::string>>> g;
  for (auto& r : t.rows()) {
    const std::string* id = r.text_of("config_id");
    const std::string* gpu = r.text_of("gpu");
    const std::string* cell = r.text_of("cell");  // a sweep: methods are ranked within a cell
    double v = r.get(output, NAN);
    if (!id || !std::isfinite(v)) continue;
    g[(gpu ? *gpu : "") + (cell ? "|" + *cell : "")].push_back({v, *id});
  }
  std::map<std::string, std::vector<std::string>> out;
  for (auto& [gpu, v] : g) {
    std::sort(v.begin(), v.end(), [](auto& a, auto& b) {
      return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    for (auto& [x, id] : v) out[gpu].push_back(id);
  }
  return out;
}

// Pairs (a above b) ranked by the truth whose paired interval (over the truth's frames) excludes
// zero, that `rung` ranks the other way round (among configs finite in both).
int resolved_swaps(const ResultTable& rung, const ResultTable& top, const ResultTable& top_frames,
                   const std::string& output) {
  auto rr = rankings(rung, output), tr = rankings(top, output);
  auto pf = per_frame(top_frames, output);
  int swaps = 0;
  for (auto& [gpu, order] : tr) {
    std::map<std::string, size_t> pos;
    for (size_t i = 0; i < rr[gpu].size(); ++i) pos[rr[gpu][i]] = i;
    for (size_t i = 0; i < order.size(); ++i)
      for (size_t j = i + 1; j < order.size(); ++j) {
        if (!pos.count(order[i]) || !pos.count(order[j])) continue;
        if (pos[order[i]] < pos[order[j]]) continue;  // same order
        std::vector<double> d;
        for (auto& [f, a] : pf[order[i]]) {
          auto it = pf[order[j]].find(f);
          if (it != pf[order[j]].end() && std::isfinite(a) && std::isfinite(it->second))
            d.push_back(a - it->second);
        }
        MeanInterval ci = batch_means_interval(d);
        if (std::isfinite(ci.half_width) && std::fabs(ci.mean) > ci.half_width) ++swaps;
      }
  }
  return swaps;
}

Display config_display(const Json& doc, const std::string& file, const std::string& models) {
  if (doc.contains("display") && doc["display"].is_object()) {
    Params dp(doc["display"], file, "display");
    return Display::from_params(dp);
  }
  std::string name = doc.contains("display") && doc["display"].is_string()
                         ? doc["display"].get<std::string>()
                         : "htc_vive_pro_eye";
  return Display::load(name, models);
}

// User + system CPU time of this process (all threads): on a machine shared with other jobs a
// rung's CPU time is a steadier measure of its cost than its wall time.
double cpu_seconds() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

std::string fmt(const char* f, double v) {
  if (std::isnan(v)) return "-";
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace

bool render_spp_known() {
  Params p(Json{{"spp", 1}}, "", "render");
  try {
    (void)RenderSettings::from_params(p);
    p.finish();
  } catch (const Error&) {
    return false;
  }
  return true;
}

const std::vector<std::string>& fidelity_outputs() {
  static const std::vector<std::string> o = [] {
    std::vector<std::string> v = {"est_ms_total", "est_ms_total_p95", "shaded_fraction"};
    for (auto& n : headline_metric_names()) v.push_back(n);  // the metric registry
    return v;
  }();
  return o;
}

std::vector<FidelityRung> parse_rungs(const std::string& rungs, const std::string& top) {
  std::vector<FidelityRung> out;
  if (trim(rungs).empty()) throw Error("--rungs", "no rungs given (e.g. analytic;scale=0.25)");
  std::set<std::string> names;
  for (auto& tok : split(rungs, ';')) {
    FidelityRung r = parse_rung(tok, "--rungs");
    if (!names.insert(r.name).second) throw Error("--rungs " + r.name, "rung given twice");
    out.push_back(std::move(r));
  }
  if (top.find(';') != std::string::npos)
    throw Error("--top " + top, "the top rung is one rung (overrides separated by ',')");
  FidelityRung t = parse_rung(top, "--top");
  if (t.analytic) throw Error("--top analytic", "the top rung (the truth) must render");
  if (!t.skipped.empty()) throw Error("--top " + t.name, t.skipped);
  t.top = true;
  if (names.count(t.name))
    throw Error("--rungs " + t.name, "equals the top rung (--top), which always runs");
  out.push_back(std::move(t));
  return out;
}

ResultTable analytic_summary(const LoadedConfig& cfg, const std::string& models_dir,
                             std::vector<std::string>* notes) {
  const std::string models = models_dir.empty() ? default_models_dir() : models_dir;
  const Json& doc = cfg.doc;
  Display d = config_display(doc, cfg.file, models);
  Json sj = doc.contains("scene") ? doc["scene"] : Json::object();
  Params sp(sj, cfg.file, "scene");
  Scene scene = make_scene(sp, models);
  const SceneFeatures f = scene.features();
  Workload w = Workload::load(doc.contains("workload") && doc["workload"].is_string()
                                  ? doc["workload"].get<std::string>()
                                  : "generic",
                              models);
  // analytic_counters sees only the workload: what it leaves to the scene (-1: triangles,
  // lights) is resolved from this scene's features, as the cost model does for a rendered run.
  if (w.triangles < 0) w.triangles = double(f.triangles);
  if (w.lights < 0) w.lights = double(f.lights);
  if (w.shadowed_lights < 0) w.shadowed_lights = double(f.shadowed_lights);
  if (f.indirect) w.rsm_res = scene.vpl.rsm_size;  // the scene's VPL set (scene.vpl)
  std::vector<std::string> gnames;
  if (doc.contains("gpus") && doc["gpus"].is_array())
    for (auto& g : doc["gpus"]) gnames.push_back(g.get<std::string>());
  if (gnames.empty()) gnames.push_back("gtx1080");
  std::vector<GpuProfile> gpus;
  for (auto& g : gnames) gpus.push_back(GpuProfile::load(g, models));
  ResultTable t;
  if (!doc.contains("methods") || !doc["methods"].is_array()) return t;
  const Json& ms = doc["methods"];
  for (size_t i = 0; i < ms.size(); ++i) {
    Json params = ms[i];
    std::string method = params.value("method", "");
    std::string label = params.value("label", method);
    params.erase("method");
    params.erase("label");
    Counters c;
    try {
      c = analytic_counters(method, params, w, d, "methods[" + std::to_string(i) + "]", f.indirect);
    } catch (const Error& e) {
      if (notes) notes->push_back("analytic: " + label + " left out (" + e.what() + ")");
      continue;
    }
    for (auto& g : gpus) {
      CostInputs in;
      in.method = method;
      in.counters = &c;
      in.features = f;
      in.display = d;
      in.workload = &w;
      FrameCost fc = estimate_frame(g, in);
      ResultRow r;
      r.set_text("config_id", gpus.size() > 1 ? label + "@" + g.name : label);
      r.set_text("method", method);
      r.set_text("label", label);
      r.set_text("gpu", g.name);
      r.set("frames", 1);
      double shaded = c.get("shaded_samples");
      r.set("shaded_samples", shaded);
      r.set("shaded_fraction", shaded / (double(d.width) * d.height));
      r.set("prims_submitted", c.get("prims_submitted", double(f.triangles)));
      r.set("prims_culled", c.get("prims_culled", 0.0));
      for (auto& [cn, cv] : c.items())
        if (cn != "shaded_samples" && cn != "prims_submitted" && cn != "prims_culled")
          r.set(cn, cv);
      r.set("est_ms_total", fc.total_ms);
      r.set("est_ms_total_p95", fc.total_ms);
      for (auto& pc : fc.passes) r.set("est_ms_" + pc.pass, pc.ms);
      t.add(std::move(r));
    }
  }
  return t;
}

ResultTable compare_to_truth(const std::string& rung, const ResultTable& rung_summary,
                             const ResultTable& top_summary,
                             const std::vector<std::string>& outputs,
                             const ResultTable* rung_frames, const ResultTable* top_frames) {
  ResultTable out;
  auto rm = by_config(rung_summary);
  std::vector<std::string> cols = outputs;
  if (cols.empty()) {
    auto tc = top_summary.numeric_columns();
    std::set<std::string> present(tc.begin(), tc.end());
    for (auto& o : fidelity_outputs())
      if (present.count(o)) cols.push_back(o);
  }
  for (auto& trow : top_summary.rows()) {
    const std::string* id = trow.text_of("config_id");
    if (!id || !rm.count(*id)) continue;
    const ResultRow& rrow = *rm[*id];
    for (auto& o : cols) {
      double tv = num_or_nan(trow, o), rv = num_or_nan(rrow, o);
      // Exact in both (PSNR of `full`: +inf): no error.
      double err = (std::isinf(tv) && tv == rv) ? 0.0 : rv - tv;
      double ht = num_or_nan(trow, o + "_ci95"), hr = num_or_nan(rrow, o + "_ci95");
      double ci = std::sqrt(ht * ht + hr * hr);
      if (std::isinf(tv) && tv == rv) ci = 0;
      double paired = NAN;
      if (rung_frames && top_frames) {
        auto a = per_frame(*rung_frames, o), b = per_frame(*top_frames, o);
        auto &fa = a[*id], &fb = b[*id];
        bool same = !fa.empty() && fa.size() == fb.size();
        std::vector<double> d;
        for (auto& [fr, v] : fa) {
          auto it = fb.find(fr);
          if (it == fb.end()) {
            same = false;
            break;
          }
          if (std::isfinite(v) && std::isfinite(it->second)) d.push_back(v - it->second);
        }
        if (same && !d.empty()) paired = batch_means_interval(d).half_width;
      }
      ResultRow r;
      r.set_text("rung", rung);
      r.set_text("config_id", *id);
      const std::string* m = trow.text_of("method");
      r.set_text("method", m ? *m : "");
      r.set_text("output", o);
      r.set("top", tv);
      r.set("value", rv);
      r.set("err", err);
      r.set("err_rel", std::fabs(tv) > 0 && std::isfinite(tv) ? err / std::fabs(tv) : NAN);
      r.set("err_ci95", ci);
      r.set("err_ci95_paired", paired);
      out.add(std::move(r));
    }
  }
  return out;
}

bool same_ranking(const ResultTable& a, const ResultTable& b, const std::string& output) {
  auto ra = rankings(a, output), rb = rankings(b, output);
  // Compare only configs finite in both (e.g. the analytic rung has no PSNR at all).
  for (auto& [gpu, oa] : ra) {
    std::set<std::string> in_b(rb[gpu].begin(), rb[gpu].end());
    std::set<std::string> in_a(oa.begin(), oa.end());
    std::vector<std::string> x, y;
    for (auto& id : oa)
      if (in_b.count(id)) x.push_back(id);
    for (auto& id : rb[gpu])
      if (in_a.count(id)) y.push_back(id);
    if (x != y) return false;
  }
  return true;
}

FidelityResult run_fidelity(const LoadedConfig& cfg, const FidelityOptions& opt) {
  using Clock = std::chrono::steady_clock;
  std::vector<FidelityRung> rungs = parse_rungs(opt.rungs, opt.top);
  FidelityResult res;
  std::string name = cfg.doc.contains("name") && cfg.doc["name"].is_string()
                         ? cfg.doc["name"].get<std::string>()
                         : fs::path(cfg.file).stem().string();
  res.out_dir = opt.out_dir.empty() ? "results/" + safe_file_name(name) + "_fidelity" : opt.out_dir;
  fs::create_directories(res.out_dir + "/rungs");

  // The top rung's config; every other rung's overrides apply on top of it.
  LoadedConfig top_cfg = cfg;
  for (auto& o : rungs.back().overrides) apply_override(top_cfg.doc, o);
  auto rung_cfg = [&](const FidelityRung& r) {
    LoadedConfig c = top_cfg;
    for (auto& o : r.overrides) apply_override(c.doc, o);
    if (r.stride > 1) {  // the same span of the trace, every N-th frame
      const Json fr = c.doc.contains("frames") ? c.doc["frames"] : Json::object();
      long stride =
          fr.contains("stride") && fr["stride"].is_number_integer() ? fr["stride"].get<long>() : 1;
      long count =
          fr.contains("count") && fr["count"].is_number_integer() ? fr["count"].get<long>() : 0;
      c.doc["frames"]["stride"] = stride * r.stride;
      if (count > 0) c.doc["frames"]["count"] = (count + r.stride - 1) / r.stride;
    }
    // The ladder measures the simulation, not image writing.
    c.doc["outputs"]["image_frames"] = Json::array();
    return c;
  };

  // A sweep config: every rung runs the whole sweep (shared references, sweep_runner.h); rows
  // are per cell x config, config_id "<cell index>/<config_id>".
  const bool is_sweep = cfg.doc.contains("sweep");
  auto prefixed = [](const ResultTable& t, int cell) {
    ResultTable out;
    for (auto& r : t.rows()) {
      ResultRow x;
      for (auto& [k, v] : r.text)
        x.set_text(k, k == "config_id" ? std::to_string(cell) + "/" + v : v);
      x.set_text("cell", std::to_string(cell));
      for (auto& [k, v] : r.num) x.set(k, v);
      out.add(std::move(x));
    }
    return out;
  };
  auto append = [](ResultTable& dst, const ResultTable& src) {
    for (auto& r : src.rows()) dst.add(r);
  };

  // Every rung's overrides are applied once before anything runs: a bad path fails at once,
  // not after the top rung's minutes. (Unknown keys are found when the rung's config is read.)
  for (auto& r : rungs)
    if (!r.analytic && r.skipped.empty()) (void)rung_cfg(r);

  struct Done {
    const FidelityRung* rung;
    double wall_s = NAN, cpu_s = NAN;
    std::string dir;
    ResultTable summary, frames;
    Json resolved;
  };
  std::vector<Done> done;
  // The truth first (its wall time is the unit), then the rungs in the given order.
  std::vector<size_t> order{rungs.size() - 1};
  for (size_t i = 0; i + 1 < rungs.size(); ++i) order.push_back(i);
  std::map<size_t, size_t> slot;
  for (size_t i : order) {
    const FidelityRung& r = rungs[i];
    Done d;
    d.rung = &r;
    if (!r.skipped.empty()) {
      res.notes.push_back("rung " + r.name + " skipped: " + r.skipped);
      slot[i] = done.size();
      done.push_back(std::move(d));
      continue;
    }
    if (opt.progress) {
      std::printf("fidelity: rung %s%s ...\n", r.name.c_str(), r.top ? " (top, the truth)" : "");
      std::fflush(stdout);
    }
    auto t0 = Clock::now();
    const double c0 = cpu_seconds();
    if (r.analytic && is_sweep) {
      std::vector<std::string> notes;
      SweepPlan plan = expand_sweep(top_cfg);
      for (auto& cell : plan.cells) {
        LoadedConfig cc = top_cfg;
        cc.doc = cell.doc;
        append(d.summary, prefixed(analytic_summary(cc, opt.models_dir, &notes), cell.index));
      }
      for (auto& n : notes) res.notes.push_back(n);
    } else if (r.analytic) {
      std::vector<std::string> notes;
      d.summary = analytic_summary(top_cfg, opt.models_dir, &notes);
      for (auto& n : notes) res.notes.push_back(n);
    } else if (is_sweep) {
      LoadedConfig rc = rung_cfg(r);
      SweepPlan plan = expand_sweep(rc);
      validate_cells(plan);
      SweepOptions so;
      so.out_dir = res.out_dir + "/rungs/" + std::to_string(i) + "-" + safe_file_name(r.name);
      so.models_dir = opt.models_dir;
      so.threads = opt.threads;
      so.watchdog_s = opt.watchdog_s;
      so.command_line = opt.command_line + " [rung " + r.name + "]";
      run_sweep(plan, rc, so);
      d.dir = so.out_dir;
      for (auto& cell : plan.cells) {
        std::string cd = so.out_dir + "/runs/" + cell.id();
        append(d.summary, prefixed(read_cell_summary(cd), cell.index));
      }
      d.resolved = top_cfg.doc;
    } else {
      RunOptions ro;
      ro.out_dir = res.out_dir + "/rungs/" + std::to_string(i) + "-" + safe_file_name(r.name);
      ro.models_dir = opt.models_dir;
      ro.threads = opt.threads;
      ro.print_summary = false;
      ro.watchdog_s = opt.watchdog_s;
      ro.command_line = opt.command_line + " [rung " + r.name + "]";
      RunResult rr = run_experiment(rung_cfg(r), ro);
      d.dir = rr.out_dir;
      d.summary = std::move(rr.summary);
      d.frames = std::move(rr.frames);
      try {
        d.resolved = Json::parse(read_file(rr.out_dir + "/manifest.json"))["resolved_config"];
      } catch (const std::exception&) {
        d.resolved = nullptr;
      }
    }
    d.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
    d.cpu_s = cpu_seconds() - c0;
    slot[i] = done.size();
    done.push_back(std::move(d));
  }
  const Done& top = done[slot[rungs.size() - 1]];

  // ---- comparison ----
  ResultTable table;
  Json jr = Json::array();
  std::string md;
  auto cols = top.summary.numeric_columns();
  std::set<std::string> present(cols.begin(), cols.end());
  std::vector<std::string> outs;
  for (auto& o : fidelity_outputs())
    if (present.count(o)) outs.push_back(o);
  md +=
      "| rung | wall s | x top | CPU s | x top | frame time err % (max) | p95 err % (max) | "
      "shaded err (max) |";
  for (auto& o : outs)
    if (o != "est_ms_total" && o != "est_ms_total_p95" && o != "shaded_fraction")
      md += " " + o + " err (max) |";
  md +=
      " ranking kept | within 0.2 dB, 2% / and <= 1/4 wall / <= 1/4 CPU "
      "|\n|---|---:|---:|---:|---:|---:|---:|---:|";
  for (auto& o : outs)
    if (o != "est_ms_total" && o != "est_ms_total_p95" && o != "shaded_fraction") md += "---:|";
  md += "---|---|\n";
  for (size_t ri = 0; ri < rungs.size(); ++ri) {
    const Done& d = done[slot[ri]];
    const FidelityRung& r = rungs[ri];
    Json rj{{"index", ri},  {"name", r.name},           {"analytic", r.analytic},
            {"top", r.top}, {"overrides", r.overrides}, {"stride_factor", r.stride}};
    if (!r.skipped.empty()) {
      rj["skipped"] = r.skipped;
      jr.push_back(rj);
      md += "| " + r.name + " | skipped: " + r.skipped + " |\n";
      continue;
    }
    double ratio = top.wall_s > 0 ? d.wall_s / top.wall_s : NAN;
    double cpu_ratio = top.cpu_s > 0 ? d.cpu_s / top.cpu_s : NAN;
    // Analytic (issue 13 item 4): also every pass estimate and the counters frames.csv holds
    // at the display's resolution (shaded samples, primitives, VPLs). The other pixel counters
    // of frames.csv are at the simulated resolution, so they are not compared.
    std::vector<std::string> o_here = outs;
    if (r.analytic) {
      o_here.clear();
      for (auto& c : d.summary.numeric_columns())
        if (present.count(c) && (std::find(outs.begin(), outs.end(), c) != outs.end() ||
                                 c.rfind("est_ms_", 0) == 0 || c == "shaded_samples" ||
                                 c == "prims_submitted" || c == "prims_culled" || c == "vpls_kept"))
          o_here.push_back(c);
    }
    ResultTable cmp = compare_to_truth(r.name, d.summary, top.summary, o_here,
                                       r.analytic ? nullptr : &d.frames, &top.frames);
    std::map<std::string, double> max_abs, max_rel;
    std::map<std::string, bool> rank_same;
    std::map<std::string, int> swaps;
    for (auto& o : o_here) {
      rank_same[o] = same_ranking(d.summary, top.summary, o);
      swaps[o] = resolved_swaps(d.summary, top.summary, top.frames, o);
    }
    for (auto& row : cmp.rows()) {
      ResultRow x;
      x.set("rung_index", double(ri));
      for (auto& [k, v] : row.text) x.set_text(k, v);
      const std::string& o = *row.text_of("output");
      x.set("wall_s", d.wall_s);
      x.set("wall_ratio", ratio);
      x.set("cpu_s", d.cpu_s);
      x.set("cpu_ratio", cpu_ratio);
      x.set("frames", done[slot[ri]].summary.rows().empty()
                          ? NAN
                          : done[slot[ri]].summary.rows().front().get("frames", NAN));
      for (auto& [k, v] : row.num) x.set(k, v);
      if (r.top) x.set("err_ci95", 0.0);  // the truth against itself: no uncertainty
      x.set("ranking_same", rank_same[o] ? 1 : 0);
      x.set("ranking_resolved_swaps", swaps[o]);
      double e = row.get("err", NAN), rel = row.get("err_rel", NAN);
      if (std::isfinite(e))
        max_abs[o] = std::max(max_abs.count(o) ? max_abs[o] : 0.0, std::fabs(e));
      if (std::isfinite(rel))
        max_rel[o] = std::max(max_rel.count(o) ? max_rel[o] : 0.0, std::fabs(rel));
      table.add(std::move(x));
    }
    bool rank_all = true;
    int swaps_all = 0;
    for (auto& o : outs)
      if (rank_same.count(o)) {
        rank_all = rank_all && rank_same[o];
        swaps_all += swaps[o];
      }
    // The issue's test (docs/fidelity.md): PSNR and FPSNR within 0.2 dB, mean and p95 frame time
    // within 2%, at <= 1/4 of the top rung's wall time. SSIM and FLIP are reported, not tested
    // (no dB scale).
    auto within = [&](const std::string& o, double lim, bool rel) {
      if (!present.count(o)) return true;
      auto& m = rel ? max_rel : max_abs;
      return m.count(o) && m[o] <= lim;
    };
    const bool errors_ok = !r.top && within("psnr", 0.2, false) && within("fpsnr", 0.2, false) &&
                           within("est_ms_total", 0.02, true) &&
                           within("est_ms_total_p95", 0.02, true);
    const bool good = errors_ok && ratio <= 0.25;
    // On a machine shared with other jobs the wall-time ratio is noisy; CPU time is reported
    // beside it (docs/fidelity.md).
    const bool good_cpu = errors_ok && cpu_ratio <= 0.25;
    auto mx = [](std::map<std::string, double>& m, const std::string& o) {
      return m.count(o) ? m[o] : NAN;
    };
    Json errs = Json::object();
    for (auto& o : o_here) {
      auto jn = [](double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); };
      errs[o] = {{"max_abs_err", jn(mx(max_abs, o))},
                 {"max_rel_err", jn(mx(max_rel, o))},
                 {"ranking_same", rank_same[o]},
                 {"ranking_resolved_swaps", swaps[o]}};
    }
    rj["wall_s"] = d.wall_s;
    rj["wall_ratio"] = ratio;
    rj["cpu_s"] = d.cpu_s;
    rj["cpu_ratio"] = cpu_ratio;
    rj["out_dir"] = d.dir;
    rj["outputs"] = errs;
    rj["ranking_same_all_outputs"] = rank_all;
    rj["ranking_resolved_swaps"] = swaps_all;
    rj["within_0p2dB_2pct"] = errors_ok;
    rj["within_0p2dB_2pct_quarter_time"] = good;
    rj["within_0p2dB_2pct_quarter_cpu"] = good_cpu;
    jr.push_back(rj);
    if (good || good_cpu)
      res.notes.push_back("rung " + r.name +
                          " keeps PSNR/FPSNR within 0.2 dB and frame time within 2% at " +
                          fmt("%.3f", ratio) + " of the top rung's wall time, " +
                          fmt("%.3f", cpu_ratio) + " of its CPU time");
    md += "| " + r.name + (r.top ? " (top)" : "") + " | " + fmt("%.1f", d.wall_s) + " | " +
          fmt("%.3f", ratio) + " | " + fmt("%.1f", d.cpu_s) + " | " + fmt("%.3f", cpu_ratio) +
          " | " + fmt("%.2f", 100 * mx(max_rel, "est_ms_total")) + " | " +
          fmt("%.2f", 100 * mx(max_rel, "est_ms_total_p95")) + " | " +
          fmt("%.4f", mx(max_abs, "shaded_fraction")) + " |";
    for (auto& o : outs)
      if (o != "est_ms_total" && o != "est_ms_total_p95" && o != "shaded_fraction")
        md +=
            " " +
            fmt(find_metric(o) && find_metric(o)->unit == "dB" ? "%.3f" : "%.4f", mx(max_abs, o)) +
            " |";
    md += std::string(" ") + (rank_all ? "yes" : "no") +
          (swaps_all ? " (" + std::to_string(swaps_all) + " resolved swaps)" : "") + " | " +
          (r.top ? "-"
                 : std::string(errors_ok ? "yes" : "no") + " / " + (good ? "yes" : "no") + " / " +
                       (good_cpu ? "yes" : "no")) +
          " |\n";
  }
  res.table = std::move(table);
  res.markdown = md;
  if (std::none_of(jr.begin(), jr.end(), [](const Json& j) {
        return j.value("within_0p2dB_2pct_quarter_time", false) ||
               j.value("within_0p2dB_2pct_quarter_cpu", false);
      }))
    res.notes.push_back(
        "no cheaper rung keeps PSNR/FPSNR within 0.2 dB and frame time within 2% at <= 1/4 of "
        "the top rung's wall or CPU time");

  Json rows = Json::array();
  for (auto& r : res.table.rows()) {
    Json o;
    for (auto& [k, v] : r.text) o[k] = v;
    for (auto& [k, v] : r.num) o[k] = std::isfinite(v) ? Json(v) : Json(format_number(v));
    rows.push_back(o);
  }
  res.json = Json{{"name", name},
                  {"version", version_string()},
                  {"git_commit", git_commit()},
                  {"command_line", opt.command_line},
                  {"config_file", cfg.file},
                  {"top", rungs.back().name},
                  {"resolved_config", top.resolved},
                  {"rungs", jr},
                  {"notes", res.notes},
                  {"rows", rows}};
  write_file_atomic(res.out_dir + "/fidelity.csv", res.table.to_csv());
  write_file_atomic(res.out_dir + "/fidelity.json", res.json.dump(2) + "\n");
  write_file_atomic(res.out_dir + "/fidelity.md", res.markdown);
  return res;
}

}  // namespace fovsim
