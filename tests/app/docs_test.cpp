// The method tables in docs/methods.md and configs/README.md are the ones generated from the
// methods' declarations (`fovsim methods --markdown`); regenerate with `make docs`.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "sim/core/counter_list.h"
#include "sim/cost/gpu_profile.h"
#include "sim/experiment/run_config.h"
#include "sim/foveation/factory.h"
#include "sim/trace/map_keys.h"

namespace {
std::string generated_section(const std::string& rel, const char* begin = fovsim::kMethodDocsBegin,
                              const char* end = fovsim::kMethodDocsEnd) {
  std::ifstream f(std::string(FOVSIM_SOURCE_DIR) + "/" + rel);
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string s = ss.str();
  auto b = s.find(begin);
  auto e = s.find(end);
  if (b == std::string::npos || e == std::string::npos || e < b)
    return "<markers missing in " + rel + ">";
  b = s.find('\n', b) + 1;
  return s.substr(b, e - b);
}
}  // namespace

TEST(Docs, MethodTablesMatchDeclarations) {
  const std::string want = "\n" + fovsim::methods_markdown();
  for (const char* f : {"docs/methods.md", "configs/README.md"})
    EXPECT_EQ(generated_section(f), want) << f << " differs from the declarations: run `make docs`";
}

// Every counter is documented in docs/cost_model.md by the table generated from its
// declaration (sim/core/counter_list.h).
TEST(Docs, CounterTableMatchesDeclarations) {
  const std::string want = "\n" + fovsim::counters_markdown();
  EXPECT_EQ(
      generated_section("docs/cost_model.md", fovsim::kCounterDocsBegin, fovsim::kCounterDocsEnd),
      want)
      << "docs/cost_model.md differs from the counter list: run `make docs`";
}

// The column map's keys in traces/README.md are the table the importer reads them through
// (sim/trace/map_keys.cpp).
TEST(Docs, MapKeyTableMatchesDeclarations) {
  const std::string want = "\n" + fovsim::map_keys_markdown();
  EXPECT_EQ(generated_section("traces/README.md", fovsim::kMapKeyDocsBegin, fovsim::kMapKeyDocsEnd),
            want)
      << "traces/README.md differs from the map-key declarations: run `make docs`";
}

// docs/cost_model.md "GPU profile" is the table generated from gpu_profile_keys().
TEST(Docs, GpuProfileKeyTableMatchesDeclarations) {
  const std::string want = "\n" + fovsim::gpu_profile_keys_markdown();
  EXPECT_EQ(generated_section("docs/cost_model.md", fovsim::kProfileKeyDocsBegin,
                              fovsim::kProfileKeyDocsEnd),
            want)
      << "docs/cost_model.md differs from the GPU-profile key declarations: run `make docs`";
}

// Docs, --help and every comment name papers by author and year (README.md "References") and
// point into docs/architecture.md, never to internal handles a reader cannot resolve: a seed
// paper's number, a section of a design document kept outside the repository, a tracker number.
const std::regex& handle_pattern() {
  static const std::regex bad(R"(seed 00[0-9]|DESIGN(\.md)? §|\b[Ii]ssues? #?[0-9]+\b)");
  return bad;
}

// Every other run-config key (top level, render, frames, outputs, metrics, latency, GPU spec)
// is documented in configs/README.md by the tables generated from its declaration.
TEST(Docs, ConfigKeyTablesMatchDeclarations) {
  const std::string want = "\n" + fovsim::config_keys_markdown();
  EXPECT_EQ(
      generated_section("configs/README.md", fovsim::kConfigDocsBegin, fovsim::kConfigDocsEnd),
      want)
      << "configs/README.md differs from the declarations: run `make docs`";
  EXPECT_FALSE(std::regex_search(want, handle_pattern()));
}

// User-facing docs and --help name papers by author and year (README.md "References"), never
// by internal handles a reader cannot resolve.
TEST(Docs, UserDocsCitePapersNotInternalHandles) {
  const std::regex& bad = handle_pattern();
  std::vector<std::string> files{"README.md", "configs/README.md", "traces/README.md",
                                 "results/README.md", "models/scenes/README.md"};
  for (auto& e : std::filesystem::directory_iterator(std::string(FOVSIM_SOURCE_DIR) + "/docs"))
    if (e.path().extension() == ".md") files.push_back("docs/" + e.path().filename().string());
  for (auto& rel : files) {
    std::ifstream f(std::string(FOVSIM_SOURCE_DIR) + "/" + rel);
    std::string line;
    for (int n = 1; std::getline(f, line); ++n)
      EXPECT_FALSE(std::regex_search(line, bad)) << rel << ":" << n << ": " << line;
  }
  const std::string summary = fovsim::methods_markdown();
  EXPECT_FALSE(std::regex_search(summary, bad)) << "fovsim methods --markdown cites a handle";
  std::ifstream readme(std::string(FOVSIM_SOURCE_DIR) + "/README.md");
  std::stringstream ss;
  ss << readme.rdbuf();
  EXPECT_NE(ss.str().find("## References"), std::string::npos);
  for (const char* f : {"LICENSE", "CITATION.cff"})
    EXPECT_TRUE(std::filesystem::exists(std::string(FOVSIM_SOURCE_DIR) + "/" + f)) << f;
}

// The same for the code and data: sources, tests, Python, plots, scripts, benchmarks, configs
// and models (their "source" strings end up in `fovsim methods`, manifests and plots).
TEST(Docs, CodeCitesPapersNotInternalHandles) {
  namespace fs = std::filesystem;
  const std::regex& bad = handle_pattern();
  const fs::path root(FOVSIM_SOURCE_DIR);
  const std::vector<std::string> exts{".cpp", ".h", ".inc", ".py", ".sh", ".json", ".md", ".txt"};
  int scanned = 0;
  for (const char* dir :
       {"sim", "tests", "python", "viz", "scripts", "bench", "configs", "models"}) {
    if (!fs::is_directory(root / dir)) continue;
    for (auto& e : fs::recursive_directory_iterator(root / dir)) {
      if (!e.is_regular_file()) continue;
      const fs::path& p = e.path();
      const std::string rel = fs::relative(p, root).generic_string();
      if (std::find(exts.begin(), exts.end(), p.extension().string()) == exts.end()) continue;
      if (rel.rfind("tests/golden/", 0) == 0 || rel.rfind("tests/fuzz/corpus/", 0) == 0 ||
          e.file_size() > (4u << 20))
        continue;
      std::ifstream f(p);
      std::string line;
      for (int n = 1; std::getline(f, line); ++n)
        EXPECT_FALSE(std::regex_search(line, bad)) << rel << ":" << n << ": " << line;
      ++scanned;
    }
  }
  for (const char* f : {"CMakeLists.txt", "Makefile"}) {
    std::ifstream in(root / f);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n)
      EXPECT_FALSE(std::regex_search(line, bad)) << f << ":" << n << ": " << line;
  }
  EXPECT_GT(scanned, 300);  // the walk found the tree
}

// Comments and docs cite docs/architecture.md by section title (`docs/architecture.md "Cost
// model"`, several as `"A", "B"`), never by number: every title cited is a heading there
// (`## ` or `### `), and no file cites a number ("§6") but those
// tests/style/architecture_citations_pending.txt still lists. A citation may wrap across
// comment lines.
TEST(Docs, CitedArchitectureSectionsExist) {
  namespace fs = std::filesystem;
  const fs::path root(FOVSIM_SOURCE_DIR);
  auto slurp = [](const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
  };
  // One line: comment markers at line starts dropped, whitespace runs made one space.
  auto joined = [](const std::string& s) {
    static const std::regex wrap(R"(\s*\n\s*(//+|#+|\*)?\s*)");
    return std::regex_replace(s, wrap, " ");
  };
  std::set<std::string> titles;
  {
    std::ifstream f(root / "docs/architecture.md");
    std::string line;
    while (std::getline(f, line))
      if (line.rfind("## ", 0) == 0 || line.rfind("### ", 0) == 0)
        titles.insert(line.substr(line.find(' ') + 1));
  }
  ASSERT_TRUE(titles.count("Data flow of one frame"));
  std::set<std::string> pending;
  {
    std::ifstream f(root / "tests/style/architecture_citations_pending.txt");
    std::string line;
    while (std::getline(f, line))
      if (!line.empty() && line[0] != '#') pending.insert(line);
  }
  // architecture.md, then one or more quoted titles separated by ", " (quotes may be escaped
  // inside a C++ string, or single inside a Python one).
  static const std::regex cite(
      R"re(architecture\.md[,:]? (\\?["'][^"'\\]+\\?["'](, \\?["'][^"'\\]+\\?["'])*))re");
  static const std::regex quoted(R"re(\\?["']([^"'\\]+)\\?["'])re");
  static const std::regex numbered(R"(architecture\.md[,:]? §)");
  const std::vector<std::string> exts{".cpp", ".h", ".inc", ".py", ".sh", ".json", ".md", ".txt"};
  std::vector<fs::path> files{root / "CMakeLists.txt", root / "Makefile", root / "README.md"};
  for (const char* dir : {"sim", "tests", "python", "viz", "scripts", "bench", "configs", "models",
                          "docs", "results", "traces"}) {
    if (!fs::is_directory(root / dir)) continue;
    for (auto& e : fs::recursive_directory_iterator(root / dir)) {
      const fs::path& p = e.path();
      if (!e.is_regular_file() || e.file_size() > (1u << 20)) continue;
      if (std::find(exts.begin(), exts.end(), p.extension().string()) == exts.end()) continue;
      const std::string rel = fs::relative(p, root).generic_string();
      if (rel.rfind("tests/golden/", 0) == 0 || rel.rfind("tests/fuzz/corpus/", 0) == 0) continue;
      files.push_back(p);
    }
  }
  int cited = 0;
  for (const fs::path& p : files) {
    const std::string rel = fs::relative(p, root).generic_string();
    if (rel == "tests/app/docs_test.cpp") continue;  // this test's own examples
    const std::string raw = slurp(p);
    if (raw.find("architecture.md") == std::string::npos) continue;
    const std::string text = joined(raw);
    if (!pending.count(rel)) {
      EXPECT_FALSE(std::regex_search(text, numbered))
          << rel << " cites docs/architecture.md by section number: cite its title";
    }
    for (std::sregex_iterator it(text.begin(), text.end(), cite), end; it != end; ++it) {
      const std::string list = (*it)[1];
      for (std::sregex_iterator q(list.begin(), list.end(), quoted); q != end; ++q) {
        ++cited;
        EXPECT_TRUE(titles.count((*q)[1])) << rel << " cites docs/architecture.md \"" << (*q)[1]
                                           << "\", which is not a section title there";
      }
    }
  }
  EXPECT_GT(cited, 40);  // the scan found the citations
}
