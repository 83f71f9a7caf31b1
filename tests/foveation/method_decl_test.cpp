// Each method's declaration (MethodEntry::params, the table docs are generated from) agrees
// with the parser that run/sweep/predict/density use: every declared key is accepted at its
// declared default, the parsed default equals the declared one wherever the method reports it
// as a CSV column, and an undeclared key is an error naming it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include "sim/core/error.h"
#include "sim/foveation/factory.h"

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
