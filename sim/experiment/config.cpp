#include "sim/experiment/config.h"

#include <filesystem>
#include <set>

#include "sim/core/error.h"

namespace fovsim {

namespace fs = std::filesystem;

std::string resolve_path(const std::string& base_dir, const std::string& p) {
  if (p.empty() || fs::path(p).is_absolute() || base_dir.empty()) return p;
  return (fs::path(base_dir) / p).lexically_normal().string();
}

static void merge_into(Json& dst, const Json& src) {
  if (dst.is_object() && src.is_object()) {
    for (auto it = src.begin(); it != src.end(); ++it) {
      if (dst.contains(it.key()) && dst[it.key()].is_object() && it.value().is_object())
        merge_into(dst[it.key()], it.value());
      else
        dst[it.key()] = it.value();
    }
  } else {
    dst = src;
  }
}

static Json load_with_bases(const std::string& path, std::set<std::string>& seen) {
  std::error_code ec;
  std::string canon = fs::weakly_canonical(path, ec).string();
  if (ec) throw Error(path, "cannot resolve path: " + ec.message());
  if (seen.count(canon)) throw Error(path, "config inheritance cycle through \"base\"");
  seen.insert(canon);
  Json doc = Params::parse_json_file(path);
  if (!doc.is_object()) throw Error(path, "a config must be a JSON object");
  if (doc.contains("base")) {
    if (!doc["base"].is_string())
      throw Error(path + ": base", "expected a path string, got " + describe_json(doc["base"]));
    std::string base =
        resolve_path(fs::path(path).parent_path().string(), doc["base"].get<std::string>());
    if (!fs::exists(base, ec))
      throw Error(path + ": base", "base config \"" + base + "\" not found");
    Json merged = load_with_bases(base, seen);
    doc.erase("base");
    merge_into(merged, doc);
    return merged;
  }
  return doc;
}

LoadedConfig load_config(const std::string& path, const std::vector<std::string>& overrides) {
  LoadedConfig c;
  c.file = path;
  c.base_dir = fs::path(path).parent_path().string();
  std::set<std::string> seen;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error(path, "config file not found");
  c.doc = load_with_bases(path, seen);
  for (auto& o : overrides) c.overridden.emplace_back(apply_override(c.doc, o), o);
  return c;
}

std::string default_models_dir() {
  if (const char* e = std::getenv("FOVSIM_MODELS")) return e;
  if (fs::exists("models/displays")) return "models";
  return std::string(FOVSIM_SOURCE_DIR) + "/models";
}

}  // namespace fovsim
