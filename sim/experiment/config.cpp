#include "sim/experiment/config.h"

#include <filesystem>
#include <set>

#include "sim/core/error.h"
#include "sim/core/files.h"

namespace fovsim {

namespace fs = std::filesystem;

std::string resolve_path(const std::string& base_dir, const std::string& p) {
  if (p.empty() || fs::path(p).is_absolute() || base_dir.empty()) return p;
  return (fs::path(base_dir) / p).lexically_normal().string();
}

namespace {

// Merges `src` (written by file number `idx` of the chain) into `dst`; `who` mirrors `dst`:
// an object where `dst` is a merged object, else the number of the file that wrote the value.
// Recursion follows the JSON nesting, which parse_json_text bounds by kMaxJsonDepth.
void merge_into(Json& dst, Json& who, const Json& src, int idx) {
  if (!src.is_object()) {
    dst = src;
    who = idx;
    return;
  }
  if (!dst.is_object()) dst = Json::object();
  if (!who.is_object()) who = Json::object();
  for (auto it = src.begin(); it != src.end(); ++it)
    merge_into(dst[it.key()], who[it.key()], it.value(), idx);
}

// (JSON path, file) of every value in `who` written by a file other than number 0.
void list_inherited(const Json& who, const std::string& path, const std::vector<std::string>& files,
                    std::vector<std::pair<std::string, std::string>>& out) {
  if (who.is_object()) {
    for (auto it = who.begin(); it != who.end(); ++it)
      list_inherited(it.value(), path.empty() ? it.key() : path + "." + it.key(), files, out);
  } else if (who.is_number_integer() && who.get<int>() > 0) {
    out.emplace_back(path, files[size_t(who.get<int>())]);
  }
}

}  // namespace

// The chain CONFIG -> base -> base of base ... is followed in a loop (no recursion: a chain of
// any length costs no stack) up to kMaxBaseDepth files, then merged from the last base on.
static Json load_with_bases(const std::string& path, LoadedConfig& c) {
  std::vector<std::string> files{path};
  std::vector<Json> docs;
  std::set<std::string> seen;
  for (;;) {
    const std::string& f = files.back();
    std::error_code ec;
    std::string canon = fs::weakly_canonical(f, ec).string();
    if (ec) throw Error(f, "cannot resolve path: " + ec.message());
    if (seen.count(canon)) throw Error(f, "config inheritance cycle through \"base\"");
    seen.insert(canon);
    Json doc = Params::parse_json_file(f);
    if (!doc.is_object()) throw Error(f, "a config must be a JSON object");
    if (!doc.contains("base")) {
      docs.push_back(std::move(doc));
      break;
    }
    if (!doc["base"].is_string())
      throw Error(f + ": base", "expected a path string, got " + describe_json(doc["base"]));
    // Relative to the file that names it, whatever its depth in the chain.
    std::string base =
        resolve_path(fs::path(f).parent_path().string(), doc["base"].get<std::string>());
    doc.erase("base");
    docs.push_back(std::move(doc));
    if (path_kind(base, f + ": base") == PathKind::missing)
      throw Error(f + ": base", "base config \"" + base + "\" not found");
    if (int(files.size()) >= kMaxBaseDepth)
      throw Error(f + ": base", "\"base\" chain longer than " + std::to_string(kMaxBaseDepth) +
                                    " files (the limit of config inheritance; starting at " + path +
                                    ")");
    files.push_back(base);
  }
  Json merged = Json::object(), who = Json::object();
  for (size_t i = docs.size(); i-- > 0;) merge_into(merged, who, docs[i], int(i));
  list_inherited(who, "", files, c.inherited);
  return merged;
}

LoadedConfig load_config(const std::string& path, const std::vector<std::string>& overrides) {
  LoadedConfig c;
  c.file = path;
  c.base_dir = fs::path(path).parent_path().string();
  if (path_kind(path) == PathKind::missing) throw Error(path, "config file not found");
  c.doc = load_with_bases(path, c);
  for (auto& o : overrides) c.overridden.emplace_back(apply_override(c.doc, o), o);
  return c;
}

std::string default_models_dir() {
  if (const char* e = std::getenv("FOVSIM_MODELS")) return e;
  if (fs::exists("models/displays")) return "models";
  return std::string(FOVSIM_SOURCE_DIR) + "/models";
}

}  // namespace fovsim
