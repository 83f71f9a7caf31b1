// File scenes from hostile input: a node hierarchy nested past kMaxNodeDepth (glTF 2 and 1.0,
// .gltf and .glb) or with a cycle is one error naming the file and the limit, never a stack
// overflow; model files reached through a link out of the model's folder are refused; colours
// that are not finite and scenes that collapse to a point after their transforms are refused.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "sim/core/error.h"
#include "sim/core/limits.h"
#include "sim/scene/builtin.h"

using namespace fovsim;
namespace fs = std::filesystem;

namespace {

const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";
// One triangle (0,0,0), (1,0,0), (0,1,0) as 36 bytes of float32.
const char* kTriangle =
    "data:application/octet-stream;base64,"
    "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";

std::string dir() {
  static const std::string d = [] {
    fs::path p = fs::temp_directory_path() / ("fovsim_scene_rel_" + std::to_string(::getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p.string();
  }();
  return d;
}

std::string write(const std::string& name, const std::string& text) {
  const std::string p = dir() + "/" + name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

std::string error_of(const Json& scene) {
  try {
    Params root(Json{{"scene", scene}}, "test.json");
    Params p = root.child("scene");
    make_scene(p, kModels);
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("NOT A fovsim::Error: ") + e.what();
  }
  return "NO ERROR";
}

// A glTF 2 document: one triangle mesh under a chain of `depth` nested nodes (node i's child is
// node i + 1), the last node scaled by `scale`.
Json chain_gltf(int depth, double scale = 1.0) {
  Json nodes = Json::array();
  for (int i = 0; i < depth; ++i) {
    Json n = Json::object();
    if (i + 1 < depth) n["children"] = Json::array({i + 1});
    if (i + 1 == depth) {
      n["mesh"] = 0;
      n["scale"] = Json::array({scale, scale, scale});
    }
    nodes.push_back(n);
  }
  return Json{{"asset", {{"version", "2.0"}}},
              {"scene", 0},
              {"scenes", Json::array({{{"nodes", Json::array({0})}}})},
              {"nodes", nodes},
              {"meshes",
               Json::array({{{"primitives", Json::array({{{"attributes", {{"POSITION", 0}}}}})}}})},
              {"accessors", Json::array({{{"bufferView", 0},
                                          {"componentType", 5126},
                                          {"count", 3},
                                          {"type", "VEC3"},
                                          {"min", {0, 0, 0}},
                                          {"max", {1, 1, 0}}}})},
              {"bufferViews", Json::array({{{"buffer", 0}, {"byteLength", 36}}})},
              {"buffers", Json::array({{{"byteLength", 36}, {"uri", kTriangle}}})}};
}

// A glTF 2 binary container holding `json` as its JSON chunk.
std::string glb_of(const std::string& json) {
  std::string j = json;
  while (j.size() % 4) j += ' ';
  auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  return "glTF" + u32(2) + u32(uint32_t(20 + j.size())) + u32(uint32_t(j.size())) +
         u32(0x4E4F534Au) + j;
}

}  // namespace

TEST(SceneReliability, NodeHierarchyDeeperThanTheLimitIsOneError) {
  const std::string limit = "nested deeper than " + std::to_string(kMaxNodeDepth) + " levels";
  // 20,000 levels: the file that overflowed the importer's stack.
  const std::string deep = write("deep.gltf", chain_gltf(20000).dump());
  std::string e = error_of({{"type", "file"}, {"path", deep}});
  EXPECT_NE(e.find(deep + ": node hierarchy " + limit), std::string::npos) << e;
  const std::string glb = write("deep.glb", glb_of(chain_gltf(20000).dump()));
  e = error_of({{"type", "file"}, {"path", glb}});
  EXPECT_NE(e.find(glb + ": node hierarchy " + limit), std::string::npos) << e;
  // glTF 1.0: nodes keyed by id, children by id.
  Json v1 = {{"asset", {{"version", "1.0"}}}, {"nodes", Json::object()}};
  for (int i = 0; i < 300; ++i)
    v1["nodes"]["n" + std::to_string(i)] =
        i + 1 < 300 ? Json{{"children", {"n" + std::to_string(i + 1)}}} : Json::object();
  const std::string old = write("deep1.gltf", v1.dump());
  e = error_of({{"type", "file"}, {"path", old}});
  EXPECT_NE(e.find(old + ": node hierarchy " + limit), std::string::npos) << e;
  // A cycle and a node with two parents are not trees.
  Json cyc = chain_gltf(3);
  cyc["nodes"][2]["children"] = Json::array({1});
  e = error_of({{"type", "file"}, {"path", write("cycle.gltf", cyc.dump())}});
  EXPECT_NE(e.find("is a child of more than one node"), std::string::npos) << e;
  Json self = chain_gltf(1);
  self["nodes"][0]["children"] = Json::array({0});
  e = error_of({{"type", "file"}, {"path", write("self.gltf", self.dump())}});
  EXPECT_NE(e.find("glTF node 0 is its own ancestor"), std::string::npos) << e;
  // At the limit the model loads.
  EXPECT_EQ(
      error_of({{"type", "file"}, {"path", write("ok.gltf", chain_gltf(kMaxNodeDepth).dump())}}),
      "NO ERROR");
  // JSON nested past kMaxJsonDepth inside a model is refused by the checked parser.
  Json nested = chain_gltf(1);
  nested["extras"] = Json::parse(std::string(100, '[') + std::string(100, ']'));
  e = error_of({{"type", "file"}, {"path", write("nested.gltf", nested.dump())}});
  EXPECT_NE(e.find("JSON nested deeper than 64 levels"), std::string::npos) << e;
}

TEST(SceneReliability, ModelFilesThroughLinksOutOfTheFolderAreRefused) {
  const std::string outside = dir() + "_outside";
  fs::create_directories(outside);
  std::ofstream(outside + "/secret.mtl") << "newmtl m\nKd 1 0 0\n";
  fs::create_directories(dir() + "/obj");
  fs::create_symlink(outside + "/secret.mtl", dir() + "/obj/m.mtl");
  const std::string obj =
      write("obj/tri.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  std::string e = error_of({{"type", "file"}, {"path", obj}});
  EXPECT_NE(e.find("outside the model's folder"), std::string::npos) << e;
  // A link loop says so, not "not found".
  fs::create_symlink(dir() + "/obj/loop_b.mtl", dir() + "/obj/loop_a.mtl");
  fs::create_symlink(dir() + "/obj/loop_a.mtl", dir() + "/obj/loop_b.mtl");
  const std::string loop =
      write("obj/loop.obj", "mtllib loop_a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  e = error_of({{"type", "file"}, {"path", loop}});
  EXPECT_NE(e.find("symbolic link loop"), std::string::npos) << e;
  fs::remove_all(outside);
}

TEST(SceneReliability, NonFiniteColoursAndDegenerateTransformsAreRefused) {
  // OBJ Kd nan, glTF factors that overflow a float (1e39).
  write("nan.mtl", "newmtl m\nKd nan 0.5 0.5\n");
  std::string e =
      error_of({{"type", "file"},
                {"path", write("nan.obj",
                               "mtllib nan.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")}});
  EXPECT_NE(e.find("base colour component nan is not a finite value"), std::string::npos) << e;
  Json big = chain_gltf(1);
  big["materials"] = Json::array({{{"emissiveFactor", {1e39, 0, 0}}}});
  big["meshes"][0]["primitives"][0]["material"] = 0;
  e = error_of({{"type", "file"}, {"path", write("big.gltf", big.dump())}});
  EXPECT_NE(e.find("emission component inf is not a finite value"), std::string::npos) << e;
  // A node scale of 0 and a scene.scale that is 0 in single precision: a point, not a scene.
  e = error_of({{"type", "file"}, {"path", write("zero.gltf", chain_gltf(2, 0.0).dump())}});
  EXPECT_NE(e.find("zero area in the world"), std::string::npos) << e;
  e = error_of(
      {{"type", "file"}, {"path", write("tiny.gltf", chain_gltf(1).dump())}, {"scale", 1e-300}});
  EXPECT_NE(e.find("zero area in the world"), std::string::npos) << e;
  e = error_of(
      {{"type", "file"}, {"path", write("small.gltf", chain_gltf(1).dump())}, {"scale", 1e-9}});
  EXPECT_NE(e.find("m across after every transform, under 1e-06 m"), std::string::npos) << e;
}
