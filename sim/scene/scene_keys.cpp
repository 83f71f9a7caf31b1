#include "sim/scene/scene_keys.h"

#include <cmath>
#include <cstdio>

#include "sim/core/limits.h"
#include "sim/scene/builtin.h"

namespace fovsim {

const ParamTable<SceneKeys>& scene_table() {
  using K = SceneKeys;
  static const auto t =
      ParamTable<K>()
          .text("type", nullptr, {"atrium", "patterns", "cornell", "file"}, &K::type)
          .required()
          .doc("", "which scene (models/scenes/README.md); its keys: the tables below")
          .number("max_triangles", kDefaultMaxTriangles, Range::closed(1, 2e9), &K::max_triangles)
          .doc("",
               "most triangles the scene may have: built-in tessellation (`cornell.cell`) is "
               "checked before it is generated, file scenes after import")
          .documented("vpl", "object", "", "", "",
                      "how the frame's VPLs are made (`scene.vpl` below); only for a scene with "
                      "indirect light (an error otherwise)")
          .documented("comment", "any", "", "", "", "ignored");
  return t;
}

const ParamTable<VplKeys>& vpl_table() {
  using K = VplKeys;
  static const auto t =
      ParamTable<K>()
          .integer("rsm_size", 64, Range::closed(1, 1024), &K::rsm_size)
          .doc("Yang et al. 2021 §7", "RSM texels per edge per light; VPLs <= lights x rsm_size^2")
          .number("min_dist", 0.01, Range::above(0, 1), &K::min_dist)
          .doc("", "distance clamp d_min of the 1/d^2 term, fraction of the scene diagonal")
          .boolean("shadow_rays", false, &K::shadow_rays)
          .doc("",
               "exact VPL -> receiver visibility in the shading of the reference and every "
               "method (expensive; the FLC paper's shading has none)")
          .number("max_vpls", kDefaultMaxVpls, Range::closed(1, 1e9), &K::max_vpls)
          .doc("",
               "most VPLs a frame may have, counted as lights x `rsm_size`^2 before any RSM is "
               "rendered; over it the scene is refused naming `scene.vpl.rsm_size`. Every "
               "reference pixel is shaded by every VPL, so the reference's work per frame is "
               "pixels x VPLs");
  return t;
}

const ParamTable<AtriumKeys>& atrium_table() {
  using K = AtriumKeys;
  static const auto t =
      ParamTable<K>()
          .integer("complexity", 3, Range::closed(1, kAtriumMaxComplexity), &K::complexity)
          .doc("",
               "tessellation level (column facets/segments, arch segments, baluster facets, "
               "floor/wall grid); the layout and textures do not change. Triangles: 1: "
               "27,706; 2: 40,616; 3: 75,956; 4: 151,340; 5: 371,772; 6: 1,055,372")
          .boolean("dynamic", false, &K::dynamic)
          .doc("",
               "the sculpture spins about +y (period `anim_period`) and bobs 0.15 m; it "
               "becomes an Embree instance")
          .boolean("moving_light", false, &K::moving_light)
          .doc("", "the point lamp walks +-8 m along the left arcade (period 2 x `anim_period`)")
          .boolean("indirect", false, &K::indirect)
          .doc("",
               "one-bounce indirect light from VPLs (`scene.vpl`); the reference and every "
               "method include it")
          .boolean("sun", true, &K::sun)
          .doc("", "the directional sun through the skylight")
          .number("sun_elevation_deg", 62.0, Range::closed(5, 90), &K::sun_elevation_deg)
          .doc("", "sun elevation above the horizon")
          .number("sun_azimuth_deg", 35.0, Range::closed(-360, 360), &K::sun_azimuth_deg)
          .doc("", "sun azimuth, from -z towards +x")
          .number("sun_intensity", 2.2, Range::closed(0, 1e4), &K::sun_intensity)
          .doc("", "irradiance scale of the sun")
          .number("lamp_intensity", 6.0, Range::closed(0, 1e6), &K::lamp_intensity)
          .doc("", "point lamp intensity (I / d^2)")
          .number("spot_intensity", 40.0, Range::closed(0, 1e6), &K::spot_intensity)
          .doc("", "spot light intensity (I / d^2, 10-16 deg cone)")
          .number("anim_duration", 60.0, Range::above(0, 3600), &K::anim_duration)
          .doc("", "seconds covered by keyframes (held after)")
          .number("anim_period", 8.0, Range::above(0, 3600), &K::anim_period)
          .doc("", "seconds per sculpture revolution")
          .number("texture_scale", 1.0, Range::above(0, 100), &K::texture_scale)
          .doc("", "multiplies every texture frequency (more or less high-frequency detail)");
  return t;
}

const ParamTable<PatternsKeys>& patterns_table() {
  using K = PatternsKeys;
  static const auto t =
      ParamTable<K>()
          .number("angle", 0.0, Range::closed(-3600, 3600), &K::angle)
          .doc("Ye et al. 2022 §6.1", "pattern rotation about the view axis, degrees")
          .text("pattern", "stripes",
                {"stripes", "checker", "grating", "bricks", "noise", "radial"}, &K::pattern)
          .doc("Ye et al. 2022 Fig. 12",
               "which pattern: `stripes` stands in for (a), `checker` for (b), `grating` "
               "(sinusoids at 3 octaves x 4 orientations) for (c)")
          .number("frequency", 40.0, Range::above(0, 1e4), &K::frequency)
          .doc("",
               "cycles per metre (at 1 m, 40 is about 20 px per cycle at the centre of a Vive "
               "Pro Eye)")
          .number("distance", 1.0, Range::above(0, 1e4), &K::distance)
          .doc("", "plane distance from `default_eye`")
          .number("size", 0.0, Range::closed(0, kMaxCoordinateM), &K::size)
          .doc("", "plane edge in metres; 0 = 8 x distance")
          .number("contrast", 1.0, Range::closed(0, 1), &K::contrast)
          .doc("", "pattern contrast around mid-grey");
  return t;
}

const ParamTable<CornellKeys>& cornell_table() {
  using K = CornellKeys;
  static const auto t =
      ParamTable<K>()
          .number("light_intensity", 1.6, Range::closed(0, 1e6), &K::light_intensity)
          .doc("", "light intensity (I / d^2); the panel's emission follows it")
          .text("light", "point", {"point", "spot"}, &K::light)
          .doc("", "light type (spot: 50-70 deg cone, pointing down)")
          .number("cell", 0.25, Range::above(0, 10), &K::cell)
          .doc("",
               "tessellation cell edge in metres (the triangle count it gives is checked "
               "against `max_triangles` before tessellating)")
          .boolean("textured", false, &K::textured)
          .doc("", "checker texture on the two boxes");
  return t;
}

const ParamTable<FileSceneKeys>& file_scene_table() {
  using K = FileSceneKeys;
  static const auto t =
      ParamTable<K>()
          .text("path", nullptr, {}, &K::path)
          .required()
          .doc("",
               "model file (any format assimp reads: glTF 2, OBJ, ...); relative paths are "
               "resolved against the folder of the config that wrote it, then "
               "`models/scenes/`")
          .number("scale", 1.0, Range::above(0, 1e9), &K::scale)
          .doc("", "uniform scale")
          .numbers("translate", {0, 0, 0}, Range::any(), &K::translate)
          .shown("[0, 0, 0]", "[x, y, z], each within +-1e5 m")
          .doc("",
               "translation (applied last); beyond the coordinate bound it is refused naming "
               "`scene.translate`")
          .numbers("rotate_deg", {0, 0, 0}, Range::any(), &K::rotate_deg)
          .shown("[0, 0, 0]", "[x, y, z]")
          .doc("", "rotation about x, then y, then z (degrees)")
          .numbers("default_eye", {}, Range::any(), &K::default_eye)
          .shown("in front of the model", "[x, y, z]")
          .doc("",
               "viewpoint for trace placement; default: on +z, 1.3 x the bounding radius from "
               "the centre")
          .boolean("default_lights", true, &K::default_lights)
          .doc("", "add a shadowed key light and a fill light when the file has no lights")
          .number("exposure", 1.0, Range::above(0, 1e6), &K::exposure)
          .doc("", "suggested tone-mapping exposure (the default of `render.tonemap.exposure`)")
          .text("on_missing_texture", "fail", {"fail", "base_color"}, &K::on_missing_texture)
          .doc("",
               "a texture that is missing, truncated, empty (0x0) or not an image: an error "
               "naming the file, or (`base_color`) a warning naming it and the material's "
               "base colour")
          .number("max_texture_pixels", kDefaultMaxTexturePixels, Range::closed(1, 1e10),
                  &K::max_texture_pixels)
          .shown("67108864")
          .doc("",
               "most pixels a texture may claim in its header (8192^2 by default); checked "
               "before it is decoded")
          .validate([](const K& k, Params& p) {
            if (k.translate.size() != 3) p.fail("translate", "expected 3 numbers [x, y, z]");
            for (double v : k.translate)  // a translation past the bound moves every vertex
              if (!(std::fabs(v) <= kMaxCoordinateM)) {
                char b[160];
                std::snprintf(b, sizeof b,
                              "translation %.6g m is beyond the coordinate bound +-1e5 m", v);
                p.fail("translate", b);
              }
            if (k.rotate_deg.size() != 3)
              p.fail("rotate_deg", "expected 3 numbers [x, y, z] (degrees, applied x, y, z)");
            if (!k.default_eye.empty() && k.default_eye.size() != 3)
              p.fail("default_eye", "expected 3 numbers [x, y, z]");
          });
  return t;
}

}  // namespace fovsim
