// The fidelity ladder's report (fidelity_report.h): every rung against the top rung.
#include "sim/experiment/fidelity_report.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "sim/core/counter_list.h"
#include "sim/core/files.h"
#include "sim/core/text.h"
#include "sim/core/version.h"
#include "sim/metrics/registry.h"

namespace fovsim {

namespace {

// A number in the ladder table; NaN (not measured) is "-".
std::string fmt_dash(const char* f, double v) {
  return fmt(f, v, "-");
}

// The ladder table's header: one column per headline output besides frame time and shading.
std::string ladder_header(const std::vector<std::string>& outs) {
  std::string md;
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
  return md;
}

// Rung `ri` against the truth `top`: its rows of fidelity.csv, its fidelity.json entry, its line
// of the ladder table, and a note when it passes the test of docs/fidelity.md.
// Long because: one rung's numbers go to three outputs at once (fidelity.csv rows, its
// fidelity.json entry, its line of fidelity.md) from the same comparison against the top rung;
// writing them side by side keeps the three in step.
void report_rung(size_t ri, const FidelityRung& r, const RungRun& d, const RungRun& top,
                 const std::vector<std::string>& outs, const std::set<std::string>& present,
                 ResultTable& table, Json& jr, std::string& md, std::vector<std::string>& notes) {
  Json rj{{"index", ri},  {"name", r.name},           {"analytic", r.analytic},
          {"top", r.top}, {"overrides", r.overrides}, {"stride_factor", r.stride}};
  if (!r.skipped.empty()) {
    rj["skipped"] = r.skipped;
    jr.push_back(rj);
    md += "| " + r.name + " | skipped: " + r.skipped + " |\n";
    return;
  }
  double ratio = top.wall_s > 0 ? d.wall_s / top.wall_s : NAN;
  double cpu_ratio = top.cpu_s > 0 ? d.cpu_s / top.cpu_s : NAN;
  // Analytic: also every pass estimate and the counters frames.csv holds at the display's
  // resolution (declared: at_display_resolution, sim/core/counter_list.h). The other pixel
  // counters of frames.csv are at the simulated resolution, so they are not compared.
  std::vector<std::string> o_here = outs;
  if (r.analytic) {
    o_here.clear();
    for (auto& c : d.summary.numeric_columns()) {
      const auto k = find_counter(c);
      if (present.count(c) && (std::find(outs.begin(), outs.end(), c) != outs.end() ||
                               c.rfind("est_ms_", 0) == 0 || (k && at_display_resolution(k->id))))
        o_here.push_back(c);
    }
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
    x.set("frames", d.summary.rows().empty() ? NAN : d.summary.rows().front().get("frames", NAN));
    for (auto& [k, v] : row.num) x.set(k, v);
    if (r.top) x.set("err_ci95", 0.0);  // the truth against itself: no uncertainty
    x.set("ranking_same", rank_same[o] ? 1 : 0);
    x.set("ranking_resolved_swaps", swaps[o]);
    double e = row.get("err", NAN), rel = row.get("err_rel", NAN);
    if (std::isfinite(e)) max_abs[o] = std::max(max_abs.count(o) ? max_abs[o] : 0.0, std::fabs(e));
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
  // The test (docs/fidelity.md): PSNR and FPSNR within 0.2 dB, mean and p95 frame time
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
    notes.push_back("rung " + r.name +
                    " keeps PSNR/FPSNR within 0.2 dB and frame time within 2% at " +
                    fmt_dash("%.3f", ratio) + " of the top rung's wall time, " +
                    fmt_dash("%.3f", cpu_ratio) + " of its CPU time");
  md += "| " + r.name + (r.top ? " (top)" : "") + " | " + fmt_dash("%.1f", d.wall_s) + " | " +
        fmt_dash("%.3f", ratio) + " | " + fmt_dash("%.1f", d.cpu_s) + " | " +
        fmt_dash("%.3f", cpu_ratio) + " | " + fmt_dash("%.2f", 100 * mx(max_rel, "est_ms_total")) +
        " | " + fmt_dash("%.2f", 100 * mx(max_rel, "est_ms_total_p95")) + " | " +
        fmt_dash("%.4f", mx(max_abs, "shaded_fraction")) + " |";
  for (auto& o : outs)
    if (o != "est_ms_total" && o != "est_ms_total_p95" && o != "shaded_fraction")
      md += " " +
            fmt_dash(find_metric(o) && find_metric(o)->unit == "dB" ? "%.3f" : "%.4f",
                     mx(max_abs, o)) +
            " |";
  md += std::string(" ") + (rank_all ? "yes" : "no") +
        (swaps_all ? " (" + std::to_string(swaps_all) + " resolved swaps)" : "") + " | " +
        (r.top ? "-"
               : std::string(errors_ok ? "yes" : "no") + " / " + (good ? "yes" : "no") + " / " +
                     (good_cpu ? "yes" : "no")) +
        " |\n";
}

}  // namespace

void write_fidelity_report(const std::string& name, const LoadedConfig& cfg,
                           const FidelityOptions& opt, const std::vector<FidelityRung>& rungs,
                           const std::vector<RungRun>& runs, FidelityResult& res) {
  const RungRun& top = runs.back();
  ResultTable table;
  Json jr = Json::array();
  auto cols = top.summary.numeric_columns();
  std::set<std::string> present(cols.begin(), cols.end());
  std::vector<std::string> outs;
  for (auto& o : fidelity_outputs())
    if (present.count(o)) outs.push_back(o);
  std::string md = ladder_header(outs);
  for (size_t ri = 0; ri < rungs.size(); ++ri)
    report_rung(ri, rungs[ri], runs[ri], top, outs, present, table, jr, md, res.notes);
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
}

}  // namespace fovsim
