#include "sim/experiment/tracking_summary.h"

#include <algorithm>
#include <cmath>

#include "sim/core/stats.h"
#include "sim/experiment/intervals.h"

namespace fovsim {

const std::vector<std::string>& tracking_states() {
  static const std::vector<std::string> s = {"valid", "held", "lost"};
  return s;
}

ResultTable summarize_tracking(const ResultTable& frames, const ResultTable& summary) {
  std::vector<std::string> names;
  const auto cols = frames.numeric_columns();
  for (auto& m : headline_metrics())
    if (paired_source_column(m) == m && std::find(cols.begin(), cols.end(), m) != cols.end())
      names.push_back(m);
  ResultTable out;
  for (const ResultRow& srow : summary.rows()) {
    ResultRow r;
    for (auto& kv : srow.text)
      if (kv.first != "tracking") r.set_text(kv.first, kv.second);
    r.num = srow.num;
    const std::string* id = srow.text_of("config_id");
    for (const std::string& st : tracking_states()) {
      std::vector<const ResultRow*> rows;  // frame order (frames.csv is written in it)
      for (auto& fr : frames.rows()) {
        const std::string *fid = fr.text_of("config_id"), *fs = fr.text_of("tracking");
        if (id && fid && *fid == *id && fs && *fs == st) rows.push_back(&fr);
      }
      r.set("frames_" + st, double(rows.size()));
      for (auto& n : names) {
        std::vector<double> x;
        for (auto* fr : rows) {
          const double v = fr->get(n, NAN);
          if (std::isfinite(v)) x.push_back(v);
        }
        const MeanInterval mi = batch_means_interval(x);
        r.set(n + "_" + st, x.empty() ? double(NAN) : mi.mean);
        r.set(n + "_" + st + "_ci95", x.empty() ? double(NAN) : mi.half_width);
      }
    }
    out.add(std::move(r));
  }
  return out;
}

}  // namespace fovsim
