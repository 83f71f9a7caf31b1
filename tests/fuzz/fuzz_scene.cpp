// libFuzzer target: scene files (OBJ + MTL, glTF) with a texture, through make_scene's checks
// (references confined to the model's folder, texture headers checked before decoding,
// geometry finite and within the coordinate bound). Input: first byte picks the format, the
// rest is split at the first "\n---\n" into the model text and the texture bytes. Every
// failure must be a fovsim::Error; anything else (another exception, a crash, a sanitizer
// report, a hang on a reference) is a bug. Build: `make fuzz` (tests/fuzz/README.md).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "sim/core/error.h"
#include "sim/core/params.h"
#include "sim/scene/scene.h"

using namespace fovsim;

namespace {
std::string dir() {
  static const std::string d = [] {
    auto p = std::filesystem::temp_directory_path() /
             ("fovsim_fuzz_scene_" + std::to_string(::getpid()));
    std::filesystem::create_directories(p);
    return p.string();
  }();
  return d;
}
void put(const std::string& path, const std::string& s) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(s.data(), std::streamsize(s.size()));
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const bool gltf = data[0] & 1;
  std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  std::string tex;
  const size_t cut = text.find("\n---\n");
  if (cut != std::string::npos) {
    tex = text.substr(cut + 5);
    text.resize(cut);
  }
  const std::string model = dir() + (gltf ? "/m.gltf" : "/m.obj");
  put(model, text);
  put(dir() + "/m.mtl", "newmtl m\nKd 1 1 1\nmap_Kd t.png\n");
  put(dir() + "/t.png", tex);
  try {
    Params p(Json{{"type", "file"},
                  {"path", model},
                  {"max_texture_pixels", 1 << 20},
                  {"max_triangles", 1e6},
                  {"on_missing_texture", (data[0] & 2) ? "base_color" : "fail"}},
             "fuzz.json", "scene");
    Scene s = make_scene(p, "");
    (void)s.triangle_count();
  } catch (const Error&) {
  }
  return 0;
}
