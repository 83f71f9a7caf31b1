#include "sim/experiment/search_verdict.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/core/stats.h"
#include "sim/experiment/search.h"
#include "sim/experiment/table.h"

namespace fovsim {

std::vector<BoundaryHit> boundary_hits(const std::vector<SearchDim>& space,
                                       const std::vector<double>& x) {
  std::vector<BoundaryHit> out;
  if (space.empty() || x.size() != space.size()) return out;
  // The ends as the searcher can reach them (quantization and integer rounding applied).
  Searcher s(space, true, 1, 1);
  const std::vector<double> lo = s.to_real(std::vector<double>(space.size(), 0.0));
  const std::vector<double> hi = s.to_real(std::vector<double>(space.size(), 1.0));
  for (size_t d = 0; d < space.size(); ++d) {
    if (!(hi[d] > lo[d])) continue;
    const double tol = 1e-9 * (hi[d] - lo[d]);
    if (std::fabs(x[d] - lo[d]) <= tol)
      out.push_back({d, -1, x[d]});
    else if (std::fabs(x[d] - hi[d]) <= tol)
      out.push_back({d, +1, x[d]});
  }
  return out;
}

std::string describe_boundary(const std::vector<SearchDim>& space,
                              const std::vector<BoundaryHit>& hits) {
  std::string s;
  for (size_t i = 0; i < hits.size(); ++i) {
    const BoundaryHit& h = hits[i];
    s += (i ? "; " : "") + std::string(h.end < 0 ? "lower" : "upper") + " end of " +
         space[h.dim].path + " (" + format_number(h.value) + ")";
  }
  return s.empty() ? s : "the optimum lies on the " + s + ": widen the space there";
}

ScoreComparison compare_scores(double winner, double runner_up, const std::vector<double>& w_frames,
                               const std::vector<double>& r_frames, double w_ci95, double r_ci95) {
  ScoreComparison c;
  c.delta = winner - runner_up;
  c.ci95 = NAN;
  if (!w_frames.empty() && w_frames.size() == r_frames.size()) {
    std::vector<double> d;
    for (size_t i = 0; i < w_frames.size(); ++i)
      if (std::isfinite(w_frames[i]) && std::isfinite(r_frames[i]))
        d.push_back(w_frames[i] - r_frames[i]);
    const MeanInterval mi = mean_interval(d);
    if (std::isfinite(mi.half_width)) {
      c.ci95 = mi.half_width;
      c.paired = true;
      c.frames = d.size();
    } else {
      c.why = mi.why;
    }
  }
  if (!c.paired && std::isfinite(w_ci95) && std::isfinite(r_ci95))
    c.ci95 = std::sqrt(w_ci95 * w_ci95 + r_ci95 * r_ci95);
  if (std::isfinite(c.ci95) && std::isfinite(c.delta)) {
    c.tied = std::fabs(c.delta) <= c.ci95 ? 1 : 0;
    c.why.clear();
  } else if (c.why.empty()) {
    c.why = "no 95% interval of either score";
  }
  return c;
}

std::string describe_comparison(const ScoreComparison& c, const std::string& column) {
  char buf[160];
  if (c.tied < 0) {
    std::snprintf(buf, sizeof buf, "winner - runner-up %s %+.4g, noise unknown: ", column.c_str(),
                  c.delta);
    return buf + c.why;
  }
  std::snprintf(buf, sizeof buf, "(%s %+.4g ± %.4g, %s)", column.c_str(), c.delta, c.ci95,
                c.paired ? ("paired over " + std::to_string(c.frames) + " frames").c_str()
                         : "intervals of the two means");
  return std::string(c.tied ? "winner and runner-up tied within noise "
                            : "winner beats runner-up beyond noise ") +
         buf;
}

bool is_frame_budget_column(const std::string& c) {
  return c == "headroom_ms" || c == "fits_budget" || c == "p_fit" ||
         c.rfind("est_ms_total", 0) == 0;
}

std::vector<std::string> non_binding_constraints(const SearchSpec& sp,
                                                 const std::vector<std::vector<double>>& values) {
  std::vector<std::string> out;
  if (values.empty()) return out;
  for (size_t k = 0; k < sp.constraints.size(); ++k) {
    const SearchConstraint& c = sp.constraints[k];
    bool violated = false;
    double lo = INFINITY, hi = -INFINITY;
    for (auto& v : values) {
      const double x = k < v.size() ? v[k] : NAN;
      if (std::isnan(x) || x < c.min || x > c.max) violated = true;
      if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
    }
    if (violated) continue;
    out.push_back("constraint " + c.describe() + " does not bind: all " +
                  std::to_string(values.size()) + " evaluated points meet it (" + c.column +
                  " from " + format_number(lo) + " to " + format_number(hi) + ")");
  }
  return out;
}

std::string budget_sentence(const std::string& what, double ms, double budget_ms) {
  if (!(std::isfinite(ms) && std::isfinite(budget_ms) && ms <= budget_ms)) return "";
  char buf[96];
  std::snprintf(buf, sizeof buf, " fits at %.2f ms of %.2f ms", ms, budget_ms);
  return "budget does not bind: " + what + buf;
}

}  // namespace fovsim
