// The column map's declared keys (sim/trace/map_keys.cpp): each typed row is the one the
// importer reads (its path appears in importer.cpp's getter calls), reads back its own default
// from an empty block, and refuses a value outside its list naming the key.
#include "sim/trace/map_keys.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>

#include "sim/core/error.h"

using namespace fovsim;

namespace {
std::string importer_source() {
  std::ifstream f(std::string(FOVSIM_SOURCE_DIR) + "/sim/trace/importer.cpp");
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}
}  // namespace

TEST(MapKeys, EveryTypedKeyIsReadThroughTheTable) {
  const std::string src = importer_source();
  std::set<std::string> seen;
  for (const MapKey& k : map_keys()) {
    EXPECT_TRUE(seen.insert(k.path + " (" + k.variant + ")").second) << k.path << " twice";
    EXPECT_FALSE(k.doc.empty()) << k.path;
    if (k.type == MapKeyType::Other) continue;
    EXPECT_NE(src.find("\"" + k.path + "\""), std::string::npos)
        << k.path << " is declared but importer.cpp does not read it through map_keys.h";
    if (!k.variant.empty()) {
      EXPECT_NE(src.find("\"" + k.variant + "\""), std::string::npos) << k.path << " " << k.variant;
    }
  }
}

TEST(MapKeys, DefaultsReadBackAndListsAreChecked) {
  for (const MapKey& k : map_keys()) {
    if (k.def.is_null() || k.type == MapKeyType::Other) continue;
    Params p(Json::object(), "map.json");
    switch (k.type) {
      case MapKeyType::String:
        EXPECT_EQ(Json(map_string(p, k.path, k.variant)), k.def) << k.path;
        break;
      case MapKeyType::Bool:
        EXPECT_EQ(Json(map_boolean(p, k.path, k.variant)), k.def) << k.path;
        break;
      case MapKeyType::Int:
        EXPECT_EQ(Json(map_integer(p, k.path, k.variant)), k.def) << k.path;
        break;
      case MapKeyType::Number:
        EXPECT_EQ(map_number(p, k.path, k.variant), k.def.get<double>()) << k.path;
        break;
      case MapKeyType::Numbers:
        EXPECT_EQ(Json(map_numbers(p, k.path, k.variant)), k.def) << k.path;
        break;
      case MapKeyType::Other:
        break;
    }
    if (k.type == MapKeyType::String && !k.allowed.empty()) {
      const std::string key = k.path.substr(k.path.rfind('.') + 1);
      Params bad(Json{{key, "no such value"}}, "map.json");
      try {
        map_string(bad, k.path, k.variant);
        ADD_FAILURE() << k.path << " accepted a value outside its list";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      }
    }
  }
}

TEST(MapKeys, TheMarkdownTableHasARowPerKey) {
  const std::string md = map_keys_markdown();
  size_t rows = 0;
  for (size_t i = md.find('\n'); i != std::string::npos; i = md.find('\n', i + 1)) ++rows;
  EXPECT_EQ(rows, map_keys().size() + 2);  // the header and its rule
  EXPECT_NE(md.find("| `time.max_step_s` | number | `"), std::string::npos) << md;
}
