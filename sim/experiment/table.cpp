#include "sim/experiment/table.h"

#include <cmath>
#include <cstdio>
#include <unordered_set>

#include "sim/core/error.h"

namespace fovsim {

void ResultRow::set_text(const std::string& k, const std::string& v) {
  for (auto& kv : text)
    if (kv.first == k) {
      kv.second = v;
      return;
    }
  text.emplace_back(k, v);
}

void ResultRow::set(const std::string& k, double v) {
  for (auto& kv : num)
    if (kv.first == k) {
      kv.second = v;
      return;
    }
  num.emplace_back(k, v);
}

double ResultRow::get(const std::string& k, double fallback) const {
  for (auto& kv : num)
    if (kv.first == k) return kv.second;
  return fallback;
}

const std::string* ResultRow::text_of(const std::string& k) const {
  for (auto& kv : text)
    if (kv.first == k) return &kv.second;
  return nullptr;
}

void ResultTable::add(ResultRow r) {
  rows_.push_back(std::move(r));
}

template <class Get>
static std::vector<std::string> collect(const std::vector<ResultRow>& rows, Get get) {
  std::vector<std::string> cols;
  std::unordered_set<std::string> seen;
  for (auto& r : rows)
    for (auto& kv : get(r))
      if (seen.insert(kv.first).second) cols.push_back(kv.first);
  return cols;
}

std::vector<std::string> ResultTable::text_columns() const {
  return collect(
      rows_, [](const ResultRow& r) -> const auto& { return r.text; });
}
std::vector<std::string> ResultTable::numeric_columns() const {
  return collect(
      rows_, [](const ResultRow& r) -> const auto& { return r.num; });
}

std::string format_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string csv_escape(const std::string& raw) {
  // Control bytes (NUL, ESC, CR, LF, ...) of user text are written as \xNN: a CSV cell never
  // carries them raw to a terminal, a spreadsheet or a line-based reader.
  const std::string s = escape_control(raw);
  if (s.find_first_of(",\"") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) o += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

std::string ResultTable::to_csv() const {
  auto tc = text_columns(), nc = numeric_columns();
  std::string out;
  bool first = true;
  for (auto& c : tc) out += (first ? "" : ",") + c, first = false;
  for (auto& c : nc) out += (first ? "" : ",") + c, first = false;
  out += "\n";
  for (auto& r : rows_) {
    first = true;
    for (auto& c : tc) {
      const std::string* v = r.text_of(c);
      out += (first ? "" : ",") + (v ? csv_escape(*v) : std::string());
      first = false;
    }
    for (auto& c : nc) {
      bool found = false;
      for (auto& kv : r.num)
        if (kv.first == c) {
          out += (first ? "" : ",") + format_number(kv.second);
          found = true;
          break;
        }
      if (!found) out += first ? "" : ",";
      first = false;
    }
    out += "\n";
  }
  return out;
}

}  // namespace fovsim
