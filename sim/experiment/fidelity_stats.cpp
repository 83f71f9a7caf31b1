// The fidelity ladder's statistics (fidelity.h): a rung's error against the top rung with its
// 95% interval, the methods' ranking, and the swaps whose order the truth resolves. Intervals are
// the batch means of sim/core/stats.h, as for the run intervals of intervals.cpp.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "sim/core/stats.h"
#include "sim/experiment/fidelity.h"

namespace fovsim {

namespace {

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

}  // namespace

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

}  // namespace fovsim
