// `trace import --guess`: a starting map from the header and first rows, assumptions marked.
#include "sim/trace/guess.h"

#include <cmath>

#include "sim/trace/importer.h"
#include "test_util.h"

using namespace fovsim;
using namespace fovsim::test;

static bool mentions(const Json& m, const std::string& s) {
  return m["comment"].dump().find(s) != std::string::npos;
}

TEST(Guess, UnityEulerTabSeparated) {
  std::string rec =
      write_tmp("pico.tsv",
                "Timeline\tHead Position. x\tHead Position. y\tHead Position. z\tHead Rotation. x\t"
                "Head Rotation. y\tHead Rotation. z\tCombine Eye Gaze Vector. x\tCombine Eye Gaze "
                "Vector. y\tCombine Eye Gaze Vector. z\tEye Left Blinking\n"
                "0.011\t0\t1.6\t0\t0\t90\t0\t0\t0\t1\tFalse\n"
                "0.022\t0\t1.6\t0\t0\t90\t0\t0\t0\t1\tTrue\n"
                "0.033\t0\t1.6\t0\t0\t90\t0\t0\t0\t1\tFalse\n");
  Json m = guess_map(rec);
  EXPECT_EQ(m["delimiter"], "tab");
  EXPECT_EQ(m["coordinates"], "unity");
  EXPECT_EQ(m["time"]["column"], "Timeline");
  EXPECT_EQ(m["time"]["unit"], "s");
  EXPECT_EQ(m["head_orientation"]["type"], "euler");
  EXPECT_EQ(m["gaze"]["columns"][0], "Combine Eye Gaze Vector. x");
  EXPECT_TRUE(
      mentions(m, "ASSUMPTION: head orientation is Euler angles in degrees applied Z, X, Y"));
  EXPECT_TRUE(mentions(m, "ASSUMPTION: \\\"Eye Left Blinking\\\" True/1 means blinking"));
  // The guessed map imports the file.
  std::string map = write_tmp("guess.json", m.dump(2));
  Trace tr = import_trace(rec, map, vive());
  ASSERT_EQ(tr.samples.size(), 3u);
  EXPECT_FALSE(tr.samples[1].valid);
  EXPECT_LT(rad2deg(angle_between(tr.samples[0].head_rot * glm::dvec3(0, 0, -1), {1, 0, 0})), 1e-9);
}

TEST(Guess, OpenXrQuaternionsNanosecondsConfidence) {
  std::string rec = write_tmp(
      "xr.csv",
      "time,head_px,head_py,head_pz,head_qx,head_qy,head_qz,head_qw,gaze_dir_x,gaze_dir_y,"
      "gaze_dir_z,confidence\n"
      "1700000000000000000,0,1.6,0,0,0,0,1,0.1,0,-1,0.9\n"
      "1700000000011111111,0,1.6,0,0,0,0,1,0.1,0,-1,0.3\n"
      "1700000000022222222,0,1.6,0,0,0,0,1,0.1,0,-1,0.9\n");
  Json m = guess_map(rec);
  EXPECT_EQ(m["delimiter"], "comma");
  EXPECT_EQ(m["time"]["unit"], "ns");  // from the median step, 1.1e7
  EXPECT_EQ(m["coordinates"], "opengl");
  EXPECT_EQ(m["head_orientation"]["order"], "xyzw");
  EXPECT_EQ(m["head_position"]["columns"][1], "head_py");
  EXPECT_EQ(m["valid"][0]["min"], 0.6);
  EXPECT_TRUE(mentions(m, "ASSUMPTION: coordinates are OpenGL"));
  std::string map = write_tmp("guess.json", m.dump(2));
  Trace tr = import_trace(rec, map, vive());
  ASSERT_EQ(tr.samples.size(), 3u);
  EXPECT_NEAR(tr.samples[1].t, 0.011111111, 1e-12);
  EXPECT_FALSE(tr.samples[1].valid);
  EXPECT_GT(tr.samples[0].gaze_dir.x, 0.09);
}

TEST(Guess, NoHeaderAndUnreadable) {
  std::string rec = write_tmp("n.csv", "0;1;2\n1;1;2\n");
  Json m = guess_map(rec);
  EXPECT_EQ(m["delimiter"], "semicolon");
  EXPECT_EQ(m["header"], false);
  EXPECT_TRUE(mentions(m, "ASSUMPTION: no header row"));
  std::string one = write_tmp("one.csv", "t,x\n");
  expect_error([&] { guess_map(one); }, {"one.csv", "too few rows"});
}
