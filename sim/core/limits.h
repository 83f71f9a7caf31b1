// Stated bounds on input values that are in the documented ranges of no single key but that
// downstream code cannot handle (configs/README.md "Limits on input").
#pragma once

namespace fovsim {

// Largest |x|, |y| or |z| (metres) of a head position, an eye point or a scene vertex in
// world space. Geometry is traced in single precision (Embree): at 1e5 m a float still
// resolves 8 mm, and Embree's build asserts on coordinates near 1e20 long before FLT_MAX.
// Head positions beyond it are refused by the trace reader (`trace validate` and `run`
// alike), scene geometry and scene.default_eye by the scene factory.
constexpr double kMaxCoordinateM = 1e5;

// Default of scene.max_triangles: most triangles a scene may have (built-in tessellation is
// checked before it is generated, file scenes after import).
constexpr double kDefaultMaxTriangles = 2e7;

// Default of scene.max_texture_pixels (file scenes): most pixels a texture may claim in its
// header before it is decoded (8192 x 8192). `compare` has its own limit (files.h
// max_image_pixels).
constexpr double kDefaultMaxTexturePixels = 67108864;

// Default of scene.vpl.max_vpls: most VPLs a frame may have, counted as lights x
// scene.vpl.rsm_size^2 before any reflective shadow map is rendered. Every reference pixel is
// shaded by every VPL (the FLC paper's TBDS ground truth), so the reference's work per frame is
// pixels x VPLs: 2^18 VPLs are 4 lights at rsm_size 256 (the default 64 gives 4096 per light).
constexpr double kDefaultMaxVpls = 262144;

// Smallest size (diagonal of the world bounds, metres) of a scene after every transform: a
// scene.scale that rounds to nothing in single precision (1e-300) or node scales of 0 leave a
// point, which renders as a one-colour image every method matches exactly.
constexpr double kMinSceneExtentM = 1e-6;

// Largest colour component of a material (base colour, emission) and of a light's colour:
// finite, non-negative and at most this (a glTF factor of 1e39 is infinite as a float).
constexpr double kMaxColorValue = 1e6;

// Deepest node hierarchy a model file may have (glTF 1.0 and 2, .gltf and .glb: checked on its
// JSON before the importer sees it; every format: checked again on the imported tree). assimp
// builds, validates and frees the tree recursively, so a deeper chain (20,000 nested nodes fit
// in a 450 KB file) would overflow the stack; real models nest a few dozen levels.
constexpr int kMaxNodeDepth = 256;

}  // namespace fovsim
