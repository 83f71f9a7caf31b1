#include "sim/experiment/intervals.h"

#include <cmath>
#include <map>
#include <set>

#include "sim/core/stats.h"
#include "sim/foveation/factory.h"

namespace fovsim {

bool has_interval(const std::string& column) {
  static const std::set<std::string> skip = [] {
    std::set<std::string> s = {"frame", "t", "gaze_x", "gaze_y", "ref_ms", "sim_ms"};
    for (auto& e : method_table())
      for (auto& p : e.params()) s.insert(p.name);
    return s;
  }();
  return !skip.count(column);
}

const std::vector<std::string>& headline_metrics() {
  static const std::vector<std::string> m = {"est_ms_total", "shaded_fraction", "psnr", "ssim",
                                             "fpsnr"};
  return m;
}

ResultTable paired_differences(const ResultTable& frames) {
  // Per config, in first-seen order: its rows by frame index.
  std::vector<std::string> order;
  std::map<std::string, std::string> gpu_of;
  std::map<std::string, std::vector<const ResultRow*>> rows;
  for (auto& r : frames.rows()) {
    const std::string* id = r.text_of("config_id");
    std::string key = id ? *id : "";
    if (!rows.count(key)) {
      order.push_back(key);
      const std::string* g = r.text_of("gpu");
      gpu_of[key] = g ? *g : "";
    }
    rows[key].push_back(&r);
  }
  auto cols = frames.numeric_columns();
  std::set<std::string> present(cols.begin(), cols.end());
  ResultTable out;
  for (size_t i = 0; i < order.size(); ++i) {
    for (size_t j = i + 1; j < order.size(); ++j) {
      const std::string &a = order[i], &b = order[j];
      if (gpu_of[a] != gpu_of[b]) continue;
      std::map<double, const ResultRow*> b_by_frame;
      for (auto* r : rows[b]) b_by_frame[r->get("frame", NAN)] = r;
      for (auto& m : headline_metrics()) {
        if (!present.count(m)) continue;
        std::vector<double> va, vb, d;  // frame order of config a
        for (auto* ra : rows[a]) {
          auto it = b_by_frame.find(ra->get("frame", NAN));
          if (it == b_by_frame.end()) continue;
          double x = ra->get(m, NAN), y = it->second->get(m, NAN);
          if (!std::isfinite(x) || !std::isfinite(y)) continue;
          va.push_back(x);
          vb.push_back(y);
          d.push_back(x - y);
        }
        MeanInterval ci = batch_means_interval(d);
        ResultRow row;
        row.set_text("config_a", a);
        row.set_text("config_b", b);
        row.set_text("gpu", gpu_of[a]);
        row.set_text("metric", m);
        row.set("frames", double(d.size()));
        row.set("mean_a", batch_means_interval(va).mean);
        row.set("mean_b", batch_means_interval(vb).mean);
        row.set("diff", ci.mean);
        row.set("diff_ci95", ci.half_width);
        row.set("diff_lo", ci.lo());
        row.set("diff_hi", ci.hi());
        row.set("differs", std::isnan(ci.half_width) ? NAN : (ci.lo() > 0 || ci.hi() < 0) ? 1 : 0);
        out.add(std::move(row));
      }
    }
  }
  return out;
}

}  // namespace fovsim
