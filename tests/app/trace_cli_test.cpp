// The trace subcommands as a user runs them: synth -> validate -> stats, and clear errors.
#include <gtest/gtest.h>

#include "tests/app/app_util.h"

using namespace fovsim_test;

TEST(TraceCli, SynthValidateStatsRoundTrip) {
  std::string dir = temp_dir("trace_cli");
  auto s =
      run_cmd(fovsim_bin() + " trace synth --scenario free-viewing --seed 7 --duration 1.5 -o " +
              dir + "/a.csv");
  ASSERT_EQ(s.code, 0) << s.output;
  auto s2 =
      run_cmd(fovsim_bin() + " trace synth --scenario free-viewing --seed 7 --duration 1.5 -o " +
              dir + "/b.csv");
  ASSERT_EQ(s2.code, 0) << s2.output;
  EXPECT_EQ(read_text(dir + "/a.csv"), read_text(dir + "/b.csv"));  // seeded, reproducible
  Csv c = read_csv(dir + "/a.csv");
  EXPECT_NEAR(double(c.rows.size()), 1.5 * 90 + 1, 2.0);  // 90 Hz default (Vive Pro Eye)
  auto v = run_cmd(fovsim_bin() + " trace validate " + dir + "/a.csv");
  EXPECT_EQ(v.code, 0) << v.output;
  auto st = run_cmd(fovsim_bin() + " trace stats " + dir + "/a.csv");
  EXPECT_EQ(st.code, 0) << st.output;
  EXPECT_NE(st.output.find("Hz"), std::string::npos) << st.output;
}

TEST(TraceCli, MalformedTraceNamesLineAndColumn) {
  std::string dir = temp_dir("trace_bad");
  write_text(dir + "/bad.csv",
             "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz\n"
             "0,0,0,0,1,0,0,0,0,0,-1\n"
             "0.011,0,0,0,1,0,0,0,0,nan,-1\n");
  auto v = run_cmd(fovsim_bin() + " trace validate " + dir + "/bad.csv");
  EXPECT_EQ(v.code, 2) << v.output;
  EXPECT_NE(v.output.find("bad.csv:3:"), std::string::npos) << v.output;
  auto m = run_cmd(fovsim_bin() + " trace import " + dir + "/bad.csv --map " + dir +
                   "/missing_map.json -o " + dir + "/o.csv");
  EXPECT_EQ(m.code, 2) << m.output;
  EXPECT_NE(m.output.find("missing_map.json"), std::string::npos) << m.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/o.csv"));
}

// `trace import` never writes a file that `trace validate` rejects; --guess prints a map.
TEST(TraceCli, ImportChecksTheFovAndGuessesAMap) {
  std::string dir = temp_dir("trace_import_fov");
  write_text(dir + "/map.json", R"({"delimiter": "comma", "header": true, "coordinates": "opengl",
    "time": {"column": "time", "unit": "ms"}, "head_position": {"constant": [0, 1.6, 0]},
    "head_orientation": {"constant": [1, 0, 0, 0]},
    "gaze": {"type": "direction", "space": "head", "columns": ["gaze_dir_x", "gaze_dir_y", "gaze_dir_z"]}})");
  write_text(
      dir + "/rec.csv",
      "time,gaze_dir_x,gaze_dir_y,gaze_dir_z\n0,0,0,-1\n10,0.9,0,-0.43589\n20,0,0,-1\n30,0,0,-1\n");
  auto f = run_cmd(fovsim_bin() + " trace import " + dir + "/rec.csv --map " + dir +
                   "/map.json -o " + dir + "/o.csv");
  EXPECT_EQ(f.code, 2) << f.output;
  EXPECT_NE(f.output.find("rec.csv:3:4: gaze outside the display FOV"), std::string::npos)
      << f.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/o.csv"));
  auto s = run_cmd(fovsim_bin() + " trace import " + dir + "/rec.csv --map " + dir +
                   "/map.json --on-bad skip -o " + dir + "/o.csv");
  EXPECT_EQ(s.code, 0) << s.output;
  EXPECT_NE(s.output.find("(mean)"), std::string::npos) << s.output;
  auto v = run_cmd(fovsim_bin() + " trace validate " + dir + "/o.csv");
  EXPECT_EQ(v.code, 0) << v.output;
  auto g = run_cmd(fovsim_bin() + " trace import " + dir + "/rec.csv --guess");
  EXPECT_EQ(g.code, 0) << g.output;
  EXPECT_NE(g.output.find("ASSUMPTION: time is column \\\"time\\\" in ms"), std::string::npos)
      << g.output;
  auto n = run_cmd(fovsim_bin() + " trace import " + dir + "/rec.csv -o " + dir + "/x.csv");
  EXPECT_EQ(n.code, 2) << n.output;
  EXPECT_NE(n.output.find("--map"), std::string::npos) << n.output;
}

// Real recordings v3: a run asking for more trace than its frames need runs on the shipped
// sample (it is 4 s long); an all-invalid trace is refused by validate, import and run.
TEST(TraceCli, LongDurationRunsAndAllInvalidIsRefused) {
  std::string dir = temp_dir("trace_v3");
  auto r = run_cmd(fovsim_bin() +
                   " run configs/quickstart.json trace.duration=1 frames.count=2 render.scale=0.04 "
                   "'methods=[{\"method\": \"full\"}]' outputs.image_frames=[] --out " +
                   dir + "/run -q --no-plots");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output.find("covers"), std::string::npos) << r.output;
  write_text(dir + "/inv.csv",
             "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,valid\n0,0,0,0,1,0,0,0,0,0,-1,0\n"
             "0.011,0,0,0,1,0,0,0,0,0,-1,0\n0.022,0,0,0,1,0,0,0,0,0,-1,0\n");
  auto v = run_cmd(fovsim_bin() + " trace validate " + dir + "/inv.csv");
  EXPECT_EQ(v.code, 2) << v.output;
  EXPECT_NE(v.output.find("inv.csv: all 3 samples are flagged invalid"), std::string::npos)
      << v.output;
  auto x = run_cmd(fovsim_bin() + " run configs/quickstart.json trace.file=" + dir +
                   "/inv.csv frames.count=2 render.scale=0.04 'methods=[{\"method\": \"full\"}]' "
                   "--out " +
                   dir + "/run2 -q --no-plots");
  EXPECT_EQ(x.code, 2) << x.output;
  EXPECT_NE(x.output.find("all 3 samples are flagged invalid"), std::string::npos) << x.output;
}

// --guess prints the map on stdout and how it was chosen on stderr; the map imports the file;
// a failed import's hint names the map key judged wrong from the data.
TEST(TraceCli, GuessReportsOnStderrAndImportHints) {
  std::string dir = temp_dir("trace_guess_search");
  const std::string rec = "tests/data/trace_layouts/heldout/varjo_base_gaze_log.csv";
  auto g = run_cmd("(" + fovsim_bin() + " trace import " + rec + " --guess 2> " + dir +
                   "/err.txt > " + dir + "/map.json)");
  ASSERT_EQ(g.code, 0) << g.output;
  const std::string err = read_text(dir + "/err.txt");
  EXPECT_NE(err.find("guess: tested"), std::string::npos) << err;
  EXPECT_NE(err.find("runner-up (score"), std::string::npos) << err;
  auto i = run_cmd(fovsim_bin() + " trace import " + rec + " --map " + dir + "/map.json -o " + dir +
                   "/o.csv");
  EXPECT_EQ(i.code, 0) << i.output;
  write_text(dir + "/gl.json", R"({"delimiter": "comma", "header": true, "coordinates": "opengl",
    "time": {"column": "raw_timestamp", "unit": "ns"}, "head_position": {"constant": [0, 1.6, 0]},
    "head_orientation": {"constant": [1, 0, 0, 0]},
    "gaze": {"type": "direction", "space": "head",
             "columns": ["gaze_forward_x", "gaze_forward_y", "gaze_forward_z"]},
    "valid": [{"column": "status", "valid_values": ["2"]}]})");
  auto h = run_cmd(fovsim_bin() + " trace import " + rec + " --map " + dir + "/gl.json -o " + dir +
                   "/h.csv");
  EXPECT_EQ(h.code, 2) << h.output;
  EXPECT_NE(h.output.find("gaze points behind the eye"), std::string::npos) << h.output;
  EXPECT_NE(h.output.find("(hint: gaze z > 0 on 100 % of rows: try `coordinates: unity"),
            std::string::npos)
      << h.output;
}
