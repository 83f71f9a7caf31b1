// Dumps full-resolution G-buffers (HTC Vive Pro Eye, 1440 x 1600; atrium complexity 1, 3, 6;
// three view directions) of the Embree ISA path chosen by FOVSIM_EMBREE_ISA, for
// bench/isa_gbuffer_diff.py, which runs this under every path and counts the pixels that
// differ (tests/golden/README.md "Same numbers on every CPU").
// Usage: FOVSIM_EMBREE_ISA=sse2 build/isa_gbuffer OUT_PREFIX
// Writes OUT_PREFIX_<complexity>_<view>.bin: n (uint64), then depth, object id, normal,
// albedo, uv, position (n values each, float32 / int32 components, row-major).
#include <cstdio>
#include <fstream>
#include <memory>

#include "sim/render/renderer.h"
using namespace fovsim;
int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: isa_gbuffer OUT_PREFIX\n");
    return 2;
  }
  std::string out = argv[1];
  const std::string models = std::string(FOVSIM_SOURCE_DIR) + "/models";
  Display d = Display::load("htc_vive_pro_eye", models);
  for (int cx : {1, 3, 6}) {
    Params p(Json{{"type", "atrium"}, {"complexity", cx}});
    Scene scene = make_scene(p, models);
    Renderer r(scene, RenderSettings{});
    int k = 0;
    for (double yaw : {-8.0, 35.0, 120.0}) {
      Camera cam = Camera::from_pose(d, glm::dvec3(scene.default_eye),
                                     glm::angleAxis(deg2rad(yaw), glm::dvec3(0, 1, 0)));
      GBuffer g;
      r.trace_gbuffer(cam, ~0u & ~uint32_t(kMotion), g);
      std::ofstream f(out + "_" + std::to_string(cx) + "_" + std::to_string(k++) + ".bin",
                      std::ios::binary);
      const size_t n = g.depth.size();
      f.write((const char*)&n, sizeof n);
      f.write((const char*)g.depth.data(), n * 4);
      f.write((const char*)g.object_id.data(), n * 4);
      f.write((const char*)g.normal.data(), n * 12);
      f.write((const char*)g.albedo.data(), n * 12);
      f.write((const char*)g.uv.data(), n * 8);
      f.write((const char*)g.position.data(), n * 12);
      if (!f) {
        std::fprintf(stderr, "isa_gbuffer: cannot write %s_*.bin\n", out.c_str());
        return 1;
      }
    }
  }
}
