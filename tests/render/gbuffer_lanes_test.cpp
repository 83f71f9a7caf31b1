// The G-buffer's packet-wide kernels (sim/render/gbuffer_lanes.h) at every lane width the CPU
// has (4: SSE2, 8: AVX2, 16: AVX-512F) against each other and against the per-sample path,
// bit for bit: whole frames (static atrium, a tessellated plane seen head-on and at grazing
// angles), rays through mesh vertices and edge midpoints, and the kernels on synthetic lanes
// with degenerate and extreme inputs.
#include "sim/render/gbuffer_lanes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "sim/render/renderer.h"
#include "sim/scene/mesh_builder.h"

using namespace fovsim;

namespace {

const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";

struct WidthReset {
  ~WidthReset() { set_gbuffer_lane_width(0); }
};

Display disp(int w, int h) {
  Display d;
  d.width = w;
  d.height = h;
  d.fov_h_deg = 100;
  d.fov_v_deg = 90;
  return d;
}

// A 40 x 40 m plane z = 0 facing +z, 16 x 16 cells with vertex normals and uvs.
Scene grid_scene() {
  Scene s;
  Material m;
  m.base_color = glm::vec3(0.5f);
  s.materials.push_back(m);
  Mesh mesh;
  MeshBuilder b(mesh);
  b.grid({-20, -20, 0}, {40, 0, 0}, {0, 40, 0}, 16, 16, 0);
  s.meshes.push_back(std::move(mesh));
  Object o;
  o.mesh = 0;
  s.objects.push_back(o);
  s.build_submodels();
  return s;
}

template <class V>
bool same(const V& a, const V& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
}
void expect_same(const GBuffer& a, const GBuffer& b, const std::string& what) {
  EXPECT_TRUE(same(a.depth, b.depth)) << what;
  EXPECT_TRUE(same(a.position, b.position)) << what;
  EXPECT_TRUE(same(a.normal, b.normal)) << what;
  EXPECT_TRUE(same(a.albedo, b.albedo)) << what;
  EXPECT_TRUE(same(a.uv, b.uv)) << what;
  EXPECT_TRUE(same(a.footprint, b.footprint)) << what;
  EXPECT_TRUE(same(a.material, b.material)) << what;
  EXPECT_TRUE(same(a.object_id, b.object_id)) << what;
  EXPECT_TRUE(same(a.submodel, b.submodel)) << what;
}

}  // namespace

TEST(GBufferLanes, FourLanesAlwaysAvailable) {
  const std::vector<int> w = gbuffer_lane_widths();
  ASSERT_FALSE(w.empty());
  EXPECT_EQ(w[0], 4);
  WidthReset reset;
  for (int x : w) {
    set_gbuffer_lane_width(x);
    EXPECT_EQ(gbuffer_lane_width(), x);
  }
}

// Every width writes the per-sample path's bits (kMotion sends every hit through
// SampleWriter::hit), on frames whose widths are not multiples of 4 (partial blocks).
TEST(GBufferLanes, FramesAtEveryWidthGiveThePerSampleBits) {
  WidthReset reset;
  struct Case {
    Scene scene;
    glm::dvec3 eye;
    std::vector<glm::dquat> views;
  };
  std::vector<Case> cases;
  {
    Params p(Json{{"type", "atrium"}, {"complexity", 2}});
    Scene s = make_scene(p, kModels);
    const glm::dvec3 eye(s.default_eye);
    cases.push_back(
        {std::move(s),
         eye,
         {glm::angleAxis(-0.3, glm::dvec3(0, 1, 0)), glm::angleAxis(2.6, glm::dvec3(0, 1, 0))}});
  }
  // The plane head-on, obliquely, and from 1 cm above it looking almost along it (grazing).
  cases.push_back({grid_scene(),
                   glm::dvec3(0.3, -0.2, 6.0),
                   {glm::dquat(1, 0, 0, 0), glm::angleAxis(0.9, glm::dvec3(1, 0, 0))}});
  cases.push_back(
      {grid_scene(),
       glm::dvec3(0.1, -19.0, 0.01),
       {glm::angleAxis(1.5607, glm::dvec3(1, 0, 0)),
        glm::angleAxis(1.5707, glm::dvec3(1, 0, 0)) * glm::angleAxis(0.4, glm::dvec3(0, 1, 0))}});
  const uint32_t ch = ~0u & ~uint32_t(kMotion);
  for (size_t c = 0; c < cases.size(); ++c) {
    Renderer r(cases[c].scene, RenderSettings{});
    for (size_t v = 0; v < cases[c].views.size(); ++v) {
      const Camera cam = Camera::from_pose(disp(75, 61), cases[c].eye, cases[c].views[v]);
      GBuffer per_sample;
      r.trace_gbuffer(cam, ch | kMotion, per_sample, nullptr, &cam);
      size_t hits = 0;
      for (size_t i = 0; i < per_sample.size(); ++i) hits += per_sample.hit(i);
      EXPECT_GT(hits, per_sample.size() / 4) << c << " " << v;
      for (int w : gbuffer_lane_widths()) {
        set_gbuffer_lane_width(w);
        GBuffer g;
        r.trace_gbuffer(cam, ch, g);
        expect_same(g, per_sample,
                    "case " + std::to_string(c) + " view " + std::to_string(v) + " width " +
                        std::to_string(w));
      }
    }
  }
}

// Rays aimed at the plane's interior vertices and edge midpoints (hits on an edge or a vertex:
// the refinement's clamps decide), traced as points: every width gives the same bits.
TEST(GBufferLanes, VertexAndEdgeHitsAtEveryWidth) {
  WidthReset reset;
  Scene s = grid_scene();
  Renderer r(s, RenderSettings{});
  const Camera cam = Camera::from_pose(disp(200, 160), glm::dvec3(0.37, -0.21, 7.0),
                                       glm::angleAxis(0.5, glm::dvec3(1, 0, 0)));
  std::vector<glm::vec2> pts;
  const Mesh& m = s.meshes[0];
  for (const glm::uvec3& t : m.triangles)
    for (int e = 0; e < 3; ++e) {
      const glm::vec3 a = m.positions[t[e]], b = m.positions[t[(e + 1) % 3]];
      for (const glm::vec3& p : {a, 0.5f * (a + b)}) {
        // Interior points only: a ray through the plane's outer boundary may miss it.
        if (!(std::fabs(p.x) < 19.f && std::fabs(p.y) < 19.f)) continue;
        glm::dvec2 px;
        if (cam.project_world(glm::dvec3(p), px) && px.x > 0 && px.y > 0 && px.x < cam.width &&
            px.y < cam.height)
          pts.emplace_back(glm::vec2(px));
      }
    }
  ASSERT_GT(pts.size(), 500u);
  const uint32_t ch = ~0u & ~uint32_t(kMotion);
  set_gbuffer_lane_width(4);
  GBuffer ref;
  r.trace_points(cam, pts, ch, ref);
  size_t hits = 0;
  for (size_t i = 0; i < ref.size(); ++i) hits += ref.hit(i);
  EXPECT_GT(hits, pts.size() * 9 / 10);
  for (int w : gbuffer_lane_widths()) {
    set_gbuffer_lane_width(w);
    GBuffer g;
    r.trace_points(cam, pts, ch, g);
    expect_same(g, ref, "width " + std::to_string(w));
  }
}

// The kernel itself on synthetic lanes, m = 1..16: random triangles and rays mixed with
// degenerate triangles (zero area, collinear), rays parallel to the plane (det = 0), hits behind
// the origin, zero or missing vertex normals, zero cones, degenerate uvs and huge coordinates.
// Every width must give width 4's bits on lanes [0, m).
TEST(GBufferLanes, KernelWidthsAgreeOnDegenerateAndExtremeLanes) {
  WidthReset reset;
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> U(-1.f, 1.f);
  auto fill = [&](FastLanes& F, int m) {
    F.m = m;
    for (int j = 0; j < m; ++j) {
      const int kind = int(rng() % 8);
      float* in[] = {F.p0x, F.p0y, F.p0z, F.p1x, F.p1y, F.p1z, F.p2x, F.p2y,
                     F.p2z, F.n0x, F.n0y, F.n0z, F.n1x, F.n1y, F.n1z, F.n2x,
                     F.n2y, F.n2z, F.u0x, F.u0y, F.u1x, F.u1y, F.u2x, F.u2y};
      for (float* a : in) a[j] = U(rng) * 3.f;
      glm::vec3 d(U(rng), U(rng), U(rng) - 1.5f);
      d = glm::normalize(d);
      F.dx[j] = d.x;
      F.dy[j] = d.y;
      F.dz[j] = d.z;
      F.t[j] = 2.f + U(rng);
      F.bu[j] = 0.3f;
      F.bv[j] = 0.3f;
      F.cone[j] = 1e-3f;
      F.hasn[j] = 1.f;
      switch (kind) {
        case 1:  // zero-area triangle
          F.p1x[j] = F.p0x[j];
          F.p1y[j] = F.p0y[j];
          F.p1z[j] = F.p0z[j];
          break;
        case 2: {  // ray parallel to the triangle's plane: d = e1 (det = 0)
          const glm::vec3 e(F.p1x[j] - F.p0x[j], F.p1y[j] - F.p0y[j], F.p1z[j] - F.p0z[j]);
          F.dx[j] = e.x;
          F.dy[j] = e.y;
          F.dz[j] = e.z;
          break;
        }
        case 3:  // zero vertex normals, or none
          F.n0x[j] = F.n0y[j] = F.n0z[j] = F.n1x[j] = F.n1y[j] = F.n1z[j] = 0.f;
          F.n2x[j] = F.n2y[j] = F.n2z[j] = 0.f;
          F.hasn[j] = (rng() & 1) ? 1.f : 0.f;
          break;
        case 4:  // zero cone, degenerate uvs
          F.cone[j] = 0.f;
          F.u1x[j] = F.u0x[j];
          F.u1y[j] = F.u0y[j];
          break;
        case 5:  // huge coordinates
          F.p0x[j] *= 1e30f;
          F.p1y[j] *= 1e30f;
          F.p2z[j] *= 1e30f;
          break;
        case 6:  // a grazing ray: almost in the triangle's plane
          F.dx[j] = F.p1x[j] - F.p0x[j] + 1e-6f;
          F.dy[j] = F.p1y[j] - F.p0y[j];
          F.dz[j] = F.p1z[j] - F.p0z[j];
          break;
        default:
          break;
      }
    }
  };
  const float org[3] = {0.1f, -0.2f, 4.f};
  const std::vector<int> widths = gbuffer_lane_widths();
  for (int round = 0; round < 400; ++round) {
    const int m = 1 + round % 16;
    FastLanes in;
    fill(in, m);
    set_gbuffer_lane_width(4);
    FastLanes ref = in;
    gbuffer_lanes(ref, org[0], org[1], org[2]);
    for (int w : widths) {
      set_gbuffer_lane_width(w);
      FastLanes F = in;
      gbuffer_lanes(F, org[0], org[1], org[2]);
      const float* a[] = {F.t, F.bu, F.bv, F.Px, F.Py, F.Pz, F.Nx, F.Ny, F.Nz, F.U, F.V, F.fw};
      const float* b[] = {ref.t,  ref.bu, ref.bv, ref.Px, ref.Py, ref.Pz,
                          ref.Nx, ref.Ny, ref.Nz, ref.U,  ref.V,  ref.fw};
      for (int k = 0; k < 12; ++k)
        ASSERT_EQ(std::memcmp(a[k], b[k], sizeof(float) * size_t(m)), 0)
            << "round " << round << " width " << w << " array " << k;
    }
  }
}

// gbuffer_block_rays at every width against the scalar expression it evaluates.
TEST(GBufferLanes, BlockRaysAtEveryWidthMatchTheScalarExpression) {
  WidthReset reset;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.5, 1.5);
  for (int round = 0; round < 200; ++round) {
    double hx[4], hx2[4], hy[4], hy2[4], R[9];
    for (int k = 0; k < 4; ++k) {
      hx[k] = U(rng);
      hy[k] = U(rng);
      hx2[k] = hx[k] * hx[k];
      hy2[k] = hy[k] * hy[k];
    }
    const glm::dmat3 Rm =
        glm::mat3_cast(glm::normalize(glm::dquat(U(rng), U(rng), U(rng), U(rng))));
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) R[3 * c + r] = Rm[c][r];
    const double cone1 = 1e-3 * (1.0 + U(rng));
    float ex[16], ey[16], ez[16], ec[16];
    for (int j = 0; j < 16; ++j) {
      const double x = hx[j & 3], y = hy[j >> 2];
      const double s = 1.0 / std::sqrt((hx2[j & 3] + hy2[j >> 2]) + 1.0);
      const double ux = x * s, uy = y * s, uz = -s;
      ex[j] = float((R[0] * ux + R[3] * uy) + R[6] * uz);
      ey[j] = float((R[1] * ux + R[4] * uy) + R[7] * uz);
      ez[j] = float((R[2] * ux + R[5] * uy) + R[8] * uz);
      ec[j] = float(cone1 * s * std::sqrt(s));
    }
    for (int w : gbuffer_lane_widths()) {
      set_gbuffer_lane_width(w);
      float dx[16], dy[16], dz[16], cn[16];
      gbuffer_block_rays(hx, hx2, hy, hy2, R, cone1, dx, dy, dz, cn);
      EXPECT_EQ(std::memcmp(dx, ex, sizeof dx), 0) << round << " " << w;
      EXPECT_EQ(std::memcmp(dy, ey, sizeof dy), 0) << round << " " << w;
      EXPECT_EQ(std::memcmp(dz, ez, sizeof dz), 0) << round << " " << w;
      EXPECT_EQ(std::memcmp(cn, ec, sizeof cn), 0) << round << " " << w;
    }
  }
}

// The batch kernel (FastBatch, 64 lanes: trace_gbuffer's chunks) at every width gives, lane
// for lane, what the 16-lane kernel at width 4 gives for the same lanes in groups of 16.
TEST(GBufferLanes, BatchKernelMatchesPacketKernelAtEveryWidth) {
  WidthReset reset;
  std::mt19937 rng(777);
  std::uniform_real_distribution<float> U(-1.f, 1.f);
  const float org[3] = {0.3f, 0.1f, 2.f};
  for (int m : {1, 15, 16, 17, 40, 63, 64}) {
    FastBatch in;
    in.m = m;
    for (int j = 0; j < m; ++j) {
      float* arr[] = {in.p0x, in.p0y, in.p0z, in.p1x, in.p1y, in.p1z, in.p2x, in.p2y,
                      in.p2z, in.n0x, in.n0y, in.n0z, in.n1x, in.n1y, in.n1z, in.n2x,
                      in.n2y, in.n2z, in.u0x, in.u0y, in.u1x, in.u1y, in.u2x, in.u2y};
      for (float* a : arr) a[j] = U(rng) * 3.f;
      glm::vec3 d = glm::normalize(glm::vec3(U(rng), U(rng), U(rng) - 1.5f));
      in.dx[j] = d.x;
      in.dy[j] = d.y;
      in.dz[j] = d.z;
      in.t[j] = 2.f + U(rng);
      in.bu[j] = in.bv[j] = 0.25f;
      in.cone[j] = (j % 5 == 0) ? 0.f : 1e-3f;
      in.hasn[j] = (j % 3 == 0) ? 0.f : 1.f;
    }
    // Reference: groups of 16 through the packet kernel at width 4.
    set_gbuffer_lane_width(4);
    std::vector<float> ref[12];
    for (int g0 = 0; g0 < m; g0 += 16) {
      FastLanes F;
      F.m = std::min(16, m - g0);
      const float* src[] = {in.t,   in.bu,  in.bv,  in.dx,  in.dy,  in.dz,  in.cone, in.hasn,
                            in.p0x, in.p0y, in.p0z, in.p1x, in.p1y, in.p1z, in.p2x,  in.p2y,
                            in.p2z, in.n0x, in.n0y, in.n0z, in.n1x, in.n1y, in.n1z,  in.n2x,
                            in.n2y, in.n2z, in.u0x, in.u0y, in.u1x, in.u1y, in.u2x,  in.u2y};
      float* dst[] = {F.t,   F.bu,  F.bv,  F.dx,  F.dy,  F.dz,  F.cone, F.hasn, F.p0x, F.p0y, F.p0z,
                      F.p1x, F.p1y, F.p1z, F.p2x, F.p2y, F.p2z, F.n0x,  F.n0y,  F.n0z, F.n1x, F.n1y,
                      F.n1z, F.n2x, F.n2y, F.n2z, F.u0x, F.u0y, F.u1x,  F.u1y,  F.u2x, F.u2y};
      for (int a = 0; a < 32; ++a) std::memcpy(dst[a], src[a] + g0, sizeof(float) * size_t(F.m));
      gbuffer_lanes(F, org[0], org[1], org[2]);
      const float* out[] = {F.t, F.bu, F.bv, F.Px, F.Py, F.Pz, F.Nx, F.Ny, F.Nz, F.U, F.V, F.fw};
      for (int k = 0; k < 12; ++k) ref[k].insert(ref[k].end(), out[k], out[k] + F.m);
    }
    for (int w : gbuffer_lane_widths()) {
      set_gbuffer_lane_width(w);
      auto F = std::make_unique<FastBatch>(in);
      gbuffer_lanes(*F, org[0], org[1], org[2]);
      const float* out[] = {F->t,  F->bu, F->bv, F->Px, F->Py, F->Pz,
                            F->Nx, F->Ny, F->Nz, F->U,  F->V,  F->fw};
      for (int k = 0; k < 12; ++k)
        ASSERT_EQ(std::memcmp(out[k], ref[k].data(), sizeof(float) * size_t(m)), 0)
            << "m " << m << " width " << w << " array " << k;
    }
  }
}
