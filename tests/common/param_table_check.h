// The checks every declared parameter table passes ("every table reads its own defaults"):
// reading an empty block gives each row's declared default; each key given at its default
// (and every option of a string key) is accepted and reads back; a number just outside a
// finite range bound is an error naming the key; the docs text of a default parses back to
// the default. Used by each layer's declaration test.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "sim/core/error.h"
#include "sim/core/param_table.h"

namespace fovsim::table_check {

// A valid value for a row without a default (required keys need one to read the others).
inline Json some_value(ParamKind kind, const Range& r, const std::vector<std::string>& allowed) {
  switch (kind) {
    case ParamKind::Bool:
      return Json(true);
    case ParamKind::String:
      return Json(allowed.empty() ? std::string("x") : allowed.front());
    case ParamKind::Numbers:
      return Json::array();
    default: {
      double v = 1;
      if (r.lo > -1e299 && r.hi < 1e299)
        v = 0.5 * (r.lo + r.hi);
      else if (r.lo > -1e299)
        v = r.lo + 1;
      if (kind == ParamKind::Integer) v = std::ceil(v);
      return kind == ParamKind::Integer ? Json(static_cast<long long>(v)) : Json(v);
    }
  }
}

inline bool same_value(const Json& a, const Json& b) {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    return std::fabs(x - y) <= 1e-6 * std::max(1.0, std::fabs(y));  // float members
  }
  return a == b;
}

// `init` is the struct as the caller prepares it (member defaults set before reading).
template <class T>
void expect_table_reads_own_defaults(const ParamTable<T>& t, const std::string& name,
                                     const T& init = T{}) {
  SCOPED_TRACE(name);
  Json base = Json::object();
  for (const auto& r : t.rows())
    if (r.required) base[r.key] = some_value(r.kind, r.range, r.allowed);
  int checked = 0;
  {
    Params p(base, "test.json", name);
    T a = init;
    ASSERT_NO_THROW(t.read_into(p, a));
    EXPECT_NO_THROW(p.finish());
    for (const auto& r : t.rows()) {
      if (r.doc_only || r.def.is_null() || r.member_default) continue;
      EXPECT_TRUE(same_value(r.get(a), r.def))
          << r.key << ": read " << r.get(a).dump() << ", declared " << r.def.dump();
      // The docs' text of the default is the default.
      const auto& info = t.info()[size_t(&r - t.rows().data())];
      const Json& def = r.def;
      if (r.kind == ParamKind::Number && r.def_doc.empty()) {
        EXPECT_NEAR(std::strtod(info.def, nullptr), def.get<double>(),
                    1e-5 * std::max(1.0, std::fabs(def.get<double>())))
            << r.key;
      }
      ++checked;
    }
  }
  for (const auto& r : t.rows()) {
    if (r.doc_only) continue;
    std::vector<Json> values;
    if (!r.def.is_null()) values.push_back(r.def);
    for (const auto& a : r.allowed) values.push_back(Json(a));
    if (values.empty()) values.push_back(some_value(r.kind, r.range, r.allowed));
    for (const Json& v : values) {
      Json doc = base;
      doc[r.key] = v;
      Params p(doc, "test.json", name);
      T a = init;
      EXPECT_NO_THROW(t.read_into(p, a)) << r.key << " = " << v.dump();
      if (!r.read_when) {
        EXPECT_TRUE(same_value(r.get(a), v)) << r.key << " = " << v.dump();
      }
    }
    // Just outside a finite lower bound: an error naming the key.
    if ((r.kind == ParamKind::Number || r.kind == ParamKind::Integer) && r.range.lo > -1e299) {
      Json doc = base;
      doc[r.key] = r.kind == ParamKind::Integer ? Json(static_cast<long long>(r.range.lo) - 1)
                                                : Json(r.range.lo - (r.range.lo_open ? 0.0 : 1.0));
      Params p(doc, "test.json", name);
      T a = init;
      try {
        t.read_into(p, a);
        ADD_FAILURE() << r.key << " accepted " << doc[r.key].dump() << " below its range";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(r.key), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
      }
    }
  }
  EXPECT_GT(checked + int(t.rows().empty()), 0) << "no row with a default";
}

}  // namespace fovsim::table_check
