// One typed declaration per parameter, bound to the struct it fills (the role of pbrt-v4's
// ParameterDictionary lookups and Mitsuba 3's Properties, but declared once, as a table).
//
// A ParamTable<T> lists the keys of one config block -- a method, a lighting strategy, the
// metric config, a GPU spec, a run-config block -- each with its type, default, range,
// citation, meaning, the member of T it fills and, optionally, its frames.csv column. The same
// rows drive:
//   - parsing: read(Params&) / read_into(Params&, T&) call the Params getters (so every error keeps
//   its located
//     message: "file: methods[1].sigma: value 0.5 is out of range [1, inf]") and then the
//     table's validator for cross-key rules (r2 >= r1);
//   - defaults and range checks (one place: the row);
//   - documentation: info() / markdown() (`fovsim methods --markdown`, `fovsim config-keys
//     --markdown`, configs/README.md and docs/methods.md are generated from them);
//   - CSV columns: columns(t) / text_columns(t) in row order;
//   - tests: every table reads its own defaults (tests/core/param_table_test.cpp and the
//     per-layer declaration tests).
//
// Adding a key is one row, e.g. in the block's table:
//   .number("max_pixels", 5e7, Range::closed(1, 1e10), &RenderConfig::max_pixels)
//   .doc("", "largest simulated resolution (width x height after scale)")
// then use the struct member where the value is needed.
#pragma once
#include <cmath>
#include <cstdio>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "sim/core/param_info.h"
#include "sim/core/params.h"

namespace fovsim {

enum class ParamKind { Number, Integer, Bool, String, Numbers };

// Number formatting of defaults and ranges in generated docs: "%.6g" without "e+0" noise.
std::string param_doc_number(double v);
// "[1, inf)", "(0, 1]" for docs (an infinite bound is written open).
std::string param_doc_range(const Range& r);
// Default and range as docs write them: "none" / "required" without a default; "a | b" for
// strings; nothing for booleans and unbounded numbers.
std::string param_def_text(const Json& def, bool required);
std::string param_range_text(ParamKind kind, const Range& r,
                             const std::vector<std::string>& allowed);
// One Markdown table (key, type, default, range, [source,] meaning) of `rows`.
std::string param_markdown(const std::vector<ParamInfo>& rows, bool with_source = true);

template <class T>
struct ParamRow {
  std::string key;
  ParamKind kind = ParamKind::Number;
  Json def;                     // null: no default (optional unless `required`)
  bool required = false;        // no default: the key must be given
  bool member_default = false;  // the default is the member's value when read (scene's exposure)
  bool doc_only = false;        // documented here, read by the code its doc names
  Range range;
  std::vector<std::string> allowed;  // String: the accepted values (empty: any)
  std::string def_doc, range_doc;    // doc text overriding the generated one
  std::string type_doc;              // doc_only rows: the type as docs write it
  std::string source, doc;
  std::string column;  // frames.csv column ("" = none)
  std::function<void(T&, const Json&)> set;
  std::function<Json(const T&)> get;
  std::function<double(const T&)> column_value;  // default: get() as a number
  std::function<bool(const T&)> column_when;     // default: always
  std::function<bool(const Params&)> read_when;  // default: always read
  // Reads the key through `p` (located errors, resolved document) into `t`.
  void read(Params& p, T& t) const {
    if (doc_only || (read_when && !read_when(p))) return;
    if (member_default) {
      const Json d = get(t);
      if (kind == ParamKind::Number)
        set(t, Json(p.number(key, d.get<double>(), range)));
      else if (kind == ParamKind::Integer)
        set(t, Json(p.integer(key, d.get<int>(), range)));
      else if (kind == ParamKind::Bool)
        set(t, Json(p.boolean(key, d.get<bool>())));
      else if (kind == ParamKind::String)
        set(t, Json(p.string(key, d.get<std::string>(), allowed)));
      return;
    }
    if (def.is_null() && !required && !p.has(key)) return;
    switch (kind) {
      case ParamKind::Number:
        set(t,
            Json(def.is_null() ? p.number(key, range) : p.number(key, def.get<double>(), range)));
        break;
      case ParamKind::Integer:
        set(t, Json(def.is_null() ? p.integer(key, range) : p.integer(key, def.get<int>(), range)));
        break;
      case ParamKind::Bool:
        set(t, Json(p.boolean(key, def.is_null() ? false : def.get<bool>())));
        break;
      case ParamKind::String:
        set(t, Json(def.is_null() ? p.string(key, allowed)
                                  : p.string(key, def.get<std::string>(), allowed)));
        break;
      case ParamKind::Numbers:
        set(t, Json(p.numbers(
                   key, def.is_null() ? std::vector<double>{} : def.get<std::vector<double>>(),
                   range)));
        break;
    }
  }
};

template <class T>
class ParamTable {
 public:
  using Row = ParamRow<T>;
  using Validator = std::function<void(const T&, Params&)>;

  // A double, float or integer member read as a JSON number in `r`.
  template <class Acc>
  ParamTable& number(const char* key, double def, Range r, Acc acc) {
    return add(key, ParamKind::Number, Json(def), r, acc);
  }
  // An int (or wider integer) member read as a JSON integer in `r`.
  template <class Acc>
  ParamTable& integer(const char* key, int def, Range r, Acc acc) {
    return add(key, ParamKind::Integer, Json(def), r, acc);
  }
  template <class Acc>
  ParamTable& boolean(const char* key, bool def, Acc acc) {
    return add(key, ParamKind::Bool, Json(def), Range::any(), acc);
  }
  // A std::string member; `allowed` (if not empty) lists the accepted values.
  template <class Acc>
  ParamTable& text(const char* key, const char* def, std::vector<std::string> allowed, Acc acc) {
    add(key, ParamKind::String, def ? Json(def) : Json(), Range::any(), acc);
    rows_.back().allowed = std::move(allowed);
    return *this;
  }
  // A member of any type chosen by name: options map each accepted string to its value.
  template <class Acc, class V>
  ParamTable& choice(const char* key, const char* def, std::vector<std::pair<std::string, V>> opts,
                     Acc acc) {
    Row r;
    r.key = key;
    r.kind = ParamKind::String;
    r.def = Json(def);
    for (auto& o : opts) r.allowed.push_back(o.first);
    r.set = [acc, opts](T& t, const Json& v) {
      for (auto& o : opts)
        if (o.first == v.get<std::string>()) std::invoke(acc, t) = o.second;
    };
    r.get = [acc, opts](const T& t) {
      for (auto& o : opts)
        if (std::invoke(acc, t) == o.second) return Json(o.first);
      return Json();
    };
    rows_.push_back(std::move(r));
    return *this;
  }
  // An array of numbers, each in `r` (std::vector<double> member).
  template <class Acc>
  ParamTable& numbers(const char* key, std::vector<double> def, Range r, Acc acc) {
    return add(key, ParamKind::Numbers, Json(def), r, acc);
  }

  // A row whose member is written and read by the given functions (a value kept in two forms).
  ParamTable& custom(const char* key, ParamKind kind, Json def, Range r,
                     std::function<void(T&, const Json&)> set, std::function<Json(const T&)> get) {
    Row row;
    row.key = key;
    row.kind = kind;
    row.def = std::move(def);
    row.range = r;
    row.set = std::move(set);
    row.get = std::move(get);
    rows_.push_back(std::move(row));
    return *this;
  }

  // Modifiers of the last row.
  ParamTable& doc(const char* source, const char* meaning) {
    rows_.back().source = source;
    rows_.back().doc = meaning;
    return *this;
  }
  // No default: the key is read only when given (its member keeps the struct's value).
  ParamTable& optional() {
    rows_.back().def = Json();
    return *this;
  }
  // No default: the key must be given.
  ParamTable& required() {
    rows_.back().def = Json();
    rows_.back().required = true;
    return *this;
  }
  // The default is the member's value when the table is read (set by the caller: the scene's
  // exposure, the config file's stem); `shown` says what it is in docs.
  ParamTable& default_from_member(const char* shown) {
    rows_.back().member_default = true;
    rows_.back().def_doc = shown;
    return *this;
  }
  // A key documented in this table but read elsewhere (a string-or-object `display`, the
  // `gpus` array): read() skips it; `type`, `def` and `range` are the doc's text.
  ParamTable& documented(const char* key, const char* type, const char* def, const char* range,
                         const char* source, const char* meaning) {
    Row r;
    r.key = key;
    r.doc_only = true;
    r.type_doc = type;
    r.def_doc = def;
    r.range_doc = range;
    r.source = source;
    r.doc = meaning;
    rows_.push_back(std::move(r));
    return *this;
  }
  // Documentation text instead of the generated default / range ("scene's", "[r1, 180]").
  ParamTable& shown(const char* def_doc, const char* range_doc = "") {
    rows_.back().def_doc = def_doc;
    rows_.back().range_doc = range_doc;
    return *this;
  }
  // A frames.csv column of this key (named `name`, the key by default); `value` replaces the
  // member's value (radius-scaled r1), `when` limits it to some settings.
  ParamTable& column(const char* name = nullptr, std::function<double(const T&)> value = {},
                     std::function<bool(const T&)> when = {}) {
    rows_.back().column = name ? name : rows_.back().key;
    rows_.back().column_value = std::move(value);
    rows_.back().column_when = std::move(when);
    return *this;
  }
  // Reads the key only when `when` holds (rmfr's fx is not read when fx_px is given).
  ParamTable& read_if(std::function<bool(const Params&)> when) {
    rows_.back().read_when = std::move(when);
    return *this;
  }
  // Cross-key rules, run after every row was read (fail with p.fail(key, ...)).
  ParamTable& validate(Validator v) {
    validators_.push_back(std::move(v));
    return *this;
  }

  // Reads every row into t (members of keys not given get their defaults), then validates.
  void read_into(Params& p, T& t) const {
    for (const Row& r : rows_) r.read(p, t);
    for (const Validator& v : validators_) v(t, p);
  }
  T read(Params& p) const {
    T t{};
    read_into(p, t);
    return t;
  }

  const std::vector<Row>& rows() const { return rows_; }
  const Row* find(const std::string& key) const {
    for (const Row& r : rows_)
      if (r.key == key) return &r;
    return nullptr;
  }

  // Numeric columns (Number, Integer, Bool rows with a column) in row order.
  std::vector<std::pair<std::string, double>> columns(const T& t) const {
    std::vector<std::pair<std::string, double>> c;
    for (const Row& r : rows_) {
      if (r.column.empty() || r.doc_only || r.kind == ParamKind::String ||
          r.kind == ParamKind::Numbers)
        continue;
      if (r.column_when && !r.column_when(t)) continue;
      c.emplace_back(r.column, r.column_value ? r.column_value(t) : json_number(r.get(t)));
    }
    return c;
  }
  // String columns (as written in the config) in row order.
  std::vector<std::pair<std::string, std::string>> text_columns(const T& t) const {
    std::vector<std::pair<std::string, std::string>> c;
    for (const Row& r : rows_)
      if (!r.column.empty() && r.kind == ParamKind::String && (!r.column_when || r.column_when(t)))
        c.emplace_back(r.column, r.get(t).template get<std::string>());
    return c;
  }

  // The rows as text descriptors (stable addresses: the table is built once, then read-only).
  const std::vector<ParamInfo>& info() const {
    static std::mutex m;  // built on first use, possibly from several threads
    std::lock_guard<std::mutex> lock(m);
    if (info_.size() != rows_.size()) {
      text_.clear();
      info_.clear();
      for (const Row& r : rows_) {
        text_.push_back(!r.type_doc.empty() ? r.type_doc : kind_name(r.kind));
        const char* type = text_.back().c_str();
        text_.push_back(!r.def_doc.empty() || r.doc_only ? r.def_doc : def_text(r));
        const char* def = text_.back().c_str();
        text_.push_back(!r.range_doc.empty() || r.doc_only ? r.range_doc : range_text(r));
        info_.push_back(
            {r.key.c_str(), type, def, text_.back().c_str(), r.source.c_str(), r.doc.c_str()});
      }
    }
    return info_;
  }
  std::string markdown(bool with_source = true) const {
    return param_markdown(info(), with_source);
  }

 private:
  template <class Acc>
  ParamTable& add(const char* key, ParamKind kind, Json def, Range range, Acc acc) {
    Row r;
    r.key = key;
    r.kind = kind;
    r.def = std::move(def);
    r.range = range;
    r.set = [acc](T& t, const Json& v) {
      auto& m = std::invoke(acc, t);
      using M = std::decay_t<decltype(m)>;
      if constexpr (std::is_same_v<M, bool>)
        m = v.get<bool>();
      else if constexpr (std::is_arithmetic_v<M>)
        m = static_cast<M>(v.get<double>());
      else
        m = v.get<M>();
    };
    r.get = [acc](const T& t) { return Json(std::invoke(acc, t)); };
    rows_.push_back(std::move(r));
    return *this;
  }
  static double json_number(const Json& j) {
    if (j.is_boolean()) return j.get<bool>() ? 1 : 0;
    return j.get<double>();
  }
  static std::string kind_name(ParamKind k) {
    switch (k) {
      case ParamKind::Number:
        return "number";
      case ParamKind::Integer:
        return "int";
      case ParamKind::Bool:
        return "bool";
      case ParamKind::String:
        return "string";
      case ParamKind::Numbers:
        return "number[]";
    }
    return "";
  }
  static std::string def_text(const Row& r) { return param_def_text(r.def, r.required); }
  static std::string range_text(const Row& r) {
    return param_range_text(r.kind, r.range, r.allowed);
  }

  std::vector<Row> rows_;
  std::vector<Validator> validators_;
  mutable std::deque<std::string> text_;  // deque: push_back keeps c_str() valid
  mutable std::vector<ParamInfo> info_;
};

}  // namespace fovsim
