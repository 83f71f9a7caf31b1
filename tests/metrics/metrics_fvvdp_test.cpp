// FovVideoVDP v1.2 (Mantiuk et al. 2021) against the sanity values of its restatement
// (../shared/metrics/FovVideoVDP.md §15, §8, §5, §3): the reference implementation's JOD on
// formula-defined gratings and uniform images, intermediate values, exact properties, thread
// invariance and the streaming API.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "sim/core/error.h"
#include "sim/metrics/fvvdp.h"
#include "sim/metrics/registry.h"

using namespace fovsim;

namespace {

constexpr double kPiT = 3.14159265358979323846;

// Gr(H, W, a, P, m, phi): 8-bit grating, equal channels, constant down each column (§15.2).
Image grating(int H, int W, double a, double P, double m = 128, double phi = 0) {
  Image im(W, H, 3);
  for (int x = 0; x < W; ++x) {
    const double v = std::floor(m + a * std::sin(2 * kPiT * x / P + phi) + 0.5);
    const float f = float(v) / 255.f;
    for (int y = 0; y < H; ++y)
      for (int c = 0; c < 3; ++c) im.at(x, y)[c] = f;
  }
  return im;
}

Image uniform(int H, int W, int v) {
  return Image(W, H, 3, float(v) / 255.f);
}

double jod1(const Image& test, const Image& ref, const std::string& disp, bool fov = false,
            std::vector<std::pair<double, double>> gaze = {}) {
  return fvvdp({test}, {ref}, FvvdpDisplay::standard(disp), 0, fov, gaze).jod;
}

struct Case {
  const char* id;
  double jod, tol;
};

}  // namespace

TEST(Fvvdp, ImageSanityRowsAtoE) {
  // §15.2 rows with their reference (PyTorch) JOD; 4 decimals -> 2e-4, 5 decimals -> 3e-5.
  EXPECT_EQ(jod1(grating(256, 256, 16, 16), grating(256, 256, 16, 16), "standard_4k"), 10.0);
  EXPECT_EQ(jod1(uniform(256, 256, 140), uniform(256, 256, 128), "standard_4k"), 10.0);
  EXPECT_NEAR(jod1(uniform(135, 240, 140), uniform(135, 240, 128), "standard_fhd"), 9.9487, 2e-4);
  EXPECT_NEAR(jod1(uniform(120, 160, 140), uniform(120, 160, 128), "standard_fhd"), 9.9631, 2e-4);
  EXPECT_NEAR(jod1(uniform(1080, 1920, 140), uniform(1080, 1920, 128), "standard_fhd"), 9.98053,
              3e-5);
  EXPECT_NEAR(jod1(uniform(256, 320, 140), uniform(256, 320, 128), "standard_4k"), 9.96700, 3e-5);
  const Image u = uniform(256, 256, 128);
  const Case c[] = {{"C1", 9.8801, 2e-4}, {"C2", 9.7044, 2e-4},  {"C4", 9.1080, 2e-4},
                    {"C8", 7.8812, 2e-4}, {"C16", 6.2225, 2e-4}, {"C32", 4.9819, 2e-4}};
  const double amp[] = {1, 2, 4, 8, 16, 32};
  for (int i = 0; i < 6; ++i)
    EXPECT_NEAR(jod1(grating(256, 256, amp[i], 16), u, "standard_4k"), c[i].jod, c[i].tol)
        << c[i].id;
  EXPECT_NEAR(jod1(u, grating(256, 256, 16, 16), "standard_4k"), 6.3121, 2e-4) << "C-swap";
  const Image g8 = grating(256, 256, 8, 16);
  EXPECT_NEAR(jod1(g8, u, "standard_fhd"), 6.7197, 2e-4) << "D-fhd";
  EXPECT_NEAR(jod1(g8, u, "standard_hmd"), 5.2023, 2e-4) << "D-hmd";
  EXPECT_NEAR(jod1(g8, u, "htc_vive_pro"), 5.2091, 2e-4) << "D-vive";
  const double P[] = {4, 8, 32, 64};
  const double e[] = {9.8561, 9.4209, 6.5411, 5.5044};
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(jod1(grating(256, 256, 8, P[i]), u, "standard_4k"), e[i], 2e-4) << "E" << P[i];
}

TEST(Fvvdp, FoveatedSanityRowsF) {
  const Image g8 = grating(256, 256, 8, 16), u = uniform(256, 256, 128);
  EXPECT_NEAR(jod1(g8, u, "htc_vive_pro", true), 8.1035, 2e-4) << "F1";
  EXPECT_NEAR(jod1(g8, u, "htc_vive_pro", true, {{128, 128}}), 8.1035, 2e-4) << "F1 explicit";
  EXPECT_NEAR(jod1(g8, u, "htc_vive_pro", true, {{0, 0}}), 8.9266, 2e-4) << "F2";
  EXPECT_NEAR(jod1(g8, u, "standard_4k", true), 9.4932, 2e-4) << "F3";
}

TEST(Fvvdp, VideoSanityRowsGHI) {
  const FvvdpDisplay fhd = FvvdpDisplay::standard("standard_fhd");
  std::vector<Image> t, r;
  for (int k = 0; k < 8; ++k) {
    t.push_back(grating(128, 128, 16, 16, k % 2 == 0 ? 124 : 132));
    r.push_back(grating(128, 128, 16, 16));
  }
  EXPECT_NEAR(fvvdp(t, r, fhd, 30, false).jod, 9.9461, 2e-4) << "G";
  t.clear();
  for (int k = 0; k < 8; ++k) t.push_back(grating(128, 128, 16, 16, 128, kPiT * k / 4));
  EXPECT_NEAR(fvvdp(t, r, fhd, 30, false).jod, 3.8942, 2e-4) << "H";
  std::vector<Image> ti(8, grating(128, 128, 8, 16)), ri(8, uniform(128, 128, 128));
  const FvvdpResult I = fvvdp(ti, ri, fhd, 30, false);
  EXPECT_NEAR(I.jod, 6.5871, 2e-4) << "I";
  const FvvdpResult I2 = fvvdp({ti[0]}, {ri[0]}, fhd, 30, false);  // N = 1: still image
  EXPECT_NEAR(I2.jod, 6.5903, 2e-4) << "I2";
  EXPECT_EQ(I2.channels, 1);
  EXPECT_EQ(I.channels, 2);
  EXPECT_NE(I.jod, I2.jod);  // §15.1 (6)
}

TEST(Fvvdp, C8IntermediateValues) {
  const FvvdpDisplay d = FvvdpDisplay::standard("standard_4k");
  FvvdpReferenceStream rs(d, 256, 256, {});
  FvvdpTestStream ts(rs);
  rs.push(uniform(256, 256, 128));
  ts.push(grating(256, 256, 8, 16), rs);
  ASSERT_EQ(rs.bands(), 7);
  const double f[] = {37.70122, 12.16996, 6.08498, 3.04249, 1.52124, 0.76062, 0.38031};
  const double s0[] = {2.90461, 51.8045, 185.533, 447.029, 718.848, 754.990, 493.058};
  const double s5[] = {2.53544, 38.6959, 161.694, 578.290, 1710.26, 3604.34, 5480.24};
  const double q[] = {5.1996e-4, 30.907, 3062.1, 179.68, 287.84, 191.87, 42.968};
  double sum = 0, listed = 0;
  for (int b = 0; b < 7; ++b) {
    listed += q[b];
    EXPECT_NEAR(rs.band_frequencies()[size_t(b)], f[b], 1e-5) << b;
    for (float La : rs.adaptation(b)) ASSERT_NEAR(La, 43.64093148, 43.64 * 2e-7) << b;
    EXPECT_NEAR(rs.sensitivity(b, 0)[0], s0[b], s0[b] * 1e-4) << b;
    const double S5 = 6.500997515 * fvvdp_detail::csf_table(f[b], 5, 43.64093, 0);
    EXPECT_NEAR(S5, s5[b], s5[b] * 1e-4) << b;
    EXPECT_NEAR(ts.q_band(b, 0), q[b], b == 0 ? 2e-5 : q[b] * 2e-4) << b;
    EXPECT_EQ(ts.q_band(b, 1), 0.0);
    sum += ts.q_band(b, 0);
  }
  EXPECT_NEAR(sum, listed, listed * 1e-4);  // the spec's Q = 3795.3
  EXPECT_NEAR(ts.jod(), 7.8812, 2e-4);
  EXPECT_EQ(ts.jod(), fvvdp_jod_from_q(sum));
}

TEST(Fvvdp, CsfFormulaWorkedExample) {
  // §8.2 (d): rho 4, omega 0, L 100, e 0 -> 56.418164; omega 5, e 10 -> 14.282318.
  EXPECT_NEAR(fvvdp_detail::csf_formula(4, 0, 100, 0), 56.418164, 56.418164 * 1e-7);
  EXPECT_NEAR(fvvdp_detail::csf_formula(4, 5, 100, 10), 14.282318, 14.282318 * 1e-7);
}

TEST(Fvvdp, CsfTableLookupsMatchTheReferenceTables) {
  // §8.3 table: rho, omega, L, e, formula, table (reference).
  const double rows[][6] = {
      {1, 0, 100, 0, 111.99628, 111.27734}, {4, 0, 100, 0, 56.41816, 56.07957},
      {8, 0, 100, 0, 21.80156, 21.68419},   {4, 0, 1, 0, 14.85884, 14.75466},
      {4, 5, 100, 0, 60.35269, 60.18653},   {4, 0, 100, 10, 18.33483, 18.22511},
      {16, 0, 30, 0, 3.80399, 3.78574}};
  for (const auto& r : rows) {
    EXPECT_NEAR(fvvdp_detail::csf_formula(r[0], r[1], r[2], r[3]), r[4], r[4] * 2e-6) << r[0];
    EXPECT_NEAR(fvvdp_detail::csf_table(r[0], r[1], r[2], r[3]), r[5], r[5] * 1e-4) << r[0];
  }
}

TEST(Fvvdp, TemporalTapsAt30Fps) {
  const double L[][2] = {{23.976, 6}, {24, 6},  {25, 7},  {29.97, 8}, {30, 8},  {50, 13},
                         {59.94, 15}, {60, 15}, {90, 23}, {120, 30},  {144, 36}};
  for (const auto& l : L) EXPECT_EQ(fvvdp_detail::filter_length(l[0]), int(l[1])) << l[0];
  std::vector<double> fs, ft;
  fvvdp_detail::temporal_taps(30, fs, ft);
  const double FS[] = {1.258092e-36, 0.2922941, 0.3916274, 0.1911500,
                       0.0771588,    0.0303983, 0.0122501, 0.0051213};
  const double FT[] = {0.4770169,  0.1621096,  -0.3271742, -0.1860309,
                       -0.0763121, -0.0296175, -0.0116340, 0};
  ASSERT_EQ(fs.size(), 8u);
  double sum_s = 0, sum_t = 0;
  for (int k = 0; k < 8; ++k) {
    EXPECT_NEAR(fs[size_t(k)], FS[k], k == 0 ? 1e-42 : 1e-7) << k;
    EXPECT_NEAR(ft[size_t(k)], FT[k], 1e-7) << k;
    sum_s += fs[size_t(k)];
    sum_t += ft[size_t(k)];
  }
  EXPECT_NEAR(sum_s, 1.0, 1e-15);
  EXPECT_NEAR(sum_t, 0.0083578, 1e-7);
  fvvdp_detail::temporal_taps(60, fs, ft);
  double s60 = 0;
  for (double v : ft) s60 += v;
  EXPECT_NEAR(s60, 0.0124931, 1e-7);
  EXPECT_THROW(fvvdp_detail::temporal_taps(4, fs, ft), Error);
}

TEST(Fvvdp, StandardDisplays) {
  // §3.3: ppd and Y_black of the four entries.
  struct D {
    const char* name;
    double ppd, black, w_m, h_m;
  } ds[] = {{"standard_4k", 75.40244934516305, 0.5978873577, 0.6641405593, 0.3735790646},
            {"standard_fhd", 37.842503853602885, 0.5978873577, 0.5313124474, 0.2988632517},
            {"standard_hmd", 13.153262507309297, 0.1, 5.732283888, 6.369204320},
            {"htc_vive_pro", 13.153262507309297, 0.1, 5.732283888, 6.369204320}};
  for (const auto& e : ds) {
    const FvvdpDisplay d = FvvdpDisplay::standard(e.name);
    EXPECT_EQ(d.ppd, e.ppd) << e.name;
    EXPECT_NEAR(d.y_black, e.black, 1e-10) << e.name;
    EXPECT_NEAR(d.w_m, e.w_m, 1e-9) << e.name;
    EXPECT_NEAR(d.h_m, e.h_m, 1e-9) << e.name;
    // The shipped display models give the same numbers.
    const Display m = Display::load(e.name, std::string(FOVSIM_SOURCE_DIR) + "/models");
    const FvvdpDisplay f = FvvdpDisplay::from_display(m);
    EXPECT_EQ(f.ppd, e.ppd) << e.name;
    EXPECT_NEAR(f.y_black, e.black, 1e-10) << e.name;
    EXPECT_EQ(f.y_peak, d.y_peak) << e.name;
  }
  EXPECT_EQ(FvvdpDisplay::standard("standard_4k").describe(false),
            "FovVideoVDP v1.2, 75.4 [pix/deg], Lpeak=200, Lblack=0.5979 [cd/m^2], non-foveated, "
            "(standard_4k)");
  EXPECT_THROW(FvvdpDisplay::standard("nope"), Error);
  // scaled_to: same physical display, ppd scales with the width.
  const FvvdpDisplay h = FvvdpDisplay::standard("standard_4k").scaled_to(1920, 1080);
  EXPECT_NEAR(h.ppd, 37.70122467, 1e-3);
  EXPECT_EQ(h.w_m, FvvdpDisplay::standard("standard_4k").w_m);
}

TEST(Fvvdp, ExactProperties) {
  const FvvdpDisplay v = FvvdpDisplay::standard("htc_vive_pro");
  const Image g = grating(96, 80, 20, 9, 110);
  for (bool fov : {false, true}) {
    EXPECT_EQ(fvvdp({g}, {g}, v, 0, fov).jod, 10.0);
    std::vector<Image> seq;
    for (int k = 0; k < 5; ++k) seq.push_back(grating(96, 80, 20, 9, 110, k * 0.7));
    EXPECT_EQ(fvvdp(seq, seq, v, 90, fov).jod, 10.0);
  }
  // Asymmetric (§15.1 (4)) and below 10 for a visible difference.
  const Image u = uniform(96, 80, 110);
  const double a = jod1(g, u, "htc_vive_pro"), b = jod1(u, g, "htc_vive_pro");
  EXPECT_LT(a, 10.0);
  EXPECT_NE(a, b);
}

TEST(Fvvdp, BitIdenticalAtOneAndTwoThreads) {
  const FvvdpDisplay v = FvvdpDisplay::standard("htc_vive_pro");
  std::vector<Image> t, r;
  for (int k = 0; k < 4; ++k) {
    t.push_back(grating(150, 170, 12, 11, 120, 0.4 * k));
    r.push_back(grating(150, 170, 10, 13, 125, 0.3 * k));
  }
  FvvdpResult res[2];
  for (int n = 1; n <= 2; ++n) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(n));
    res[n - 1] = fvvdp(t, r, v, 60, true, {{40, 30}, {50, 60}, {100, 90}, {20, 140}});
  }
  EXPECT_EQ(std::memcmp(&res[0].jod, &res[1].jod, sizeof(double)), 0);
  for (size_t n = 0; n < 4; ++n)
    for (int b = 0; b < res[0].bands; ++b)
      for (int c = 0; c < 2; ++c)
        EXPECT_EQ(res[0].q[n][size_t(b)][size_t(c)], res[1].q[n][size_t(b)][size_t(c)]);
}

TEST(Fvvdp, StreamingMatchesOneShot) {
  // One shared reference side, two methods, frame by frame.
  const FvvdpDisplay d = FvvdpDisplay::standard("standard_fhd");
  std::vector<Image> r, t1, t2;
  for (int k = 0; k < 5; ++k) {
    r.push_back(grating(64, 96, 10, 12, 128, 0.5 * k));
    t1.push_back(grating(64, 96, 12, 12, 128, 0.5 * k));
    t2.push_back(grating(64, 96, 10, 12, 128, 0.6 * k));
  }
  const std::vector<std::pair<double, double>> gaze = {
      {10, 20}, {30, 5}, {60, 40}, {90, 60}, {0, 0}};
  FvvdpReferenceStream rs(d, 96, 64, {60, true});
  FvvdpTestStream s1(rs), s2(rs);
  for (size_t k = 0; k < 5; ++k) {
    rs.push(r[k], gaze[k].first, gaze[k].second);
    s1.push(t1[k], rs);
    s2.push(t2[k], rs);
  }
  EXPECT_EQ(s1.jod(), fvvdp(t1, r, d, 60, true, gaze).jod);
  EXPECT_EQ(s2.jod(), fvvdp(t2, r, d, 60, true, gaze).jod);
  EXPECT_LT(s1.jod(), 10.0);
  // Out of step: a test frame before its reference frame.
  EXPECT_THROW(s1.push(t1[0], rs), Error);
  // reset() starts a new sequence: the same numbers again.
  rs.reset();
  s1.reset();
  for (size_t k = 0; k < 5; ++k) {
    rs.push(r[k], gaze[k].first, gaze[k].second);
    s1.push(t1[k], rs);
  }
  EXPECT_EQ(s1.jod(), fvvdp(t1, r, d, 60, true, gaze).jod);
  // Still-image stream: every push is an independent image.
  FvvdpReferenceStream ri(d, 96, 64, {});
  FvvdpTestStream si(ri);
  ri.push(r[2]);
  EXPECT_EQ(si.push(t1[2], ri), fvvdp({t1[2]}, {r[2]}, d, 0, false).mean_q);
}

// A test stream scored against a second reference with another stream's work on the same test
// frames (push with `same`; the engine's metrics.foveation_loss): the numbers of an independent
// stream, heat maps included; pushing on its own afterwards is an internal error until reset().
TEST(Fvvdp, SharedTestFramesGiveTheSameNumbers) {
  const FvvdpDisplay d = FvvdpDisplay::standard("standard_fhd");
  std::vector<Image> r1, r2, t;
  for (int k = 0; k < 6; ++k) {
    r1.push_back(grating(64, 96, 10, 12, 128, 0.5 * k));
    r2.push_back(grating(64, 96, 11, 12, 128, 0.4 * k));
    t.push_back(grating(64, 96, 12, 12, 128, 0.5 * k));
  }
  FvvdpReferenceStream a_ref(d, 96, 64, {60, true}), b_ref(d, 96, 64, {60, true});
  FvvdpTestStream a(a_ref), b(b_ref), own(b_ref);
  b.enable_heatmap(true);
  own.enable_heatmap(true);
  for (size_t k = 0; k < 6; ++k) {
    a_ref.push(r1[k], 20, 30);
    b_ref.push(r2[k], 20, 30);
    a.push(t[k], a_ref);
    const double q_own = own.push(t[k], b_ref);
    EXPECT_EQ(b.push(t[k], b_ref, a, a_ref), q_own) << "frame " << k;
    ASSERT_EQ(b.heatmap().data, own.heatmap().data) << "frame " << k;
  }
  EXPECT_EQ(b.jod(), own.jod());
  EXPECT_NE(b.jod(), a.jod());
  EXPECT_THROW(b.push(t[0], b_ref), InternalError);
  // Out of step (a has not pushed this frame): b scores on its own, which it can no longer.
  b.reset();
  own.reset();
  a.reset();
  a_ref.reset();
  b_ref.reset();
  a_ref.push(r1[0], 20, 30);
  b_ref.push(r2[0], 20, 30);
  EXPECT_EQ(b.push(t[0], b_ref, a, a_ref), own.push(t[0], b_ref));  // a behind: b's own work
  b_ref.push(r2[1], 20, 30);
  EXPECT_NO_THROW(b.push(t[1], b_ref, b, b_ref));  // itself as `same`: its own work
}

// The floor of metrics.foveation_loss: the test frames are the ones a second reference stream was
// just pushed (`full` at the methods' sampling rate); scored with that stream's frames (push
// with `frames_of`) they give the numbers of a stream of their own, as a video and as still
// images, and the borrowing stream holds no frames of its own.
TEST(Fvvdp, ReferenceFramesGiveTheFloorTheNumbersOfItsOwnStream) {
  const FvvdpDisplay d = FvvdpDisplay::standard("standard_fhd");
  for (double fps : {60.0, 0.0}) {
    FvvdpReferenceStream a_ref(d, 96, 64, {fps, true}), b_ref(d, 96, 64, {fps, true});
    FvvdpTestStream floor(a_ref), own(a_ref);
    floor.enable_heatmap(true);
    own.enable_heatmap(true);
    for (int k = 0; k < 5; ++k) {
      const Image r = grating(64, 96, 10, 12, 128, 0.5 * k);
      const Image f = grating(64, 96, 11, 12, 128, 0.45 * k);  // `full`: b_ref's frames
      a_ref.push(r, 20, 30);
      b_ref.push(f, 20, 30);
      const double q_own = own.push(f, a_ref);
      EXPECT_EQ(floor.push(f, a_ref, b_ref), q_own) << "fps " << fps << " frame " << k;
      ASSERT_EQ(floor.heatmap().data, own.heatmap().data) << "frame " << k;
      if (fps == 0) {  // still images: every push starts again
        a_ref.reset();
        b_ref.reset();
        floor.reset();
        own.reset();
      }
    }
    if (fps > 0) {
      EXPECT_EQ(floor.jod(), own.jod());
      EXPECT_THROW(floor.push(grating(64, 96, 11, 12, 128, 0), a_ref), InternalError);
    }
  }
  // A reference stream of another display (other luminance): the floor's own work, the same
  // numbers.
  FvvdpDisplay other = d;
  other.y_peak *= 2;
  FvvdpReferenceStream a_ref(d, 96, 64, {60, true}), c_ref(other, 96, 64, {60, true});
  FvvdpTestStream floor(a_ref), own(a_ref);
  const Image r = grating(64, 96, 10, 12, 128, 0), f = grating(64, 96, 11, 12, 128, 0);
  a_ref.push(r, 20, 30);
  c_ref.push(f, 20, 30);
  EXPECT_EQ(floor.push(f, a_ref, c_ref), own.push(f, a_ref));
}

TEST(Fvvdp, BadInput) {
  const FvvdpDisplay d = FvvdpDisplay::standard("standard_fhd");
  const Image a = uniform(32, 32, 10), b = uniform(32, 40, 10);
  EXPECT_THROW(fvvdp({a}, {b}, d, 0, false), Error);
  EXPECT_THROW(fvvdp({a, a}, {a}, d, 30, false), Error);
  EXPECT_THROW(fvvdp({a, a}, {a, a}, d, 0, false), Error);
  EXPECT_THROW(fvvdp({uniform(3, 3, 1)}, {uniform(3, 3, 1)}, d, 0, false), Error);
}

TEST(Fvvdp, HeatMap) {
  const FvvdpDisplay d = FvvdpDisplay::standard("standard_fhd");
  FvvdpReferenceStream rs(d, 256, 256, {});
  FvvdpTestStream plain(rs), heat(rs);
  heat.enable_heatmap(true);
  // A difference in one small patch: the map is high near it and zero far away; enabling the
  // map does not change the score.
  Image r = grating(256, 256, 10, 12), t = r;
  for (int y = 20; y < 40; ++y)
    for (int x = 20; x < 40; ++x)
      for (int c = 0; c < 3; ++c) t.at(x, y)[c] += 0.05f;
  rs.push(r);
  EXPECT_EQ(plain.push(t, rs), heat.push(t, rs));
  const Image& h = heat.heatmap();
  ASSERT_EQ(h.width, 256);
  ASSERT_EQ(h.height, 256);
  ASSERT_EQ(h.channels, 1);
  double near = 0, far = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      near += h.at(x, y)[0];
      far += h.at(x + 192, y + 192)[0];
    }
  for (float v : h.data) ASSERT_GE(v, 0.f);
  EXPECT_GT(near, 0.0);
  EXPECT_LT(far, 1e-3 * near);
  FvvdpTestStream same(rs);
  same.enable_heatmap(true);
  same.push(r, rs);
  for (float v : same.heatmap().data) ASSERT_EQ(v, 0.f);
}

namespace fovsim {
namespace {

// The settle time the run leaves out of FovVideoVDP's means (sim/experiment/startup.h): the
// sustained filter's 95% weight point, ~0.17 s at any frame rate; nothing for still images.
TEST(Fvvdp, SettleFramesFromTheSustainedFilter) {
  EXPECT_EQ(fvvdp_detail::settle_frames(90), 15);  // 0.167 s
  EXPECT_EQ(fvvdp_detail::settle_frames(60), 9);
  EXPECT_EQ(fvvdp_detail::settle_frames(120), 20);
  EXPECT_EQ(fvvdp_detail::settle_frames(0), 0);
  std::vector<double> fs, ft;
  fvvdp_detail::temporal_taps(90, fs, ft);
  double before = 0;
  for (int k = 0; k < 15; ++k) before += fs[size_t(k)];
  EXPECT_LT(before, 0.95);
  EXPECT_GE(before + fs[15], 0.95);
  EXPECT_EQ(fvvdp_sequence_metric().settle_frames(90), 15);
}

}  // namespace
}  // namespace fovsim

TEST(Fvvdp, TorchCpuSumRoundsAsAFloat32Accumulator) {
  using fvvdp_detail::torch_cpu_sum;
  // 1e8 has a float32 spacing of 8: one accumulator loses every +1, double keeps them.
  const std::vector<float> v = {1e8f, 1.f, 1.f, 1.f, 1.f};
  EXPECT_EQ(torch_cpu_sum(v.data(), v.size(), 1), 1e8);
  EXPECT_EQ(torch_cpu_sum(v.data(), v.size(), 0), 1e8 + 4);
  // Chunks only above the grain (32768 values): two chunks of 32768 summed apart, then combined.
  std::vector<float> w(size_t(2) * kFvvdpTorchGrain, 1.f);
  w[0] = 1e8f;
  w[size_t(kFvvdpTorchGrain)] = 0.5f;
  const double two = torch_cpu_sum(w.data(), w.size(), 2);
  EXPECT_EQ(two, double(1e8f + float(0.5 + (kFvvdpTorchGrain - 1))));
  EXPECT_EQ(torch_cpu_sum(w.data(), w.size(), 1), 1e8);  // every later +1 lost
  EXPECT_EQ(torch_cpu_sum(w.data(), 100, 2), torch_cpu_sum(w.data(), 100, 1));  // below grain
}

TEST(Fvvdp, PoolingSumsAsTheReferenceDoesWhereDIsClamped) {
  // A still 1440x1600 pair on htc_vive_pro whose reference has a strong grating and whose test
  // is flat (an extreme blur): D is clamped at 1e4 on most pixels of the first bands, so the
  // reference's float32 pooling sum drifts. Expected values from an independent float64
  // implementation of the spec in numpy with the same sums emulated (not from fovsim).
  const Image ref = grating(1600, 1440, 60, 10), test = uniform(1600, 1440, 128);
  const FvvdpDisplay d = FvvdpDisplay::standard("htc_vive_pro");
  const double exact = fvvdp({test}, {ref}, d, 0, false, {}, 0).jod;
  const double one = fvvdp({test}, {ref}, d, 0, false, {}, 1).jod;
  const double two = fvvdp({test}, {ref}, d, 0, false, {}, 2).jod;
  const double sixteen = fvvdp({test}, {ref}, d, 0, false, {}, 16).jod;
  EXPECT_NEAR(exact, 3.480937, 1e-5);
  EXPECT_NEAR(one, 3.478882, 1e-5);
  EXPECT_NEAR(two, 3.482758, 1e-5);
  EXPECT_NEAR(sixteen, 3.481619, 1e-5);
  EXPECT_GT(std::fabs(one - exact), 1.5e-3);  // the effect is larger than the 1e-3 regression bar
  EXPECT_EQ(fvvdp({test}, {ref}, d, 0, false).jod,
            one);  // the default: the reference on one thread
}
