// Tracking loss as a simulated condition: the gaze a method sees under trace.on_invalid.
#include "sim/trace/tracking.h"

#include "test_util.h"

using namespace fovsim;
using namespace fovsim::test;

namespace {
Trace with_dropout() {
  Trace tr;
  for (int k = 0; k < 10; ++k) {
    TraceSample s;
    s.t = 0.01 * k;
    s.gaze_dir = glm::normalize(glm::dvec3(0.01 * k, 0, -1));
    s.valid = !(k >= 4 && k <= 6);
    tr.samples.push_back(s);
  }
  return tr;
}
}  // namespace

TEST(Tracking, ValidFramesAreUnchangedUnderEveryPolicy) {
  Trace tr = with_dropout();
  for (auto p : {OnInvalid::Hold, OnInvalid::Centre, OnInvalid::Full, OnInvalid::Widen}) {
    TrackingPolicy pol;
    pol.on_invalid = p;
    TrackedGaze g = tracked_gaze(tr, 2, pol);
    EXPECT_EQ(g.gaze_dir, tr.samples[2].gaze_dir);  // bit-identical
    EXPECT_TRUE(g.valid);
    EXPECT_STREQ(g.state, "valid");
    EXPECT_FALSE(g.render_full);
    EXPECT_EQ(g.ecc_scale, 1.0);
  }
}

TEST(Tracking, PoliciesOnALostFrame) {
  Trace tr = with_dropout();
  TrackingPolicy pol;
  TrackedGaze h = tracked_gaze(tr, 6, pol);  // hold (default)
  EXPECT_EQ(h.gaze_dir, tr.samples[3].gaze_dir);
  EXPECT_STREQ(h.state, "held");
  EXPECT_NEAR(h.since_valid_s, 0.03, 1e-12);
  pol.on_invalid = OnInvalid::Centre;
  TrackedGaze c = tracked_gaze(tr, 6, pol);
  EXPECT_EQ(c.gaze_dir, glm::dvec3(0, 0, -1));
  EXPECT_STREQ(c.state, "lost");
  pol.on_invalid = OnInvalid::Full;
  EXPECT_TRUE(tracked_gaze(tr, 5, pol).render_full);
  EXPECT_FALSE(tracked_gaze(tr, 7, pol).render_full);  // tracking returned
  pol.on_invalid = OnInvalid::Widen;
  pol.widen_per_s = 10;
  EXPECT_NEAR(tracked_gaze(tr, 4, pol).ecc_scale, 1 / 1.1, 1e-12);
  EXPECT_NEAR(tracked_gaze(tr, 6, pol).ecc_scale, 1 / 1.3, 1e-12);
  OnInvalid o;
  EXPECT_TRUE(parse_on_invalid("widen", o));
  EXPECT_EQ(o, OnInvalid::Widen);
  EXPECT_FALSE(parse_on_invalid("center", o));
  EXPECT_STREQ(on_invalid_name(OnInvalid::Centre), "centre");
}

TEST(Tracking, RunKeysAreValidatedWithTheirPath) {
  auto load = [](const Json& block) {
    Params root(Json{{"trace", block}}, "run.json");
    Params tp = root.child("trace");
    TrackingPolicy pol;
    Trace tr = load_trace(tp, vive(), src(""), 0.1, &pol);
    root.finish();
    return pol;
  };
  TrackingPolicy p =
      load(Json{{"file", "traces/sample_walk.csv"}, {"on_invalid", "widen"}, {"widen_per_s", 5}});
  EXPECT_EQ(p.on_invalid, OnInvalid::Widen);
  EXPECT_EQ(p.widen_per_s, 5);
  expect_error(
      [&] {
        load(Json{{"file", "traces/sample_walk.csv"}, {"on_invalid", "center"}});
      },
      {"run.json: trace.on_invalid", "centre"});
  expect_error(
      [&] {
        load(Json{{"file", "traces/sample_walk.csv"}, {"widen_per_s", 5}});
      },
      {"run.json: trace.widen_per_s", "only used with"});
}
