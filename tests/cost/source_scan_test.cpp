// The cost layer knows no method by its name (docs/architecture.md "Cost model"): a method declares
// its cost in its own file (sim/foveation/method_cost.h), so no file under sim/cost/ compares with,
// or branches on, a method's or lighting strategy's name. The names come from the registry
// (method_list.h, lighting_list.h) when the test runs, so a new method is covered the day it
// is registered.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "sim/cost/gpu_profile.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/lighting.h"

namespace fovsim {
namespace {

namespace fs = std::filesystem;

struct Literal {
  int line;
  std::string text;
};

// The string literals of C++ source `src` outside comments (contents as written; raw strings
// included), with their line numbers.
std::vector<Literal> string_literals(const std::string& src) {
  std::vector<Literal> out;
  int line = 1;
  const size_t n = src.size();
  auto ident = [&](size_t i) {
    return i < n && (std::isalnum(static_cast<unsigned char>(src[i])) || src[i] == '_');
  };
  for (size_t i = 0; i < n; ++i) {
    const char c = src[i];
    if (c == '\n') {
      ++line;
    } else if (c == '/' && i + 1 < n && src[i + 1] == '/') {
      while (i < n && src[i] != '\n') ++i;
      --i;
    } else if (c == '/' && i + 1 < n && src[i + 1] == '*') {
      for (i += 2; i + 1 < n && !(src[i] == '*' && src[i + 1] == '/'); ++i)
        if (src[i] == '\n') ++line;
      ++i;
    } else if (c == '\'' && !(i > 0 && ident(i - 1))) {  // a character literal, not 1'000
      for (++i; i < n && src[i] != '\''; ++i)
        if (src[i] == '\\') ++i;
    } else if (c == 'R' && i + 1 < n && src[i + 1] == '"' && !(i > 0 && ident(i - 1))) {
      const size_t open = src.find('(', i + 2);
      if (open == std::string::npos) break;
      const std::string close = ")" + src.substr(i + 2, open - i - 2) + "\"";
      const size_t end = src.find(close, open);
      if (end == std::string::npos) break;
      const std::string body = src.substr(open + 1, end - open - 1);
      out.push_back({line, body});
      line += int(std::count(body.begin(), body.end(), '\n'));
      i = end + close.size() - 1;
    } else if (c == '"') {
      std::string text;
      for (++i; i < n && src[i] != '"'; ++i) {
        if (src[i] == '\\' && i + 1 < n) text += src[i++];
        text += src[i];
      }
      out.push_back({line, text});
    }
  }
  return out;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(SourceScan, CostLayerKnowsNoMethodByName) {
  // The lexer finds a literal in code and none in comments.
  const auto probe = string_literals("a = \"x\"; // \"y\"\n/* \"z\" */ b = R\"(w)\"; c = '\"';\n");
  ASSERT_EQ(probe.size(), 2u);
  EXPECT_EQ(probe[0].text, "x");
  EXPECT_EQ(probe[1].text, "w");
  EXPECT_EQ(probe[1].line, 2);

  std::set<std::string> names;
  for (const MethodEntry& e : method_table()) names.insert(e.name);
  for (const LightingEntry& e : lighting_table()) names.insert(e.name);
  ASSERT_FALSE(names.empty());
  // The seeds' published tables keep their methods' names (validate.cpp's units are those
  // tables); gpu_profile.cpp declares the cost model kinds, one of which is also a word a
  // method is named by ("linear": the first version's linear model, not the baseline).
  const std::string validation = "validate.cpp";
  const std::set<std::string> model_kinds = {model_name(CostModelKind::Linear),
                                             model_name(CostModelKind::Roofline)};
  const fs::path dir = fs::path(FOVSIM_SOURCE_DIR) / "sim" / "cost";
  std::vector<fs::path> files;
  for (const auto& f : fs::directory_iterator(dir))
    if (f.path().extension() == ".cpp" || f.path().extension() == ".h") files.push_back(f.path());
  std::sort(files.begin(), files.end());
  ASSERT_GT(files.size(), 10u);
  std::string hits;
  for (const fs::path& f : files) {
    const std::string file = f.filename().string();
    if (file == validation) continue;
    for (const Literal& l : string_literals(slurp(f))) {
      if (!names.count(l.text)) continue;
      if (file == "gpu_profile.cpp" && model_kinds.count(l.text)) continue;
      hits += "sim/cost/" + file + ":" + std::to_string(l.line) + ": \"" + l.text + "\"\n";
    }
  }
  EXPECT_TRUE(hits.empty())
      << "the cost layer names a method or lighting strategy; declare the behaviour in the "
         "method's own file instead (MethodCost, FoveationMethod::analytic_counters, "
         "budget_knob, widen_cost_keys: sim/foveation/method_cost.h):\n"
      << hits;
}

}  // namespace
}  // namespace fovsim
