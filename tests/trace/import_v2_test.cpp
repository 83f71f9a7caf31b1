// Map features for real exports, each on a small file made in the test.
#include <cmath>

#include "sim/trace/importer.h"
#include "sim/trace/stats.h"
#include "sim/trace/synth.h"
#include "test_util.h"

using namespace fovsim;
using namespace fovsim::test;

namespace {

Json base_map() {
  return Json::parse(R"({"delimiter": "comma", "header": true, "coordinates": "fovsim",
    "time": {"column": "t", "unit": "ms"}, "head_position": {"constant": [0, 1.6, 0]},
    "head_orientation": {"constant": [1, 0, 0, 0]},
    "gaze": {"type": "direction", "space": "head", "columns": ["x", "y", "z"]}})");
}

double deg_between(const glm::dvec3& a, const glm::dvec3& b) {
  return rad2deg(angle_between(a, b));
}

}  // namespace

// Item 1: two fields fused in the export ("666.5324True"): rows one field short.
TEST(ImportV2, FusedFieldsAcceptedWhenUsedColumnsArePresent) {
  std::string rec = write_tmp("fused.csv",
                              "t,x,y,z,pupil,blink\n"
                              "0,0,0,-1,3.1,False\n"
                              "10,0,0,-1,666.5324True\n"
                              "20,0,0,-1,3.0False\n");
  Json j = base_map();
  std::string exact = write_tmp("exact.json", j.dump());
  expect_error(
      [&] { import_trace(rec, exact, vive()); },
      {"fused.csv:3:", "expected 6 fields as in the header, got 5", "\"row_fields\": \"used\""});
  // Skipping every row says why, not just "no usable rows".
  j["on_bad_row"] = "skip";
  std::string fused_only =
      write_tmp("all.csv", "t,x,y,z,pupil,blink\n0,0,0,-1,1True\n10,0,0,-1,2True\n");
  std::string skip = write_tmp("skip.json", j.dump());
  expect_error([&] { import_trace(fused_only, skip, vive()); },
               {"no usable rows: all 2 data rows were dropped",
                "2 samples skipped (wrong field count", "all.csv:2:"});
  // A skip that drops more than max_skipped_fraction is an error naming the reason.
  j["max_skipped_fraction"] = 0.25;
  std::string frac = write_tmp("frac.json", j.dump());
  expect_error([&] { import_trace(rec, frac, vive()); },
               {"2 of 3 data rows (66.7 %) were skipped, more than max_skipped_fraction = 0.25",
                "wrong field count", "fused.csv:3:"});
  // row_fields = used: rows are accepted when every column the map uses exists and parses.
  Json u = base_map();
  u["row_fields"] = "used";
  std::string used = write_tmp("used.json", u.dump());
  ImportReport rep;
  Trace tr = import_trace(rec, used, vive(), &rep);
  EXPECT_EQ(tr.samples.size(), 3u);
  EXPECT_EQ(rep.skipped_rows, 0);
  // ... but a row missing a used column still fails at its line.
  std::string shorter = write_tmp("short.csv", "t,x,y,z,pupil,blink\n0,0,0,-1,3,False\n10,0,0\n");
  expect_error([&] { import_trace(shorter, used, vive()); },
               {"short.csv:3:", "column \"z\" (field 4) is missing"});
  u["row_fields"] = "some";
  std::string badkey = write_tmp("bad.json", u.dump());
  expect_error([&] { import_trace(rec, badkey, vive()); },
               {"bad.json: row_fields", "allowed: exact, used"});
}

// Item 2: duplicate header names are an error only when the map refers to them.
TEST(ImportV2, DuplicateHeaderNamesOnlyMatterWhenUsed) {
  std::string rec = write_tmp("dup.csv", "index,t,x,y,z,index\n1,0,0,0,-1,1\n2,10,0,0,-1,2\n");
  std::string map = write_tmp("m.json", base_map().dump());
  EXPECT_EQ(import_trace(rec, map, vive()).samples.size(), 2u);
  Json j = base_map();
  j["valid"] = Json::array({Json{{"column", "index"}, {"min", 0}}});
  std::string used = write_tmp("used.json", j.dump());
  expect_error([&] { import_trace(rec, used, vive()); },
               {"used.json: valid[0].column", "\"index\" appears more than once", "fields 1, 6",
                "1-based index"});
  j["valid"][0]["column"] = 6;  // by index: fine
  std::string byidx = write_tmp("idx.json", j.dump());
  EXPECT_EQ(import_trace(rec, byidx, vive()).samples.size(), 2u);
}

// Item 3: head orientation as a forward vector (and optionally an up vector).
TEST(ImportV2, HeadOrientationFromForwardAndUp) {
  Json j = base_map();
  j["head_orientation"] = Json{{"type", "forward"}, {"forward", {"fx", "fy", "fz"}}};
  std::string fwd = write_tmp("fwd.json", j.dump());
  std::string rec = write_tmp("f.csv",
                              "t,fx,fy,fz,ux,uy,uz,x,y,z\n"
                              "0,1,0,0,0,1,0,0,0,-1\n"
                              "10,0,-0.5,-0.8660254,0,0.8660254,-0.5,0,0,-1\n"
                              "20,0,0,-2,1,0,0,0,0,-1\n");
  Trace tr = import_trace(rec, fwd, vive());
  ASSERT_EQ(tr.samples.size(), 3u);
  const glm::dvec3 F(0, 0, -1), U(0, 1, 0);
  EXPECT_LT(deg_between(tr.samples[0].head_rot * F, {1, 0, 0}), 1e-9);  // turned right
  EXPECT_LT(deg_between(tr.samples[0].head_rot * U, {0, 1, 0}), 1e-9);  // no roll without "up"
  EXPECT_LT(deg_between(tr.samples[1].head_rot * F, {0, -0.5, -0.8660254}),
            1e-6);  // pitched 30 deg down
  // With an up vector: sample 2 looks ahead rolled 90 deg (up = +x).
  j["head_orientation"]["up"] = {"ux", "uy", "uz"};
  std::string fu = write_tmp("fu.json", j.dump());
  Trace t2 = import_trace(rec, fu, vive());
  EXPECT_LT(deg_between(t2.samples[2].head_rot * F, F), 1e-9);
  EXPECT_LT(deg_between(t2.samples[2].head_rot * U, {1, 0, 0}), 1e-9);
  EXPECT_LT(deg_between(t2.samples[1].head_rot * U, {0, 0.8660254, -0.5}), 1e-6);
  // A vertical forward without up has no heading: an error at the row.
  std::string vert = write_tmp("v.csv", "t,fx,fy,fz,ux,uy,uz,x,y,z\n0,0,1,0,0,1,0,0,0,-1\n");
  expect_error([&] { import_trace(vert, fwd, vive()); }, {"v.csv:2:", "zero or vertical"});
}

// Item 4: gaze in another frame than the head pose (SRanipal eye frame: right-handed,
// +x to the user's left, +y up, +z forward) next to a Unity head pose.
TEST(ImportV2, GazeCoordinatesSeparateFromTheHead) {
  Json j = base_map();
  j["coordinates"] = "unity";
  j["head_position"] = Json{{"columns", {"px", "py", "pz"}}, {"unit", "m"}};
  j["gaze"]["coordinates"] = Json{{"x", "-x"}, {"y", "+y"}, {"z", "-z"}};
  std::string map = write_tmp("sr.json", j.dump());
  std::string rec = write_tmp("sr.csv", "t,px,py,pz,x,y,z\n0,0.1,1.6,0.2,-0.2,0,1\n");
  Trace tr = import_trace(rec, map, vive());
  // Head position in Unity axes: x stays (not mirrored), z flips.
  EXPECT_NEAR(tr.samples[0].head_pos.x, 0.1, 1e-12);
  EXPECT_NEAR(tr.samples[0].head_pos.z, -0.2, 1e-12);
  // SRanipal x = -0.2 is to the user's right: fovsim +x.
  EXPECT_GT(tr.samples[0].gaze_dir.x, 0.19);
  EXPECT_LT(deg_between(tr.samples[0].gaze_dir, glm::normalize(glm::dvec3(0.2, 0, -1))), 1e-9);
  // One shared setting would mirror it (the bug the key fixes).
  j["gaze"].erase("coordinates");
  std::string shared = write_tmp("shared.json", j.dump());
  EXPECT_LT(import_trace(rec, shared, vive()).samples[0].gaze_dir.x, -0.19);
  j["gaze"] = Json{{"type", "screen"}, {"columns", {"x", "y"}}, {"coordinates", "unity"}};
  std::string bad = write_tmp("bad.json", j.dump());
  expect_error([&] { import_trace(rec, bad, vive()); }, {"bad.json: gaze.coordinates", "no axes"});
}

// Item 5: validity as a bitmask, a numeric threshold, and per eye.
TEST(ImportV2, BitmaskThresholdAndPerEyeValidity) {
  Json j = base_map();
  j["gaze"] = Json{{"type", "direction"},
                   {"space", "head"},
                   {"left", {"lx", "ly", "lz"}},
                   {"right", {"rx", "ry", "rz"}},
                   {"combine", "mean"}};
  j["valid"] = Json::array({Json{{"column", "vl"}, {"all_bits", 2}, {"eye", "left"}},
                            Json{{"column", "vr"}, {"all_bits", 2}, {"eye", "right"}},
                            Json{{"column", "conf"}, {"min", 0.6}}});
  std::string map = write_tmp("v.json", j.dump());
  std::string rec =
      write_tmp("v.csv",
                "t,lx,ly,lz,rx,ry,rz,vl,vr,conf\n"
                "0,0.1,0,-1,-0.1,0,-1,31,31,0.9\n"  // both eyes
                "10,0.2,0,-1,9,9,9,31,29,0.9\n"     // right eye invalid (bit 1 clear): left only
                "20,0,0,-1,0,0,-1,1,0,0.9\n"        // neither eye: invalid row
                "30,0,0,-1,0,0,-1,31,31,0.5\n"      // low confidence: invalid
                "40,0,0,-1,0,0,-1,31,31,0.6\n");    // threshold is inclusive
  ImportReport rep;
  Trace tr = import_trace(rec, map, vive(), &rep);
  ASSERT_EQ(tr.samples.size(), 5u);
  EXPECT_TRUE(tr.samples[0].valid);
  EXPECT_LT(deg_between(tr.samples[0].gaze_dir, {0, 0, -1}), 1e-9);
  EXPECT_TRUE(tr.samples[1].valid);
  EXPECT_LT(deg_between(tr.samples[1].gaze_dir, glm::normalize(glm::dvec3(0.2, 0, -1))), 1e-9);
  EXPECT_FALSE(tr.samples[2].valid);
  EXPECT_FALSE(tr.samples[3].valid);
  EXPECT_TRUE(tr.samples[4].valid);
  EXPECT_EQ(rep.invalid_rows, 2);
  EXPECT_EQ(rep.one_eye_rows, 1);
  // "eye" needs per-eye gaze; a bitmask must be a positive integer.
  Json k = base_map();
  k["valid"] = Json::array({Json{{"column", "x"}, {"all_bits", 2}, {"eye", "left"}}});
  std::string bad = write_tmp("bad.json", k.dump());
  std::string rec1 = write_tmp("one.csv", "t,x,y,z\n0,0,0,-1\n");
  expect_error([&] { import_trace(rec1, bad, vive()); },
               {"bad.json: valid[0].eye", "per-eye gaze"});
  k["valid"] = Json::array({Json{{"column", "x"}, {"all_bits", 0}}});
  std::string bad2 = write_tmp("bad2.json", k.dump());
  expect_error([&] { import_trace(rec1, bad2, vive()); }, {"bad2.json: valid[0].all_bits"});
}

// Item 6: wrapping counters, bursts after a stall, repeated head poses.
TEST(ImportV2, WrappingMillisecondCounter) {
  Json j = base_map();
  j["time"]["wrap_bits"] = 32;
  std::string map = write_tmp("w.json", j.dump());
  std::string rec =
      write_tmp("w.csv", "t,x,y,z\n4294967286,0,0,-1\n4294967294,0,0,-1\n6,0,0,-1\n14,0,0,-1\n");
  ImportReport rep;
  Trace tr = import_trace(rec, map, vive(), &rep);
  ASSERT_EQ(tr.samples.size(), 4u);
  EXPECT_NEAR(tr.samples[2].t, 0.016, 1e-12);
  EXPECT_NEAR(tr.samples[3].t, 0.024, 1e-12);
  EXPECT_EQ(rep.time_wraps, 1);
  // Without wrap_bits the wrap is a non-monotonic time at its line.
  std::string plain = write_tmp("p.json", base_map().dump());
  expect_error([&] { import_trace(rec, plain, vive()); }, {"w.csv:4:1", "not strictly increasing"});
}

TEST(ImportV2, BurstsAfterAStallKeptDroppedOrRetimed) {
  std::string rec =
      write_tmp("b.csv",
                "t,x,y,z\n0,0,0,-1\n10,0,0,-1\n20,0,0,-1\n30,0,0,-1\n80,0.1,0,-1\n80.1,0.2,0,-1\n"
                "80.2,0.3,0,-1\n90,0,0,-1\n100,0,0,-1\n");
  Json j = base_map();
  std::string keep = write_tmp("k.json", j.dump());
  ImportReport rep;
  Trace tr = import_trace(rec, keep, vive(), &rep);
  EXPECT_EQ(rep.burst_samples, 2);
  ASSERT_EQ(tr.warnings.size(), 1u);
  EXPECT_NE(tr.warnings[0].find("b.csv:7"), std::string::npos) << tr.warnings[0];
  TraceStats st = trace_stats(tr);
  EXPECT_EQ(st.bursts, 2);
  EXPECT_GT(st.speed_p99, 1000.0);  // 5.7 deg in 0.1 ms
  ASSERT_FALSE(st.warnings.empty());
  EXPECT_NE(format_stats(st).find("implausible        eye-speed p99"), std::string::npos);
  j["time"]["on_burst"] = "drop";
  std::string drop = write_tmp("d.json", j.dump());
  Trace td = import_trace(rec, drop, vive());
  ASSERT_EQ(td.samples.size(), 7u);
  EXPECT_NEAR(td.samples[5].t, 0.090, 1e-12);
  j["time"]["on_burst"] = "retime";
  std::string retime = write_tmp("r.json", j.dump());
  Trace tt = import_trace(rec, retime, vive());
  ASSERT_EQ(tt.samples.size(), 9u);
  // Samples 80, 80.1, 80.2 ms were buffered in the stall after 30 ms: spread over (30, 80.2].
  EXPECT_NEAR(tt.samples[4].t, 0.030 + 0.0502 / 3, 1e-12);
  EXPECT_NEAR(tt.samples[5].t, 0.030 + 0.0502 * 2 / 3, 1e-12);
  EXPECT_NEAR(tt.samples[6].t, 0.0802, 1e-12);
  EXPECT_EQ(trace_stats(tt).bursts, 0);
  // An explicit threshold.
  j["time"]["on_burst"] = "keep";
  j["time"]["burst_below_s"] = 0.00005;
  std::string thr = write_tmp("t.json", j.dump());
  ImportReport r2;
  import_trace(rec, thr, vive(), &r2);
  EXPECT_EQ(r2.burst_samples, 0);
}

TEST(ImportV2, RepeatedHeadPosesDetectedAndInterpolated) {
  Json j = base_map();
  j["head_orientation"] =
      Json{{"type", "quaternion"}, {"columns", {"qw", "qx", "qy", "qz"}}, {"order", "wxyz"}};
  j["gaze"]["space"] = "world";
  std::string keep = write_tmp("k.json", j.dump());
  // Yaw 0 held for three gaze samples, then yaw -90 (turned right), updated per render frame.
  std::string rec = write_tmp("r.csv",
                              "t,qw,qx,qy,qz,x,y,z\n"
                              "0,1,0,0,0,0,0,-1\n"
                              "10,1,0,0,0,0,0,-1\n"
                              "20,1,0,0,0,0,0,-1\n"
                              "30,0.7071067811865476,0,-0.7071067811865476,0,1,0,-0.3\n");
  ImportReport rep;
  Trace tr = import_trace(rec, keep, vive(), &rep);
  EXPECT_EQ(rep.repeated_poses, 2);
  EXPECT_EQ(trace_stats(tr).repeated_poses, 2);
  ASSERT_EQ(tr.warnings.size(), 1u);
  EXPECT_NE(tr.warnings[0].find("r.csv:3"), std::string::npos) << tr.warnings[0];
  j["repeated_pose"] = "interpolate";
  std::string interp = write_tmp("i.json", j.dump());
  Trace ti = import_trace(rec, interp, vive());
  const glm::dvec3 F(0, 0, -1);
  // 1/3 and 2/3 of the way to the 90 deg turn.
  EXPECT_NEAR(deg_between(ti.samples[1].head_rot * F, F), 30.0, 1e-9);
  EXPECT_NEAR(deg_between(ti.samples[2].head_rot * F, F), 60.0, 1e-9);
  // World-space gaze keeps its world direction: straight ahead in world, 30 deg left in the head.
  EXPECT_LT(deg_between(ti.samples[1].head_rot * ti.samples[1].gaze_dir, F), 1e-9);
  EXPECT_EQ(trace_stats(ti).repeated_poses, 0);
}

// Plausibility report: human ranges (eccentricity p95 <= 35 deg, eye-speed p99 <= 700 deg/s).
TEST(ImportV2, PlausibilityWarnings) {
  Trace tr;
  for (int k = 0; k < 100; ++k) {
    TraceSample s;
    s.t = k / 90.0;
    double e = deg2rad(k < 90 ? 40.0 : 5.0);  // 90 % of samples 40 deg off-axis
    s.gaze_dir = {std::sin(e), 0, -std::cos(e)};
    tr.samples.push_back(s);
  }
  TraceStats st = trace_stats(tr);
  ASSERT_EQ(st.warnings.size(), 1u);
  EXPECT_NE(st.warnings[0].find("eccentricity p95 40.0 deg is above 35 deg"), std::string::npos)
      << st.warnings[0];
  EXPECT_EQ(st.repeated_poses, 0);  // a constant head is not checked for repeats
  EXPECT_TRUE(st.constant_head);
  // The eye model's scenarios stay inside human ranges.
  for (const char* sc : {"free-viewing", "walk-through"}) {
    SynthOptions o;
    o.scenario = sc;
    o.seed = 1;
    o.duration_s = 10;
    o.rate_hz = 90;
    TraceStats ss = trace_stats(synthesize(EyeModel{}, o, vive()));
    EXPECT_TRUE(ss.warnings.empty()) << sc << ": " << ss.warnings[0];
    EXPECT_LT(ss.speed_p99, kPlausibleSpeedP99) << sc;
    EXPECT_LT(ss.ecc_p95, kPlausibleEccP95) << sc;
  }
}

// Bursts stamped with the same millisecond: an error unless bursts are dropped or retimed.
TEST(ImportV2, BurstsWithEqualTimes) {
  std::string rec = write_tmp(
      "eq.csv",
      "t,x,y,z\n0,0,0,-1\n4,0,0,-1\n8,0,0,-1\n20,0,0,-1\n20,0,0,-1\n20,0,0,-1\n24,0,0,-1\n");
  Json j = base_map();
  std::string keep = write_tmp("k.json", j.dump());
  expect_error([&] { import_trace(rec, keep, vive()); },
               {"eq.csv:6:1", "not strictly increasing: 20 after 20"});
  j["time"]["on_burst"] = "retime";
  std::string retime = write_tmp("r.json", j.dump());
  Trace tr = import_trace(rec, retime, vive());
  ASSERT_EQ(tr.samples.size(), 7u);
  // The stall is 8 -> 20 ms; the three samples stamped 20 ms are spread over it: 12, 16, 20.
  EXPECT_NEAR(tr.samples[3].t, 0.012, 1e-12);
  EXPECT_NEAR(tr.samples[4].t, 0.016, 1e-12);
  EXPECT_NEAR(tr.samples[5].t, 0.020, 1e-12);
  j["time"]["on_burst"] = "drop";
  std::string drop = write_tmp("d.json", j.dump());
  EXPECT_EQ(import_trace(rec, drop, vive()).samples.size(), 5u);
}
