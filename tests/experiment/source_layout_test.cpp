// The experiment layer's layout (docs/architecture.md "The experiment folder"): the frame
// engine stays split by concern (engine.cpp is the frame loop; each concern of a cell has its
// own file), the engine and `fovsim run`'s runner do not include each other, no experiment file
// reaches up into the command line, and the engine names no per-frame metric (they come from
// the registry, sim/metrics/frame_metric.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::string kRoot = FOVSIM_SOURCE_DIR;

std::vector<std::string> lines_of(const std::string& rel) {
  std::ifstream f(kRoot + "/" + rel);
  std::vector<std::string> out;
  for (std::string l; std::getline(f, l);) out.push_back(l);
  return out;
}

// The project headers `rel` includes ("sim/...").
std::vector<std::string> includes_of(const std::string& rel) {
  static const std::regex inc(R"re(^\s*#\s*include\s+"(sim/[^"]+)")re");
  std::vector<std::string> out;
  std::smatch m;
  for (const std::string& l : lines_of(rel))
    if (std::regex_search(l, m, inc)) out.push_back(m[1]);
  return out;
}

// Every file `rel` includes, directly or through other project headers.
std::set<std::string> include_closure(const std::string& rel) {
  std::set<std::string> seen;
  std::vector<std::string> todo{rel};
  while (!todo.empty()) {
    const std::string f = todo.back();
    todo.pop_back();
    for (const std::string& h : includes_of(f))
      if (seen.insert(h).second) todo.push_back(h);
  }
  return seen;
}

std::vector<std::string> experiment_sources() {
  std::vector<std::string> out;
  for (auto& e : fs::directory_iterator(kRoot + "/sim/experiment")) {
    const std::string ext = e.path().extension().string();
    if (ext == ".cpp" || ext == ".h")
      out.push_back("sim/experiment/" + e.path().filename().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(SourceScan, EngineStaysTheFrameLoop) {
  const size_t n = lines_of("sim/experiment/engine.cpp").size();
  EXPECT_GT(n, 100u) << "engine.cpp not found";
  EXPECT_LE(n, 800u) << "sim/experiment/engine.cpp has " << n
                     << " lines: give the new concern its own file, "
                     << "docs/architecture.md \"The experiment folder\"";
}

TEST(SourceScan, EngineAndRunnerDoNotIncludeEachOther) {
  for (const char* f : {"sim/experiment/engine.cpp", "sim/experiment/engine.h"}) {
    const auto c = include_closure(f);
    EXPECT_EQ(c.count("sim/experiment/runner.h"), 0u) << f << " reaches runner.h";
  }
  // Every file the engine is split into, too.
  for (const std::string& f : experiment_sources())
    if (f.find("/cell") != std::string::npos || f.find("/reference_side") != std::string::npos ||
        f.find("/shared_config") != std::string::npos ||
        f.find("/memory_plan") != std::string::npos || f.find("/summary") != std::string::npos)
      EXPECT_EQ(include_closure(f).count("sim/experiment/runner.h"), 0u) << f;
  EXPECT_EQ(include_closure("sim/experiment/runner.h").count("sim/experiment/engine.h"), 0u)
      << "runner.h reaches engine.h";
}

TEST(SourceScan, ExperimentFilesDoNotIncludeTheCommandLine) {
  for (const std::string& f : experiment_sources())
    for (const std::string& h : include_closure(f))
      EXPECT_NE(h.rfind("sim/app/", 0), 0u) << f << " includes " << h;
}

TEST(SourceScan, EngineNamesNoPerFrameMetric) {
  // Outside comments, the engine's files reach per-frame metrics only through the registry.
  static const std::regex named(
      R"(\bflip\w*|\bssim\w*|\bfpsnr\b|\bcfg\.(psnr|regions|temporal)\b)");
  for (const std::string& f : experiment_sources()) {
    const std::string name = fs::path(f).filename().string();
    if (name.rfind("engine", 0) != 0 && name.rfind("cell", 0) != 0 &&
        name.rfind("reference_side", 0) != 0 && name.rfind("memory_plan", 0) != 0)
      continue;
    int n = 0;
    for (const std::string& l : lines_of(f)) {
      ++n;
      const size_t c = l.find("//");
      const std::string code = c == std::string::npos ? l : l.substr(0, c);
      EXPECT_FALSE(std::regex_search(code, named)) << f << ":" << n << ": " << l;
    }
  }
}
