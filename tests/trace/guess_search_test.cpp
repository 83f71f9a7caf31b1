// `trace import --guess` by hypothesis search (sim/trace/map_search.cpp): guess -> import on
// files in the layouts of public exports (tests/data/trace_layouts, made by its
// make_layouts.py), unit cases for each convention the data decides, and the failure hints.
#include <filesystem>

#include "sim/trace/importer.h"
#include "sim/trace/map_search.h"
#include "sim/trace/stats.h"
#include "test_util.h"

using namespace fovsim;
using namespace fovsim::test;

namespace {

struct Imported {
  MapSearchResult guess;
  Trace trace;
  TraceStats st;
};

// Guess, then import the file with the guessed map exactly as `trace import --map` does.
Imported guess_and_import(const std::string& file) {
  Imported r;
  r.guess = search_map(file, vive());
  std::string map =
      write_tmp(std::filesystem::path(file).filename().string() + ".map.json", r.guess.map.dump(2));
  r.trace = import_trace(file, map, vive());
  r.st = trace_stats(r.trace);
  return r;
}

// The success criterion of the guesser on real recordings.
void expect_plausible(const Imported& r, const std::string& what) {
  std::string rep;
  for (auto& l : r.guess.report) rep += l + "\n";
  EXPECT_LT(r.st.ecc_p95, 35) << what << "\n" << rep;
  EXPECT_LT(r.st.speed_p99, 1000) << what << "\n" << rep;
  EXPECT_LT(r.st.head_speed_max, 1000) << what << "\n" << rep;
  EXPECT_LT(r.st.invalid_fraction, 0.9) << what << "\n" << rep;
  EXPECT_GT(r.st.samples, 100u) << what;
}

std::vector<std::string> layout_files(const std::string& set) {
  std::vector<std::string> out;
  for (auto& e : std::filesystem::directory_iterator(src("tests/data/trace_layouts/" + set)))
    out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

// Rows of a generated recording: the eye at `az` deg right of head forward, a blink every
// 50th row; `row(i, t, az, blink)` formats one.
std::string rows(const std::string& header, int n, double hz,
                 const std::function<std::string(int, double, double, bool)>& row) {
  std::string s = header + "\n";
  for (int i = 0; i < n; ++i) {
    const double t = i / hz;
    s += row(i, t, 8 * std::sin(3 * t), i % 50 >= 47) + "\n";
  }
  return s;
}

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.6f", v);
  return b;
}

}  // namespace

TEST(GuessSearch, TunedLayoutsImportPlausibly) {
  const auto files = layout_files("tuned");
  ASSERT_EQ(files.size(), 3u);
  for (auto& f : files) expect_plausible(guess_and_import(f), f);
}

TEST(GuessSearch, HeldOutLayoutsImportPlausibly) {
  const auto files = layout_files("heldout");
  ASSERT_EQ(files.size(), 5u);
  for (auto& f : files) expect_plausible(guess_and_import(f), f);
}

// Pupil Cloud: "blink id" is empty outside blinks.
TEST(GuessSearch, EmptyMeansValid) {
  Imported r = guess_and_import(src("tests/data/trace_layouts/heldout/pupil_cloud_gaze.csv"));
  EXPECT_EQ(r.guess.map["valid"].dump(), R"([{"column":"blink id","valid_values":[""]}])");
  EXPECT_NEAR(r.st.invalid_fraction, 4.0 / 400, 1e-9);
}

// SRanipal: per-eye bitmasks, the SRanipal eye frame next to a Unity head, (0,0,0) on blinks.
TEST(GuessSearch, SranipalBitmaskAndFrames) {
  Imported r = guess_and_import(src("tests/data/trace_layouts/tuned/sranipal_unity.csv"));
  EXPECT_EQ(r.guess.map["coordinates"], "unity");
  EXPECT_EQ(r.guess.map["head_orientation"]["order"], "xyzw");
  // SRanipal's eye frame (+x left): the data cannot tell, the SDK's field names do.
  EXPECT_EQ(r.guess.map["gaze"]["coordinates"]["x"], "-x");
  ASSERT_TRUE(r.guess.map.contains("valid")) << r.guess.map.dump();
  EXPECT_NE(r.guess.map["valid"].dump().find("eye_data_validata_bit_mask"), std::string::npos);
  EXPECT_GT(r.st.invalid_fraction, 0.03);
  EXPECT_LT(r.st.invalid_fraction, 0.1);
}

// Tobii Pro Lab: "Valid"/"Invalid" words, gyroscope rows without gaze, microseconds by name.
TEST(GuessSearch, TobiiValidityWords) {
  Imported r = guess_and_import(src("tests/data/trace_layouts/tuned/tobii_pro_lab_glasses2.tsv"));
  EXPECT_EQ(r.guess.map["time"]["unit"], "us");
  EXPECT_NE(r.guess.map["valid"].dump().find("\"Valid\""), std::string::npos) << r.guess.map.dump();
  EXPECT_NEAR(r.st.rate_mean_hz, 100 * 360.0 / 300, 25);  // eye and gyroscope rows
}

// A bitmask whose largest value (7: left, right and combined bits) is rare: requiring every
// bit of it flags almost every row invalid, one bit alone is the right test.
TEST(GuessSearch, BitmaskRareLargestValue) {
  std::string f = write_tmp(
      "mask.csv", rows("time,eye_valid_mask,gaze_dir_x,gaze_dir_y,gaze_dir_z", 300, 90,
                       [](int i, double t, double az, bool blink) {
                         const double a = deg2rad(az);
                         std::string mask = blink ? "0" : i % 100 == 3 ? "7" : "3";
                         return num(t) + "," + mask + "," +
                                (blink ? "0,0,0" : num(std::sin(a)) + ",0," + num(-std::cos(a)));
                       }));
  Imported r = guess_and_import(f);
  EXPECT_NEAR(r.st.invalid_fraction, 18.0 / 300, 0.01) << r.guess.map.dump();
  EXPECT_FALSE(r.trace.samples[48].valid);
  EXPECT_TRUE(r.trace.samples[3].valid);
}

// Unity axes: +Z forward on every row, the head a quaternion x,y,z,w. The names say nothing
// about the convention; the sign of the dominant gaze component does.
TEST(GuessSearch, UnityPlusZForward) {
  std::string f = write_tmp(
      "unity.csv", rows("t,head_qx,head_qy,head_qz,head_qw,gaze_dir_x,gaze_dir_y,gaze_dir_z", 300,
                        90, [](int, double t, double az, bool) {
                          const double yaw = 0.3 * std::sin(t);  // Unity: about +Y, left-handed
                          const double a = deg2rad(az);
                          return num(t) + ",0," + num(std::sin(yaw / 2)) + ",0," +
                                 num(std::cos(yaw / 2)) + "," + num(std::sin(a)) + ",0.05," +
                                 num(std::cos(a));
                        }));
  Imported r = guess_and_import(f);
  EXPECT_EQ(r.guess.map["coordinates"], "unity");
  EXPECT_EQ(r.guess.map["head_orientation"]["order"], "xyzw");
  EXPECT_NEAR(r.trace.samples[0].gaze_dir.z, -1, 0.01);
}

// A zero vector on blink rows and no validity column: the sentinel becomes a condition.
TEST(GuessSearch, ZeroVectorSentinel) {
  std::string f = write_tmp(
      "zero.csv", rows("time_s,gaze_dir_x,gaze_dir_y,gaze_dir_z", 300, 60,
                       [](int, double t, double az, bool blink) {
                         const double a = deg2rad(az);
                         return num(t) + "," +
                                (blink ? "0,0,0" : num(std::sin(a)) + ",0," + num(-std::cos(a)));
                       }));
  Imported r = guess_and_import(f);
  EXPECT_NEAR(r.st.invalid_fraction, 18.0 / 300, 1e-9) << r.guess.map.dump();
  EXPECT_EQ(r.guess.map.value("on_bad_row", ""), "fail");
}

// A confidence column: low confidence on rows whose gaze is noise.
TEST(GuessSearch, ConfidenceThreshold) {
  std::string f = write_tmp(
      "conf.csv", rows("timestamp,confidence,gaze_dir_x,gaze_dir_y,gaze_dir_z", 300, 120,
                       [](int i, double t, double az, bool blink) {
                         const double a = deg2rad(blink ? 80.0 * ((i % 3) - 1) : az);
                         return num(t) + "," + (blink ? "0.12" : "0.95") + "," + num(std::sin(a)) +
                                ",0," + num((blink && i % 3 == 0 ? 1 : -1) * std::cos(a));
                       }));
  Imported r = guess_and_import(f);
  ASSERT_TRUE(r.guess.map.contains("valid"));
  EXPECT_EQ(r.guess.map["valid"][0]["column"], "confidence");
  EXPECT_NEAR(r.st.invalid_fraction, 18.0 / 300, 1e-9);
}

// Time units from the median step when the name says none (ns) or the wrong one (a
// "timestamp [ms]" column stepping 8333: microseconds).
TEST(GuessSearch, TimeUnitFromStep) {
  auto file = [](const std::string& name, const std::string& tname, double scale) {
    return write_tmp(name, rows(tname + ",gaze_dir_x,gaze_dir_y,gaze_dir_z", 300, 120,
                                [scale](int, double t, double az, bool) {
                                  const double a = deg2rad(az);
                                  char b[40];
                                  std::snprintf(b, sizeof b, "%.0f", 1e3 + t * scale);
                                  return std::string(b) + "," + num(std::sin(a)) + ",0," +
                                         num(-std::cos(a));
                                }));
  };
  Imported ns = guess_and_import(file("ns.csv", "time", 1e9));
  EXPECT_EQ(ns.guess.map["time"]["unit"], "ns");
  EXPECT_NEAR(ns.st.rate_hz, 120, 1);
  Imported us = guess_and_import(file("us.csv", "timestamp [ms]", 1e6));
  EXPECT_EQ(us.guess.map["time"]["unit"], "us");
  EXPECT_NEAR(us.st.rate_hz, 120, 1);
}

// Euler angles in radians (the names say nothing): values within [-pi, pi] that vary.
TEST(GuessSearch, EulerRadians) {
  std::string f = write_tmp(
      "rad.csv", rows("t,head_rot_x,head_rot_y,head_rot_z,gaze_dir_x,gaze_dir_y,gaze_dir_z", 300,
                      90, [](int, double t, double az, bool) {
                        const double a = deg2rad(az);
                        return num(t) + ",0.02," + num(0.8 * std::sin(t)) + ",0," +
                               num(std::sin(a)) + ",0," + num(std::cos(a));
                      }));
  Imported r = guess_and_import(f);
  EXPECT_EQ(r.guess.map["head_orientation"]["unit"], "rad");
  EXPECT_GT(r.st.head_speed_p50, 5);  // read as degrees the head would hardly move
}

// The report names the runner-up and the margin; a mirrored x in head space is ambiguous.
TEST(GuessSearch, ReportsRunnerUpAndMargin) {
  Imported r =
      guess_and_import(src("tests/data/trace_layouts/tuned/pupil_core_gaze_positions.csv"));
  ASSERT_GE(r.guess.report.size(), 2u);
  EXPECT_NE(r.guess.report[0].find("chosen"), std::string::npos);
  std::string all;
  for (auto& l : r.guess.report) all += l + "\n";
  EXPECT_NE(all.find("runner-up (score"), std::string::npos) << all;
  EXPECT_NE(all.find("margin"), std::string::npos) << all;
  EXPECT_NE(all.find("differs in gaze.coordinates"), std::string::npos) << all;
  // Pupil's world camera frame is OpenCV's (+y down, +z forward): from the field names.
  EXPECT_EQ(r.guess.map["coordinates"].dump(), R"({"x":"+x","y":"-y","z":"-z"})");
  EXPECT_EQ(r.guess.map["valid"][0]["column"], "confidence");
}

// No header: the time is the increasing column, the gaze the unit-norm triple.
TEST(GuessSearch, NoHeader) {
  std::string f = write_tmp("nohdr.csv", rows("", 300, 90, [](int i, double t, double az, bool) {
                                           const double a = deg2rad(az);
                                           return std::to_string(i % 7) + "," + num(t) + "," +
                                                  num(std::sin(a)) + ",0," + num(-std::cos(a));
                                         }).substr(1));
  Imported r = guess_and_import(f);
  EXPECT_EQ(r.guess.map["time"]["column"], 2);
  EXPECT_EQ(r.guess.map["gaze"]["columns"].dump(), "[3,4,5]");
  EXPECT_NEAR(r.st.rate_hz, 90, 0.5);
}

// A "gaze point" that is a head-relative direction (a toolbox export named it a point; as a
// world point it would be looked at from the head position, behind the eye).
TEST(GuessSearch, GazePointThatIsADirection) {
  std::string f = write_tmp(
      "pt.csv", rows("time,head_pos_x,head_pos_y,head_pos_z,gaze_point_x,gaze_point_y,gaze_point_z",
                     300, 90, [](int, double t, double az, bool) {
                       const double a = deg2rad(az);
                       return num(t) + ",0.1,1.6," + num(0.2 * t) + "," + num(2 * std::sin(a)) +
                              ",0," + num(-2 * std::cos(a));
                     }));
  Imported r = guess_and_import(f);
  EXPECT_EQ(r.guess.map["gaze"]["type"], "direction") << r.guess.map.dump();
  EXPECT_LT(r.st.ecc_p95, 9);
}

// Metadata lines starting with '#' before the header.
TEST(GuessSearch, LeadingCommentLines) {
  std::string f = write_tmp("hash.csv", "## Recorded with logger 1.2\n## Subject: S01\n" +
                                            rows("time_s;gaze_dir_x;gaze_dir_y;gaze_dir_z", 200, 60,
                                                 [](int, double t, double az, bool) {
                                                   const double a = deg2rad(az);
                                                   return num(t) + ";" + num(std::sin(a)) + ";0;" +
                                                          num(-std::cos(a));
                                                 }));
  Imported r = guess_and_import(f);
  EXPECT_EQ(r.guess.map["comment_prefix"], "#");
  EXPECT_EQ(r.guess.map["delimiter"], "semicolon");
  EXPECT_EQ(r.trace.samples.size(), 200u);
}

TEST(GuessSearch, NothingImportsIsAnError) {
  std::string f = write_tmp("words.csv", "a,b\nx,y\nz,w\n");
  expect_error([&] { search_map(f, vive()); }, {"words.csv", "no column map imports"});
}

// Hints: the map key most likely wrong, judged from the data.
TEST(GuessSearch, HintNamesCoordinates) {
  std::string f =
      write_tmp("u.csv", rows("t,gx,gy,gz", 200, 90, [](int, double t, double az, bool) {
                  const double a = deg2rad(az);
                  return num(t) + "," + num(std::sin(a)) + ",0," + num(std::cos(a));
                }));
  std::string map = write_tmp("m.json",
                              R"({"delimiter": "comma", "header": true, "coordinates": "opengl",
          "time": {"column": "t", "unit": "s"}, "head_position": {"constant": [0, 0, 0]},
          "head_orientation": {"constant": [1, 0, 0, 0]},
          "gaze": {"type": "direction", "space": "head", "columns": ["gx", "gy", "gz"]}})");
  expect_error([&] { import_trace_hinted(f, map, vive()); },
               {"u.csv:2:", "gaze points behind the eye",
                "hint: gaze z > 0 on 100 % of rows: try `coordinates: unity"});
}

TEST(GuessSearch, HintNamesValidity) {
  std::string f = write_tmp(
      "b.csv", rows("t,mask,gx,gy,gz", 200, 90, [](int i, double t, double az, bool blink) {
        const double a = deg2rad(az);
        return num(t) + "," +
               (blink   ? "0"
                : i % 2 ? "3"
                        : "1") +
               "," + num(std::sin(a)) + ",0," + num(-std::cos(a));
      }));
  std::string map = write_tmp("m.json",
                              R"({"delimiter": "comma", "header": true, "coordinates": "opengl",
          "time": {"column": "t", "unit": "s"}, "head_position": {"constant": [0, 0, 0]},
          "head_orientation": {"constant": [1, 0, 0, 0]},
          "gaze": {"type": "direction", "space": "head", "columns": ["gx", "gy", "gz"]},
          "valid": [{"column": "mask", "all_bits": 4}]})");
  std::string e = expect_error([&] { import_trace_hinted(f, map, vive()); },
                               {"b.csv", "flagged invalid", "hint:", "try `valid:"});
  EXPECT_EQ(e.find('\n'), std::string::npos);
}

TEST(GuessSearch, NoHintForAGoodMapsOtherErrors) {
  std::string map = write_tmp("m.json", "{\"delimiter\": \"comma\"}");
  std::string f = write_tmp("x.csv", "t\n1\n");
  std::string e = expect_error([&] { import_trace_hinted(f, map, vive()); }, {"m.json"});
  EXPECT_EQ(e.find("hint"), std::string::npos);
}

// A real recording when the shared data folder has one (never committed).
TEST(GuessSearch, RealRecordingWhenPresent) {
  for (const char* dir : {"../shared/data/traces", "../../shared/data/traces"}) {
    const std::string f = src(std::string(dir) + "/pico_neo3_pro_boxing.tsv");
    if (!std::filesystem::exists(f)) continue;
    expect_plausible(guess_and_import(f), f);
    return;
  }
  GTEST_SKIP() << "no shared/data/traces/pico_neo3_pro_boxing.tsv next to the checkout";
}
