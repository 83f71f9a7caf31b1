#include <cmath>

#include "sim/trace/convert.h"
#include "sim/trace/importer.h"
#include "sim/trace/stats.h"
#include "test_util.h"

using namespace fovsim;
using namespace fovsim::test;

static void expect_vec(const glm::dvec3& a, const glm::dvec3& b, double tol = 1e-9) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

// Unity: left-handed, +Y up, +Z forward; eulerAngles applied Z, then X, then Y (extrinsic);
// positive X looks down, positive Y turns right, positive Z rolls the right side up.
TEST(Import, UnityEulerOnKnownAngles) {
  const glm::dvec3 fwd(0, 0, -1), right(1, 0, 0), up(0, 1, 0);
  double s30 = 0.5, c30 = std::sqrt(3.0) / 2;
  expect_vec(unity_euler_to_fovsim(0, 0, 0) * fwd, fwd);
  expect_vec(unity_euler_to_fovsim(0, 90, 0) * fwd, right);            // yaw right
  expect_vec(unity_euler_to_fovsim(30, 0, 0) * fwd, {0, -s30, -c30});  // pitch down
  expect_vec(unity_euler_to_fovsim(0, 0, 30) * right, {c30, s30, 0});  // roll: right side up
  expect_vec(unity_euler_to_fovsim(30, 90, 0) * fwd, {c30, -s30, 0});  // pitch then yaw
  // Order matters: Z first, then X. Roll 90 then pitch 90 sends the right axis to forward.
  expect_vec(unity_euler_to_fovsim(90, 0, 90) * right, fwd);
  expect_vec(unity_euler_to_fovsim(90, 0, 90) * up, {-1, 0, 0});
  // 360-wrapped angles are the same rotation.
  glm::dquat a = unity_euler_to_fovsim(10, 358, 355), b = unity_euler_to_fovsim(10, -2, -5);
  EXPECT_NEAR(std::fabs(glm::dot(a, b)), 1.0, 1e-12);
  // Intrinsic XYZ equals extrinsic ZYX.
  glm::dvec3 ang(0.3, -0.7, 1.1);
  glm::dmat3 e1 = euler_matrix(ang, "XYZ", true), e2 = euler_matrix(ang, "ZYX", false);
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(e1[c][r], e2[c][r], 1e-12);
}

TEST(Import, AxisMaps) {
  AxisMap ue = axis_map_from(Json("unreal"), "m");
  expect_vec(ue.vec({1, 0, 0}), {0, 0, -1});  // UE forward
  expect_vec(ue.vec({0, 1, 0}), {1, 0, 0});   // UE right
  expect_vec(ue.vec({0, 0, 1}), {0, 1, 0});   // UE up
  AxisMap custom = axis_map_from(Json{{"x", "+y"}, {"y", "+z"}, {"z", "-x"}}, "m");
  EXPECT_EQ(custom.M, ue.M);
  expect_error(
      [] {
        axis_map_from(Json{{"x", "+y"}, {"y", "+y"}, {"z", "-x"}}, "map.json: coordinates");
      },
      {"map.json: coordinates", "distinct"});
  expect_error([] { axis_map_from(Json("blender"), "map.json: coordinates"); },
               {"unknown coordinate convention"});
}

static const char* kMap = R"({
  "delimiter": "tab", "header": true, "coordinates": "unity", "on_bad_row": "fail",
  "time": {"column": "ts", "unit": "100ns"},
  "head_position": {"columns": ["hx", "hy", "hz"], "unit": "cm"},
  "head_orientation": {"type": "euler", "columns": ["rx", "ry", "rz"], "order": "ZXY", "sequence": "extrinsic", "unit": "deg"},
  "gaze": {"type": "direction", "space": "head", "left": ["lx", "ly", "lz"], "right": ["rgx", "rgy", "rgz"], "combine": "mean"},
  "valid": [{"column": "blink", "invalid_values": ["1"]}]
})";
static const char* kRec =
    "ts\thx\thy\thz\trx\try\trz\tlx\tly\tlz\trgx\trgy\trgz\tblink\n"
    "638000000000000000\t0\t160\t0\t0\t90\t0\t0.1\t0\t1\t-0.1\t0\t1\t0\n"
    "638000000000111111\t10\t160\t0\t0\t90\t0\t0\t0\t1\t0\t0\t1\t0\n"
    "638000000000222222\t20\t160\t0\t0\t90\t0\t0\t0\t0\t0\t0\t0\t1\n";

TEST(Import, EpochTimeUnitsEulerPerEyeAndBlinks) {
  std::string map = write_tmp("map.json", kMap), rec = write_tmp("rec.tsv", kRec);
  ImportReport rep;
  Trace tr = import_trace(rec, map, vive(), &rep);
  ASSERT_EQ(tr.samples.size(), 3u);
  EXPECT_EQ(rep.invalid_rows, 1);
  EXPECT_NEAR(rep.time_offset_s, 63800000000.0, 1e-3);
  EXPECT_NEAR(tr.samples[1].t, 0.0111111, 1e-12);  // 100 ns ticks, exact after rebasing
  EXPECT_NEAR(tr.samples[2].t, 0.0222222, 1e-12);
  expect_vec(tr.samples[1].head_pos, {0.1, 1.6, 0});  // cm -> m; unity z flips (0 stays 0)
  expect_vec(tr.samples[0].head_rot * glm::dvec3(0, 0, -1), {1, 0, 0});
  // Mean of the two eyes: looking straight ahead in head space (Unity +Z -> fovsim -Z).
  expect_vec(tr.samples[0].gaze_dir, {0, 0, -1});
  EXPECT_TRUE(tr.samples[1].valid);
  EXPECT_FALSE(tr.samples[2].valid);
  expect_vec(tr.samples[2].gaze_dir, tr.samples[1].gaze_dir);  // zero vector while blinking: held
}

TEST(Import, ScreenAndWorldPointGaze) {
  std::string map =
      write_tmp("m.json", R"({"delimiter": "semicolon", "header": false, "coordinates": "fovsim",
    "time": {"column": 1, "unit": "ms"}, "head_position": {"constant": [0, 1.5, 0]},
    "head_orientation": {"type": "quaternion", "columns": [2, 3, 4, 5], "order": "xyzw"},
    "gaze": {"type": "point", "columns": [6, 7, 8], "unit": "m"}})");
  std::string rec =
      write_tmp("r.csv", "0;0;0;0;1;0;1.5;-2\n5;0;0.7071067812;0;0.7071067812;-2;1.5;0\n");
  Trace tr = import_trace(rec, map, vive());
  ASSERT_EQ(tr.samples.size(), 2u);
  EXPECT_NEAR(tr.samples[1].t, 0.005, 1e-12);
  expect_vec(tr.samples[0].gaze_dir, {0, 0, -1});
  // Head yawed 90 deg left looks down -X; the point at x=-2 is straight ahead.
  expect_vec(tr.samples[1].gaze_dir, {0, 0, -1}, 1e-8);

  std::string map2 =
      write_tmp("s.json", R"({"delimiter": "comma", "header": true, "coordinates": "fovsim",
    "time": {"column": "t", "unit": "s"}, "head_position": {"constant": [0, 0, 0]},
    "head_orientation": {"constant": [1, 0, 0, 0]},
    "gaze": {"type": "screen", "columns": ["u", "v"], "origin": "bottom-left"}})");
  std::string rec2 = write_tmp("s.csv", "t,u,v\n0,0.5,0.5\n0.1,1,1\n");
  Trace t2 = import_trace(rec2, map2, vive());
  expect_vec(t2.samples[1].gaze_dir,
             gaze_dir_from_screen(vive(), 1, 0));  // bottom-left origin: v=1 is the top
}

// Map errors name the map file and JSON path.
TEST(Import, MalformedMapsGiveClearErrors) {
  std::string rec = write_tmp("rec.tsv", kRec);
  auto bad_map = [&](const std::string& name, const std::string& text,
                     std::initializer_list<std::string> needles) {
    std::string map = write_tmp(name, text);
    return expect_error([&] { import_trace(rec, map, vive()); }, needles);
  };
  auto patched = [](const char* key, Json v) {
    Json j = Json::parse(kMap);
    j[Json::json_pointer(key)] = v;
    return j.dump();
  };
  bad_map("syntax.json", "{\"delimiter\": \"tab\",\n \"header\": tru }",
          {"syntax.json:2:", "malformed JSON"});
  bad_map("unknown.json", patched("/gaze/colour", "x"),
          {"unknown.json: gaze.colour", "unknown key"});
  bad_map("delim.json", patched("/delimiter", "pipe"),
          {"delim.json: delimiter", "allowed: comma, tab, semicolon, space"});
  bad_map("col.json", patched("/time/column", "timestamp"),
          {"col.json: time.column", "\"timestamp\" is not in the header", "rec.tsv"});
  bad_map("order.json", patched("/head_orientation/order", "ZXQ"),
          {"order.json: head_orientation.order", "three of X, Y, Z"});
  bad_map("unit.json", patched("/time/unit", "minutes"),
          {"unit.json: time.unit", "allowed: s, ms, us, ns, 100ns"});
  bad_map("ncols.json", patched("/head_position/columns", Json::array({"hx", "hy"})),
          {"ncols.json: head_position.columns", "array of 3 columns"});
  bad_map("idx.json", patched("/gaze/left/1", 99),
          {"idx.json: gaze.left[1]", "column index 99 is outside 1..14"});
  Json nocoord = Json::parse(kMap);
  nocoord.erase("coordinates");
  bad_map("nocoord.json", nocoord.dump(), {"nocoord.json: coordinates", "required"});
  bad_map("valid.json", patched("/valid/0/valid_values", Json::array({"0"})),
          {"valid.json: valid[0]",
           "exactly one of valid_values, invalid_values, all_bits, min or max"});
}

TEST(Import, MalformedRecordingsNameLines) {
  std::string map = write_tmp("map.json", kMap);
  std::string body = kRec;
  auto rec_err = [&](const std::string& name, const std::string& text,
                     std::initializer_list<std::string> needles) {
    std::string rec = write_tmp(name, text);
    return expect_error([&] { import_trace(rec, map, vive()); }, needles);
  };
  std::string head = body.substr(0, body.find('\n') + 1);
  rec_err("short.tsv", head + "638000000000000000\t0\t160\n",
          {"short.tsv:2:", "expected 14 fields as in the header, got 3"});
  rec_err("long.tsv",
          head + "638000000000000000\t0\t160\t0\t0\t90\t0\t0.1\t0\t1\t-0.1\t0\t1\t0\textra\n",
          {"long.tsv:2:", "got 15"});
  rec_err("num.tsv", head + "638000000000000000\t0\tabc\t0\t0\t90\t0\t0.1\t0\t1\t-0.1\t0\t1\t0\n",
          {"num.tsv:2:", "column \"hy\": not a number: \"abc\""});
  rec_err("mono.tsv",
          head +
              "5\t0\t160\t0\t0\t0\t0\t0\t0\t1\t0\t0\t1\t0\n4\t0\t160\t0\t0\t0\t0\t0\t0\t1\t0\t0\t1"
              "\t0\n",
          {"mono.tsv:3:1", "time not strictly increasing"});
  rec_err("behind.tsv", head + "5\t0\t160\t0\t0\t0\t0\t0\t0\t-1\t0\t0\t-1\t0\n",
          {"behind.tsv:2:", "behind the eye"});
  // on_bad_row = skip drops such rows and reports each kind with its first line.
  Json j = Json::parse(kMap);
  j["on_bad_row"] = "skip";
  std::string map2 = write_tmp("skip.json", j.dump());
  std::string rec = write_tmp(
      "mixed.tsv", body + "638000000000333333\t0\t160\n" +
                       "638000000000444444\t0\tabc\t0\t0\t90\t0\t0.1\t0\t1\t-0.1\t0\t1\t0\n");
  ImportReport rep;
  Trace tr = import_trace(rec, map2, vive(), &rep);
  EXPECT_EQ(tr.samples.size(), 3u);
  EXPECT_EQ(rep.skipped_rows, 2);
  ASSERT_EQ(rep.notes.size(), 2u);
  EXPECT_NE(rep.notes[0].find("mixed.tsv:5:"), std::string::npos) << rep.notes[0];
  EXPECT_NE(rep.notes[1].find("mixed.tsv:6:"), std::string::npos) << rep.notes[1];
}

// The real Pico Neo 3 Pro recording (not committed): skip when absent.
TEST(Import, PicoNeo3ProRecording) {
  std::string rec =
      std::string(FOVSIM_SOURCE_DIR) + "/../shared/data/traces/pico_neo3_pro_boxing.tsv";
  if (!file_exists(rec)) GTEST_SKIP() << "recording not present: " << rec;
  ImportReport rep;
  Trace tr = import_trace(rec, src("traces/maps/pico_neo3_pro.json"), vive(), &rep);
  TraceStats st = trace_stats(tr);
  EXPECT_EQ(rep.data_rows, 492);
  EXPECT_EQ(rep.skipped_rows, 0);
  EXPECT_NEAR(st.rate_hz, 90.0, 0.5);
  EXPECT_NEAR(st.duration_s, 5.4556, 0.01);
  EXPECT_EQ(st.gaps, 0);
  EXPECT_EQ(rep.invalid_rows, 8);  // blink rows (zero gaze vectors)
  // Plausible eye-in-head angles: within the oculomotor range, looking forward.
  EXPECT_GT(st.ecc_p50, 5.0);
  EXPECT_LT(st.ecc_p50, 25.0);
  EXPECT_LT(st.ecc_max, 35.0);
  for (auto& s : tr.samples) ASSERT_TRUE(gaze_inside_fov(vive(), s.gaze_dir));
  // First row: Unity eulerAngles (19.8792, 0.6523, 8.2767): the head is pitched ~20 deg down.
  glm::dquat q0 = unity_euler_to_fovsim(19.8792, 0.6523, 8.2767);
  EXPECT_NEAR(std::fabs(glm::dot(tr.samples[0].head_rot, q0)), 1.0, 1e-9);
  glm::dvec3 f = tr.samples[0].head_rot * glm::dvec3(0, 0, -1);
  EXPECT_NEAR(rad2deg(std::asin(f.y)), -19.88, 0.5);
  // The eyes look up ~15 deg in the head (Unity y = 0.2678 of the gaze vector), so the gaze
  // in world is close to level, towards the opponent's head/chest (NameOfLookedObject).
  EXPECT_NEAR(tr.samples[0].gaze_dir.y, 0.2678, 1e-3);
  glm::dvec3 w = tr.samples[0].head_rot * tr.samples[0].gaze_dir;
  EXPECT_LT(std::fabs(rad2deg(std::asin(w.y))), 10.0);
}

TEST(Import, EulerSignsFlipAnAxis) {
  Json j = Json::parse(kMap);
  j["head_orientation"]["signs"] = Json::array({1, -1, 1});
  std::string map = write_tmp("signs.json", j.dump()), rec = write_tmp("rec.tsv", kRec);
  Trace tr = import_trace(rec, map, vive());
  expect_vec(tr.samples[0].head_rot * glm::dvec3(0, 0, -1), {-1, 0, 0});  // yaw 90 now turns left
  j["head_orientation"]["signs"] = Json::array({1, 2, 1});
  std::string bad = write_tmp("bad.json", j.dump());
  expect_error([&] { import_trace(rec, bad, vive()); },
               {"bad.json: head_orientation.signs", "1 or -1"});
}
