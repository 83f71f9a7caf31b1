#include "sim/experiment/recost.h"

#include <algorithm>
#include <filesystem>
#include <map>

#include "sim/core/counter_list.h"
#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/passes.h"
#include "sim/cost/workload.h"
#include "sim/foveation/factory.h"
#include "sim/scene/scene.h"
#include "sim/trace/csv_table.h"

namespace fovsim {

namespace {

// The counters of one frames.csv row (every numeric column but est_ms_*), shaded_samples back
// at the simulated resolution `sim_px` (frames.csv reports it at the real display's).
Counters row_counters(const std::vector<std::string>& header, const CsvRow& row,
                      const std::string& csv_path, double sim_px) {
  Counters c;  // the row's counter columns (counter_list.h); other columns are not counters
  double shaded_fraction = 0;
  bool has_fraction = false;
  for (size_t i = 0; i < header.size(); ++i) {
    const std::string& h = header[i];
    if (h.rfind("est_ms_", 0) == 0 || row.fields[i].text.empty()) continue;
    // A counter (counter_list.h, and shaded_fraction that rescales shaded_samples) is a count
    // or a fraction: finite and >= 0. A negative or non-finite one would be costed as a
    // cheaper (or a nan) frame, so it is an error naming the cell, like a missing one.
    const bool counter = h == "shaded_fraction" || find_counter(h).has_value();
    double v = 0;
    std::string why;
    if (!parse_number(row.fields[i].text, v, why)) {
      if (!counter) continue;
      throw Error(file_location(csv_path, row.line, row.fields[i].col),
                  "counter " + h + ": " + why + " (a counter is a finite number >= 0)");
    }
    if (counter && v < 0)
      throw Error(file_location(csv_path, row.line, row.fields[i].col),
                  "counter " + h + " = " + printable(row.fields[i].text) +
                      " is negative (a counter is a finite number >= 0)");
    if (h == "shaded_fraction") shaded_fraction = v, has_fraction = true;
    c.set_named(h, v);
  }
  // frames.csv reports shaded_samples at the real display's resolution; counters are
  // costed at the simulated one (like every other pixel counter in the file).
  // Without shaded_fraction the display-resolution shaded_samples would be costed as if
  // simulated: an error, as for any other missing counter (below).
  if (!has_fraction)
    throw Error(file_location(csv_path, row.line),
                "counter shaded_fraction missing or empty (the cost model needs it; "
                "re-costing would use display-resolution samples): use the run's own frames.csv");
  c.set(Counter::shaded_samples, shaded_fraction * sim_px);
  return c;
}

// One frame costed on one GPU, added to the row of its configuration in `acc`. A counter the
// cost model needs but the row lacks is an error at `where`.
void add_frame(std::vector<RecostRow>& acc, const GpuProfile& gpu, const CostInputs& ci,
               const std::string& id, const std::string& label, const std::string& where) {
  const FrameCost fc = estimate_frame(gpu, ci);
  // A counter the cost model needs for this method but the row lacks (its column removed
  // or its cell empty) would be costed as 0: an error naming it, never a cheaper frame.
  if (!fc.missing_counters.empty()) {
    std::string list;
    for (auto& m : fc.missing_counters) list += (list.empty() ? "" : ", ") + m;
    throw Error(where, "method \"" + escape_control(ci.method, 40) + "\": counter" +
                           (fc.missing_counters.size() == 1 ? " " : "s ") + list +
                           " missing or empty (the cost model needs " +
                           (fc.missing_counters.size() == 1 ? "it" : "them") +
                           "; re-costing would count 0): use the run's own frames.csv");
  }
  RecostRow* r = nullptr;
  for (auto& x : acc)
    if (x.config_id == id) r = &x;
  if (!r) {
    acc.push_back(RecostRow{gpu.name, id, ci.method, label});
    r = &acc.back();
  }
  r->frames += 1;
  r->total_ms += fc.total_ms;
  for (auto& pc : fc.passes) {
    bool found = false;
    for (auto& kv : r->pass_ms)
      if (kv.first == pc.pass) kv.second += pc.ms, found = true;
    if (!found) r->pass_ms.emplace_back(pc.pass, pc.ms);
  }
}

// A configuration's means over its frames, with the GPU profile's prediction interval.
void finish_row(RecostRow& r, const GpuProfile& gpu) {
  r.total_ms /= r.frames;
  for (auto& kv : r.pass_ms) kv.second /= r.frames;
  const PredictionInterval& iv = gpu.interval;  // per pass multiplicative: on the means
  if (iv.level > 0) {
    std::vector<PassSpan> parts;
    for (auto& [pass, ms] : r.pass_ms) {
      const IntervalFactors f = iv.for_pass(pass);
      parts.push_back({ms, ms * f.lo_factor, ms * f.hi_factor});
    }
    combine_pass_intervals(parts, &r.lo_ms, &r.hi_ms);
    const IntervalFactors tf = iv.for_total();  // conformal on frame totals when known
    if (tf.n > 0) r.lo_ms = r.total_ms * tf.lo_factor, r.hi_ms = r.total_ms * tf.hi_factor;
    r.level = iv.level;
  }
}

RecostResult recost_one(const RecostOptions& o) {
  const std::string man_path = o.results + "/manifest.json", csv_path = o.results + "/frames.csv";
  Json man = Params::parse_json_file(man_path);
  if (man.value("status", "") != "complete")
    throw Error(man_path, "run is not complete (status \"" + man.value("status", "?") + "\")");
  if (!man.contains("scene") || !man["scene"].contains("features"))
    throw Error(man_path + ": scene.features",
                "missing (results written by an older fovsim: rerun the config)");
  const SceneFeatures f = SceneFeatures::from_json(man["scene"]["features"]);
  RecostResult res;
  Display& d = res.display;
  if (!o.display.empty()) {
    d = Display::load(o.display, o.models);
  } else {
    Params dp(man.at("display"), man_path, "display");
    d = Display::from_params(dp);
  }
  if (o.width) d.width = o.width;
  if (o.height) d.height = o.height;
  if (o.eyes) d.eyes = o.eyes;
  const Json& sim = man.at("simulated_resolution");
  const double sim_px = sim.at(0).get<double>() * sim.at(1).get<double>();
  std::string wname = o.workload.empty() ? "generic" : o.workload;
  if (o.workload.empty() && man.contains("resolved_config") &&
      man["resolved_config"].contains("workload"))
    wname = man["resolved_config"]["workload"].get<std::string>();
  Workload w = Workload::load(wname, o.models);
  res.workload = w.name;

  const std::vector<CsvRow> rows = read_csv_rows(csv_path, ',', 0);
  if (rows.empty()) throw Error(csv_path, "empty frames.csv");
  std::vector<std::string> header;
  for (const CsvField& h : rows.front().fields) header.push_back(h.text);
  int c_id = -1, c_method = -1, c_gpu = -1, c_lighting = -1, c_label = -1;
  for (size_t i = 0; i < header.size(); ++i) {
    if (header[i] == "config_id") c_id = int(i);
    if (header[i] == "label") c_label = int(i);
    if (header[i] == "method") c_method = int(i);
    if (header[i] == "gpu") c_gpu = int(i);
    if (header[i] == "lighting") c_lighting = int(i);
  }
  if (c_id < 0 || c_method < 0) throw Error(csv_path + ":1", "missing config_id or method column");

  std::vector<GpuProfile> gpus;
  for (auto& g : o.gpus) gpus.push_back(GpuProfile::load(g, o.models));
  std::vector<std::vector<RecostRow>> acc(gpus.size());
  std::string first_gpu;
  std::map<std::string, CostPasses> declared;  // per method + lighting strategy
  // The run's means left out each method's warm-up rows (manifest `startup`,
  // sim/experiment/startup.h): so do these, to match its summary.
  std::map<std::string, int> skip, seen;
  if (man.contains("startup") && man["startup"].value("excluded", false) &&
      man["startup"].contains("methods") && man["startup"]["methods"].is_object())
    for (auto& [label, n] : man["startup"]["methods"].items())
      if (n.is_number_integer()) skip[label] = n.get<int>();
  for (size_t ri = 1; ri < rows.size(); ++ri) {
    const CsvRow& row = rows[ri];
    if (row.fields.size() != header.size())
      throw Error(file_location(csv_path, row.line), "expected " + std::to_string(header.size()) +
                                                         " fields, got " +
                                                         std::to_string(row.fields.size()));
    auto cell = [&](int i) -> const std::string& { return row.fields[size_t(i)].text; };
    // A run costed for several GPUs repeats each frame per GPU: the counters are the same, use one.
    if (c_gpu >= 0) {
      if (first_gpu.empty()) first_gpu = cell(c_gpu);
      if (cell(c_gpu) != first_gpu) continue;
    }
    const Counters c = row_counters(header, row, csv_path, sim_px);
    std::string id = cell(c_id);
    if (auto at = id.find('@'); at != std::string::npos) id = id.substr(0, at);
    if (auto sk = skip.find(id); sk != skip.end() && seen[id]++ < sk->second) continue;
    for (size_t gi = 0; gi < gpus.size(); ++gi) {
      CostInputs ci;
      ci.method = cell(c_method);
      // The passes the row's method and lighting strategy declare (an unknown method is
      // reported by estimate_frame).
      if (is_cost_method(ci.method)) {
        const std::string lighting = c_lighting >= 0 ? cell(c_lighting) : "";
        auto [it, fresh] = declared.try_emplace(ci.method + "\n" + lighting);
        if (fresh) it->second = declared_passes(ci.method, lighting);
        ci.passes = it->second;
      }
      ci.counters = &c;
      ci.features = f;
      ci.display = d;
      ci.pixel_scale = double(d.width) * double(d.height) / sim_px;
      ci.workload = &w;
      add_frame(acc[gi], gpus[gi], ci, id, c_label >= 0 ? cell(c_label) : id,
                file_location(csv_path, row.line));
    }
  }
  for (size_t gi = 0; gi < gpus.size(); ++gi)
    for (RecostRow& r : acc[gi]) {
      finish_row(r, gpus[gi]);
      res.rows.push_back(std::move(r));
    }
  return res;
}

}  // namespace

RecostResult recost_results(const RecostOptions& o) {
  // A sweep folder (sweep.json, runs/<cell>/): every cell, config ids prefixed "<cell>/".
  if (!file_exists(o.results + "/manifest.json") && file_exists(o.results + "/sweep.json")) {
    std::vector<std::string> cells;
    std::error_code ec;
    for (auto& e : std::filesystem::directory_iterator(o.results + "/runs", ec))
      if (e.is_directory() && file_exists(e.path().string() + "/manifest.json"))
        cells.push_back(e.path().filename().string());
    std::sort(cells.begin(), cells.end());
    if (cells.empty())
      throw Error(o.results + "/runs", "no finished cell (runs/<cell>/manifest.json) to re-cost");
    RecostResult all;
    for (size_t k = 0; k < cells.size(); ++k) {
      RecostOptions c = o;
      c.results = o.results + "/runs/" + cells[k];
      RecostResult r = recost_one(c);
      if (k == 0) all.display = r.display, all.workload = r.workload;
      for (auto& row : r.rows) {
        row.config_id = cells[k] + "/" + row.config_id;
        all.rows.push_back(std::move(row));
      }
    }
    return all;
  }
  return recost_one(o);
}

}  // namespace fovsim
