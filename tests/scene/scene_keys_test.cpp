// The `scene` tables (common keys, `vpl`, each scene type) read their own declared defaults
// and ranges.
#include "sim/scene/scene_keys.h"

#include <gtest/gtest.h>

#include "tests/common/param_table_check.h"

using namespace fovsim;

TEST(SceneKeys, EveryTableReadsItsOwnDefaults) {
  table_check::expect_table_reads_own_defaults(scene_table(), "scene");
  table_check::expect_table_reads_own_defaults(vpl_table(), "scene.vpl");
  table_check::expect_table_reads_own_defaults(atrium_table(), "scene");
  table_check::expect_table_reads_own_defaults(patterns_table(), "scene");
  table_check::expect_table_reads_own_defaults(cornell_table(), "scene");
  table_check::expect_table_reads_own_defaults(file_scene_table(), "scene");
}

TEST(SceneKeys, FileSceneShapeRulesAreLocated) {
  Params p(Json{{"path", "m.gltf"}, {"translate", {1, 2}}}, "run.json", "scene");
  try {
    file_scene_table().read(p);
    ADD_FAILURE() << "a 2-element translate accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("scene.translate: expected 3 numbers"), std::string::npos)
        << e.what();
  }
}
