// JSON parameter wrapper (nori PropertyList / pbrt ParameterDictionary role, docs/architecture.md
// "Errors and conventions"). Every read names its JSON path; wrong types and out-of-range values
// throw fovsim::Error with "file: json.path"; keys never read are reported by finish() as unknown,
// so a typo never silently falls back to a default. Reads record the value used (defaults included)
// into a shared "resolved" document written to manifest.json.
#pragma once
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

namespace fovsim {

using Json = nlohmann::json;

// Deepest nesting of arrays/objects accepted in any JSON input (configs, sweep specs, column
// maps, override values). fovsim's own configs nest fewer than 10 levels; the limit is
// checked on the text before parsing, so no recursive JSON code ever sees deeper input.
constexpr int kMaxJsonDepth = 64;

// Parses JSON text (comments allowed). Syntax errors, numbers out of double range
// (1e400) and nesting deeper than kMaxJsonDepth throw fovsim::Error located at
// `file`:line:column; an empty `file` reports "<where>: ...".
Json parse_json_text(const std::string& text, const std::string& file);
// As parse_json_text, keeping the keys in file order (for files fovsim rewrites in their
// authors' layout, such as fitted workloads).
nlohmann::ordered_json parse_json_text_ordered(const std::string& text, const std::string& file);
// Throws when `text` nests arrays/objects deeper than kMaxJsonDepth (strings and comments
// are skipped), with the line and column of the first bracket over the limit.
void check_json_depth(const std::string& text, const std::string& file);

struct Range {
  double lo = -1e300, hi = 1e300;
  bool lo_open = false, hi_open = false;
  static Range any() { return {}; }
  static Range closed(double a, double b) { return {a, b, false, false}; }
  static Range above(double a, double b = 1e300) { return {a, b, true, false}; }  // (a, b]
  static Range at_least(double a) { return {a, 1e300, false, false}; }
  bool contains(double v) const;
  std::string str() const;  // "[1, 64]", "(0, inf)"
};

// The one check of a numeric argument outside a config (CLI flags, Python arguments): returns
// v when it is finite and in `r`, else throws fovsim::Error(where, "value V is out of range R")
// -- the message a config key gets. NaN and infinities are never in range.
double check_number(const std::string& where, double v, const Range& r);
// As check_number, and v must be an integer.
long check_integer(const std::string& where, double v, const Range& r);

class Params {
 public:
  // `file` is used in error locations; `path` is the JSON path of `j` ("" at the root).
  Params(Json j, std::string file = "", std::string path = "");
  // Parses a JSON file; syntax errors report file:line:col.
  static Params from_file(const std::string& file);
  static Json parse_json_file(const std::string& file);

  bool has(const std::string& key) const;
  const std::string& file() const { return st_->file; }
  const std::string& path() const { return path_; }
  std::string path_of(const std::string& key) const;
  std::string where(const std::string& key = "") const;  // "file: path.key"
  [[noreturn]] void fail(const std::string& key, const std::string& msg) const;

  // Typed getters. The two-argument-default forms are optional keys; the others required.
  double number(const std::string& key, double def, Range r = Range::any());
  double number(const std::string& key, Range r = Range::any());
  int integer(const std::string& key, int def, Range r = Range::any());
  int integer(const std::string& key, Range r = Range::any());
  bool boolean(const std::string& key, bool def);
  std::string string(const std::string& key, const std::string& def,
                     const std::vector<std::string>& allowed = {});
  std::string string(const std::string& key, const std::vector<std::string>& allowed = {});
  std::vector<double> numbers(const std::string& key, const std::vector<double>& def,
                              Range r = Range::any());

  // Nested object (missing -> empty object, so its own getters apply defaults).
  Params child(const std::string& key);
  // Array of objects.
  std::vector<Params> children(const std::string& key);
  // Raw access (marks the key used; records it resolved as given).
  const Json& raw(const std::string& key);
  const Json& json() const { return j_; }

  // Throws for the first key below this object that no getter read.
  void finish() const;
  // The resolved document (all reads with defaults filled in) of the root.
  const Json& resolved() const { return st_->resolved; }
  // Marks a key as consumed without reading it (e.g. documentation keys like "comment").
  void ignore(const std::string& key);
  // Values that came from the command line: (JSON path as apply_override returns it, the
  // override text). An error at or below such a path names "override 'TEXT'" instead of
  // the config file, so a typo on the command line is not blamed on the file.
  void set_origins(std::vector<std::pair<std::string, std::string>> origins);
  // Values written by a "base" file of the config: (JSON path, that file). An error at or
  // below such a path reads "config.json: trace.file (inherited from base.json): ...", and
  // source_dir() resolves a relative path there against the base file's folder.
  void set_inherited(const std::vector<std::pair<std::string, std::string>>& inherited);
  // Folder of the base file that wrote `key` (at or above it), or "" when this object's own
  // config (or a command-line override) wrote it.
  std::string source_dir(const std::string& key) const;

 private:
  struct State {
    std::string file;
    Json resolved = Json::object();
    std::set<std::string> used;  // JSON pointers of keys that were read
    std::vector<std::pair<std::string, std::string>> origins;  // see set_origins
    std::map<std::string, std::string> inherited;              // see set_inherited
  };
  const std::string* inherited_from(const std::string& path) const;
  std::string locate(const std::string& path) const;  // "file: path" or "override '…': path"
  Params(Json j, std::shared_ptr<State> st, std::string path, Json::json_pointer ptr);
  const Json* find(const std::string& key) const;
  void mark(const std::string& key, const Json& value);
  void check_range(const std::string& key, double v, const Range& r) const;
  void finish_rec(const Json& j, const Json::json_pointer& ptr, const std::string& path) const;

  Json j_;
  std::shared_ptr<State> st_;
  std::string path_;
  Json::json_pointer ptr_;
};

// A command-line value: JSON when it is valid JSON (numbers, true/false, arrays, quoted
// strings), else the text as a string. Nesting beyond kMaxJsonDepth and numbers out of double
// range are errors naming `where` (e.g. "override render.scale", "--param kfr.alpha=...").
Json parse_value_or_string(const std::string& text, const std::string& where);

// Applies a command-line override "a.b[2].c=value" to a JSON document. The value is parsed
// as JSON when it is valid JSON (numbers, true/false, arrays, quoted strings), else taken as
// a string. Intermediate objects are created; array indices must exist. Returns the JSON
// path (numeric indices) of what it introduced: the first key it created ("rendr" for
// "rendr.scale=1"), else the key it replaced ("methods[0].sigma" for "methods[kfr].sigma=2").
std::string apply_override(Json& doc, const std::string& assignment);
// Levels a config path ("a.b[2].c": 4) nests a document: apply_override and the sweep's axis
// paths refuse more than kMaxJsonDepth.
size_t json_path_depth(const std::string& path);

// The name in `names` closest to `word` by edit distance (insertions, deletions,
// substitutions, transpositions), or "" when none is within max(1, |word| / 2) edits:
// for "did you mean" hints ("rn" -> "run").
std::string closest_name(const std::string& word, const std::vector<std::string>& names);

// Describes a JSON value's type for error messages ("a number", "a string \"abc\"").
std::string describe_json(const Json& v);

}  // namespace fovsim
