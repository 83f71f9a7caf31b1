// The method lists tests iterate, taken from the registry (sim/foveation/method_list.h), so a
// test that should hold for every method of a kind covers a new method without an edit.
// SourceScan.MethodNamesAreListedOnlyInTheRegistry fails on a hand-written list of method names
// anywhere else that does not say why it is a subset.
#pragma once
#include <string>
#include <vector>

#include "sim/foveation/factory.h"

namespace fovsim::test {

// Every registered method, in registration order.
inline const std::vector<std::string>& all_methods() {
  return method_names();
}

// The methods whose parameter table declares `key` ("sigma", "radius_scale", ...).
inline std::vector<std::string> methods_with_key(const std::string& key) {
  std::vector<std::string> out;
  for (const MethodEntry& e : method_table())
    for (const ParamInfo& p : e.params())
      if (key == p.name) {
        out.push_back(e.name);
        break;
      }
  return out;
}

// The methods whose shading rate an iso-budget target sets (key target_shaded_fraction).
inline std::vector<std::string> iso_budget_methods() {
  return methods_with_key("target_shaded_fraction");
}

// The baselines whose foveal region is two eccentricity radii (key radius_scale).
inline std::vector<std::string> radial_methods() {
  return methods_with_key("radius_scale");
}

}  // namespace fovsim::test
