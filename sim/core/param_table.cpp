#include "sim/core/param_table.h"

#include <cstdio>
#include <string>

namespace fovsim {

std::string param_doc_number(double v) {
  if (v >= 1e299) return "inf";
  if (v <= -1e299) return "-inf";
  char b[40];
  std::snprintf(b, sizeof b, "%.6g", v);
  std::string s = b;
  for (const char* noise : {"e+0", "e+", "e-0"}) {
    const auto i = s.find(noise);
    if (i != std::string::npos) {
      s = s.substr(0, i) + (noise[1] == '-' ? "e-" : "e") + s.substr(i + std::string(noise).size());
      break;
    }
  }
  return s;
}

std::string param_doc_range(const Range& r) {
  const bool lo_open = r.lo_open || r.lo <= -1e299, hi_open = r.hi_open || r.hi >= 1e299;
  return std::string(lo_open ? "(" : "[") + param_doc_number(r.lo) + ", " + param_doc_number(r.hi) +
         (hi_open ? ")" : "]");
}

std::string param_def_text(const Json& def, bool required) {
  if (def.is_null()) return required ? "required" : "none";
  if (def.is_boolean()) return def.get<bool>() ? "true" : "false";
  if (def.is_string()) return def.get<std::string>();
  if (def.is_array()) {
    std::string s = "[";
    for (const auto& v : def) s += (s.size() > 1 ? ", " : "") + param_doc_number(v.get<double>());
    return s + "]";
  }
  return param_doc_number(def.get<double>());
}

std::string param_range_text(ParamKind kind, const Range& r,
                             const std::vector<std::string>& allowed) {
  if (kind == ParamKind::Bool) return "";
  if (kind == ParamKind::String) {
    std::string s;
    for (const auto& a : allowed) s += (s.empty() ? "" : " | ") + a;
    return s;
  }
  if (r.lo <= -1e299 && r.hi >= 1e299) return "";
  return param_doc_range(r);
}

std::string param_markdown(const std::vector<ParamInfo>& rows, bool with_source) {
  auto cell = [](const std::string& s) {
    std::string r;
    for (char c : s) r += (c == '|') ? std::string("\\|") : std::string(1, c);
    return r.empty() ? std::string(" ") : r;
  };
  std::string md = with_source
                       ? "| key | type | default | range | source | meaning |\n"
                         "|---|---|---|---|---|---|\n"
                       : "| key | type | default | range | meaning |\n|---|---|---|---|---|\n";
  for (const ParamInfo& p : rows) {
    md += "| `" + std::string(p.name) + "` | " + cell(p.type) + " | " + cell(p.def) + " | " +
          cell(p.range) + " | ";
    if (with_source) md += cell(p.source) + " | ";
    md += cell(p.doc) + " |\n";
  }
  return md;
}

}  // namespace fovsim
