#include "sim/experiment/memory_plan.h"

#include <algorithm>

#include "sim/core/memory_info.h"
#include "sim/experiment/cell.h"

namespace fovsim {

double MemoryEstimator::cell(const Cell& c) const {
  const MetricsConfig& m = c.metric.cfg;
  const Seq q = sequence(m);
  double b = 0;
  for (auto& mr : c.methods) {
    const bool fl = m.foveation_loss && !aliased(side_taa(c, mr));
    b += 3 * image() + frame_metrics_state_bytes(m, pixels()) + q.test + (fl ? q.borrowing : 0) +
         double(TaaPass::bytes(sh.sim_display.width, sh.sim_display.height, mr.impl->taa()));
  }
  b += double(sh.count) * double(c.methods.size() * c.cost.gpus.size()) * 4096;
  return b;
}

double MemoryEstimator::workspace(const Cell& c) const {
  const MetricsConfig& m = c.metric.cfg;
  bool any_fl = false;
  double taa = 0;
  for (auto& mr : c.methods) {
    any_fl = any_fl || (m.foveation_loss && !aliased(side_taa(c, mr)));
    taa = std::max(taa, double(TaaPass::scratch_bytes(sh.sim_display.width, sh.sim_display.height,
                                                      mr.impl->taa())));
  }
  return image() + scratch(m) + (any_fl ? scratch(m) : 0) + sequence(m).scratch + taa;
}

double MemoryPlan::workspaces(size_t p) const {
  double w = 0;
  for (size_t i : passes[p]) w = std::max(w, workspace[i]);
  return w * double(std::min(passes[p].size(), size_t(std::max(threads, 1))));
}

Json MemoryPlan::record(size_t p, size_t sides_in_pass, double side_bytes, double seq_ref,
                        const std::string& fl_reference) const {
  double pass_bytes = group + double(sides_in_pass) * side_bytes + workspaces(p);
  for (size_t i : passes[p]) pass_bytes += cell[i];
  return Json{{"budget_bytes", std::isfinite(budget) ? Json(budget) : Json("unlimited")},
              {"budget_from", budget_from},
              {"passes", passes.size()},
              {"pass", p + 1},
              {"cells_in_pass", passes[p].size()},
              {"reference_sides", sides_in_pass},
              {"foveation_loss_reference", fl_reference},
              {"resident_at_start_bytes", resident},
              {"estimate_bytes",
               {{"group", group},
                {"reference_side", side_bytes},
                {"sequence_reference", seq_ref},
                {"cell", cell.empty() ? 0.0 : cell[passes[p].front()]},
                {"workspaces", workspaces(p)},
                {"pass", pass_bytes}}}};
}

// The budget (--memory-budget, run.memory_gb, else 75% of MemAvailable) and the passes: cells
// in order, as many per pass as the estimate fits in what the budget leaves after the memory
// resident now and the group's shared data; at least one per pass.
MemoryPlan plan_memory(const EngineOptions& opt, const Shared& sh,
                       const std::vector<std::unique_ptr<Cell>>& cells,
                       const MemoryEstimator& est) {
  MemoryPlan p;
  if (opt.memory_budget_gb > 0) {
    p.budget = opt.memory_budget_gb * 1e9;
    p.budget_from = "--memory-budget";
  } else if (sh.memory_gb > 0) {
    p.budget = sh.memory_gb * 1e9;
    p.budget_from = "run.memory_gb";
  } else if (const uint64_t avail = available_memory_bytes(); avail > 0) {
    p.budget = 0.75 * double(avail);
    p.budget_from = "75% of MemAvailable";
  } else {
    p.budget_from = "unlimited (MemAvailable unreadable)";
  }
  p.resident = double(current_rss_bytes());
  p.group = est.group();
  p.threads = std::max(est.threads, 1);
  const double room = p.budget - p.resident - p.group;
  std::vector<std::string> keys;  // the metrics blocks of the current pass (one side each)
  double used = 0;                // sides and cells of the current pass
  double ws_max = 0;              // its largest workspace
  auto ws_total = [&](size_t n, double w) { return w * double(std::min(n, size_t(p.threads))); };
  for (size_t i = 0; i < cells.size(); ++i) {
    const Cell& c = *cells[i];
    p.cell.push_back(est.cell(c));
    p.workspace.push_back(est.workspace(c));
    // The reference sides its methods need that the pass does not hold yet.
    auto new_sides = [&] {
      double b = 0;
      std::vector<std::string> seen = keys;
      for (auto& m : c.methods) {
        const std::string key = method_side_key(c, m);
        if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
        seen.push_back(key);
        b += est.side(c.metric.cfg, side_taa(c, m));
      }
      return b;
    };
    const double cost = p.cell.back() + new_sides();
    const size_t n = p.passes.empty() ? 0 : p.passes.back().size();
    const double ws_after = ws_total(n + 1, std::max(ws_max, p.workspace.back()));
    if (p.passes.empty() || (used + cost + ws_after > room && !p.passes.back().empty())) {
      p.passes.emplace_back();
      keys.clear();
      used = 0;
      ws_max = 0;
    }
    ws_max = std::max(ws_max, p.workspace.back());
    used += new_sides();
    for (auto& m : c.methods) {
      const std::string key = method_side_key(c, m);
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
    }
    used += p.cell.back();
    p.passes.back().push_back(i);
  }
  return p;
}

}  // namespace fovsim
