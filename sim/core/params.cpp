#include "sim/core/params.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/message_text.h"

namespace fovsim {

bool Range::contains(double v) const {
  if (!std::isfinite(v)) return false;
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (hi_open ? !(v < hi) : !(v <= hi)) return false;
  return true;
}

// Shortest text that reads back as the same double (%.*g with 1..17 digits): a bound or a
// value prints as given -- 4.0000001 is not "4", the default upper bound 1e300 is "1e+300"
// (a value of 1e301 is out of it, which "inf" would hide) -- and never as 300 digits.
std::string shortest_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  // The shortest round-tripping %.*g text; on a tie the one without an exponent ("10000",
  // not "1e+04"; "10", not "1e+01").
  std::string best;
  for (int digits = 1; digits <= 17; ++digits) {
    char b[40];
    std::snprintf(b, sizeof b, "%.*g", digits, v);
    if (std::strtod(b, nullptr) != v) continue;
    const std::string t = b;
    const bool shorter = best.empty() || t.size() < best.size() ||
                         (t.size() == best.size() && best.find('e') != std::string::npos &&
                          t.find('e') == std::string::npos);
    if (shorter) best = t;
  }
  return best;
}

std::string Range::str() const {
  return std::string(lo_open ? "(" : "[") + shortest_number(lo) + ", " + shortest_number(hi) +
         (hi_open ? ")" : "]");
}

double check_number(const std::string& where, double v, const Range& r) {
  if (!r.contains(v))
    throw Error(where, "value " + shortest_number(v) + " is out of range " + r.str());
  return v;
}

long check_integer(const std::string& where, double v, const Range& r) {
  check_number(where, v, r);
  if (v != std::floor(v) || std::fabs(v) > 9007199254740992.0)
    throw Error(where, "value " + shortest_number(v) + " is not an integer in " + r.str());
  return long(v);
}

std::string json_error_text(const std::exception& e) {
  std::string s = e.what();
  if (s.rfind("[json.exception.", 0) == 0) {
    const size_t p = s.find("] ");
    if (p != std::string::npos) s = s.substr(p + 2);
  }
  return s;
}

std::string describe_json(const Json& v) {
  std::string dump = v.dump(-1, ' ', false, Json::error_handler_t::replace);
  if (dump.size() > 40) dump = dump.substr(0, 37) + "...";
  switch (v.type()) {
    case Json::value_t::null:
      return "null";
    case Json::value_t::boolean:
      return "a boolean " + dump;
    case Json::value_t::string:
      return "a string " + dump;
    case Json::value_t::array:
      return "an array " + dump;
    case Json::value_t::object:
      return "an object";
    default:
      return "a number " + dump;
  }
}

Params::Params(Json j, std::string file, std::string path)
    : j_(std::move(j)), st_(std::make_shared<State>()), path_(std::move(path)) {
  st_->file = std::move(file);
  if (!j_.is_object()) throw Error(where(), "expected a JSON object, got " + describe_json(j_));
}

Params::Params(Json j, std::shared_ptr<State> st, std::string path, Json::json_pointer ptr)
    : j_(std::move(j)), st_(std::move(st)), path_(std::move(path)), ptr_(std::move(ptr)) {}

namespace {

// 1-based line and column of byte offset `byte` in `text`.
std::pair<long, long> line_col(const std::string& text, size_t byte) {
  long line = 1, col = 1;
  for (size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {line, col};
}

std::string at(const std::string& file, const std::string& text, size_t byte) {
  auto [line, col] = line_col(text, byte);
  return file_location(file.empty() ? "(json)" : file, line, col);
}

// nlohmann's DOM builder, but errors (syntax, number overflow 406) keep their byte offset
// instead of becoming exceptions without a location.
class LocatingSax : public nlohmann::detail::json_sax_dom_parser<Json> {
 public:
  explicit LocatingSax(Json& j) : json_sax_dom_parser(j, false) {}
  template <class Exception>
  bool parse_error(std::size_t byte, const std::string& token, const Exception& ex) {
    failed = true;
    // nlohmann reports the byte after the offending token: point at the token's last byte,
    // or at its first for a number out of range (the whole token is the problem).
    position = byte > 0 ? byte - 1 : 0;
    if (ex.id == 406 && byte >= token.size()) position = byte - token.size();
    message = ex.what();
    return false;
  }
  // Duplicate keys (nlohmann keeps the last silently): the JSON path is tracked per value,
  // and the n-th key of the document (counted here) is located in the text afterwards.
  using Base = nlohmann::detail::json_sax_dom_parser<Json>;
  struct Frame {
    bool array = false;
    long index = -1;
    std::string key;
    std::set<std::string> keys;
  };
  void value_event() {
    if (!frames.empty() && frames.back().array) ++frames.back().index;
  }
  bool null() { return value_event(), Base::null(); }
  bool boolean(bool v) { return value_event(), Base::boolean(v); }
  bool number_integer(Json::number_integer_t v) { return value_event(), Base::number_integer(v); }
  bool number_unsigned(Json::number_unsigned_t v) {
    return value_event(), Base::number_unsigned(v);
  }
  bool number_float(Json::number_float_t v, const std::string& s) {
    return value_event(), Base::number_float(v, s);
  }
  bool string(std::string& v) { return value_event(), Base::string(v); }
  bool binary(Json::binary_t& v) { return value_event(), Base::binary(v); }
  bool start_object(std::size_t n) {
    value_event();
    frames.push_back({});
    return Base::start_object(n);
  }
  bool end_object() {
    frames.pop_back();
    return Base::end_object();
  }
  bool start_array(std::size_t n) {
    value_event();
    frames.push_back({true, -1, "", {}});
    return Base::start_array(n);
  }
  bool end_array() {
    frames.pop_back();
    return Base::end_array();
  }
  bool key(std::string& k) {
    ++keys_seen;
    Frame& f = frames.back();
    f.key = k;
    if (!f.keys.insert(k).second) {
      duplicate = true;
      for (const Frame& g : frames) {
        if (g.array)
          dup_path += "[" + std::to_string(g.index) + "]";
        else
          dup_path += (dup_path.empty() ? "" : ".") + g.key;
      }
      return false;
    }
    return Base::key(k);
  }
  std::vector<Frame> frames;
  long keys_seen = 0;
  bool duplicate = false;
  std::string dup_path;
  bool failed = false;
  size_t position = 0;
  std::string message;
};

// Byte offset of the n-th (1-based) object key of `text` (a string followed by ':'), comments
// and other strings skipped; text.size() when not found.
size_t nth_key_offset(const std::string& text, long n) {
  const size_t len = text.size();
  for (size_t i = 0; i < len; ++i) {
    const char c = text[i];
    if (c == '/' && i + 1 < len && text[i + 1] == '/') {
      while (i + 1 < len && text[i + 1] != '\n') ++i;
    } else if (c == '/' && i + 1 < len && text[i + 1] == '*') {
      size_t e = text.find("*/", i + 2);
      i = e == std::string::npos ? len : e + 1;
    } else if (c == '"') {
      const size_t start = i;
      for (++i; i < len && text[i] != '"'; ++i)
        if (text[i] == '\\') ++i;
      size_t j = i + 1;
      while (j < len && (text[j] == ' ' || text[j] == '\t' || text[j] == '\n' || text[j] == '\r'))
        ++j;
      if (j < len && text[j] == ':' && --n == 0) return start;
    }
  }
  return len;
}

}  // namespace

void check_json_depth(const std::string& text, const std::string& file) {
  int depth = 0;
  const size_t n = text.size();
  for (size_t i = 0; i < n; ++i) {
    char c = text[i];
    if (c == '"') {  // skip a string (escapes included)
      for (++i; i < n && text[i] != '"'; ++i)
        if (text[i] == '\\') ++i;
    } else if (c == '/' && i + 1 < n && text[i + 1] == '/') {
      while (i + 1 < n && text[i + 1] != '\n') ++i;
    } else if (c == '/' && i + 1 < n && text[i + 1] == '*') {
      size_t e = text.find("*/", i + 2);
      i = e == std::string::npos ? n : e + 1;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw Error(at(file, text, i), "JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                                           " levels (the limit for any fovsim input)");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

Json parse_json_text(const std::string& text, const std::string& file) {
  check_json_depth(text, file);
  Json j;
  LocatingSax sax(j);
  Json::sax_parse(text, &sax, nlohmann::detail::input_format_t::json, /*strict=*/true,
                  /*ignore_comments=*/true);
  if (sax.duplicate)
    throw Error(at(file, text, nth_key_offset(text, sax.keys_seen)),
                "duplicate key \"" + sax.dup_path +
                    "\" (each key may appear once; JSON keeps only the last)");
  if (sax.failed) {
    std::string msg = sax.message;
    auto p = msg.find("] ");  // drop nlohmann's "[json.exception.parse_error.101] "
    if (p != std::string::npos && msg.rfind("[json.exception", 0) == 0) msg = msg.substr(p + 2);
    if (msg.rfind("number overflow", 0) == 0)
      msg += " (outside the range of a double, about +-1.8e308)";
    throw Error(at(file, text, sax.position), "malformed JSON: " + msg);
  }
  return j;
}

nlohmann::ordered_json parse_json_text_ordered(const std::string& text, const std::string& file) {
  parse_json_text(text, file);  // every check (depth, syntax, duplicates) with its location
  return nlohmann::ordered_json::parse(text, nullptr, true, /*ignore_comments=*/true);
}

Json Params::parse_json_file(const std::string& file) {
  return parse_json_text(read_file(file), file);
}

Params Params::from_file(const std::string& file) {
  return Params(parse_json_file(file), file);
}

std::string Params::path_of(const std::string& key) const {
  if (key.empty()) return path_;
  return path_.empty() ? key : path_ + "." + key;
}

void Params::set_origins(std::vector<std::pair<std::string, std::string>> origins) {
  st_->origins = std::move(origins);
}

void Params::set_inherited(const std::vector<std::pair<std::string, std::string>>& inherited) {
  st_->inherited.clear();
  for (auto& [path, file] : inherited) st_->inherited[path] = file;
}

// The base file that wrote `path` or the nearest value above it ("methods" for
// "methods[0].sigma": arrays are inherited whole).
const std::string* Params::inherited_from(const std::string& path) const {
  if (st_->inherited.empty()) return nullptr;
  std::string p = path;
  for (;;) {
    auto it = st_->inherited.find(p);
    if (it != st_->inherited.end()) return &it->second;
    size_t cut = p.find_last_of(".[");
    if (cut == std::string::npos || cut == 0) return nullptr;
    p.resize(cut);
  }
}

std::string Params::source_dir(const std::string& key) const {
  const std::string path = path_of(key);
  for (auto& o : st_->origins) {  // a command-line value is the user's, not a base file's
    const std::string& q = o.first;
    if (path.compare(0, q.size(), q) == 0 &&
        (path.size() == q.size() || path[q.size()] == '.' || path[q.size()] == '['))
      return "";
  }
  const std::string* f = inherited_from(path);
  if (!f) return "";
  std::string d = std::filesystem::path(*f).parent_path().string();
  return d.empty() ? "." : d;
}

std::string Params::locate(const std::string& path) const {
  // The last override at or above `path` set it (later overrides win, as when applied).
  for (auto it = st_->origins.rbegin(); it != st_->origins.rend(); ++it) {
    const std::string& o = it->first;
    if (path.compare(0, o.size(), o) == 0 &&
        (path.size() == o.size() || path[o.size()] == '.' || path[o.size()] == '['))
      return "override '" + escape_control(it->second, 80) + "': " + path;
  }
  std::string p = path.empty() ? "(root)" : path;
  if (const std::string* f = inherited_from(path)) p += " (inherited from " + *f + ")";
  return st_->file.empty() ? p : st_->file + ": " + p;
}

std::string Params::where(const std::string& key) const {
  return locate(path_of(key));
}

void Params::fail(const std::string& key, const std::string& msg) const {
  throw Error(where(key), msg);
}

bool Params::has(const std::string& key) const {
  return j_.contains(key);
}

const Json* Params::find(const std::string& key) const {
  auto it = j_.find(key);
  if (it == j_.end()) return nullptr;
  return &*it;
}

void Params::mark(const std::string& key, const Json& value) {
  auto p = ptr_ / key;
  st_->used.insert(p.to_string());
  st_->resolved[p] = value;
}

void Params::ignore(const std::string& key) {
  if (has(key)) st_->used.insert((ptr_ / key).to_string());
}

void Params::check_range(const std::string& key, double v, const Range& r) const {
  if (!r.contains(v)) fail(key, "value " + shortest_number(v) + " is out of range " + r.str());
}

double Params::number(const std::string& key, double def, Range r) {
  const Json* v = find(key);
  if (!v) {
    mark(key, def);
    return def;
  }
  return number(key, r);
}

double Params::number(const std::string& key, Range r) {
  const Json* v = find(key);
  if (!v) fail(key, "required number is missing (allowed range " + r.str() + ")");
  if (!v->is_number()) fail(key, "expected a number in " + r.str() + ", got " + describe_json(*v));
  double d = v->get<double>();
  check_range(key, d, r);
  mark(key, *v);
  return d;
}

int Params::integer(const std::string& key, int def, Range r) {
  if (!find(key)) {
    mark(key, def);
    return def;
  }
  return integer(key, r);
}

int Params::integer(const std::string& key, Range r) {
  // Integer keys are ints: their range is the declared one within [-2e9, 2e9] (so "[1, inf]"
  // never appears for a bound that is 2e9).
  r.lo = std::max(r.lo, -2e9);
  r.hi = std::min(r.hi, 2e9);
  const Json* v = find(key);
  if (!v) fail(key, "required integer is missing (allowed range " + r.str() + ")");
  if (!v->is_number())
    fail(key, "expected an integer in " + r.str() + ", got " + describe_json(*v));
  double d = v->get<double>();
  if (d != std::floor(d))
    fail(key, "expected an integer in " + r.str() + ", got " + shortest_number(d));
  check_range(key, d, r);
  mark(key, *v);
  return int(d);
}

bool Params::boolean(const std::string& key, bool def) {
  const Json* v = find(key);
  if (!v) {
    mark(key, def);
    return def;
  }
  if (!v->is_boolean()) fail(key, "expected true or false, got " + describe_json(*v));
  mark(key, *v);
  return v->get<bool>();
}

static std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + v[i];
  return s;
}

std::string Params::string(const std::string& key, const std::string& def,
                           const std::vector<std::string>& allowed) {
  if (!find(key)) {
    mark(key, def);
    return def;
  }
  return string(key, allowed);
}

std::string Params::string(const std::string& key, const std::vector<std::string>& allowed) {
  const Json* v = find(key);
  if (!v)
    fail(key, "required string is missing" +
                  (allowed.empty() ? "" : " (one of: " + join(allowed) + ")"));
  if (!v->is_string()) fail(key, "expected a string, got " + describe_json(*v));
  std::string s = v->get<std::string>();
  if (!allowed.empty()) {
    bool ok = false;
    for (auto& a : allowed) ok = ok || a == s;
    if (!ok)
      fail(key, "unknown value \"" + escape_control(s, 80) + "\" (allowed: " + join(allowed) + ")");
  }
  mark(key, *v);
  return s;
}

std::vector<double> Params::numbers(const std::string& key, const std::vector<double>& def,
                                    Range r) {
  const Json* v = find(key);
  if (!v) {
    mark(key, def);
    return def;
  }
  if (!v->is_array()) fail(key, "expected an array of numbers, got " + describe_json(*v));
  std::vector<double> out;
  for (size_t i = 0; i < v->size(); ++i) {
    const Json& e = (*v)[i];
    std::string k = key + "[" + std::to_string(i) + "]";
    if (!e.is_number()) fail(k, "expected a number in " + r.str() + ", got " + describe_json(e));
    check_range(k, e.get<double>(), r);
    out.push_back(e.get<double>());
  }
  mark(key, *v);
  return out;
}

Params Params::child(const std::string& key) {
  const Json* v = find(key);
  Json obj = v ? *v : Json::object();
  if (!obj.is_object()) fail(key, "expected an object, got " + describe_json(obj));
  auto p = ptr_ / key;
  st_->used.insert(p.to_string());
  if (!st_->resolved.contains(p)) st_->resolved[p] = Json::object();
  return Params(obj, st_, path_of(key), p);
}

std::vector<Params> Params::children(const std::string& key) {
  const Json* v = find(key);
  std::vector<Params> out;
  if (!v) return out;
  if (!v->is_array()) fail(key, "expected an array of objects, got " + describe_json(*v));
  auto p = ptr_ / key;
  st_->used.insert(p.to_string());
  if (!st_->resolved.contains(p)) st_->resolved[p] = Json::array();
  for (size_t i = 0; i < v->size(); ++i) {
    std::string k = key + "[" + std::to_string(i) + "]";
    if (!(*v)[i].is_object()) fail(k, "expected an object, got " + describe_json((*v)[i]));
    auto pi = p / i;
    st_->used.insert(pi.to_string());
    if (!st_->resolved.contains(pi)) st_->resolved[pi] = Json::object();
    out.push_back(Params((*v)[i], st_, path_of(k), pi));
  }
  return out;
}

const Json& Params::raw(const std::string& key) {
  const Json* v = find(key);
  if (!v) fail(key, "required key is missing");
  mark(key, *v);
  // A raw value is consumed whole: mark everything below it as used.
  std::vector<std::pair<Json::json_pointer, const Json*>> stack{{ptr_ / key, v}};
  while (!stack.empty()) {
    auto [p, node] = stack.back();
    stack.pop_back();
    st_->used.insert(p.to_string());
    if (node->is_object())
      for (auto it = node->begin(); it != node->end(); ++it)
        stack.push_back({p / it.key(), &it.value()});
    else if (node->is_array())
      for (size_t i = 0; i < node->size(); ++i) stack.push_back({p / i, &(*node)[i]});
  }
  return *v;
}

void Params::finish_rec(const Json& j, const Json::json_pointer& ptr,
                        const std::string& path) const {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      auto p = ptr / it.key();
      std::string sp = path.empty() ? it.key() : path + "." + it.key();
      if (!st_->used.count(p.to_string())) {
        // "did you mean": the keys read at this level (defaults included) are the known ones.
        std::vector<std::string> known;
        const std::string prefix = ptr.to_string() + "/";
        for (auto u = st_->used.lower_bound(prefix);
             u != st_->used.end() && u->compare(0, prefix.size(), prefix) == 0; ++u) {
          std::string rest = u->substr(prefix.size());
          if (rest.find('/') == std::string::npos)
            known.push_back(Json::json_pointer("/" + rest).back());
        }
        std::string hint = closest_name(it.key(), known);
        throw Error(locate(sp), "unknown key \"" + escape_control(it.key(), 80) + "\" (" +
                                    (hint.empty() ? "not a parameter here; check spelling"
                                                  : "did you mean \"" + hint + "\"?") +
                                    ")");
      }
      finish_rec(it.value(), p, sp);
    }
  } else if (j.is_array()) {
    for (size_t i = 0; i < j.size(); ++i) {
      auto p = ptr / i;
      if (st_->used.count(p.to_string())) finish_rec(j[i], p, path + "[" + std::to_string(i) + "]");
    }
  }
}

void Params::finish() const {
  finish_rec(j_, ptr_, path_);
}

Json parse_value_or_string(const std::string& text, const std::string& where) {
  check_json_depth(text, where);
  try {
    return Json::parse(text);
  } catch (const Json::parse_error&) {
    // Not JSON: a plain string, which must be valid UTF-8 (it is written to manifest.json).
    Json s = text;
    try {
      (void)s.dump();
    } catch (const Json::type_error&) {
      throw Error(where, "value is not valid UTF-8 text");
    }
    return s;
  } catch (const Json::exception& e) {  // valid syntax but unrepresentable (1e400)
    throw Error(where, "bad value: " + json_error_text(e));
  }
}

size_t json_path_depth(const std::string& path) {
  size_t n = 1;
  for (char c : path) n += c == '.' || c == '[';
  return n;
}

std::string apply_override(Json& doc, const std::string& assignment) {
  auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw Error("override \"" + assignment + "\"", "expected key.path=value");
  std::string key = assignment.substr(0, eq), val = assignment.substr(eq + 1);
  // Errors name the command-line text, not the config file it was applied to.
  const std::string W = "override '" + escape_control(assignment, 80) + "'";
  Json value = parse_value_or_string(val, W);
  if (!doc.is_object()) throw Error(W, "the config is not a JSON object");
  // Each component nests the document one level: bounded like JSON text (kMaxJsonDepth), so
  // no path of a 128 KB argument builds a document the recursive JSON code cannot walk.
  if (json_path_depth(key) > size_t(kMaxJsonDepth))
    throw Error(W, "path nested deeper than " + std::to_string(kMaxJsonDepth) +
                       " levels (the limit for any fovsim input)");
  Json* node = &doc;
  size_t i = 0;
  std::string walked;
  std::string created;  // the first key this override adds (its whole subtree is new)
  bool any = false;
  while (i < key.size()) {
    size_t j = key.find_first_of(".[", i);
    std::string part = key.substr(i, j == std::string::npos ? std::string::npos : j - i);
    if (part.empty() && (j == std::string::npos || key[j] == '.'))
      throw Error(
          W, "empty key in path \"" + key + "\" (expected key.path=value, e.g. render.scale=0.5)");
    if (!part.empty()) {
      if (!node->is_object() && !node->is_null())
        throw Error(W, "\"" + walked + "\" is not an object");
      walked += (walked.empty() ? "" : ".") + part;
      if (created.empty() && !(node->is_object() && node->contains(part))) created = walked;
      node = &(*node)[part];
      any = true;
    }
    if (j == std::string::npos) break;
    if (key[j] == '[') {
      if (!any) throw Error(W, "a path must start with a key (e.g. methods[0].sigma)");
      size_t close = key.find(']', j);
      if (close == std::string::npos) throw Error(W, "missing ']'");
      std::string idx = key.substr(j + 1, close - j - 1);
      long n = 0;
      // A label starts with a letter or '_'; anything else is parsed as an index.
      const bool label =
          !idx.empty() && (std::isalpha(static_cast<unsigned char>(idx[0])) || idx[0] == '_');
      if (!label) {
        if (!parse_integer(idx, 0, 1000000000L, n))
          throw Error(W, "bad array index \"" + idx + "\"");
        if (!node->is_array() || size_t(n) >= node->size())
          throw Error(W, "\"" + walked + "\" has no element [" + idx + "]");
      } else {
        // Label form, as in sweep axes (methods[kfr].sigma): the element whose "label" (or,
        // without a label, "method") is idx; none or several is an error listing the labels.
        if (!node->is_array()) throw Error(W, "\"" + walked + "\" is not an array");
        long found = -1, count = 0;
        std::string names;
        for (size_t k = 0; k < node->size(); ++k) {
          const Json& e = (*node)[k];
          if (!e.is_object()) continue;
          const Json* l =
              e.contains("label") ? &e["label"] : (e.contains("method") ? &e["method"] : nullptr);
          if (!l || !l->is_string()) continue;
          names += (names.empty() ? "" : ", ") + l->get<std::string>();
          if (l->get<std::string>() == idx) {
            found = long(k);
            ++count;
          }
        }
        if (count == 0)
          throw Error(W, "no entry of \"" + walked + "\" has label \"" + idx +
                             "\" (labels: " + names + ")");
        if (count > 1)
          throw Error(W, std::to_string(count) + " entries of \"" + walked + "\" match \"" + idx +
                             "\"; give them labels");
        n = found;
      }
      node = &(*node)[size_t(n)];
      walked += "[" + std::to_string(n) + "]";
      i = close + 1;
      if (i < key.size() && key[i] == '.') {
        ++i;
        if (i == key.size()) throw Error(W, "trailing '.' in path \"" + key + "\"");
      } else if (i < key.size() && key[i] != '[') {
        throw Error(W, "expected '.' or '[' after ']' in \"" + key + "\"");
      }
    } else {
      i = j + 1;
      if (i == key.size()) throw Error(W, "trailing '.' in path \"" + key + "\"");
    }
  }
  if (!any) throw Error(W, "empty path (expected key.path=value, e.g. render.scale=0.5)");
  *node = value;
  return created.empty() ? walked : created;
}

}  // namespace fovsim
