#include <cmath>

#include "sim/trace/trace.h"
#include "test_util.h"

using namespace fovsim;
using namespace fovsim::test;

static const char* kHead = "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,valid\n";

TEST(TraceCsv, ParsesDirectionAndScreenGaze) {
  Display d = vive();
  std::string p =
      write_tmp("a.csv", std::string("# comment line\n") + kHead +
                             "0.0,0,1.6,0,1,0,0,0,0,0,-1,1\n"
                             "0.1,0.5,1.6,0,0.7071067812,0,0.7071067812,0,0.1,0,-0.994987437,1\n"
                             "\n"
                             "0.2,0.5,1.6,0,1,0,0,0,,,,0\n");
  Trace tr = read_trace_csv(p, d);
  ASSERT_EQ(tr.samples.size(), 3u);
  EXPECT_DOUBLE_EQ(tr.samples[1].head_pos.x, 0.5);
  EXPECT_NEAR(tr.samples[1].head_rot.y, std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(glm::length(tr.samples[1].gaze_dir), 1.0, 1e-12);
  // valid=0 rows may omit gaze: the last valid gaze is held.
  EXPECT_FALSE(tr.samples[2].valid);
  EXPECT_NEAR(tr.samples[2].gaze_dir.x, tr.samples[1].gaze_dir.x, 1e-12);
  // 1 of 3 samples invalid is above the warned fraction (25 %).
  ASSERT_EQ(tr.warnings.size(), 1u);
  EXPECT_NE(tr.warnings[0].find("33.3 % of samples (1 of 3) are flagged invalid"),
            std::string::npos);

  std::string q = write_tmp("b.csv",
                            "t,px,py,pz,qw,qx,qy,qz,gaze_u,gaze_v\n0,0,0,0,1,0,0,0,0.5,0.5\n"
                            "0.01,0,0,0,1,0,0,0,1,0\n");
  Trace t2 = read_trace_csv(q, d);
  EXPECT_NEAR(t2.samples[0].gaze_dir.z, -1.0, 1e-12);
  glm::dvec3 corner = gaze_dir_from_screen(d, 1, 0);
  EXPECT_NEAR(glm::length(t2.samples[1].gaze_dir - corner), 0.0, 1e-12);
  EXPECT_GT(t2.samples[1].gaze_dir.x, 0);  // u=1 is right
  EXPECT_GT(t2.samples[1].gaze_dir.y, 0);  // v=0 is top
}

TEST(TraceCsv, WriteReadRoundTrip) {
  Display d = vive();
  Trace tr;
  for (int i = 0; i < 5; ++i) {
    TraceSample s;
    s.t = i / 90.0;
    s.head_pos = {0.1 * i, 1.6, -0.2 * i};
    s.head_rot = glm::angleAxis(0.1 * i, glm::normalize(glm::dvec3(0.2, 1, 0.1)));
    s.gaze_dir = glm::normalize(glm::dvec3(0.05 * i, -0.02, -1));
    s.valid = i != 3;
    tr.samples.push_back(s);
  }
  std::string p = tmpdir() + "/rt.csv";
  write_trace_csv(p, tr);
  Trace back = read_trace_csv(p, d);
  ASSERT_EQ(back.samples.size(), tr.samples.size());
  for (size_t i = 0; i < tr.samples.size(); ++i) {
    EXPECT_NEAR(back.samples[i].t, tr.samples[i].t, 1e-9);
    EXPECT_NEAR(glm::length(back.samples[i].head_pos - tr.samples[i].head_pos), 0, 1e-8);
    EXPECT_NEAR(std::fabs(glm::dot(back.samples[i].head_rot, tr.samples[i].head_rot)), 1, 1e-8);
    // An invalid sample shows the last valid gaze (traces/README.md), whatever it carries.
    const size_t g = tr.samples[i].valid ? i : i - 1;
    EXPECT_NEAR(glm::length(back.samples[i].gaze_dir - tr.samples[g].gaze_dir), 0, 1e-8);
    EXPECT_EQ(back.samples[i].valid, tr.samples[i].valid);
  }
}

// Each malformed input names file:line:column and what is wrong.
TEST(TraceCsv, MalformedFilesNameLineAndColumn) {
  Display d = vive();
  auto bad = [&](const std::string& name, const std::string& body,
                 std::initializer_list<std::string> needles) {
    std::string p = write_tmp(name, body);
    return expect_error([&] { read_trace_csv(p, d); }, needles);
  };
  // Unparsable number: line 3, column of "abc" (1-based char).
  bad("nan1.csv", std::string(kHead) + "0,0,0,0,1,0,0,0,0,0,-1,1\n0.1,0,0,0,1,abc,0,0,0,0,-1,1\n",
      {"nan1.csv:3:13", "column \"qx\"", "not a number: \"abc\""});
  bad("nan2.csv", std::string(kHead) + "0,0,0,0,1,0,0,0,0,0,-1,1\n0.1,nan,0,0,1,0,0,0,0,0,-1,1\n",
      {"nan2.csv:3:5", "column \"px\"", "non-finite"});
  bad("missing.csv", "t,px,py,pz,qw,qx,qy,gx,gy,gz\n0,0,0,0,1,0,0,0,0,-1\n",
      {"missing.csv:1", "missing column \"qz\""});
  bad("nogaze.csv", "t,px,py,pz,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n",
      {"nogaze.csv:1", "missing gaze columns"});
  bad("unknown.csv", "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,bogus\n",
      {"unknown.csv:1:33", "unknown column \"bogus\""});
  bad("fields.csv", std::string(kHead) + "0,0,0,0,1,0,0,0,0,0,-1\n",
      {"fields.csv:2:", "expected 12 fields", "got 11"});
  bad("mono.csv", std::string(kHead) + "0.2,0,0,0,1,0,0,0,0,0,-1,1\n0.1,0,0,0,1,0,0,0,0,0,-1,1\n",
      {"mono.csv:3:1", "time not strictly increasing", "line 2"});
  bad("quat.csv", std::string(kHead) + "0,0,0,0,1,0.1,0,0,0,0,-1,1\n",
      {"quat.csv:2:9", "norm 1.00499", "not unit"});
  bad("fov.csv", std::string(kHead) + "0,0,0,0,1,0,0,0,0.9,0,-0.43589,1\n",
      {"fov.csv:2:17", "gaze outside the display FOV", "htc_vive_pro_eye"});
  bad("behind.csv", std::string(kHead) + "0,0,0,0,1,0,0,0,0,0,1,1\n",
      {"behind.csv:2:17", "behind the eye"});
  bad("uv.csv", "t,px,py,pz,qw,qx,qy,qz,gaze_u,gaze_v\n0,0,0,0,1,0,0,0,1.2,0.5\n",
      {"uv.csv:2:17", "gaze outside the display FOV"});
  bad("flag.csv", std::string(kHead) + "0,0,0,0,1,0,0,0,0,0,-1,2\n",
      {"flag.csv:2:24", "expected 0 or 1"});
  bad("empty.csv", "", {"empty.csv", "empty trace file"});
  bad("quote.csv", std::string(kHead) + "0,\"0,0,0,1,0,0,0,0,0,-1,1\n",
      {"quote.csv:2:3", "unterminated"});
}

TEST(TraceCsv, SkipAndHoldPoliciesReportWhatTheyDid) {
  Display d = vive();
  std::string p =
      write_tmp("mixed.csv", std::string(kHead) +
                                 "0.0,0,0,0,1,0,0,0,0,0,-1,1\n"
                                 "0.1,0,0,0,1,0,0,0,0.9,0,-0.43589,1\n"  // gaze outside FOV
                                 "0.2,x,0,0,1,0,0,0,0,0,-1,1\n"          // bad number (pose)
                                 "0.0,0,0,0,1,0,0,0,0,0,-1,1\n"          // non-monotonic
                                 "0.3,1,0,0,1,0,0,0,0.1,0,-0.99498744,1\n");
  TraceReadOptions skip;
  skip.on_bad = BadSamplePolicy::Skip;
  Trace a = read_trace_csv(p, d, skip);
  ASSERT_EQ(a.samples.size(), 2u);
  EXPECT_DOUBLE_EQ(a.samples[1].t, 0.3);
  ASSERT_EQ(a.warnings.size(), 3u);
  EXPECT_NE(a.warnings[0].find("1 sample skipped (gaze outside the display FOV"), std::string::npos)
      << a.warnings[0];
  EXPECT_NE(a.warnings[0].find("mixed.csv:3:"), std::string::npos);

  TraceReadOptions hold;
  hold.on_bad = BadSamplePolicy::Hold;
  Trace b = read_trace_csv(p, d, hold);
  ASSERT_EQ(b.samples.size(), 4u);  // the non-monotonic row cannot be held: skipped
  EXPECT_NEAR(b.samples[1].gaze_dir.z, -1.0, 1e-12);  // held gaze
  EXPECT_DOUBLE_EQ(b.samples[2].head_pos.x, 0.0);     // held pose
  bool saw_held = false, saw_skip = false;
  for (auto& w : b.warnings) {
    saw_held |= w.find("held") != std::string::npos;
    saw_skip |= w.find("skipped (cannot hold)") != std::string::npos;
  }
  EXPECT_TRUE(saw_held);
  EXPECT_TRUE(saw_skip);
}

TEST(TraceCsv, CommittedSampleTraceIsValid) {
  Trace tr = read_trace_csv(src("traces/sample_walk.csv"), vive());
  EXPECT_GT(tr.duration(), 2.0);
  EXPECT_TRUE(tr.warnings.empty());
}
