// Each method's and lighting strategy's declaration (its ParamTable: the rows the parser
// reads and the docs are generated from) reads its own defaults: every declared key is
// accepted at its declared default, the value an empty block resolves to is the declared
// default (the resolved document records every read), the parsed default equals the declared
// one wherever the method reports it as a CSV column, a value below a declared range is an
// error naming the key, and an undeclared key is an error naming it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "sim/core/error.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/lighting_flc.h"
#include "sim/foveation/mapping_spec.h"
#include "tests/common/method_lists.h"
#include "tests/common/param_table_check.h"

using namespace fovsim;

namespace {
bool no_default(const char* d) {
  return !*d || !std::strcmp(d, "none") || !std::strcmp(d, "-") || !std::strcmp(d, "—");
}
Json default_json(const ParamInfo& p) {
  const std::string t = p.type;
  if (t == "bool") return Json(std::string(p.def) == "true");
  if (t == "string") return Json(std::string(p.def));
  char* end = nullptr;
  const double v = std::strtod(p.def, &end);
  if (t == "int") return Json(static_cast<long long>(v));
  return Json(v);
}
}  // namespace

TEST(MethodDecl, DeclaredKeysAcceptedAtTheirDefaults) {
  for (const auto& e : method_table())
    for (const ParamInfo& p : e.params()) {
      if (no_default(p.def)) continue;
      SCOPED_TRACE(std::string(e.name) + "." + p.name + " = " + p.def);
      Params params(Json{{p.name, default_json(p)}}, "test", e.name);
      EXPECT_NO_THROW(make_method(e.name, params));
    }
}

TEST(MethodDecl, ParsedDefaultsEqualDeclaredDefaults) {
  int checked = 0;
  for (const auto& e : method_table()) {
    Params params(Json::object(), "test", e.name);
    const auto cols = make_method(e.name, params)->param_columns();
    for (const ParamInfo& p : e.params()) {
      const std::string t = p.type;
      if (no_default(p.def) || (t != "number" && t != "int")) continue;
      // flc's lp_sigma column is the effective buffer ratio: 1 while log_polar is off.
      if (std::string(e.name) == "flc" && std::string(p.name) == "lp_sigma") continue;
      for (const auto& [k, v] : cols)
        if (k == p.name) {
          EXPECT_DOUBLE_EQ(v, std::strtod(p.def, nullptr)) << e.name << "." << p.name;
          ++checked;
        }
    }
  }
  EXPECT_GE(checked,
            15);  // sigma, alpha, fx, fy, r1, r2, s1..s3, p_min, epsilon, A, D, vpl_budget, ...
}

TEST(MethodDecl, UndeclaredKeyIsAnErrorNamingIt) {
  for (const auto& e : method_table()) {
    Params params(Json{{"sigam", 1.8}}, "test.json", std::string("methods[") + e.name + "]");
    try {
      make_method(e.name, params);
      ADD_FAILURE() << e.name << " accepted an undeclared key";
    } catch (const Error& err) {
      EXPECT_NE(std::string(err.what()).find("sigam"), std::string::npos) << err.what();
    }
  }
}

TEST(MethodDecl, MappingAndLightingTablesReadTheirOwnDefaults) {
  int tables = 0;
  for (const auto& e : method_table()) {
    Params params(Json::object(), "test", e.name);
    const auto m = make_method(e.name, params);
    const MappingSpec* s = m->mapping_spec();
    if (!s || std::string(e.name) == "rmfr_auto") continue;  // rmfr_auto: rmfr inside
    fovsim::table_check::expect_table_reads_own_defaults(s->geometry().table(), e.name, *s);
    ++tables;
  }
  EXPECT_GE(tables, 5);  // kfr, rmfr, hyperbolic, linear, fvrs and any mapping method added
  fovsim::table_check::expect_table_reads_own_defaults(flc_lighting_table(), "lighting");
}

// Every key with a declared default resolves to it when the block is empty (the resolved
// document is what manifest.json records), for every method and lighting strategy.
TEST(MethodDecl, EmptyBlockResolvesToDeclaredDefaults) {
  auto check = [](const std::string& what, const Json& resolved,
                  const std::vector<ParamInfo>& decl) {
    for (const ParamInfo& p : decl) {
      if (no_default(p.def)) continue;
      SCOPED_TRACE(what + "." + p.name);
      ASSERT_TRUE(resolved.contains(p.name)) << resolved.dump();
      const Json& v = resolved[p.name];
      if (v.is_number())
        EXPECT_NEAR(v.get<double>(), std::strtod(p.def, nullptr),
                    1e-5 * std::max(1.0, std::fabs(v.get<double>())));
      else if (v.is_boolean())
        EXPECT_EQ(v.get<bool>() ? "true" : "false", std::string(p.def));
      else
        EXPECT_EQ(v.get<std::string>(), std::string(p.def));
    }
  };
  for (const auto& e : method_table()) {
    Params params(Json::object(), "test", "");
    make_method(e.name, params);
    check(e.name, params.resolved(), e.params());
  }
  for (const auto& e : lighting_table()) {
    Params params(Json{{"method", e.name}}, "test", "");
    make_lighting(params);
    check(std::string("lighting ") + e.name, params.resolved(), e.params());
  }
}

// The name lists commands and tests iterate come from the registry: every registered method is
// in method_names() (in registration order), and methods_with_sampling_geometry() holds exactly
// those whose default instance exposes a MappingSpec (what `fovsim density` evaluates).
TEST(MethodDecl, NameListsComeFromTheRegistry) {
  const auto& names = method_names();
  ASSERT_EQ(names.size(), method_table().size());
  for (size_t i = 0; i < names.size(); ++i) EXPECT_EQ(names[i], method_table()[i].name);
  // Each method names itself by its registered name (method_ids.h, generated from the list).
  for (const auto& e : method_table()) {
    Params p(Json::object(), "test", e.name);
    EXPECT_EQ(make_method(e.name, p)->name(), e.name);
  }
  const auto& geo = methods_with_sampling_geometry();
  for (const auto& e : method_table()) {
    Params p(Json::object(), "test", e.name);
    const bool has = make_method(e.name, p)->mapping_spec() != nullptr;
    EXPECT_EQ(has, std::find(geo.begin(), geo.end(), e.name) != geo.end()) << e.name;
  }
  EXPECT_EQ(std::find(geo.begin(), geo.end(), "full"), geo.end());
  EXPECT_NE(std::find(geo.begin(), geo.end(), "kfr"), geo.end());
}

// A hand-written list of method names outside the registry leaves a new method out silently:
// in sim/, bench/, tests/ and the bindings, every braced list of two or more registered method
// names is an error unless a comment on it (its line or the two above) says why it is a
// subset; the lists come from the registry (method_names(), tests/common/method_lists.h). A
// method's file names itself through method_ids.h, never by a second literal.
TEST(SourceScan, MethodNamesAreListedOnlyInTheRegistry) {
  namespace fs = std::filesystem;
  const std::set<std::string> names(method_names().begin(), method_names().end());
  const std::regex list(R"re(\{\s*"\w+"(\s*,\s*"\w+")+\s*,?\s*\})re");
  const std::regex word(R"re("(\w+)")re");
  const std::regex self(R"re(kMethod\s*=\s*")re");
  std::string bad;
  for (const char* top : {"sim", "bench", "tests", "python"})
    for (auto& e : fs::recursive_directory_iterator(std::string(FOVSIM_SOURCE_DIR) + "/" + top)) {
      const std::string ext = e.path().extension().string();
      if (!e.is_regular_file() || (ext != ".cpp" && ext != ".h" && ext != ".inc")) continue;
      const std::string rel = fs::relative(e.path(), FOVSIM_SOURCE_DIR).string();
      std::ifstream in(e.path());
      std::stringstream ss;
      ss << in.rdbuf();
      const std::string text = ss.str();
      auto line_of = [&](size_t pos) {
        return std::count(text.begin(), text.begin() + long(pos), '\n') + 1;
      };
      for (std::sregex_iterator it(text.begin(), text.end(), list), end; it != end; ++it) {
        const std::string m = it->str();
        size_t n = 0, listed = 0;
        for (std::sregex_iterator w(m.begin(), m.end(), word); w != end; ++w, ++n)
          listed += names.count((*w)[1].str());
        if (listed < 2 || listed != n) continue;
        const size_t bol = text.rfind('\n', size_t(it->position()));
        const size_t start = bol == std::string::npos ? 0 : bol + 1;
        if (text.substr(start, size_t(it->position()) - start).find("//") != std::string::npos)
          continue;  // in a comment
        // The match's line and the two before it: a comment saying it is a subset.
        size_t from = size_t(it->position());
        for (int k = 0; k < 3 && from != std::string::npos && from > 0; ++k)
          from = text.rfind('\n', from - 1);
        if (from == std::string::npos) from = 0;
        const size_t to = text.find('\n', size_t(it->position()) + m.size());
        if (text.substr(from, to - from).find("subset") != std::string::npos) continue;
        bad += rel + ":" + std::to_string(line_of(size_t(it->position()))) + ": " + m + "\n";
      }
      for (std::sregex_iterator it(text.begin(), text.end(), self), end; it != end; ++it)
        bad += rel + ":" + std::to_string(line_of(size_t(it->position()))) +
               ": a method named by a second literal (use method_id::<name>, method_ids.h)\n";
    }
  EXPECT_TRUE(bad.empty()) << "method names listed outside the registry (iterate method_names() "
                              "or tests/common/method_lists.h, or say why the list is a "
                              "subset):\n"
                           << bad;
}

// The lists tests iterate are the registry's.
TEST(MethodDecl, TestMethodListsComeFromTheRegistry) {
  EXPECT_EQ(test::all_methods(), method_names());
  // An iso-budget target is solved on a sampling geometry.
  const auto& geo = methods_with_sampling_geometry();
  for (const std::string& m : test::iso_budget_methods())
    EXPECT_NE(std::find(geo.begin(), geo.end(), m), geo.end()) << m;
  EXPECT_FALSE(test::iso_budget_methods().empty());
  EXPECT_FALSE(test::radial_methods().empty());
}
