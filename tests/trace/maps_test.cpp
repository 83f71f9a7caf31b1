// The shipped column maps (traces/maps/*.json), each on a file generated in the vendor's
// documented layout: head turned 90 deg right, eyes 10 deg further right in the head.
#include <cmath>
#include <cstdio>

#include "sim/trace/importer.h"
#include "test_util.h"

using namespace fovsim;
using namespace fovsim::test;

namespace {

const double kS10 = std::sin(deg2rad(10.0)), kC10 = std::cos(deg2rad(10.0));
const double kR = std::sqrt(0.5);

std::string fmt(const char* f, double a = 0, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}

// Head looks down world +x (90 deg right) and the eyes 10 deg right of head forward.
void expect_right_right(const TraceSample& s) {
  glm::dvec3 f = s.head_rot * glm::dvec3(0, 0, -1);
  EXPECT_LT(rad2deg(angle_between(f, {1, 0, 0})), 1e-4) << f.x << " " << f.y << " " << f.z;
  EXPECT_LT(rad2deg(angle_between(s.gaze_dir, {kS10, 0, -kC10})), 1e-4)
      << s.gaze_dir.x << " " << s.gaze_dir.y << " " << s.gaze_dir.z;
}

Trace import_map(const std::string& map, const std::string& name, const std::string& text,
                 ImportReport* rep = nullptr) {
  return import_trace(write_tmp(name, text), src("traces/maps/" + map), vive(), rep);
}

}  // namespace

TEST(Maps, HtcViveProEyeSranipal) {
  std::string h =
      "timestamp,eye_valid_L,eye_valid_R,gaze_direction_L.x,gaze_direction_L.y,gaze_direction_L.z,"
      "gaze_direction_R.x,gaze_direction_R.y,gaze_direction_R.z,head_pos.x,head_pos.y,head_pos.z,"
      "head_rot.x,head_rot.y,head_rot.z,head_rot.w\n";
  // SRanipal x points to the user's left: looking right is x < 0. Row 2: right eye bit 1 clear.
  std::string row = fmt("%.9f,0,%.9f,0.3,1.7,-0.4,0,%.9f,0,%.9f\n", -kS10, kC10, kR, kR);
  std::string text = h + "1000,31,31," + fmt("%.9f,0,%.9f,", -kS10, kC10) + row + "1008,31,29," +
                     fmt("%.9f,0,%.9f,", -kS10, kC10) +
                     "0.9,0.9,0.9,0.3,1.7,-0.4,0,0.7071067812,0,0.7071067812\n" +
                     "1016,0,0,0,0,0,0,0,0,0.3,1.7,-0.4,0,0.7071067812,0,0.7071067812\n";
  ImportReport rep;
  Trace tr = import_map("htc_vive_pro_eye_sranipal.json", "sranipal.csv", text, &rep);
  ASSERT_EQ(tr.samples.size(), 3u);
  expect_right_right(tr.samples[0]);
  expect_right_right(tr.samples[1]);  // left eye alone
  EXPECT_FALSE(tr.samples[2].valid);
  EXPECT_EQ(rep.one_eye_rows, 1);
  EXPECT_NEAR(tr.samples[0].head_pos.z, 0.4, 1e-12);  // Unity z flips, x is not mirrored
  EXPECT_NEAR(tr.samples[0].head_pos.x, 0.3, 1e-12);
}

TEST(Maps, MetaQuestProOpenXr) {
  std::string h =
      "time_ns,head_px,head_py,head_pz,head_qx,head_qy,head_qz,head_qw,gaze_qx,gaze_qy,gaze_qz,"
      "gaze_qw,gaze_flags\n";
  // OpenXR: yaw -90 deg about +Y turns right; the gaze pose is yawed -100 deg in world.
  double a = deg2rad(-100.0) / 2;
  std::string row =
      fmt(",0,1.6,0,0,%.12f,0,%.12f,", -kR, kR) + fmt("0,%.12f,0,%.12f,", std::sin(a), std::cos(a));
  std::string text = h + "1700000000000000000" + row + "3\n" + "1700000000011111111" + row + "0\n";
  Trace tr = import_map("meta_quest_pro_openxr.json", "quest.csv", text);
  ASSERT_EQ(tr.samples.size(), 2u);
  expect_right_right(tr.samples[0]);
  EXPECT_FALSE(tr.samples[1].valid);  // orientation-valid bit clear
  EXPECT_NEAR(tr.samples[1].t, 0.011111111, 1e-12);
}

TEST(Maps, TobiiXr) {
  std::string h =
      "Timestamp,HeadPosition.x,HeadPosition.y,HeadPosition.z,HeadRotation.x,HeadRotation.y,"
      "HeadRotation.z,"
      "HeadRotation.w,GazeRay.Origin.x,GazeRay.Origin.y,GazeRay.Origin.z,GazeRay.Direction.x,"
      "GazeRay.Direction.y,"
      "GazeRay.Direction.z,GazeRay.IsValid,IsLeftEyeBlinking,IsRightEyeBlinking\n";
  // Unity: +Y rotation turns right; world gaze 100 deg right of +Z.
  double y = deg2rad(100.0);
  std::string row = fmt("0,1.6,0,0,%.12f,0,%.12f,0,1.6,0,", kR, kR) +
                    fmt("%.12f,0,%.12f,", std::sin(y), std::cos(y));
  std::string text =
      h + "12.5," + row + "True,False,False\n" + "12.5111," + row + "True,True,False\n";
  Trace tr = import_map("tobii_xr.json", "tobii.csv", text);
  ASSERT_EQ(tr.samples.size(), 2u);
  expect_right_right(tr.samples[0]);
  EXPECT_FALSE(tr.samples[1].valid);  // left eye blinking
}

TEST(Maps, PupilCoreGazePositions) {
  std::string h =
      "gaze_timestamp,world_index,confidence,norm_pos_x,norm_pos_y,base_data,gaze_point_3d_x,gaze_"
      "point_3d_y,"
      "gaze_point_3d_z,eye_center0_3d_x,eye_center0_3d_y,eye_center0_3d_z,gaze_normal0_x,gaze_"
      "normal0_y,"
      "gaze_normal0_z\n";
  double x = 500 * std::tan(deg2rad(10.0)), yd = 500 * std::tan(deg2rad(5.0));
  std::string text = h + "3301.25,12,0.97,0.6,0.5,3301.25-0 3301.26-1," + fmt("%.9f,0,500,", x) +
                     "20,15,-20,0.1,0,1\n" + "3301.254,12,0.95,0.5,0.6,3301.254-0," +
                     fmt("0,%.9f,500,", -yd) + "20,15,-20,0,-0.1,1\n" +
                     "3301.258,13,0.4,0.5,0.5,3301.258-1,0,0,500,20,15,-20,0,0,1\n";
  Trace tr = import_map("pupil_core.json", "gaze_positions.csv", text);
  ASSERT_EQ(tr.samples.size(), 3u);
  // No head pose: the scene camera is the head. OpenCV axes: +y is down.
  EXPECT_LT(rad2deg(angle_between(tr.samples[0].gaze_dir, {kS10, 0, -kC10})), 1e-6);
  EXPECT_NEAR(rad2deg(std::asin(tr.samples[1].gaze_dir.y)), 5.0, 1e-6);  // looking up
  EXPECT_TRUE(tr.samples[1].valid);
  EXPECT_FALSE(tr.samples[2].valid);  // confidence 0.4 < 0.6
  EXPECT_NEAR(tr.samples[2].t, 0.008, 1e-9);
}

TEST(Maps, Varjo) {
  std::string h =
      "capture_time_ns,gaze_status,gaze_forward_x,gaze_forward_y,gaze_forward_z,hmd_px,hmd_py,hmd_"
      "pz,hmd_qw,hmd_qx,hmd_qy,hmd_qz\n";
  std::string row = fmt("%.12f,0,%.12f,0,1.7,0,%.12f,0,%.12f,0\n", kS10, kC10, kR, -kR);
  std::string text = h + "5000000000,2," + row + "5005000000,0," + row;
  Trace tr = import_map("varjo.json", "varjo.csv", text);
  ASSERT_EQ(tr.samples.size(), 2u);
  expect_right_right(tr.samples[0]);
  EXPECT_FALSE(tr.samples[1].valid);
}

TEST(Maps, SmiUnity360) {
  std::string h =
      "timestamp_ms,cam_x,cam_y,cam_z,cam_rx,cam_ry,cam_rz,gaze_dir_x,gaze_dir_y,gaze_dir_z,gaze_"
      "valid,pupil_mm,"
      "blink\n";
  std::string g = fmt("%.12f,0,%.12f,", kS10, kC10);
  // 250 Hz, a 32-bit millisecond counter wrapping, the last two fields fused in some rows,
  // a stall flushing two samples 0 ms apart... and head pose updated per render frame.
  std::string text = h + "4294967288,0,1.6,0,0,90,0," + g + "1,3.5,False\n" +
                     "4294967292,0,1.6,0,0,90,0," + g + "1,3.5True\n" + "0,0,1.6,0,0,90,0," + g +
                     "1,3.4True\n" + "4,0,1.6,0,0,90,0," + g + "1,3.4,False\n" +
                     "8,0,1.6,0,0,90,0," + g + "0,3.4,True\n";
  ImportReport rep;
  Trace tr = import_map("smi_unity_360.json", "smi.csv", text, &rep);
  ASSERT_EQ(tr.samples.size(), 5u);
  EXPECT_EQ(rep.time_wraps, 1);
  EXPECT_NEAR(tr.samples[4].t, 0.016, 1e-12);
  expect_right_right(tr.samples[0]);
  expect_right_right(tr.samples[2]);
  EXPECT_FALSE(tr.samples[4].valid);
}

TEST(Maps, PupilNeonCloudGazeCsv) {
  std::string h =
      "section id,recording id,timestamp [ns],gaze x [px],gaze y [px],worn,fixation id,blink "
      "id,azimuth [deg],"
      "elevation [deg]\n";
  std::string text = h + "a1,r1,1700000000000000000,900.1,500.2,1.0,1,,10,0\n" +
                     "a1,r1,1700000000005000000,800.0,400.0,1.0,1,,0,5\n" +
                     "a1,r1,1700000000010000000,800.0,400.0,1.0,,3,0,0\n" +
                     "a1,r1,1700000000015000000,800.0,400.0,0.0,,,0,0\n";
  ImportReport rep;
  Trace tr = import_map("pupil_neon_cloud.json", "gaze.csv", text, &rep);
  ASSERT_EQ(tr.samples.size(), 4u);
  EXPECT_LT(rad2deg(angle_between(tr.samples[0].gaze_dir, {kS10, 0, -kC10})),
            1e-9);                                                       // 10 deg right
  EXPECT_NEAR(rad2deg(std::asin(tr.samples[1].gaze_dir.y)), 5.0, 1e-9);  // 5 deg up
  EXPECT_FALSE(tr.samples[2].valid);                                     // in a blink
  EXPECT_FALSE(tr.samples[3].valid);                                     // not worn
  EXPECT_NEAR(tr.samples[3].t, 0.015, 1e-12);
  EXPECT_EQ(rep.invalid_rows, 2);
}
