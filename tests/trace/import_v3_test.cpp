// Real recordings v3: importer and reader bugs found on public exports, each on a small
// file generated here, and the plausibility checks on validity and head motion.
#include <cmath>

#include "sim/trace/importer.h"
#include "sim/trace/stats.h"
#include "sim/trace/trace.h"
#include "sim/trace/tracking.h"
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

Trace load(const Json& block, const std::string& base, double needed_s) {
  Params root(Json{{"trace", block}}, "run.json");
  Params tp = root.child("trace");
  Trace tr = load_trace(tp, vive(), base, needed_s);
  root.finish();
  return tr;
}

bool has_warning(const Trace& tr, const std::string& needle) {
  for (auto& w : tr.warnings)
    if (w.find(needle) != std::string::npos) return true;
  return false;
}

}  // namespace

// Bug 1: a duration longer than the frames need is checked against the whole recording.
TEST(ImportV3, DurationBeyondWhatTheFramesNeedIsNotShort) {
  Trace tr = load(Json{{"file", "traces/sample_walk.csv"}, {"duration", 1.0}}, src(""), 0.266667);
  EXPECT_FALSE(tr.samples.empty());
  EXPECT_LE(tr.samples.size(), 30u);  // still only what the frames use is resampled
  EXPECT_FALSE(has_warning(tr, "covers")) << (tr.warnings.empty() ? "" : tr.warnings[0]);
  // truncate/hold print no false warning either.
  Trace t2 = load(Json{{"file", "traces/sample_walk.csv"}, {"duration", 1.0}, {"on_short", "hold"}},
                  src(""), 0.1);
  EXPECT_FALSE(has_warning(t2, "covers"));
  EXPECT_LE(t2.samples.size(), 15u);
  // A really short trace still fails, naming its real length (4 s).
  expect_error(
      [&] {
        load(Json{{"file", "traces/sample_walk.csv"}, {"duration", 10.0}}, src(""), 0.1);
      },
      {"trace.duration", "covers 4.0", "asks for 10.0"});
}

// Bug 2: retimed burst samples keep the head pose of their arrival time.
TEST(ImportV3, RetimedBurstKeepsTheArrivalPose) {
  // 10 ms samples, a stall 30 -> 135 ms, then a burst; the head turns at 100 deg/s about Y.
  std::string csv = "t,yaw,x,y,z\n";
  auto row = [&](double t, double yaw) {
    char b[100];
    std::snprintf(b, sizeof b, "%.1f,%.4f,0,0,-1\n", t, yaw);
    csv += b;
  };
  for (int k = 0; k <= 3; ++k) row(10.0 * k, 0.1 * 10 * k);  // 0..30 ms: 0..3 deg
  row(135, 20.0);                                            // ended the stall
  for (int k = 1; k <= 9; ++k) row(135 + 0.1 * k, 20.0);     // buffered samples
  for (int k = 1; k <= 5; ++k) row(135.9 + 10 * k, 20.0 + k);
  std::string rec = write_tmp("burst.csv", csv);
  Json j = base_map();
  j["head_orientation"] = {{"type", "euler"},
                           {"columns", {"x", "yaw", "x"}},
                           {"order", "ZXY"},
                           {"sequence", "extrinsic"},
                           {"unit", "deg"}};
  j["time"]["on_burst"] = "retime";
  Trace tr = import_trace(rec, write_tmp("m.json", j.dump()), vive());
  TraceStats st = trace_stats(tr);
  EXPECT_LT(st.head_speed_max, 300.0) << format_stats(st);
  // The old behaviour, on request: the pose moves with the gaze (a 10 deg turn in one slot).
  j["time"]["burst_pose"] = "sample";
  Trace old = import_trace(rec, write_tmp("s.json", j.dump()), vive());
  TraceStats so = trace_stats(old);
  EXPECT_GT(so.head_speed_max, 1000.0);
  ASSERT_FALSE(so.head_jumps.empty());
  EXPECT_NE(so.head_jumps[0].find("line 6"), std::string::npos) << so.head_jumps[0];
  EXPECT_NE(format_stats(so).find("implausible        head speed max"), std::string::npos);
  j["time"]["burst_pose"] = "later";
  expect_error([&] { import_trace(rec, write_tmp("b.json", j.dump()), vive()); },
               {"time.burst_pose", "arrival"});
}

// Bug 3 / item 2: an all-invalid trace is refused; a mostly invalid one is warned about.
TEST(ImportV3, AllInvalidIsRefusedMostlyInvalidWarned) {
  Json j = base_map();
  j["valid"] = Json::array({{{"column", "ok"}, {"valid_values", {"1"}}}});
  std::string map = write_tmp("m.json", j.dump());
  std::string all = write_tmp("all.csv", "t,x,y,z,ok\n0,0,0,-1,0\n10,0,0,-1,0\n20,0,0,-1,0\n");
  expect_error([&] { import_trace(all, map, vive()); },
               {"all.csv", "all 3 samples are flagged invalid", "valid conditions"});
  std::string most = write_tmp("most.csv", "t,x,y,z,ok\n0,0,0,-1,1\n10,0,0,-1,0\n20,0,0,-1,0\n");
  Trace tr = import_trace(most, map, vive());
  EXPECT_TRUE(has_warning(tr, "66.7 % of samples (2 of 3) are flagged invalid, more than 25 %"));
  EXPECT_NE(format_stats(trace_stats(tr)).find("implausible        66.7 %"), std::string::npos);
  // The canonical reader (validate, run) refuses it too.
  std::string c = write_tmp("c.csv",
                            "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,valid\n0,0,0,0,1,0,0,0,0,0,-1,0\n"
                            "0.01,0,0,0,1,0,0,0,0,0,-1,0\n");
  expect_error([&] { read_trace_csv(c, vive()); }, {"c.csv", "all 2 samples are flagged invalid"});
}

// Bug 4: rows flagged invalid show the last valid gaze, not their own (finite, in-FOV) junk.
TEST(ImportV3, InvalidRowsHoldTheLastValidGaze) {
  Json j = base_map();
  j["valid"] = Json::array({{{"column", "conf"}, {"min", 0.6}}});
  std::string rec =
      write_tmp("r.csv", "t,x,y,z,conf\n0,0.1,0,-1,0.9\n10,-0.3,0.2,-1,0.1\n20,0,0,-1,0.9\n");
  Trace tr = import_trace(rec, write_tmp("m.json", j.dump()), vive());
  ASSERT_EQ(tr.samples.size(), 3u);
  EXPECT_FALSE(tr.samples[1].valid);
  EXPECT_EQ(tr.samples[1].gaze_dir, tr.samples[0].gaze_dir);
  std::string c = write_tmp("c.csv",
                            "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,valid\n0,0,0,0,1,0,0,0,0,0,-1,1\n"
                            "0.01,0,0,0,1,0,0,0,0.6,0,-0.8,0\n0.02,0,0,0,1,0,0,0,0,0,-1,1\n");
  Trace t2 = read_trace_csv(c, vive());
  EXPECT_EQ(t2.samples[1].gaze_dir, glm::dvec3(0, 0, -1));
}

// Bug 5: row_fields = used names the missing column and its field index.
TEST(ImportV3, UsedFieldsNamesTheMissingColumn) {
  Json j = base_map();
  j["row_fields"] = "used";
  std::string rec = write_tmp("u.csv", "t,a,x,y,z\n0,1,0,0,-1\n10,1,0,0\n");
  expect_error([&] { import_trace(rec, write_tmp("m.json", j.dump()), vive()); },
               {"u.csv:3:", "column \"z\" (field 5) is missing", "the row has 4 fields"});
}

// Bug 6: a last line cut inside its last field (no final newline) is dropped and reported.
TEST(ImportV3, CutLastLineIsDroppedAndReported) {
  Json j = base_map();
  j["gaze"]["columns"] = {"x", "y", "z"};
  j["head_orientation"] = {{"type", "euler"},
                           {"columns", {"p", "p", "yaw"}},
                           {"order", "ZXY"},
                           {"sequence", "extrinsic"},
                           {"unit", "deg"}};
  std::string map = write_tmp("m.json", j.dump());
  std::string cut = write_tmp(
      "cut.csv", "t,x,y,z,p,yaw\n0,0,0,-1,0,358.9170\n10,0,0,-1,0,358.9176\n20,0,0,-1,0,358");
  Trace tr = import_trace(cut, map, vive());
  EXPECT_EQ(tr.samples.size(), 2u);
  EXPECT_TRUE(has_warning(tr, "cut.csv:4: the file's last line 4 ends in \"358\""));
  // A short last line is truncation, not fused fields.
  std::string shrt =
      write_tmp("short.csv", "t,x,y,z,p,yaw\n0,0,0,-1,0,1.5\n10,0,0,-1,0,1.5\n20,0,0");
  Trace t2 = import_trace(shrt, map, vive());
  EXPECT_EQ(t2.samples.size(), 2u);
  EXPECT_TRUE(has_warning(t2, "has 3 of 6 fields and no final newline"));
  // With a final newline, the same short line is an error at its line.
  std::string nl = write_tmp("nl.csv", "t,x,y,z,p,yaw\n0,0,0,-1,0,1.5\n10,0,0,-1,0,1.5\n20,0,0\n");
  expect_error([&] { import_trace(nl, map, vive()); }, {"nl.csv:4:", "expected 6 fields"});
  // The canonical reader too.
  std::string c = write_tmp("c.csv",
                            "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz\n0,0,0,0,1,0,0,0,0,0,-1.0\n"
                            "0.01,0,0,0,1,0,0,0,0,0,-1.0\n0.02,0,0,0,1,0,0,0,0,0,-1");
  Trace t3 = read_trace_csv(c, vive());
  EXPECT_EQ(t3.samples.size(), 2u);
  EXPECT_TRUE(has_warning(t3, "looks cut off"));
}

// Bug 7: messages of validate.
TEST(ImportV3, ValidateMessages) {
  std::string c = write_tmp("c.csv",
                            "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz\n1.0000001,0,0,0,1,0,0,0,0,0,-1\n"
                            "1.0000001,0,0,0,1,0,0,0,0,0,-1\n");
  expect_error([&] { read_trace_csv(c, vive()); },
               {"c.csv:3:1", "t=1.0000001 after t=1.0000001 (line 2)"});
  // A constant head has no repeated poses to count.
  std::string k = write_tmp("k.csv",
                            "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz\n0,0,0,0,1,0,0,0,0,0,-1\n"
                            "0.01,0,0,0,1,0,0,0,0,0,-1\n0.02,0,0,0,1,0,0,0,0,0,-1\n");
  TraceStats st = trace_stats(read_trace_csv(k, vive()));
  EXPECT_EQ(st.repeated_poses, 0);
  EXPECT_NE(format_stats(st).find("not checked (constant head pose)"), std::string::npos);
  // A wrong delimiter: the header is one field.
  std::string semi = write_tmp("s.csv", "t;px;py\n0;0;0\n");
  expect_error([&] { read_trace_csv(semi, vive()); }, {"s.csv:1:1", "single field"});
  std::string rec = write_tmp("r.csv", "t;x;y;z\n0;0;0;-1\n");
  expect_error([&] { import_trace(rec, write_tmp("m.json", base_map().dump()), vive()); },
               {"time.column", "single field", "the header contains ;"});
}

// Item 3: head speed p99 and max, and the 5 largest jumps by line.
TEST(ImportV3, HeadJumpsNamedByLine) {
  std::string csv = "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz\n";
  for (int k = 0; k < 20; ++k) {
    double yaw = k == 12 ? 0.3 : 0.0;  // a 17 deg jump and back at line 14
    char b[160];
    std::snprintf(b, sizeof b, "%.3f,0,0,0,%.9f,0,%.9f,0,0,0,-1\n", 0.01 * k, std::cos(yaw / 2),
                  std::sin(yaw / 2));
    csv += b;
  }
  Trace tr = read_trace_csv(write_tmp("j.csv", csv), vive());
  TraceStats st = trace_stats(tr);
  EXPECT_NEAR(st.head_speed_max, 0.3 * 180 / kPi / 0.01, 1.0);
  ASSERT_EQ(st.head_jumps.size(), 2u);  // only non-zero rotations are listed
  EXPECT_NE(st.head_jumps[0].find("line 14 (t=0.12 s): 17.19 deg in 10.00 ms"), std::string::npos)
      << st.head_jumps[0];
  std::string f = format_stats(st);
  EXPECT_NE(f.find("max 1719"), std::string::npos) << f;
  EXPECT_NE(f.find("largest head jumps line 14"), std::string::npos) << f;
  EXPECT_NE(f.find("implausible        head speed max 1719 deg/s"), std::string::npos) << f;
}

// Map features: a fused field split back by suffix or pattern, so later columns line up.
TEST(ImportV3, FusedFieldSplitBySuffixOrPattern) {
  Json j = base_map();
  j["valid"] = Json::array({{{"column", "blink"}, {"valid_values", {"False"}}}});
  j["fused"] = Json::array({{{"column", "pupil"}, {"suffixes", {"True", "False"}}}});
  std::string rec = write_tmp("f.csv",
                              "t,pupil,blink,x,y,z\n0,3.5,False,0,0,-1\n10,666.5324True,0.1,0,-1\n"
                              "20,3.5,False,0,0,-1\n");
  ImportReport rep;
  Trace tr = import_trace(rec, write_tmp("m.json", j.dump()), vive(), &rep);
  ASSERT_EQ(tr.samples.size(), 3u);
  EXPECT_EQ(rep.fused_rows, 1);
  EXPECT_FALSE(tr.samples[1].valid);  // "True" is the blink field, x = 0.1 is in place
  EXPECT_TRUE(has_warning(tr, "1 row had a fused field split back into two"));
  j["fused"] = Json::array({{{"column", "pupil"}, {"pattern", "^(.*[0-9])(True|False)$"}}});
  Trace tp = import_trace(rec, write_tmp("p.json", j.dump()), vive());
  EXPECT_FALSE(tp.samples[1].valid);
  j["fused"] = Json::array({{{"column", "pupil"}, {"pattern", "(a"}}});
  expect_error([&] { import_trace(rec, write_tmp("b.json", j.dump()), vive()); },
               {"fused[0].pattern", "not a valid regular expression"});
  j["fused"] = Json::array({{{"column", "pupil"}}});
  expect_error([&] { import_trace(rec, write_tmp("c.json", j.dump()), vive()); },
               {"fused[0]", "exactly one of"});
}

// Map features: recentring, dequantisation, on_bad and on_invalid in the map.
TEST(ImportV3, RecentreDequantiseAndPoliciesInTheMap) {
  Json j = base_map();
  j["head_position"] = {{"columns", {"px", "py", "pz"}}, {"unit", "m"}, {"recentre", "first"}};
  // Position rounded to 0.1 m of a walk at 1 m/s sampled every 10 ms.
  std::string csv = "t,px,py,pz,x,y,z\n";
  for (int k = 0; k <= 40; ++k) {
    char b[100];
    std::snprintf(b, sizeof b, "%d,%.1f,1.6,-20,0,0,-1\n", 10 * k, 20 + std::round(k * 0.1) / 10);
    csv += b;
  }
  std::string rec = write_tmp("q.csv", csv);
  Trace tr = import_trace(rec, write_tmp("m.json", j.dump()), vive());
  EXPECT_EQ(tr.samples.front().head_pos, glm::dvec3(0.0));
  EXPECT_TRUE(has_warning(tr, "recentred by (20, 1.6, -20) m"));
  j["head_position"]["dequantise"] = true;
  Trace td = import_trace(rec, write_tmp("d.json", j.dump()), vive());
  // Between run centres the position is interpolated: no 0.1 m steps within 10 ms.
  double max_step = 0;
  for (size_t i = 1; i < td.samples.size(); ++i)
    max_step = std::max(max_step, glm::length(td.samples[i].head_pos - td.samples[i - 1].head_pos));
  EXPECT_LT(max_step, 0.02);
  EXPECT_TRUE(has_warning(td, "dequantised by run centres"));
  // on_bad in the map replaces --on-bad's default; the caller's explicit choice wins.
  Json g = base_map();
  g["on_bad"] = "hold";
  std::string out = write_tmp("o.csv", "t,x,y,z\n0,0,0,-1\n10,5,0,-0.1\n20,0,0,-1\n");
  Trace th = import_trace(out, write_tmp("h.json", g.dump()), vive());
  EXPECT_EQ(th.samples.size(), 3u);
  ImportOptions io;
  io.on_fov_explicit = true;  // fail, chosen by the caller
  expect_error([&] { import_trace(out, write_tmp("h2.json", g.dump()), vive(), nullptr, io); },
               {"o.csv:3:", "outside the display FOV"});
  // on_invalid in the map is the run's default.
  g.erase("on_bad");
  g["on_invalid"] = "full";
  std::string mp = write_tmp("i.json", g.dump());
  std::string rec2 = write_tmp("i.csv", "t,x,y,z\n0,0,0,-1\n10,0,0,-1\n20,0,0,-1\n");
  TrackingPolicy pol;
  Params root(Json{{"trace", {{"file", rec2}, {"map", mp}}}}, "run.json");
  Params tp = root.child("trace");
  load_trace(tp, vive(), "", 0.02, &pol);
  EXPECT_EQ(pol.on_invalid, OnInvalid::Full);
  g["on_invalid"] = "never";
  expect_error([&] { import_trace(rec2, write_tmp("n.json", g.dump()), vive()); },
               {"on_invalid", "hold"});
}
