// Bad input, as a user meets it: each kind of hostile input gives one clear line and
// exit 2 (no signal, no "internal error", no attempt to allocate beyond a stated limit);
// nothing is written outside --out; a full disk leaves no truncated image; two sweeps on one
// --out are refused by a lock.
#include <gtest/gtest.h>

#include "sim/core/files.h"
#include "tests/app/app_util.h"

using namespace fovsim_test;
namespace fs = std::filesystem;

namespace {

const std::string kTrace = std::string(FOVSIM_SOURCE_DIR) + "/tests/golden/golden_trace.csv";

std::string small_config(const std::string& extra = "",
                         const std::string& outputs = R"({"print_summary": false})") {
  return R"({"name": "harden", "render": {"scale": 0.05}, "scene": {"type": "atrium", "complexity": 1},
  "trace": {"file": ")" +
         kTrace + R"("}, "frames": {"count": 2}, "methods": [{"method": "full"}],
  "outputs": )" +
         outputs + extra + "}";
}

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

// One line "fovsim: error: ...", exit 2, containing `expect`.
void expect_user_error(const CmdResult& r, const std::string& expect) {
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_EQ(r.output.rfind("fovsim: error: ", 0), 0u) << r.output;
  EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(expect), std::string::npos) << r.output;
}

bool png_complete(const std::string& p) {
  std::string s = read_text(p);
  return s.size() >= 12 && s.compare(s.size() - 8, 4, "IEND") == 0;
}

}  // namespace

TEST(Hardening, IssueTableInputsAreLocatedUserErrors) {
  std::string dir = temp_dir("harden_table");
  const std::string bin = fovsim_bin();
  write_text(dir + "/n1e400.json", "{\"name\": 1e400}");
  expect_user_error(run_cmd(bin + " run " + dir + "/n1e400.json"), dir + "/n1e400.json:1:");

  write_text(
      dir + "/idx.json",
      small_config(R"(, "sweep": {"grid": {"methods[99999999999999999999999].sigma": [1]}})"));
  expect_user_error(run_cmd(bin + " sweep expand " + dir + "/idx.json"),
                    "has no element [99999999999999999999999]");

  expect_user_error(run_cmd(bin + " run configs/quickstart.json .=1"), "override '.=1': empty key");

  write_text(dir + "/deep_sweep.json",
             "{\"sweep\": " + std::string(200000, '[') + std::string(200000, ']') + "}");
  expect_user_error(run_cmd(bin + " sweep expand " + dir + "/deep_sweep.json"),
                    "deep_sweep.json:1:");

  std::string deep = std::string(5000, '[') + std::string(5000, ']');
  write_text(dir + "/run_deep.json", small_config(", \"comment\": " + deep));
  expect_user_error(run_cmd(bin + " run " + dir + "/run_deep.json --out " + dir + "/o"),
                    "nested deeper than 64");
  EXPECT_FALSE(fs::exists(dir + "/o/manifest.json"));

  std::string t = "[";
  for (int i = 0; i < 1000; ++i) t += (i ? "," : "") + std::to_string(i);
  t += "]";
  write_text(dir + "/cells.json",
             small_config(R"(, "sweep": {"grid": {"seed": )" + t + R"(, "frames.start": )" + t +
                          R"(, "render.spp": )" + t + "}}"));
  expect_user_error(run_cmd(bin + " sweep " + dir + "/cells.json --out " + dir + "/s"),
                    "over the limit of 100000");

  write_text(dir + "/cfg.json", small_config());
  expect_user_error(
      run_cmd(bin + " run " + dir + "/cfg.json --out " + dir + "/z trace.file='\"/dev/zero\"'"),
      "/dev/zero: not a regular file");
  expect_user_error(run_cmd(bin + " trace validate /dev/zero"), "/dev/zero: not a regular file");
  // Buffers are sized from the config before anything is allocated.
  expect_user_error(
      run_cmd(bin + " run " + dir + "/cfg.json --out " + dir + "/z render.max_pixels=1000"),
      "render.scale: simulated resolution 72x80 (5760 pixels) is over the limit render.max_pixels "
      "= 1000");
  expect_user_error(
      run_cmd(bin + " run " + dir + "/cfg.json --out " + dir + "/z 'outputs.image_frames=[1e300]'"),
      "outputs.image_frames[0]: value 1e+300 is out of range [0, 2e+09]");

  write_text(dir + "/s.json", small_config(R"(, "sweep": {"grid": {"seed": [1, 2]}})"));
  expect_user_error(run_cmd("SLURM_ARRAY_TASK_ID=abc SLURM_ARRAY_TASK_COUNT=2 " + bin + " sweep " +
                            dir + "/s.json --out " + dir + "/s2"),
                    "SLURM_ARRAY_TASK_ID=\"abc\"");
}

TEST(Hardening, LongSpanTraceRunsOnlyTheFramesAsked) {
  std::string dir = temp_dir("harden_longspan");
  write_text(dir + "/longspan.csv",
             "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,valid\n0,0,0,0,1,0,0,0,0,0,-1,1\n"
             "0.011111,0,0,0,1,0,0,0,0,0,-1,1\n10000000,0,0,0,1,0,0,0,0,0,-1,1\n");
  write_text(dir + "/c.json", small_config());
  std::string run = fovsim_bin() + " run " + dir + "/c.json --out " + dir + "/o trace.file='\"" +
                    dir + "/longspan.csv\"'";
  auto r = run_cmd(run);
  EXPECT_EQ(r.code, 0) << r.output;
  expect_user_error(run_cmd(run + " frames.count=0"), "trace.max_samples");
}

TEST(Hardening, LabelsAndNamesNeverEscapeTheOutputFolder) {
  std::string dir = temp_dir("harden_escape");
  fs::create_directories(dir + "/work/a/b/c/d");
  std::string cfg =
      R"({"name": "../../x", "render": {"scale": 0.05}, "scene": {"type": "atrium", "complexity": 1},
  "trace": {"file": ")" +
      kTrace + R"("}, "frames": {"count": 1},
  "methods": [{"method": "full", "label": "../../../../escaped_label"}],
  "outputs": {"print_summary": false, "image_frames": [0]}})";
  write_text(dir + "/work/a/b/c/d/c.json", cfg);
  std::string wd = dir + "/work/a/b/c/d";
  auto r = run_cmd("cd " + wd + " && " + fovsim_bin() + " run c.json --out out");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::exists(wd + "/out/images/frame_0/_._.._.._.._escaped_label.png"));
  EXPECT_FALSE(fs::exists(dir + "/work/escaped_label.png"));
  // Without --out the name stays one folder under results/.
  r = run_cmd("cd " + wd + " && " + fovsim_bin() + " run c.json");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::exists(wd + "/results/_._.._x/summary.csv"));
  EXPECT_FALSE(fs::exists(dir + "/work/a/b/x"));
  // Two labels that become one file name are reported, as is the reference image's name.
  std::string two = cfg;
  two.replace(two.find(R"([{"method": "full", "label": "../../../../escaped_label"}])"),
              std::string(R"([{"method": "full", "label": "../../../../escaped_label"}])").size(),
              R"([{"method": "full", "label": "a/b"}, {"method": "full", "label": "a:b"}])");
  write_text(wd + "/two.json", two);
  expect_user_error(run_cmd("cd " + wd + " && " + fovsim_bin() + " run two.json --out o2"),
                    "methods[1].label: label \"a:b\" would be written as the file name \"a_b\", as "
                    "label \"a/b\" is");
  expect_user_error(run_cmd("cd " + wd + " && " + fovsim_bin() +
                            " run c.json --out o3 'methods[0].label=\"reference\"'"),
                    "as the reference image is");
}

TEST(Hardening, FullDiskLeavesNoTruncatedImages) {
  std::string dir = temp_dir("harden_fulldisk");
  write_text(dir + "/c.json",
             small_config("", R"({"print_summary": false, "image_frames": [0, 1]})"));
  // A 48 KiB file-size limit fails writes like a full disk (EFBIG); SIGXFSZ ignored.
  auto r = run_cmd("trap '' XFSZ; ulimit -f 48; " + fovsim_bin() + " run " + dir +
                   "/c.json --out " + dir + "/o render.scale=0.3");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
  int pngs = 0;
  for (auto& e : fs::recursive_directory_iterator(dir + "/o")) {
    std::string p = e.path().string();
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos)
        << "temporary file left: " << p;
    if (e.path().extension() == ".png") {
      ++pngs;
      EXPECT_TRUE(png_complete(p)) << "truncated image under its final name: " << p;
    }
  }
  EXPECT_FALSE(fs::exists(dir + "/o/frames.csv"));
  (void)pngs;
}

TEST(Hardening, SecondSweepOnTheSameOutIsRefused) {
  std::string dir = temp_dir("harden_lock");
  write_text(dir + "/s.json", small_config(R"(, "sweep": {"grid": {"seed": [1, 2]}})"));
  {
    fovsim::DirLock held(dir + "/out", ".lock", "test");
    expect_user_error(run_cmd(fovsim_bin() + " sweep " + dir + "/s.json --out " + dir + "/out"),
                      "another fovsim sweep is writing to this folder");
    // A shard has its own lock.
    auto shard =
        run_cmd(fovsim_bin() + " sweep " + dir + "/s.json --out " + dir + "/out --shard 0/2");
    EXPECT_EQ(shard.code, 0) << shard.output;
  }
  auto r = run_cmd(fovsim_bin() + " sweep " + dir + "/s.json --out " + dir + "/out");
  EXPECT_EQ(r.code, 0) << r.output;
}

// Small fixes to the CLI as a user meets them.
TEST(Hardening, MistypedCommandGetsASuggestion) {
  expect_user_error(run_cmd(fovsim_bin() + " rn configs/quickstart.json"),
                    "unknown command 'rn' (did you mean `run`?)");
  expect_user_error(run_cmd(fovsim_bin() + " trace valdate x.csv"),
                    "unknown command 'valdate' (did you mean `validate`?)");
}

TEST(Hardening, OverrideErrorsNameTheCommandLine) {
  auto r = run_cmd(fovsim_bin() + " run configs/quickstart.json rendr.scale=1 --out " +
                   temp_dir("harden_ov") + " --no-plots");
  expect_user_error(r, "override 'rendr.scale=1': rendr: unknown key \"rendr\"");
  EXPECT_EQ(r.output.find("quickstart.json"), std::string::npos) << r.output;
  expect_user_error(run_cmd(fovsim_bin() + " run configs/quickstart.json render..scale=1"),
                    "override 'render..scale=1': empty key");
}

TEST(Hardening, TraceValidateFlagsGaps) {
  std::string dir = temp_dir("harden_gap");
  write_text(dir + "/gap.csv",
             "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz\n0,0,0,0,1,0,0,0,0,0,-1\n"
             "0.011,0,0,0,1,0,0,0,0,0,-1\n2.5,0,0,0,1,0,0,0,0,0,-1\n2.511,0,0,0,1,0,0,0,0,0,-1\n");
  auto r = run_cmd(fovsim_bin() + " trace validate " + dir + "/gap.csv");
  EXPECT_EQ(r.code, 1) << r.output;  // usable, with problems
  EXPECT_NE(r.output.find("1 gap longer than max_gap 1 s"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("gap.csv:4:1"), std::string::npos) << r.output;
  auto ok = run_cmd(fovsim_bin() + " trace validate " + dir + "/gap.csv --max-gap 3");
  EXPECT_EQ(ok.code, 0) << ok.output;
  EXPECT_NE(ok.output.find(": valid"), std::string::npos) << ok.output;
}

// density --plot from outside the repository finds viz/ beside the binary (a copied or
// installed fovsim), not in the current directory.
TEST(Hardening, DensityPlotFindsVizBesideTheBinary) {
  if (run_cmd("/usr/bin/python3 -c 'import matplotlib'").code != 0)
    GTEST_SKIP() << "no matplotlib for /usr/bin/python3";
  std::string dir = temp_dir("harden_viz");
  fs::create_directories(dir + "/inst/bin");
  fs::create_directories(dir + "/inst/viz");
  fs::create_directories(dir + "/elsewhere");
  fs::copy_file(fovsim_bin(), dir + "/inst/bin/fovsim");
  fs::permissions(dir + "/inst/bin/fovsim", fs::perms::owner_exec, fs::perm_options::add);
  // A stand-in script that records where it was found.
  write_text(dir + "/inst/viz/plot_density.py",
             "import sys\nopen(sys.argv[2], 'w').write('stand-in from inst/viz')\n");
  auto r = run_cmd("cd " + dir + "/elsewhere && FOVSIM_NO_PLOTS=0 " + dir +
                   "/inst/bin/fovsim density -m kfr --samples 16 --directions 4 --out d --plot");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(read_text(dir + "/elsewhere/d.png"), "stand-in from inst/viz") << r.output;
}
