// The keys of a column map (traces/README.md "Column maps"), declared once: path, type,
// default, allowed values or range, meaning. The importer reads every typed key through the
// getters below (so a default or a list of values is written only in the table), and the
// table in traces/README.md is generated from it (`fovsim trace keys --markdown`,
// scripts/gen_method_docs.sh; tests/app/docs_test.cpp checks they match).
//
// Adding a map key is one row in map_keys.cpp (`map_key_table`) and one getter call where the
// importer reads it (sim/trace/importer.cpp), then `make docs`.
#pragma once
#include <string>
#include <vector>

#include "sim/core/params.h"

namespace fovsim {

enum class MapKeyType { String, Bool, Int, Number, Numbers, Other };

struct MapKey {
  std::string path;     // "time.max_step_s", "valid[i].eye"; the JSON key is its last part
  std::string variant;  // "" or the `type` (or form) the key belongs to ("euler", "point")
  MapKeyType type = MapKeyType::Other;
  Json def;               // null: no default (required, or read only when given)
  bool required = false;  // the key must be given (in its variant)
  Range range;
  std::vector<std::string> allowed;       // String: the accepted values (empty: any)
  std::string type_doc, def_doc, values;  // doc text replacing the generated one
  std::string doc;
};

// Every map key, in the order of the generated table.
const std::vector<MapKey>& map_keys();
// The row of `path` in `variant`; an unknown one is a bug (FOVSIM_CHECK).
const MapKey& map_key(const std::string& path, const std::string& variant = "");

// Read the key of `path` (its last part) from `p`, the object that holds it, with the row's
// default, range and values; a row without a default makes the key required.
std::string map_string(Params& p, const std::string& path, const std::string& variant = "");
bool map_boolean(Params& p, const std::string& path, const std::string& variant = "");
int map_integer(Params& p, const std::string& path, const std::string& variant = "");
double map_number(Params& p, const std::string& path, const std::string& variant = "");
std::vector<double> map_numbers(Params& p, const std::string& path,
                                const std::string& variant = "");

// The table as Markdown (key, type, default, values, meaning).
std::string map_keys_markdown();
inline constexpr const char* kMapKeyDocsBegin =
    "<!-- BEGIN GENERATED MAP KEYS by `fovsim trace keys --markdown` (scripts/gen_method_docs.sh); "
    "do not edit -->";
inline constexpr const char* kMapKeyDocsEnd = "<!-- END GENERATED MAP KEYS -->";

}  // namespace fovsim
