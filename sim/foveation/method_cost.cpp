// Helpers of the methods' cost declarations (method_cost.h).
#include "sim/foveation/method_cost.h"

#include <cmath>

namespace fovsim {

double AnalyticFrame::column(const std::string& key, double def) const {
  if (columns)
    for (auto& [n, v] : *columns)
      if (n == key) return v;
  return def;
}

namespace {

std::vector<double> coarser_buffer_steps(double s0) {
  std::vector<double> v;
  for (int k = 1; s0 + 0.1 * k <= 4.0 + 1e-9; ++k)
    v.push_back(std::round((s0 + 0.1 * k) * 10) / 10);
  return v;
}

std::vector<double> halved_count_steps(double b0) {
  std::vector<double> v;
  for (double b = std::floor(b0 / 2); b >= 64; b = std::floor(b / 2)) v.push_back(b);
  return v;
}

}  // namespace

BudgetKnob coarser_buffer_knob(const char* key, double value) {
  BudgetKnob k;
  k.key = key;
  k.value = value;
  k.steps = coarser_buffer_steps;
  k.decimals = 1;
  return k;
}

BudgetKnob halved_count_knob(const char* key, double value) {
  BudgetKnob k;
  k.key = key;
  k.value = value;
  k.steps = halved_count_steps;
  k.decimals = 0;
  k.integer = true;
  return k;
}

}  // namespace fovsim
