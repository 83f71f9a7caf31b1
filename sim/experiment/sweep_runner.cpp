#include "sim/experiment/sweep_runner.h"

#include <sys/resource.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <set>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/memory_info.h"
#include "sim/core/message_text.h"
#include "sim/core/progress.h"
#include "sim/core/version.h"
#include "sim/experiment/engine.h"
#include "sim/experiment/intervals.h"
#include "sim/experiment/pareto.h"
#include "sim/trace/csv_table.h"

namespace fovsim {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// User + system CPU time of this process (all threads), ms.
double process_cpu_ms() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto ms = [](const timeval& t) { return double(t.tv_sec) * 1e3 + double(t.tv_usec) * 1e-3; };
  return ms(u.ru_utime) + ms(u.ru_stime);
}

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

Json num_json(double v) {
  return std::isfinite(v) ? Json(v) : Json(format_number(v));
}
double json_num(const Json& j) {
  if (j.is_number()) return j.get<double>();
  if (j.is_string()) {
    std::string s = j.get<std::string>();
    if (s == "inf") return INFINITY;
    if (s == "-inf") return -INFINITY;
  }
  return NAN;
}

Json assign_json(const SweepCell& c) {
  Json a = Json::array();
  for (auto& x : c.assign) a.push_back(Json{{"path", x.path}, {"value", x.value}});
  return a;
}

// Summary rows of one cell, prefixed with its identity and axis values, for summary.csv.
void add_cell_rows(ResultTable& out, const SweepCell& c, const ResultTable& cell_summary) {
  char idx[16];
  std::snprintf(idx, sizeof idx, "%04d", c.index);
  for (auto& r : cell_summary.rows()) {
    ResultRow n;
    const std::string* id = r.text_of("config_id");
    n.set_text("config_id", std::string(idx) + "/" + (id ? *id : ""));
    n.set_text("cell_id", c.id());
    for (auto& [k, v] : r.text)
      if (k != "config_id") n.set_text(k, v);
    n.set("cell", c.index);
    for (auto& a : c.assign) {
      if (a.value.is_number())
        n.set(a.path, a.value.get<double>());
      else if (a.value.is_string())
        n.set_text(a.path, a.value.get<std::string>());
      else if (a.value.is_boolean())
        n.set(a.path, a.value.get<bool>() ? 1 : 0);
    }
    for (auto& [k, v] : r.num) n.set(k, v);
    out.add(std::move(n));
  }
}

void write_cell_json(const std::string& dir, const SweepCell& c, const ResultTable& summary,
                     double cell_ms, const Json& target) {
  Json rows = Json::array();
  for (auto& r : summary.rows()) {
    Json t = Json::object(), n = Json::array();
    for (auto& [k, v] : r.text) t[k] = v;
    for (auto& [k, v] : r.num) n.push_back(Json::array({k, num_json(v)}));  // keeps column order
    rows.push_back(Json{{"text", t}, {"num", n}});
  }
  Json j{{"status", "complete"},      {"index", c.index},   {"hash", c.hash},
         {"assign", assign_json(c)},  {"cell_ms", cell_ms}, {"summary", rows},
         {"git_commit", git_commit()}};
  if (target.is_object()) j["target"] = target;  // --target: frames used, achieved half-widths
  write_file_atomic(dir + "/cell.json", j.dump(1) + "\n");
}

void write_sweep_json(const std::string& out, const SweepPlan& plan, const LoadedConfig& cfg) {
  Json cells = Json::array();
  for (auto& c : plan.cells)
    cells.push_back(Json{{"index", c.index}, {"id", c.id()}, {"assign", assign_json(c)}});
  Json objectives = Json::array();
  for (auto& o : plan.objectives)
    objectives.push_back(Json{{o.maximize ? "maximize" : "minimize", o.column}});
  Json j{{"tool", "fovsim"},       {"version", version_string()}, {"name", plan.name},
         {"plan_hash", plan.hash}, {"config_file", cfg.file},     {"base_dir", cfg.base_dir},
         {"config", cfg.doc},      {"axes", plan.axis_paths},     {"objectives", objectives},
         {"cells", cells}};
  if (!cfg.inherited.empty()) j["inherited"] = cfg.inherited;  // base files of each value
  std::string path = out + "/sweep.json";
  std::string text = j.dump(1) + "\n";
  if (file_exists(path) && read_file(path) == text) return;  // shards write the same file
  write_file_atomic(path, text);
}

// The config's inherited values less those a sweep axis sets in cell `c` (the sweep file
// wrote those).
std::vector<std::pair<std::string, std::string>> inherited_for(const LoadedConfig& cfg,
                                                               const SweepCell& c) {
  std::vector<std::pair<std::string, std::string>> out;
  for (auto& e : cfg.inherited) {
    bool set = false;
    for (auto& a : c.assign) {
      const std::string& q = a.path;
      set = set ||
            (e.first.compare(0, q.size(), q) == 0 &&
             (e.first.size() == q.size() || e.first[q.size()] == '.' || e.first[q.size()] == '['));
    }
    if (!set) out.push_back(e);
  }
  return out;
}

std::string cell_dir(const std::string& out, const SweepCell& c) {
  return out + "/runs/" + c.id();
}

// The columns of a cell's frames.csv that sweep pairing needs (paired_metrics()).
ResultTable read_frames_for_pairs(const std::string& path) {
  ResultTable t;
  std::vector<CsvRow> rows = read_csv_rows(path, ',', 0);
  if (rows.empty()) return t;
  // The headline metrics and the per-frame columns their paired differences read (a sequence
  // metric's pooled column, e.g. fvvdp_q for fvvdp_jod): metric list from the registry.
  std::set<std::string> metrics;
  for (auto& m : paired_metrics()) {
    metrics.insert(m);
    metrics.insert(paired_source_column(m));
  }
  std::vector<std::string> header;
  for (auto& f : rows[0].fields) header.push_back(f.text);
  for (size_t i = 1; i < rows.size(); ++i) {
    ResultRow r;
    for (size_t k = 0; k < header.size() && k < rows[i].fields.size(); ++k) {
      const std::string& h = header[k];
      const std::string& v = rows[i].fields[k].text;
      if (h == "config_id" || h == "gpu") {
        r.set_text(h, v);
      } else if (h == "frame" || metrics.count(h)) {
        r.set(h, std::strtod(v.c_str(), nullptr));  // "inf", "nan" as written by format_number
      }
    }
    t.add(std::move(r));
  }
  return t;
}

std::string value_text(const Json& v) {
  return v.is_string() ? v.get<std::string>() : v.dump();
}

// Sweep-level paired differences (paired.csv of the sweep): "within" rows are each cell's own
// config pairs (same as runs/<cell>/paired.csv); "across" rows pair the same config_id in two
// cells of one reference group (same scene, trace and frames: the references are identical,
// so frame i of one cell and frame i of the other saw the same gaze and image) whose axis
// values differ in exactly one axis, e.g. latency 0 vs 50 ms or sigma 1.8 vs 2.0.
ResultTable sweep_paired(const std::string& out, const SweepPlan& plan) {
  ResultTable all;
  std::vector<std::string> order;
  std::map<std::string, std::vector<const SweepCell*>> groups;
  for (auto& c : plan.cells) {
    std::string k = reference_key(c.doc);
    if (!groups.count(k)) order.push_back(k);
    groups[k].push_back(&c);
  }
  auto common = [](ResultRow& row, const char* kind, const SweepCell& a, const SweepCell& b) {
    row.set_text("kind", kind);
    row.set_text("cell_a_id", a.id());
    row.set_text("cell_b_id", b.id());
  };
  for (auto& k : order) {
    const auto& cells = groups[k];
    // The group's fidelity (render.scale is shared by a reference group): the known bias its
    // cells' manifests state, for the fidelity_bias columns (docs/intervals.md).
    Json fidelity;
    for (auto* c : cells) {
      const std::string mf = cell_dir(out, *c) + "/manifest.json";
      if (!file_exists(mf)) continue;
      try {
        const Json mj = parse_json_text(read_file(mf), mf);
        if (mj.contains("fidelity")) fidelity = mj["fidelity"];
      } catch (const Error&) {
        fidelity = Json();  // an unreadable manifest: no bias stated (columns nan)
      }
      break;
    }
    ResultTable group_rows;
    std::vector<ResultTable> frames;
    for (auto* c : cells) {
      std::string f = cell_dir(out, *c) + "/frames.csv";
      frames.push_back(file_exists(f) ? read_frames_for_pairs(f) : ResultTable());
    }
    // Per cell: config_id -> its rows (frame order), first-seen order of config ids.
    std::vector<std::map<std::string, std::vector<const ResultRow*>>> by_cfg(cells.size());
    std::vector<std::vector<std::string>> cfg_order(cells.size());
    for (size_t i = 0; i < cells.size(); ++i)
      for (auto& r : frames[i].rows()) {
        const std::string* id = r.text_of("config_id");
        std::string key = id ? *id : "";
        if (!by_cfg[i].count(key)) cfg_order[i].push_back(key);
        by_cfg[i][key].push_back(&r);
      }
    std::set<std::string> present;
    for (auto& t : frames)
      for (auto& c : t.numeric_columns()) present.insert(c);
    for (size_t i = 0; i < cells.size(); ++i) {
      const SweepCell& a = *cells[i];
      const ResultTable within = paired_differences(frames[i]);
      for (auto& r : within.rows()) {
        ResultRow row;
        common(row, "within", a, a);
        for (auto& [kk, v] : r.text) row.set_text(kk, v);
        row.set_text("axis", "");
        row.set_text("value_a", "");
        row.set_text("value_b", "");
        row.set("cell_a", a.index);
        row.set("cell_b", a.index);
        for (auto& [kk, v] : r.num) row.set(kk, v);
        group_rows.add(std::move(row));
      }
      for (size_t j = i + 1; j < cells.size(); ++j) {
        const SweepCell& b = *cells[j];
        int diffs = 0;
        size_t axis = 0;
        for (size_t d = 0; d < a.assign.size() && d < b.assign.size(); ++d)
          if (a.assign[d].value != b.assign[d].value) {
            ++diffs;
            axis = d;
          }
        if (diffs != 1) continue;
        for (auto& id : cfg_order[i]) {
          auto it = by_cfg[j].find(id);
          if (it == by_cfg[j].end()) continue;
          std::map<double, const ResultRow*> b_by_frame;
          for (auto* r : it->second) b_by_frame[r->get("frame", NAN)] = r;
          const std::string* g = by_cfg[i][id].front()->text_of("gpu");
          for (auto& m : paired_metrics()) {  // metric list: registry
            if (!present.count(paired_source_column(m))) continue;
            ResultRow row;
            common(row, "across", a, b);
            row.set_text("config_a", id);
            row.set_text("config_b", id);
            row.set_text("gpu", g ? *g : "");
            row.set_text("metric", m);
            row.set_text("axis", a.assign[axis].path);
            row.set_text("value_a", value_text(a.assign[axis].value));
            row.set_text("value_b", value_text(b.assign[axis].value));
            row.set("cell_a", a.index);
            row.set("cell_b", b.index);
            paired_columns(by_cfg[i][id], b_by_frame, m, row);
            group_rows.add(std::move(row));
          }
        }
      }
    }
    const ResultTable marked = with_fidelity_bias(group_rows, fidelity);
    for (auto& r : marked.rows()) all.add(r);
  }
  return all;
}

}  // namespace

static MergeReport merge_cells(const std::string& out_dir, const std::vector<std::string>& sources,
                               bool allow_partial);

std::pair<int, int> shard_range(int cells, int i, int n) {
  long a = long(cells) * i / n, b = long(cells) * (i + 1) / n;
  return {int(a), int(b)};
}

void parse_shard(const std::string& s, int& index, int& count) {
  auto slash = s.find('/');
  try {
    if (slash == std::string::npos) throw 0;
    size_t p1 = 0, p2 = 0;
    index = std::stoi(s.substr(0, slash), &p1);
    count = std::stoi(s.substr(slash + 1), &p2);
    if (p1 != slash || p2 != s.size() - slash - 1) throw 0;
  } catch (...) {
    throw Error("--shard " + s, "expected i/N, e.g. 0/4");
  }
  if (count < 1 || index < 0 || index >= count)
    throw Error("--shard " + s, "need 0 <= i < N (shards are numbered from 0)");
}

bool shard_from_env(int& index, int& count) {
  // Parsed strictly (env_integer): "abc", "", "3x" or an overflow is an error naming the
  // variable, never silently shard 0.
  auto id = env_integer("SLURM_ARRAY_TASK_ID", 0, 1000000000L);
  auto cnt = env_integer("SLURM_ARRAY_TASK_COUNT", 1, 1000000L);
  auto mn = env_integer("SLURM_ARRAY_TASK_MIN", 0, 1000000000L);
  if (!id || !cnt) return false;  // not an array job (or a SLURM without TASK_COUNT)
  long i = *id - (mn ? *mn : 0);
  long n = *cnt;
  if (i < 0 || i >= n)
    throw Error("SLURM_ARRAY_TASK_ID=" + std::to_string(*id),
                "array task ids must be contiguous (e.g. --array=0-" + std::to_string(n - 1) + ")");
  index = int(i);
  count = int(n);
  return true;
}

std::string sweep_out_dir(const SweepPlan& plan, const std::string& out_dir) {
  return out_dir.empty() ? "results/" + safe_file_name(plan.name) : out_dir;
}

bool cell_complete(const std::string& dir, const std::string& hash) {
  std::string p = dir + "/cell.json";
  if (!file_exists(p)) return false;
  try {
    Json j = parse_json_text(read_file(p), p);
    return j.value("status", "") == "complete" && j.value("hash", "") == hash &&
           j.contains("summary");
  } catch (...) {
    return false;  // unreadable: recompute
  }
}

// The build (git_commit) a complete cell was computed by; "" for a cell written before cells
// recorded it, or an unreadable one.
static std::string cell_build(const std::string& dir) {
  try {
    Json j = parse_json_text(read_file(dir + "/cell.json"), dir + "/cell.json");
    return j.contains("git_commit") && j["git_commit"].is_string()
               ? j["git_commit"].get<std::string>()
               : std::string();
  } catch (...) {
    return "";
  }
}

// One summary, one build: cells that different builds computed (shards run with different
// binaries) would mix two versions of the numbers. `builds`: git_commit -> cells.
static void refuse_mixed_builds(const std::string& out_dir,
                                const std::map<std::string, std::vector<int>>& builds) {
  if (builds.size() <= 1) return;
  std::string list;
  for (auto& [b, cells] : builds) {
    list += (list.empty() ? "" : "; ") + (b.empty() ? std::string("unrecorded") : b) + ": ";
    for (size_t i = 0; i < cells.size() && i < 8; ++i)
      list += (i ? ", " : "") + std::to_string(cells[i]);
    if (cells.size() > 8) list += ", ... (" + std::to_string(cells.size()) + " cells)";
  }
  throw Error(out_dir, "the cells were computed by " + std::to_string(builds.size()) +
                           " different builds of fovsim (git_commit " + list +
                           "): rerun `fovsim sweep` with one build to recompute the others");
}

// A complete cell counts for a rerun only when it ran with the same --target specs (none =
// the whole frame range): a cell stopped early is not the full run's cell, and vice versa.
static bool cell_targets_match(const std::string& dir, const std::vector<std::string>& specs) {
  try {
    Json j = parse_json_text(read_file(dir + "/cell.json"), dir + "/cell.json");
    std::vector<std::string> had;
    if (j.contains("target") && j["target"].contains("targets"))
      had = j["target"]["targets"].get<std::vector<std::string>>();
    return had == specs;
  } catch (...) {
    return false;
  }
}

ResultTable read_cell_summary(const std::string& dir) {
  std::string p = dir + "/cell.json";
  ResultTable t;
  try {  // a hand-edited or damaged record is a located error, never an internal one
    Json j = parse_json_text(read_file(p), p);
    for (auto& r : j.at("summary")) {
      ResultRow row;
      // Text columns in the order the runner writes them, then any others.
      const Json& tx = r.at("text");
      for (const char* k : {"config_id", "method", "label", "gpu"})
        if (tx.contains(k)) row.set_text(k, tx[k].get<std::string>());
      for (auto it = tx.begin(); it != tx.end(); ++it)
        row.set_text(it.key(), it.value().get<std::string>());
      for (auto& kv : r.at("num")) row.set(kv.at(0).get<std::string>(), json_num(kv.at(1)));
      t.add(std::move(row));
    }
  } catch (const Json::exception& e) {
    throw Error(p, "corrupt cell record: " + json_error_text(e));
  }
  return t;
}

SweepPlan load_sweep_plan(const std::string& dir) {
  std::string p = dir + "/sweep.json";
  if (!file_exists(p)) throw Error(p, "not found: is " + dir + " the output folder of a sweep?");
  // Read through Params: a damaged or hand-edited record ({}, a number for a string) is a
  // located error naming the key, never the JSON library's exception text.
  Params r(Params::parse_json_file(p), p);
  LoadedConfig cfg;
  if (!r.has("config")) r.fail("config", "missing: not a sweep record written by fovsim sweep");
  cfg.doc = r.raw("config");
  if (!cfg.doc.is_object())
    r.fail("config", "expected the sweep's config object, got " + describe_json(cfg.doc));
  cfg.file = r.string("config_file", "");
  cfg.base_dir = r.string("base_dir", "");
  if (r.has("inherited")) {
    const Json& inh = r.raw("inherited");
    for (size_t i = 0; inh.is_array() && i < inh.size(); ++i) {
      const Json& e = inh[i];
      if (!e.is_array() || e.size() != 2 || !e[0].is_string() || !e[1].is_string())
        r.fail("inherited[" + std::to_string(i) + "]",
               "expected [\"json.path\", \"base file\"], got " + describe_json(e));
      cfg.inherited.emplace_back(e[0].get<std::string>(), e[1].get<std::string>());
    }
    if (!inh.is_array()) r.fail("inherited", "expected an array, got " + describe_json(inh));
  }
  const std::string recorded = r.string("plan_hash", "");
  SweepPlan plan = expand_sweep(cfg);
  if (plan.hash != recorded)
    throw Error(p, "the recorded sweep expands differently with this fovsim version (plan hash " +
                       plan.hash + " vs " + escape_control(recorded, 80) + ")");
  return plan;
}

// Long because: its steps share the output folder's lock, the plan's cell folders and the
// report they fill — lock, stale folders, pending cells grouped by reference key, batches run
// through run_cells, summaries when the sweep is complete — each step a few lines around a
// helper (cell_complete, add_cell_rows, write_cell_json, merge_sweep); split further, every
// piece would take the same state.
SweepReport run_sweep(const SweepPlan& plan, const LoadedConfig& cfg, const SweepOptions& opt) {
  auto t0 = Clock::now();
  const double cpu0 = process_cpu_ms();
  const auto threads = thread_limit(opt.threads);
  SweepReport rep;
  std::vector<GroupStats> group_stats;  // per run_cells call: the reference cache's growth
  rep.out_dir = sweep_out_dir(plan, opt.out_dir);
  rep.cells_total = int(plan.cells.size());
  const std::string& out = rep.out_dir;
  // Two sweeps on one --out would both compute every cell: the second one stops here with a
  // clear message. Shards of one sweep (different i/N) lock separately and run side by side.
  std::string lock_name = ".lock";
  if (opt.shards > 1)
    lock_name += ".shard-" + std::to_string(opt.shard) + "-of-" + std::to_string(opt.shards);
  DirLock lock(out, lock_name,
               "another fovsim sweep" + (opt.shards > 1 ? " (shard " + std::to_string(opt.shard) +
                                                              "/" + std::to_string(opt.shards) + ")"
                                                        : std::string()));
  make_dirs(out + "/runs");  // under the lock: a link at runs/ is refused (OutputRoot)
  write_sweep_json(out, plan, cfg);

  // Folders of cells that are not in this expansion (an earlier config): reported, never read.
  std::set<std::string> ids;
  for (auto& c : plan.cells) ids.insert(c.id());
  for (auto& e : fs::directory_iterator(out + "/runs"))
    if (e.is_directory() && !ids.count(e.path().filename().string())) ++rep.stale_dirs;

  auto [first, last] = shard_range(int(plan.cells.size()), opt.shard, opt.shards);
  rep.cells_in_shard = last - first;
  std::vector<const SweepCell*> pending;
  bool columns_checked = false;  // objectives & co. name columns of the cells' summary
  for (int i = first; i < last; ++i) {
    const SweepCell& c = plan.cells[size_t(i)];
    // A cell another build computed is computed again: a sweep never mixes numbers of two
    // versions of the cost model, the metrics or the methods.
    const bool complete = cell_complete(cell_dir(out, c), c.hash) &&
                          cell_targets_match(cell_dir(out, c), opt.targets);
    const bool other_build = complete && cell_build(cell_dir(out, c)) != git_commit();
    if (other_build) ++rep.cells_other_build;
    if (complete && !other_build) {
      ++rep.cells_done_before;
      if (!columns_checked) {
        ResultTable t;
        add_cell_rows(t, c, read_cell_summary(cell_dir(out, c)));
        check_plan_columns(plan, t);
        columns_checked = true;
      }
    } else {
      pending.push_back(&c);
    }
  }

  // Group pending cells by reference key, groups in order of their first cell.
  std::vector<std::string> order;
  std::map<std::string, std::vector<const SweepCell*>> groups;
  for (auto* c : pending) {
    std::string k = reference_key(c->doc);
    if (!groups.count(k)) order.push_back(k);
    groups[k].push_back(c);
  }
  rep.groups = int(order.size());
  EngineOptions eo;
  eo.models_dir = opt.models_dir;
  eo.print_summary = false;
  eo.threads = opt.threads;
  eo.watchdog.min_s = opt.watchdog_s;
  eo.use_cache = opt.use_cache;
  eo.memory_budget_gb = opt.memory_budget_gb;
  for (auto& t : opt.targets) eo.targets.push_back(parse_target(t));  // per cell (engine.h)
  size_t pending_cells = 0;
  for (auto& k : order) pending_cells += groups[k].size();
  Progress progress("sweep cells", pending_cells);  // the engine's frames nest inside
  for (auto& k : order) {
    auto& cells = groups[k];
    size_t step = opt.batch > 0 ? size_t(opt.batch) : cells.size();
    for (size_t b = 0; b < cells.size(); b += step) {
      std::vector<CellJob> jobs;
      std::vector<const SweepCell*> batch(cells.begin() + long(b),
                                          cells.begin() + long(std::min(cells.size(), b + step)));
      for (auto* c : batch) {
        CellJob j;
        j.doc = c->doc;
        j.file = cfg.file;
        j.origins = cfg.overridden;
        j.inherited = inherited_for(cfg, *c);
        j.base_dir = cfg.base_dir;
        j.out_dir = cell_dir(out, *c);
        j.command_line = opt.command_line;
        j.extra_manifest = Json{{"sweep",
                                 {{"name", plan.name},
                                  {"cell", c->index},
                                  {"hash", c->hash},
                                  {"plan_hash", plan.hash},
                                  {"assign", assign_json(*c)}}}};
        jobs.push_back(std::move(j));
      }
      GroupStats gs;
      auto res = run_cells(jobs, eo, &gs);
      if (!columns_checked && !res.empty()) {  // before any cell is recorded as complete
        ResultTable t;
        add_cell_rows(t, *batch[0], res[0].summary);
        check_plan_columns(plan, t);
        columns_checked = true;
      }
      for (size_t i = 0; i < res.size(); ++i) {
        write_cell_json(jobs[i].out_dir, *batch[i], res[i].summary, res[i].cell_ms, res[i].target);
        rep.cell_ms += res[i].cell_ms;
      }
      rep.cells_run += int(res.size());
      progress.step(res.size());
      rep.reference_passes += gs.passes;
      rep.reference_frames += gs.frames;
      rep.reference_frames_from_cache += gs.frames_from_cache;
      rep.ref_ms += gs.ref_ms;
      rep.setup_ms += gs.setup_ms;
      group_stats.push_back(gs);
    }
  }
  rep.cache_note = cache_growth_note(group_stats);

  // Summaries once every cell of the sweep is complete here (the last shard to finish writes
  // them; concurrent writers produce the same bytes, atomically).
  bool all = true;
  for (auto& c : plan.cells) all = all && cell_complete(cell_dir(out, c), c.hash);
  if (all) {
    merge_cells(out, {}, false);  // this sweep holds the folder's lock
    rep.complete = true;
  }
  rep.wall_ms = ms_since(t0);
  rep.cpu_ms = process_cpu_ms() - cpu0;
  rep.peak_rss_bytes = peak_rss_bytes();
  return rep;
}

// merge_sweep without the lock (run_sweep holds it already).
static MergeReport merge_cells(const std::string& out_dir, const std::vector<std::string>& sources,
                               bool allow_partial) {
  SweepPlan plan = load_sweep_plan(out_dir);
  // Every --from folder is an output folder of this same sweep: a typo is an error, not
  // "no cells found there".
  for (const std::string& s : sources) {
    std::error_code ec;
    if (!fs::is_directory(s, ec))
      throw Error("--from " + s, fs::exists(s, ec) ? "not a folder" : "no such folder");
    if (!file_exists(s + "/sweep.json"))
      throw Error("--from " + s, "no sweep.json: not an output folder of a sweep");
    const Json j = Params::parse_json_file(s + "/sweep.json");
    const std::string h = j.is_object() && j.contains("plan_hash") && j["plan_hash"].is_string()
                              ? j["plan_hash"].get<std::string>()
                              : "?";
    if (h != plan.hash)
      throw Error("--from " + s,
                  "a different sweep (plan hash " + h + ", " + out_dir + " has " + plan.hash + ")");
  }
  MergeReport rep;
  rep.cells = int(plan.cells.size());
  ResultTable summary;
  std::map<std::string, std::vector<int>> builds;  // git_commit -> cells
  for (auto& c : plan.cells) {
    std::string here = cell_dir(out_dir, c);
    bool ok = cell_complete(here, c.hash);
    if (!ok) {
      for (auto& s : sources) {
        std::string there = cell_dir(s, c);
        if (!cell_complete(there, c.hash)) continue;
        // Copy into a temporary folder, then rename: a half-copied cell never looks complete.
        std::string tmp = here + ".merge-tmp";
        std::error_code ec;
        fs::remove_all(tmp, ec);
        make_dirs(fs::path(tmp).parent_path().string());
        // Links inside a source cell are not followed (nothing outside it is copied in).
        fs::copy(there, tmp, fs::copy_options::recursive | fs::copy_options::skip_symlinks, ec);
        if (ec) throw Error(there, "cannot copy cell: " + ec.message());
        fs::remove_all(here, ec);
        fs::rename(tmp, here, ec);
        if (ec) throw Error(here, "cannot move merged cell into place: " + ec.message());
        ++rep.copied;
        ok = true;
        break;
      }
    }
    if (!ok) {
      rep.missing.push_back(c.index);
      continue;
    }
    ++rep.found;
    builds[cell_build(here)].push_back(c.index);
    add_cell_rows(summary, c, read_cell_summary(here));
  }
  refuse_mixed_builds(out_dir, builds);
  if (!rep.missing.empty() && !allow_partial) {
    std::string list;
    for (size_t i = 0; i < rep.missing.size() && i < 20; ++i)
      list += (i ? ", " : "") + std::to_string(rep.missing[i]);
    if (rep.missing.size() > 20) list += ", ...";
    throw Error(out_dir, std::to_string(rep.missing.size()) + " of " + std::to_string(rep.cells) +
                             " cells are missing or incomplete (cells " + list +
                             "): run the remaining shards, or rerun `fovsim sweep` to resume");
  }

  check_plan_columns(plan, summary);
  // Pareto front over the declared objectives (per pareto.group_by, default per GPU).
  std::vector<std::string> params;
  for (auto& col : summary.numeric_columns())
    for (const char* p : {"sigma", "alpha", "fx", "fy", "epsilon", "vpl_budget", "kernel"})
      if (col == p) params.push_back(col);
  for (auto& a : plan.axis_paths) params.push_back(a);
  Json files = Json::array({"summary.csv"});
  if (!plan.objectives.empty()) {
    auto front = pareto_front(summary, plan.objectives, plan.pareto_group_by);
    std::set<size_t> on(front.begin(), front.end());
    ResultTable marked, pf;
    for (size_t i = 0; i < summary.rows().size(); ++i) {
      ResultRow r = summary.rows()[i];
      r.set("pareto", on.count(i) ? 1 : 0);
      if (on.count(i)) pf.add(r);
      marked.add(std::move(r));
    }
    summary = std::move(marked);
    write_file_atomic(out_dir + "/pareto.csv", pf.to_csv());
    files.push_back("pareto.csv");
  }
  write_file_atomic(out_dir + "/summary.csv", summary.to_csv());
  write_file_atomic(out_dir + "/paired.csv", sweep_paired(out_dir, plan).to_csv());
  files.push_back("paired.csv");
  if (plan.iso.enabled()) {
    write_file_atomic(out_dir + "/iso_budget.csv",
                      iso_budget_table(summary, plan.iso, params).to_csv());
    files.push_back("iso_budget.csv");
  }
  Json objectives = Json::array();
  for (auto& o : plan.objectives)
    objectives.push_back(Json{{o.maximize ? "maximize" : "minimize", o.column}});
  Json ss{{"name", plan.name},
          {"plan_hash", plan.hash},
          {"cells", rep.cells},
          {"cells_found", rep.found},
          {"missing", rep.missing},
          {"axes", plan.axis_paths},
          {"objectives", objectives},
          {"pareto_group_by", plan.pareto_group_by},
          {"files", files}};
  if (plan.iso.enabled())
    ss["iso_budget"] = Json{
        {"column", plan.iso.column}, {"budgets", plan.iso.budgets}, {"quality", plan.iso.quality}};
  write_file_atomic(out_dir + "/sweep_summary.json", ss.dump(2) + "\n");
  rep.summary = std::move(summary);
  return rep;
}

MergeReport merge_sweep(const std::string& out_dir, const std::vector<std::string>& sources,
                        bool allow_partial) {
  DirLock lock(out_dir, ".lock", "another fovsim sweep or merge");
  return merge_cells(out_dir, sources, allow_partial);
}

}  // namespace fovsim
