// Bugs found importing real recordings, each on a small synthetic file.
#include <cmath>

#include "sim/trace/importer.h"
#include "sim/trace/stats.h"
#include "test_util.h"

using namespace fovsim;
using namespace fovsim::test;

namespace {

const char* kSimpleMap = R"({"delimiter": "comma", "header": true, "coordinates": "fovsim",
  "time": {"column": "t", "unit": "ms"}, "head_position": {"constant": [0, 1.6, 0]},
  "head_orientation": {"constant": [1, 0, 0, 0]},
  "gaze": {"type": "direction", "space": "head", "columns": ["x", "y", "z"]}})";

std::string rows(std::initializer_list<std::string> times) {
  std::string s = "t,x,y,z\n";
  for (auto& t : times) s += t + ",0,0,-1\n";
  return s;
}

}  // namespace

TEST(ImportBugs, OverlongIntegerTimeIsNamedAtItsOwnLine) {
  std::string map = write_tmp("m.json", kSimpleMap);
  std::string mid = write_tmp("mid.csv", rows({"1000", "1010", "12345678901234567890123", "1030"}));
  std::string w =
      expect_error([&] { import_trace(mid, map, vive()); },
                   {"mid.csv:4:1", "12345678901234567890123", "does not fit a 64-bit integer"});
  EXPECT_EQ(w.find("strictly increasing"), std::string::npos) << w;
  // In the last row it used to be accepted (duration 9.99e15 s).
  std::string last = write_tmp("last.csv", rows({"1000", "1010", "12345678901234567890123"}));
  expect_error([&] { import_trace(last, map, vive()); },
               {"last.csv:4:1", "does not fit a 64-bit integer"});
}

TEST(ImportBugs, SentinelTimesAreJumpsNotAccepted) {
  std::string map = write_tmp("m.json", kSimpleMap);
  std::string f = write_tmp("max.csv", rows({"1000", "1010", "9223372036854775807"}));
  expect_error([&] { import_trace(f, map, vive()); },
               {"max.csv:4:1", "jumps forward", "at line 3", "time.max_step_s"});
  // A decimal time far in the future is the same kind of jump.
  std::string g = write_tmp("dec.csv", rows({"1000.5", "1010.5", "1e22", "1030.5"}));
  expect_error([&] { import_trace(g, map, vive()); }, {"dec.csv:4:1", "jumps forward"});
  // A first-row sentinel: the next row names the previous value and its line.
  std::string h = write_tmp("first.csv", rows({"9223372036854775807", "1010"}));
  expect_error(
      [&] { import_trace(h, map, vive()); },
      {"first.csv:3:1", "not strictly increasing: 1010 after 9223372036854775807 at line 2"});
  // Subtracting a negative first time must not overflow silently.
  std::string k = write_tmp("neg.csv", rows({"-9223372036854775807", "9223372036854775807"}));
  expect_error([&] { import_trace(k, map, vive()); },
               {"neg.csv:3:1", "overflows a 64-bit integer"});
  // Under skip, such rows are dropped and counted.
  Json j = Json::parse(kSimpleMap);
  j["on_bad_row"] = "skip";
  std::string skip = write_tmp("skip.json", j.dump());
  ImportReport rep;
  std::string f2 =
      write_tmp("max2.csv", rows({"1000", "1010", "9223372036854775807", "1020", "1030"}));
  Trace tr = import_trace(f2, skip, vive(), &rep);
  EXPECT_EQ(tr.samples.size(), 4u);
  EXPECT_EQ(rep.skipped_rows, 1);
  EXPECT_NEAR(tr.duration(), 0.03, 1e-12);
}

TEST(ImportBugs, NulByteDoesNotCutTheMessage) {
  std::string map = write_tmp("m.json", kSimpleMap);
  std::string text = "t,x,y,z\n1000,0,0,-1\n1010,0";
  text += '\0';
  text += "5,0,-1\n";
  std::string f = write_tmp("nul.csv", text);
  std::string w = expect_error([&] { import_trace(f, map, vive()); },
                               {"nul.csv:3:6", "not a number: \"0\\x005\""});
  EXPECT_EQ(w.find('\0'), std::string::npos);
}

TEST(ImportBugs, CarriageReturnOnlyLineEnds) {
  std::string map = write_tmp("m.json", kSimpleMap);
  std::string f = write_tmp("cr.csv", "t,x,y,z\r1000,0,0,-1\r1010,0,0,-1\r1020,0,0,-1\r");
  Trace tr = import_trace(f, map, vive());
  ASSERT_EQ(tr.samples.size(), 3u);
  EXPECT_NEAR(tr.samples[2].t, 0.02, 1e-12);
  // Lines are counted at each CR: the bad value is on line 3. Mixed endings count once each.
  std::string g = write_tmp("cr2.csv", "t,x,y,z\r\n1000,0,0,-1\r1010,0,abc,-1\n");
  expect_error([&] { import_trace(g, map, vive()); },
               {"cr2.csv:3:8", "column \"y\": not a number: \"abc\""});
}

TEST(ImportBugs, GazeOutsideTheFovFailsTheImportAtItsLine) {
  std::string map = write_tmp("m.json", kSimpleMap);
  std::string f = write_tmp("fov.csv", "t,x,y,z\n0,0,0,-1\n10,0.9,0,-0.43589\n20,0,0,-1\n");
  expect_error([&] { import_trace(f, map, vive()); },
               {"fov.csv:3:4", "gaze outside the display FOV (htc_vive_pro_eye", "skip or hold"});
  ImportOptions skip;
  skip.on_fov = BadSamplePolicy::Skip;
  ImportReport rep;
  Trace tr = import_trace(f, map, vive(), &rep, skip);
  EXPECT_EQ(tr.samples.size(), 2u);
  EXPECT_EQ(rep.skipped_rows, 1);
  ASSERT_EQ(tr.warnings.size(), 1u);
  EXPECT_NE(tr.warnings[0].find("fov.csv:3:4"), std::string::npos) << tr.warnings[0];
  ImportOptions hold;
  hold.on_fov = BadSamplePolicy::Hold;
  Trace th = import_trace(f, map, vive(), nullptr, hold);
  ASSERT_EQ(th.samples.size(), 3u);
  EXPECT_EQ(th.samples[1].gaze_dir, th.samples[0].gaze_dir);
  // Every imported valid sample is inside the FOV, so `trace validate` accepts what import wrote.
  for (auto& s : th.samples) EXPECT_TRUE(gaze_inside_fov(vive(), s.gaze_dir));
}

TEST(ImportBugs, RunWithAMapReadsOnlyTheRequestedRange) {
  std::string dir = tmpdir();
  write_file_atomic(dir + "/map.json", kSimpleMap);
  std::string text = "t,x,y,z\n";
  for (int k = 0; k < 500; ++k) text += std::to_string(k * 10) + ",0,0,-1\n";  // 5 s at 100 Hz
  // A bad number and an unterminated quote after 5 s.
  text += "5000,0,abc,-1\n5010,\"0,0,-1\n";
  write_file_atomic(dir + "/rec.csv", text);
  Display d = vive();
  auto load = [&](const Json& block) {
    Params p(Json{{"trace", block}}, dir + "/run.json");
    Params t = p.child("trace");
    return load_trace(t, d, dir);
  };
  Trace tr =
      load(Json{{"file", "rec.csv"}, {"map", "map.json"}, {"duration", 2.0}, {"rate_hz", 100.0}});
  EXPECT_EQ(tr.samples.size(), 200u);
  expect_error(
      [&] {
        load(Json{{"file", "rec.csv"}, {"map", "map.json"}, {"rate_hz", 100.0}});
      },
      {"rec.csv:502:8", "not a number"});
}

TEST(ImportBugs, MeanRateOfJitteredMillisecondTimes) {
  // 120 Hz stamped in whole milliseconds: intervals 8, 8, 9 ms -> median 8 ms (125 Hz).
  Trace tr;
  for (int k = 0; k < 1201; ++k) {
    TraceSample s;
    s.t = std::floor(k * 1000.0 / 120.0) / 1000.0;
    tr.samples.push_back(s);
  }
  TraceStats st = trace_stats(tr);
  EXPECT_NEAR(st.rate_hz, 125.0, 1e-6);
  EXPECT_NEAR(st.rate_mean_hz, 120.0, 1e-9);
  EXPECT_NE(format_stats(st).find("125.00 Hz (median interval), 120.00 Hz (mean)"),
            std::string::npos);
  EXPECT_EQ(st.bursts, 0);
  EXPECT_TRUE(st.warnings.empty());
}

TEST(ImportBugs, CanonicalReaderSharesLineEndsAndQuoting) {
  std::string f = write_tmp(
      "cr.csv",
      "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz\r0,0,0,0,1,0,0,0,0,0,-1\r0.01,0,0,0,1,0,0,0,0,0,-1\r");
  EXPECT_EQ(read_trace_csv(f, vive()).samples.size(), 2u);
  std::string text = "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,va";
  text += '\0';
  text += "lid\n0,0,0,0,1,0,0,0,0,0,-1,1\n";
  std::string g = write_tmp("nul.csv", text);
  std::string w = expect_error([&] { read_trace_csv(g, vive()); },
                               {"nul.csv:1:", "unknown column \"va\\x00lid\""});
  EXPECT_NE(w.find("canonical columns"), std::string::npos) << w;
}

// ±9e18 integer times are rebased and unwrapped in exact 64-bit arithmetic; what
// does not fit is a located "time value out of range", never a signed overflow (UBSan) or a
// false "not strictly increasing".
TEST(ImportBugs, TimeOutOfRangeIsLocated) {
  Json j = Json::parse(kSimpleMap);
  j["time"]["unit"] = "ns";
  j["time"]["wrap_bits"] = 62;
  j["time"]["max_step_s"] = 1e300;
  std::string map = write_tmp("wrap62.json", j.dump());
  // 2^62 - 1, then a wrap (+2^62), again up to 2^63 - 1, then a second wrap past 2^63.
  std::string f =
      write_tmp("wrap62.csv", rows({"4611686018427387903", "0", "4611686018427387903", "0"}));
  expect_error([&] { import_trace(f, map, vive()); },
               {"wrap62.csv:5:1", "time value out of range", "overflows a 64-bit integer"});
  // Under skip such rows are dropped and their wraps not counted (a dropped row never
  // unwraps the counter): 1 wrap, 2 rows skipped, times exact.
  j["on_bad_row"] = "skip";
  std::string skip = write_tmp("wrap62s.json", j.dump());
  ImportReport rep;
  std::string g =
      write_tmp("wrap62s.csv", rows({"4611686018427387903", "0", "4611686018427387903", "0", "1"}));
  Trace tr = import_trace(g, skip, vive(), &rep);
  ASSERT_EQ(tr.samples.size(), 3u);
  EXPECT_EQ(rep.skipped_rows, 2);
  EXPECT_EQ(rep.time_wraps, 1);
  EXPECT_EQ(tr.samples[1].t, 1e-9);
  // Without wrap_bits: the extremes of the 64-bit range, whose difference does not fit.
  Json plain = Json::parse(kSimpleMap);
  plain["time"]["unit"] = "ns";
  plain["time"]["max_step_s"] = 1e300;
  std::string pm = write_tmp("pm.json", plain.dump());
  std::string h = write_tmp("pm9e18.csv", rows({"-9000000000000000000", "9000000000000000000"}));
  expect_error([&] { import_trace(h, pm, vive()); }, {"pm9e18.csv:3:1", "time value out of range"});
}
