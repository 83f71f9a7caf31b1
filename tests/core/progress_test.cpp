#include "sim/core/progress.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace fovsim {
namespace {

// A sink whose clock the test sets; it records every write.
struct FakeSink {
  double t = 0;
  std::vector<std::string> writes;
  ProgressSink sink(bool terminal) {
    ProgressSink s;
    s.terminal = terminal;
    s.now = [this] { return t; };
    s.write = [this](const std::string& x) { writes.push_back(x); };
    return s;
  }
};

TEST(Progress, LogLinesAtMostOnceAMinuteAndNoneInTheFirstMinute) {
  FakeSink f;
  {
    Progress p("frames", 1000, f.sink(false));
    for (int i = 0; i < 100; ++i) {  // 100 steps in the first 59 s: nothing
      f.t = 0.59 * i;
      p.step();
    }
    EXPECT_TRUE(f.writes.empty());
    f.t = 61;
    p.step();
    ASSERT_EQ(f.writes.size(), 1u);
    EXPECT_EQ(f.writes[0].rfind("fovsim: progress: frames 101/1000", 0), 0u) << f.writes[0];
    EXPECT_NE(f.writes[0].find("ETA"), std::string::npos);
    EXPECT_EQ(f.writes[0].back(), '\n');
    for (int i = 0; i < 50; ++i) {  // another 59 s of steps: still one line
      f.t = 61 + 1.18 * i;
      p.step();
    }
    EXPECT_EQ(f.writes.size(), 1u);
    f.t = 121.5;
    p.phase("outputs");
    EXPECT_EQ(f.writes.size(), 2u);
    EXPECT_NE(f.writes[1].find("outputs"), std::string::npos);
  }
  EXPECT_EQ(f.writes.size(), 2u);  // done() writes nothing to a log
}

TEST(Progress, TerminalLineUpdatesInPlaceAndIsCleared) {
  FakeSink f;
  {
    Progress p("cells", 4, f.sink(true));
    f.t = 0;
    p.step();
    ASSERT_EQ(f.writes.size(), 1u);
    EXPECT_EQ(f.writes[0].rfind("\rcells 1/4 (25%)", 0), 0u) << f.writes[0];
    f.t = 0.1;
    p.step();  // within 0.2 s of the last update: not drawn
    EXPECT_EQ(f.writes.size(), 1u);
    f.t = 0.5;
    p.step();
    ASSERT_EQ(f.writes.size(), 2u);
    EXPECT_EQ(f.writes[1].rfind("\rcells 3/4 (75%)", 0), 0u);
  }
  ASSERT_EQ(f.writes.size(), 3u);
  EXPECT_EQ(f.writes[2].front(), '\r');
  EXPECT_EQ(f.writes[2].find_first_not_of("\r "), std::string::npos);  // blanked
}

TEST(Progress, NestedProgressReportsToTheOutermostLine) {
  FakeSink f;
  Progress cells("sweep cells", 2, f.sink(true));
  {
    Progress frames("frames", 10);  // made while `cells` is alive: nested in it
    EXPECT_TRUE(frames.nested());
    f.t = 1;
    frames.phase("reference");
    for (int i = 0; i < 5; ++i) frames.step();
    const std::string l = frames.line();
    EXPECT_EQ(l.rfind("sweep cells 0/2 · frames 5/10 (25%) · reference", 0), 0u) << l;
    EXPECT_NE(l.find("ETA"), std::string::npos);
  }
  cells.step();
  EXPECT_EQ(cells.line().rfind("sweep cells 1/2 (50%)", 0), 0u) << cells.line();
  Progress next("frames", 3);  // the first inner one is done: the next nests in its place
  EXPECT_TRUE(next.nested());
}

// A sweep runs a group of cells' frames at once (and a group too large for the memory budget in
// passes): the frames progress of a pass spans its cells, so the fraction and the ETA count
// cells, not one cell per group. Fails when the nested fraction is taken as one parent step.
TEST(Progress, NestedProgressSpansTheCellsItRunsAtOnce) {
  FakeSink f;
  Progress cells("sweep cells", 8, f.sink(true));
  {
    Progress pass1("frames x 4 cells, pass 1/2", 10);
    pass1.spans(0, 4);
    for (int i = 0; i < 5; ++i) pass1.step();
    const std::string l = pass1.line();
    EXPECT_NE(l.find("(25%)"), std::string::npos) << l;  // half of 4 of 8 cells
  }
  {
    Progress pass2("frames x 4 cells, pass 2/2", 10);
    pass2.spans(4, 4);
    for (int i = 0; i < 5; ++i) pass2.step();
    f.t = 30;
    const std::string l = pass2.line();
    EXPECT_NE(l.find("(75%)"), std::string::npos) << l;
    EXPECT_NE(l.find("ETA 10s"), std::string::npos) << l;  // 30 s for 75%: 10 s left
  }
  cells.step(8);
  EXPECT_EQ(cells.line().rfind("sweep cells 8/8 (100%)", 0), 0u) << cells.line();
}

}  // namespace
}  // namespace fovsim
