// Small text helpers shared by the report writers and flag parsers (one copy for the library).
#pragma once
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <string>
#include <vector>

namespace fovsim {

// One number through a printf format ("%.3g"); `nan_text` (when given) stands for NaN.
inline std::string fmt(const char* format, double v, const char* nan_text = nullptr) {
  if (nan_text && std::isnan(v)) return nan_text;
  char b[64];
  std::snprintf(b, sizeof b, format, v);
  return b;
}

// `s` split at every `sep`; empty fields are kept ("a,,b" -> "a", "", "b"; "" -> one "").
inline std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

// `s` without spaces and tabs at either end.
inline std::string trim(const std::string& s) {
  size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// `s` with ASCII letters lowered (locale-free: column names, file extensions).
inline std::string ascii_lower(std::string s) {
  for (char& c : s)
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
  return s;
}

// Whether `s` contains any of `words`.
inline bool contains_any(const std::string& s, std::initializer_list<const char*> words) {
  for (const char* w : words)
    if (s.find(w) != std::string::npos) return true;
  return false;
}

// `names` joined with `sep` ({"a", "b"} -> "a, b").
inline std::string join_names(const std::vector<std::string>& names, const char* sep = ", ") {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : sep) + n;
  return out;
}

}  // namespace fovsim
