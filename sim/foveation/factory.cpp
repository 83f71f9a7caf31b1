#include "sim/foveation/factory.h"

#include "sim/core/error.h"
#include "sim/foveation/methods.h"

namespace fovsim {

const std::vector<MethodEntry>& method_table() {
  // One line per method in method_list.h; each method's file defines create_<name>,
  // <name>_params and <name>_cost. A line's third argument is not read: a method's cost is its
  // own declaration (method_cost.h).
  static const std::vector<MethodEntry> table = {
#define FOVSIM_METHOD(name, summary) {#name, summary, create_##name, name##_params, name##_cost},
#include "sim/foveation/method_list.h"
#undef FOVSIM_METHOD
  };
  return table;
}

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& e : method_table()) n.push_back(e.name);
    return n;
  }();
  return names;
}

const std::vector<std::string>& methods_with_sampling_geometry() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& e : method_table()) {
      Params p(Json::object(), "", e.name);
      if (e.create(p)->mapping_spec()) n.push_back(e.name);
    }
    return n;
  }();
  return names;
}

const MethodEntry* find_method(const std::string& name) {
  for (const auto& e : method_table())
    if (name == e.name) return &e;
  return nullptr;
}

std::unique_ptr<FoveationMethod> make_method(const std::string& name, Params& p) {
  std::string names;
  for (auto& e : method_table()) {
    if (name == e.name) {
      auto m = e.create(p);
      if (p.has("lighting")) {
        if (m->own_lighting())
          p.fail("lighting", "method \"" + name +
                                 "\" has its own lighting; use {\"method\": \"full\", "
                                 "\"lighting\": {\"method\": \"" +
                                 name + "\"}} instead");
        Params lp = p.child("lighting");
        m->set_lighting(make_lighting(lp));
      } else if (!m->lighting()) {
        m->set_lighting(default_lighting());
      }
      p.finish();
      return m;
    }
    names += (names.empty() ? "" : ", ") + std::string(e.name);
  }
  p.fail("method", "unknown method \"" + name + "\" (available: " + names + ")");
}

CostPasses declared_passes(const FoveationMethod& m) {
  const MethodEntry* e = find_method(m.name());
  FOVSIM_CHECK(e, "method \"" + m.name() + "\" is not in method_list.h");
  CostPasses p = e->cost().passes;
  if (m.lighting()) m.lighting()->declare_passes(p);
  return p;
}

const std::string& full_resolution_method() {
  static const std::string name = [] {
    for (const auto& e : method_table())
      if (e.cost().passes.full_resolution) return std::string(e.name);
    FOVSIM_CHECK(false, "no method in method_list.h declares full-resolution shading");
    return std::string();
  }();
  return name;
}

CostPasses declared_passes(const std::string& method, const std::string& lighting) {
  if (!find_method(method)) throw Error("cost", "unknown method '" + method + "'");
  Params p(Json::object(), "cost", "");
  std::unique_ptr<FoveationMethod> m = make_method(method, p);
  if (!lighting.empty() && !m->own_lighting()) {
    Params lp(Json{{"method", lighting}}, "cost.lighting", "");
    m->set_lighting(make_lighting(lp));
  }
  return declared_passes(*m);
}

std::string methods_markdown() {
  return methods_only_markdown() + "### Lighting strategies (`lighting` block)\n\n" +
         lighting_markdown();
}

std::string methods_only_markdown() {
  auto cell = [](const char* s) {
    std::string r;
    for (const char* c = s; *c; ++c) r += (*c == '|') ? std::string("\\|") : std::string(1, *c);
    return r.empty() ? std::string(" ") : r;
  };
  std::string md;
  for (const auto& e : method_table()) {
    md += "#### `" + std::string(e.name) + "`\n\n" + std::string(e.summary) + ".\n\n";
    const auto& ps = e.params();
    if (ps.empty()) {
      md += "No parameters.\n\n";
      continue;
    }
    md += "| key | type | default | range | source | meaning |\n|---|---|---|---|---|---|\n";
    for (const ParamInfo& p : ps)
      md += "| `" + std::string(p.name) + "` | " + cell(p.type) + " | " + cell(p.def) + " | " +
            cell(p.range) + " | " + cell(p.source) + " | " + cell(p.doc) + " |\n";
    md += "\n";
  }
  return md;
}

MethodArg parse_method_arg(const std::string& text, const std::string& flag) {
  MethodArg m;
  m.text = text;
  const std::string where = flag + " " + text;
  const auto colon = text.find(':');
  m.name = text.substr(0, colon);
  bool known = false;
  std::string names;
  for (auto& e : method_table()) {
    known |= m.name == e.name;
    names += (names.empty() ? "" : ", ") + std::string(e.name);
  }
  if (!known) throw Error(where, "unknown method \"" + m.name + "\" (available: " + names + ")");
  if (colon == std::string::npos) return m;
  const std::string rest = text.substr(colon + 1);
  size_t i = 0;
  while (i <= rest.size()) {
    size_t j = rest.find(',', i);
    if (j == std::string::npos) j = rest.size();
    const std::string kv = rest.substr(i, j - i);
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw Error(where, "expected key=value, got \"" + kv + "\"");
    const std::string key = kv.substr(0, eq), v = kv.substr(eq + 1);
    if (m.params.contains(key)) throw Error(where, "key \"" + key + "\" given twice");
    // The checked parser (nesting bounded); text that is not JSON stays a string.
    Json jv = parse_value_or_string(v, where);
    m.params[key] = (jv.is_object() || jv.is_array()) ? Json(v) : jv;
    i = j + 1;
  }
  return m;
}

}  // namespace fovsim
