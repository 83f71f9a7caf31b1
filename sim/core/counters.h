// Per-frame counters a method fills for the cost model and frames.csv, keyed by the declared
// ids of sim/core/counter_list.h (a misspelt counter does not compile). Ordered by first
// insertion so CSV columns are stable. Not used in per-pixel loops.
#pragma once
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sim/core/counter_list.h"

namespace fovsim {

class Counters {
 public:
  struct Entry {
    CounterKey key;
    double value;
  };
  void set(Counter id, double v) { slot({id}) = v; }
  void add(Counter id, double v) { slot({id}) += v; }
  void set(Counter id, int index, double v) { slot({id, index}) = v; }  // indexed families
  void add(CounterKey k, double v) { slot(k) += v; }
  double get(Counter id, double fallback = 0.0) const { return get(CounterKey{id}, fallback); }
  double get(CounterKey k, double fallback = 0.0) const {
    for (auto& e : items_)
      if (e.key == k) return e.value;
    return fallback;
  }
  bool has(Counter id) const { return has(CounterKey{id}); }
  bool has(CounterKey k) const {
    for (auto& e : items_)
      if (e.key == k) return true;
    return false;
  }
  // A counter read back by its column name (a results file, the reference cache); false (and
  // nothing set) for a name no counter has.
  bool set_named(std::string_view name, double v) {
    auto k = find_counter(name);
    if (!k) return false;
    slot(*k) = v;
    return true;
  }
  const std::vector<Entry>& entries() const { return items_; }
  // (column name, value) in insertion order: what frames.csv writes.
  std::vector<std::pair<std::string, double>> items() const {
    std::vector<std::pair<std::string, double>> v;
    v.reserve(items_.size());
    for (auto& e : items_) v.emplace_back(e.key.name(), e.value);
    return v;
  }
  void merge(const Counters& o) {
    for (auto& e : o.items_) slot(e.key) += e.value;
  }
  void clear() { items_.clear(); }

 private:
  double& slot(CounterKey k) {
    for (auto& e : items_)
      if (e.key == k) return e.value;
    items_.push_back({k, 0.0});
    return items_.back().value;
  }
  std::vector<Entry> items_;
};

}  // namespace fovsim
