// Named values in insertion order (the metrics of a frame: psnr, ssim, rmse_ecc_<a>_<b>, ...),
// keyed by free strings because metric columns are built from the config. Counters, which are
// declared, are sim/core/counters.h. Ordered by first insertion so CSV columns are stable.
#pragma once
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fovsim {

class NamedValues {
 public:
  void set(std::string_view name, double v) { slot(name) = v; }
  void add(std::string_view name, double v) { slot(name) += v; }
  double get(std::string_view name, double fallback = 0.0) const {
    for (auto& kv : items_)
      if (kv.first == name) return kv.second;
    return fallback;
  }
  bool has(std::string_view name) const {
    for (auto& kv : items_)
      if (kv.first == name) return true;
    return false;
  }
  const std::vector<std::pair<std::string, double>>& items() const { return items_; }
  void merge(const NamedValues& o) {
    for (auto& kv : o.items_) add(kv.first, kv.second);
  }
  void clear() { items_.clear(); }

 private:
  double& slot(std::string_view name) {
    for (auto& kv : items_)
      if (kv.first == name) return kv.second;
    items_.emplace_back(std::string(name), 0.0);
    return items_.back().second;
  }
  std::vector<std::pair<std::string, double>> items_;
};

}  // namespace fovsim
