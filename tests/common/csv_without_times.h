// A CSV text without its wall-time columns (ref_ms, sim_ms and their intervals): the part of
// a run's output that must be byte-identical between runs (cache, memo and plain runs).
#pragma once
#include <sstream>
#include <string>
#include <vector>

namespace fovsim::test {

inline std::string csv_without_times(const std::string& csv) {
  std::istringstream in(csv);
  std::string line, out;
  std::vector<bool> keep;
  bool header = true;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ls(line);
    std::string x;
    while (std::getline(ls, x, ',')) f.push_back(x);
    if (header) {
      for (auto& h : f) keep.push_back(h.rfind("ref_ms", 0) != 0 && h.rfind("sim_ms", 0) != 0);
      header = false;
    }
    for (size_t i = 0; i < f.size(); ++i)
      if (i >= keep.size() || keep[i]) out += f[i] + ",";
    out += "\n";
  }
  return out;
}

}  // namespace fovsim::test
