// Reliability of inputs and outputs as a user meets them: outputs never replace what is not
// a regular file, in-range values never end in a signal, work and memory are bounded before
// they are spent, non-regular inputs never block, bad scenes and flags are one clear line.
// Every check asserts the one-line message and exit 2 (as tests/app/hardening_cli_test.cpp).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include "tests/app/app_util.h"

using namespace fovsim_test;
namespace fs = std::filesystem;

namespace {

const std::string kTrace = std::string(FOVSIM_SOURCE_DIR) + "/tests/golden/golden_trace.csv";

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

void expect_user_error(const CmdResult& r, const std::string& expect) {
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_EQ(r.output.rfind("fovsim: error: ", 0), 0u) << r.output;
  EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(expect), std::string::npos) << r.output;
}

std::string small_config(const std::string& scene = R"({"type": "atrium", "complexity": 1})",
                         const std::string& extra = "") {
  return R"({"name": "rel", "render": {"scale": 0.05}, "scene": )" + scene +
         R"(, "trace": {"file": ")" + kTrace +
         R"("}, "frames": {"count": 1}, "methods": [{"method": "full"}],
  "outputs": {"print_summary": false})" +
         extra + "}";
}

// The three kinds of non-regular targets every writer must leave alone.
struct Targets {
  std::string fifo, link, dir, link_target;
};
Targets make_targets(const std::string& d, const std::string& stem) {
  Targets t{d + "/" + stem + "_fifo", d + "/" + stem + "_link", d + "/" + stem + "_dir",
            d + "/" + stem + "_real"};
  EXPECT_EQ(::mkfifo(t.fifo.c_str(), 0644), 0);
  write_text(t.link_target, "keep\n");
  fs::create_symlink(t.link_target, t.link);
  fs::create_directories(t.dir);
  return t;
}
void expect_untouched(const Targets& t) {
  struct stat st {};
  ASSERT_EQ(::lstat(t.fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  ASSERT_EQ(::lstat(t.link.c_str(), &st), 0);
  EXPECT_TRUE(S_ISLNK(st.st_mode));
  EXPECT_EQ(read_text(t.link_target), "keep\n");
  EXPECT_TRUE(fs::is_directory(t.dir));
}

}  // namespace

TEST(Reliability, WritersNeverReplaceNonRegularFiles) {
  const std::string d = temp_dir("rel_writers"), bin = fovsim_bin();
  // trace synth -o
  {
    Targets t = make_targets(d, "synth");
    expect_user_error(run_cmd(bin + " trace synth --scenario fixate --duration 1 -o " + t.fifo),
                      "output exists and is a FIFO");
    expect_user_error(run_cmd(bin + " trace synth --scenario fixate --duration 1 -o " + t.link),
                      "output exists and is a symbolic link");
    expect_user_error(run_cmd(bin + " trace synth --scenario fixate --duration 1 -o " + t.dir),
                      "output exists and is a directory");
    expect_untouched(t);
  }
  // trace import -o
  {
    Targets t = make_targets(d, "import");
    const std::string imp = bin + " trace import " + kTrace + " --map traces/maps/varjo.json -o ";
    expect_user_error(run_cmd(imp + t.fifo), "output exists and is a FIFO");
    expect_user_error(run_cmd(imp + t.link), "output exists and is a symbolic link");
    expect_user_error(run_cmd(imp + t.dir), "output exists and is a directory");
    expect_untouched(t);
  }
  // density --out PREFIX (PREFIX.csv, PREFIX.json)
  {
    Targets t = make_targets(d, "dens");
    fs::rename(t.fifo, t.fifo + ".csv");
    EXPECT_EQ(::mkfifo(t.fifo.c_str(), 0644), 0);
    expect_user_error(run_cmd(bin + " density -m kfr --out " + t.fifo),
                      "output exists and is a FIFO");
    struct stat st {};
    ASSERT_EQ(::lstat((t.fifo + ".csv").c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode));
    EXPECT_FALSE(fs::exists(t.fifo + ".json"));
  }
  // run --out: its files (manifest.json, frames.csv, ...) under the folder
  {
    write_text(d + "/cfg.json", small_config());
    fs::create_directories(d + "/run");
    EXPECT_EQ(::mkfifo((d + "/run/manifest.json").c_str(), 0644), 0);
    expect_user_error(run_cmd(bin + " run " + d + "/cfg.json --out " + d + "/run"),
                      "manifest.json: output exists and is a FIFO");
    struct stat st {};
    ASSERT_EQ(::lstat((d + "/run/manifest.json").c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode));
  }
  // A device node, when the test may make one (root): /dev/null-like, in the temp folder.
  if (::geteuid() == 0) {
    const std::string dev = d + "/null_dev";
    if (::mknod(dev.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0) {
      expect_user_error(run_cmd(bin + " trace synth --scenario fixate --duration 1 -o " + dev),
                        "output exists and is a device");
      struct stat st {};
      ASSERT_EQ(::lstat(dev.c_str(), &st), 0);
      EXPECT_TRUE(S_ISCHR(st.st_mode));
    }
  }
}

TEST(Reliability, HugeInRangeValuesAreErrorsNotSignals) {
  const std::string d = temp_dir("rel_huge"), bin = fovsim_bin();
  const std::string png = std::string(FOVSIM_SOURCE_DIR) + "/tests/data/metrics/gray_a.png";
  if (fs::exists(png)) {
    expect_user_error(run_cmd(bin + " compare " + png + " " + png + " --ppd 1e12"),
                      "--ppd: value 1e+12 is out of range [0.01, 1e+06] px/deg");
    expect_user_error(run_cmd(bin + " compare " + png + " " + png + " --ppd 1e5"),
                      "is over the FLIP limit of");
  }
  // A head position of 1e20 m: refused by `trace validate` and by `run` alike.
  write_text(d + "/far.csv",
             "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,valid\n0,1e20,0,0,1,0,0,0,0,0,-1,1\n"
             "0.011111,1e20,0,0,1,0,0,0,0,0,-1,1\n");
  expect_user_error(run_cmd(bin + " trace validate " + d + "/far.csv"),
                    "far.csv:2:3: column \"px\": head position 1e20 m is beyond the coordinate "
                    "bound +-1e5 m");
  write_text(d + "/cfg.json", small_config());
  expect_user_error(run_cmd(bin + " run " + d + "/cfg.json --out " + d + "/o trace.file='\"" + d +
                            "/far.csv\"' trace_placement='\"absolute\"'"),
                    "beyond the coordinate bound +-1e5 m");
  write_text(d + "/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  write_text(d + "/eye.json", small_config(R"({"type": "file", "path": ")" + d +
                                           R"(/tri.obj", "default_eye": [1e20, 0, 0]})"));
  expect_user_error(run_cmd(bin + " run " + d + "/eye.json --out " + d + "/o"),
                    "scene.default_eye: eye point coordinate 1e+20 is beyond the coordinate "
                    "bound +-1e5 m");
}

TEST(Reliability, WorkIsBoundedBeforeItIsSpent) {
  const std::string d = temp_dir("rel_bounds"), bin = fovsim_bin();
  expect_user_error(
      run_cmd(bin + " trace synth --scenario fixate --duration 36000 -o " + d + "/t.csv"),
      "over the limit --max-samples");
  expect_user_error(
      run_cmd(bin + " trace synth --scenario fixate --duration 1e9 -o " + d + "/t.csv"),
      "--duration: value 1e+09 is out of range (0, 36000]");
  EXPECT_FALSE(fs::exists(d + "/t.csv"));
  write_text(
      d + "/syn.json",
      R"({"name": "rel", "render": {"scale": 0.05}, "scene": {"type": "atrium", "complexity": 1},
  "trace": {"synthetic": {"scenario": "fixate", "duration": 36000}, "rate_hz": 10000},
  "frames": {"count": 1}, "methods": [{"method": "full"}], "outputs": {"print_summary": false}})");
  expect_user_error(run_cmd(bin + " run " + d + "/syn.json --out " + d + "/o"),
                    "over the limit trace.max_samples");
  write_text(d + "/hold.json", small_config(R"({"type": "atrium", "complexity": 1})"));
  expect_user_error(run_cmd(bin + " run " + d + "/hold.json --out " + d +
                            "/o trace.on_short='\"hold\"' trace.duration=1e9"),
                    "trace.duration: holding the last sample");
  write_text(d + "/cornell.json", small_config(R"({"type": "cornell", "cell": 0.001})"));
  expect_user_error(run_cmd(bin + " run " + d + "/cornell.json --out " + d + "/o"),
                    "scene.cell: cell 0.001 m tessellates the scene into about");
  expect_user_error(run_cmd(bin + " density --directions 360 --samples 100000 --out " + d + "/dd"),
                    "rows, over the limit");
}

TEST(Reliability, NonRegularInputsNeverBlock) {
  const std::string d = temp_dir("rel_fifo_in"), bin = fovsim_bin();
  ASSERT_EQ(::mkfifo((d + "/in.png").c_str(), 0644), 0);
  expect_user_error(run_cmd(bin + " compare " + d + "/in.png " + d + "/in.png"),
                    "not a regular file");
  expect_user_error(run_cmd(bin + " compare /dev/zero /dev/zero"), "not a regular file");
  ASSERT_EQ(::mkfifo((d + "/scene.obj").c_str(), 0644), 0);
  write_text(d + "/cfg.json",
             small_config(R"({"type": "file", "path": ")" + d + R"(/scene.obj"})"));
  expect_user_error(run_cmd(bin + " run " + d + "/cfg.json --out " + d + "/o"),
                    "not a regular file");
}

TEST(Reliability, BadScenesAreRefused) {
  const std::string d = temp_dir("rel_scene"), bin = fovsim_bin();
  auto scene_run = [&](const std::string& file, const std::string& extra = "") {
    write_text(d + "/cfg.json",
               small_config(R"({"type": "file", "path": ")" + d + "/" + file + "\"" + extra + "}"));
    return run_cmd(bin + " run " + d + "/cfg.json --out " + d + "/o");
  };
  write_text(d + "/nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  expect_user_error(scene_run("nan.obj"), "non-finite coordinate");
  write_text(d + "/big.obj", "v 0 0 0\nv 3e38 0 0\nv 0 1 0\nf 1 2 3\n");
  expect_user_error(scene_run("big.obj"), "beyond the coordinate bound +-1e5 m");
  write_text(d + "/flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  expect_user_error(scene_run("flat.obj"), "all 1 triangles have zero area");
  write_text(d + "/ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  expect_user_error(scene_run("ok.obj", R"(, "translate": [1e300, 0, 0])"),
                    "scene.translate: translation 1e+300 m is beyond the coordinate bound +-1e5 m");
  // glTF buffer URIs stay inside the model's folder.
  write_text(
      d + "/esc.gltf",
      R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "../../../../../../etc/passwd", "byteLength": 36}]})");
  expect_user_error(scene_run("esc.gltf"), "\"..\" is refused");
  write_text(
      d + "/abs.gltf",
      R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "/etc/passwd", "byteLength": 36}]})");
  expect_user_error(scene_run("abs.gltf"), "absolute paths are refused");
  // A missing texture names the file (or is a warning when asked).
  write_text(d + "/tex.obj",
             "mtllib tex.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
             "usemtl m\nf 1/1 2/2 3/3\n");
  write_text(d + "/tex.mtl", "newmtl m\nKd 1 1 1\nmap_Kd missing.png\n");
  expect_user_error(scene_run("tex.obj"), "missing.png\": texture not found");
  auto r = scene_run("tex.obj", R"(, "on_missing_texture": "base_color")");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("warning:"), std::string::npos) << r.output;
  // A texture whose header claims more pixels than the limit is refused before decoding.
  write_text(d + "/tex.mtl", "newmtl m\nKd 1 1 1\nmap_Kd small.png\n");
  const std::string png = std::string(FOVSIM_SOURCE_DIR) + "/tests/data/metrics/gray_a.png";
  if (fs::exists(png)) {
    fs::copy_file(png, d + "/small.png");
    expect_user_error(scene_run("tex.obj", R"(, "max_texture_pixels": 4)"),
                      "over scene.max_texture_pixels = 4");
  }
}

TEST(Reliability, NaNAndZeroOnFlagsAreErrors) {
  const std::string bin = fovsim_bin(), d = temp_dir("rel_flags");
  expect_user_error(run_cmd(bin + " budget --gpu gtx1080 --workload atrium --hz nan"),
                    "--hz: value nan is out of range [1, 10000]");
  expect_user_error(run_cmd(bin + " budget --gpu gtx1080 --workload atrium --budget-ms 0"),
                    "--budget-ms: value 0 is out of range (0, 1e+06]");
  expect_user_error(run_cmd(bin + " budget --gpu gtx1080 --workload atrium --budget-ms nan"),
                    "--budget-ms: value nan is out of range");
  expect_user_error(run_cmd(bin + " run configs/quickstart.json --watchdog nan"),
                    "--watchdog: value nan is out of range [1, 86400] s (0: off)");
  expect_user_error(run_cmd(bin + " trace synth --scenario fixate --rate nan -o " + d + "/t.csv"),
                    "--rate: value nan is out of range (0, 10000]");
  expect_user_error(run_cmd(bin + " trace validate " + kTrace + " --max-gap nan"),
                    "--max-gap: value nan is out of range");
  expect_user_error(run_cmd(bin + " density --gaze-u nan --out " + d + "/x"),
                    "--gaze-u: value nan is out of range [0, 1]");
  expect_user_error(run_cmd(bin + " density --gaze-u 1e308 --out " + d + "/x"),
                    "--gaze-u: value 1e+308 is out of range [0, 1]");
  expect_user_error(run_cmd(bin + " density --target 0 --out " + d + "/x"),
                    "--target: value 0 is out of range (0, 1]");
  expect_user_error(run_cmd(bin + " density -m kfr --param rmfr.fx=0.3 --out " + d + "/x"),
                    "method \"rmfr\" is not selected with --method");
  write_text(d + "/g.json", small_config(R"({"type": "atrium", "complexity": 1})",
                                         R"(, "gpus": ["gtx1080", "gtx1080"])"));
  expect_user_error(run_cmd(bin + " run " + d + "/g.json --out " + d + "/o"),
                    "gpus[1]: \"gtx1080\" is also gpus[0]");
  write_text(d + "/dup.json", "{\"name\": \"a\",\n \"render\": {\"scale\": 1, \"scale\": 2}}");
  expect_user_error(run_cmd(bin + " run " + d + "/dup.json"),
                    "dup.json:2:25: duplicate key \"render.scale\"");
  expect_user_error(run_cmd(bin + " frobnicate"), "unknown command 'frobnicate' (commands: ");
}

// ---- bounds that name their key, plan columns checked like --target, messages that help ----

TEST(Reliability, VplAndDensityWorkHaveNamedLimits) {
  const std::string d = temp_dir("rel_vpl"), bin = fovsim_bin();
  write_text(d + "/vpl.json", small_config(R"({"type": "atrium", "complexity": 1, "indirect": true,
                              "vpl": {"rsm_size": 1024}})"));
  expect_user_error(run_cmd(bin + " run " + d + "/vpl.json --out " + d + "/o"),
                    "scene.vpl.rsm_size: rsm_size 1024 gives up to 3 light(s) x 1024^2 = "
                    "3.14573e+06 VPLs per frame, over scene.vpl.max_vpls = 262144");
  // The limit is overridable and names the key also when rsm_size is the default.
  expect_user_error(run_cmd(bin + " run " + d + "/vpl.json --out " + d +
                            "/o scene.vpl.rsm_size=64 scene.vpl.max_vpls=100"),
                    "over scene.vpl.max_vpls = 100");
  expect_user_error(run_cmd(bin + " density -m kfr --samples 100 --max-rows 10 --out " + d + "/x"),
                    "= 800 rows, over the limit of 10 (--max-rows)");
  EXPECT_FALSE(fs::exists(d + "/x.csv"));
}

TEST(Reliability, PlanColumnsAreCheckedLikeTarget) {
  const std::string d = temp_dir("rel_cols"), bin = fovsim_bin();
  const std::string base = small_config(R"({"type": "atrium", "complexity": 1})");
  auto with_sweep = [&](const std::string& sweep) {
    std::string cfg = base;
    cfg.insert(cfg.rfind('}'), ", \"sweep\": " + sweep);
    return cfg;
  };
  write_text(d + "/obj.json", with_sweep(R"({"grid": {"render.scale": [0.05]},
                            "objectives": [{"minimize": "est_ms_total"}, {"maximize": "fpsnr_x"}]})"));
  expect_user_error(run_cmd(bin + " sweep " + d + "/obj.json --out " + d + "/so --no-plots"),
                    "sweep.objectives[1]: no numeric column \"fpsnr_x\" can be in a cell's "
                    "summary (did you mean \"fpsnr\"?); checked before any cell runs (columns: ");
  EXPECT_FALSE(fs::exists(d + "/so"));  // refused before any cell ran
  // pareto.group_by too; a column some run writes but this one does not (gaze_error_deg needs a
  // latency block) is still refused by the first cell's summary, before any cell is recorded
  // complete.
  write_text(d + "/grp.json", with_sweep(R"({"grid": {"render.scale": [0.05]},
      "objectives": [{"minimize": "est_ms_total"}], "pareto": {"group_by": ["scene"]}})"));
  expect_user_error(run_cmd(bin + " sweep " + d + "/grp.json --out " + d + "/sg --no-plots"),
                    "sweep.pareto.group_by: no column \"scene\" can be in a cell's summary");
  EXPECT_FALSE(fs::exists(d + "/sg"));
  write_text(d + "/vdp.json", with_sweep(R"({"grid": {"render.scale": [0.05]},
      "objectives": [{"minimize": "gaze_error_deg"}]})"));
  expect_user_error(
      run_cmd(bin + " sweep " + d + "/vdp.json --out " + d + "/sv --no-plots"),
      "sweep.objectives[0]: no numeric column \"gaze_error_deg\" in the cells' summary");
  EXPECT_FALSE(fs::exists(d + "/sv/pareto.csv"));
  write_text(d + "/iso.json", with_sweep(R"({"grid": {"render.scale": [0.05]},
                            "iso_budget": {"column": "shaded", "budgets": [0.5]}})"));
  expect_user_error(run_cmd(bin + " sweep " + d + "/iso.json --out " + d + "/si --no-plots"),
                    "sweep.iso_budget.column: no numeric column \"shaded\"");
  // search: objective and constraint, refused before the first evaluation (no NaN "best").
  std::string s = base;
  s.replace(s.find(R"([{"method": "full"}])"), std::string(R"([{"method": "full"}])").size(),
            R"([{"method": "kfr", "sigma": 1.8}])");
  s.insert(s.rfind('}'), R"(, "sweep": {"search": {"space": {"methods[0].sigma": {"from": 1.5,
           "to": 2.5}}, "maximize": "psnr_typo", "evaluations": 1, "batch": 1}})");
  write_text(d + "/search.json", s);
  expect_user_error(run_cmd(bin + " search " + d + "/search.json --out " + d + "/se"),
                    "sweep.search.maximize: no numeric column \"psnr_typo\"");
  EXPECT_FALSE(fs::exists(d + "/se/search_best.csv"));
  write_text(d + "/search2.json",
             s.replace(s.find("\"maximize\": \"psnr_typo\""), 23,
                       R"("maximize": "psnr", "subject_to": {"ms": {"max": 11.1}})"));
  expect_user_error(run_cmd(bin + " search " + d + "/search2.json --out " + d + "/se2"),
                    "sweep.search.subject_to.ms: no numeric column \"ms\"");
}

TEST(Reliability, SweepAxesAndRungsSaySilentChoicesAloud) {
  const std::string d = temp_dir("rel_axes"), bin = fovsim_bin();
  std::string cfg = small_config(R"({"type": "atrium", "complexity": 1})");
  cfg.replace(cfg.find(R"({"method": "full"})"), 18, R"({"method": "kfr"})");
  cfg.insert(cfg.rfind('}'), R"(, "sweep": {"lhs": {"count": 6, "seed": 3, "axes":
    {"methods[0].sigma": {"from": 1.3, "to": 2.9, "integer": true}}}})");
  write_text(d + "/lhs.json", cfg);
  // Integer lhs values stay inside [from, to]: only 2 is there.
  auto r = run_cmd(bin + " sweep expand " + d + "/lhs.json");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output.find("sigma=1\n"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("sigma=3\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("sigma=2\n"), std::string::npos) << r.output;
  expect_user_error(
      run_cmd(
          bin + " sweep expand " + d + "/lhs.json " +
          R"('sweep.lhs.axes={"methods[0].sigma": {"from": 1.2, "to": 1.8, "integer": true}}')"),
      "sweep.lhs.axes.methods[0].sigma.integer: no integer in [1.2, 1.8]");
  // Ranges whose values coincide after the 12-digit rounding would be identical cells.
  expect_user_error(
      run_cmd(
          bin + " sweep expand " + d + "/lhs.json " +
          R"('sweep={"grid": {"methods[0].sigma": {"from": 1, "to": 1.0000000000001, "count": 10}}}')"),
      "values 0 and 1 of the range are both 1 after rounding to 12 significant "
      "digits (identical cells)");
  // A fidelity rung sets each knob once ("scale" and "render.scale" are one).
  write_text(d + "/one.json", small_config());
  expect_user_error(run_cmd(bin + " fidelity " + d + "/one.json --rungs " +
                            "'scale=0.25,render.scale=0.5' --out " + d + "/f"),
                    "--rungs scale=0.25,render.scale=0.5: \"render.scale\" is given twice in one "
                    "rung");
}

TEST(Reliability, MisleadingMessagesAreFixed) {
  const std::string d = temp_dir("rel_msgs"), bin = fovsim_bin();
  write_text(d + "/cfg.json", small_config());
  // Seeds past 2^53 are errors, not clamped to one value.
  expect_user_error(
      run_cmd(bin +
              " trace synth --scenario fixate --duration 1 --seed "
              "18446744073709551616 -o " +
              d + "/t.csv"),
      "--seed: value 1.8446744073709552e+19 is out of range [0, 9007199254740992] seed");
  expect_user_error(
      run_cmd(bin + " run " + d + "/cfg.json --out " + d +
              R"(/o 'trace={"synthetic": {"scenario": "fixate", "duration": 1, "seed": 1e20}}')"),
      "trace.synthetic.seed: value 1e+20 is out of range [0, 9007199254740992]");
  // --out "" is an error, not the default folder or the current one.
  expect_user_error(run_cmd(bin + " run " + d + "/cfg.json --out ''"),
                    "--out: output path is empty");
  expect_user_error(run_cmd(bin + " trace synth --scenario fixate --duration 1 -o ''"),
                    "--output: output path is empty");
  expect_user_error(run_cmd(bin + " density --out ''"), "--out: output path is empty");
  // Integer keys state their real range; a 300-digit value is not echoed in full.
  expect_user_error(run_cmd(bin + " run " + d + "/cfg.json --out " + d + "/o frames.count=1e301"),
                    "frames.count: value 1e+301 is out of range [0, 2e+09]");
  auto big = run_cmd(bin + " run " + d + "/cfg.json --out " + d + "/o frames.count=1" +
                     std::string(299, '0'));
  expect_user_error(big, "...': frames.count: value 1e+299 is out of range [0, 2e+09]");
  EXPECT_LT(big.output.size(), 250u) << big.output;
  // A command group without its command names the group and its commands.
  expect_user_error(run_cmd(bin + " trace"),
                    "fovsim trace needs a command (one of: import, validate, stats, synth");
  expect_user_error(
      run_cmd(bin + " trace --json frobnicate"),
      "unknown command 'frobnicate' (commands: import, validate, stats, synth, keys)");
  // Scene files obey FOVSIM_MAX_INPUT_MB like every other input.
  write_text(d + "/big.obj", std::string(2 << 20, '#'));
  write_text(d + "/big.json", small_config(R"({"type": "file", "path": ")" + d + R"(/big.obj"})"));
  expect_user_error(
      run_cmd("FOVSIM_MAX_INPUT_MB=1 " + bin + " run " + d + "/big.json --out " + d + "/o"),
      "big.obj: file is 2 MiB, over the input limit of 1 MiB");
  // Malformed models name the file and the parse error (not "No suitable reader found").
  write_text(d + "/bad.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [\n");
  write_text(d + "/gltf.json",
             small_config(R"({"type": "file", "path": ")" + d + R"(/bad.gltf"})"));
  expect_user_error(run_cmd(bin + " run " + d + "/gltf.json --out " + d + "/o"),
                    "not a glTF file: " + d + "/bad.gltf:2:1: malformed JSON");
  write_text(d + "/bad.glb", "garbage\x01\x02");
  write_text(d + "/glb.json", small_config(R"({"type": "file", "path": ")" + d + R"(/bad.glb"})"));
  expect_user_error(run_cmd(bin + " run " + d + "/glb.json --out " + d + "/o"),
                    "cannot import " + d + "/bad.glb: its contents are not a readable .glb file");
  // A broken PNG is one line: libpng's own stderr line is not printed.
  const std::string zero_png(
      "\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\0\0\0\0\0\0\x08\x02\0\0\0\0\0\0\0\0\0\0\0IEND\xae\x42"
      "\x60\x82",
      45);
  write_text(d + "/zero.png", zero_png);
  expect_user_error(run_cmd(bin + " compare " + d + "/zero.png " + d + "/zero.png"),
                    "zero.png: cannot read image");
}

TEST(Reliability, MergeAndPredictRefuseWhatTheyCannotUse) {
  const std::string d = temp_dir("rel_merge"), bin = fovsim_bin();
  std::string cfg = small_config();
  cfg.insert(cfg.rfind('}'), R"(, "sweep": {"grid": {"render.scale": [0.05]}})");
  write_text(d + "/sw.json", cfg);
  auto r = run_cmd(bin + " sweep " + d + "/sw.json --out " + d + "/sw --no-plots -q");
  ASSERT_EQ(r.code, 0) << r.output;
  expect_user_error(run_cmd(bin + " merge " + d + "/sw --from " + d + "/missing --no-plots"),
                    "--from " + d + "/missing: no such folder");
  fs::create_directories(d + "/empty");
  expect_user_error(run_cmd(bin + " merge " + d + "/sw --from " + d + "/empty --no-plots"),
                    "no sweep.json: not an output folder of a sweep");
  // predict --results: a counter the cost model needs, missing from frames.csv, is an error
  // (it used to be costed as 0: a cheaper frame).
  write_text(d + "/run.json", small_config());
  r = run_cmd(bin + " run " + d + "/run.json --out " + d + "/run --no-plots -q");
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string csv = read_text(d + "/run/frames.csv");
  std::vector<std::string> lines;
  for (size_t a = 0, b; a < csv.size(); a = b + 1) {
    b = csv.find('\n', a);
    if (b == std::string::npos) b = csv.size();
    lines.push_back(csv.substr(a, b - a));
  }
  const auto head = split_csv_line(lines[0]);
  size_t drop = 0;
  while (drop < head.size() && head[drop] != "shaded_fraction") ++drop;
  ASSERT_LT(drop, head.size());
  std::string out;
  for (auto& l : lines) {
    if (l.empty()) continue;
    auto f = split_csv_line(l);
    std::string row;
    for (size_t i = 0; i < f.size(); ++i)
      if (i != drop) row += (row.empty() ? "" : ",") + f[i];
    out += row + "\n";
  }
  write_text(d + "/run/frames.csv", out);
  expect_user_error(run_cmd(bin + " predict --results " + d + "/run --gpu gtx1080"),
                    "frames.csv:2: counter shaded_fraction missing or empty");
  // A negative or non-finite counter is refused naming the file, row and column (it used to be
  // costed: a negative count is a cheaper frame, nan a nan one).
  auto with_value = [&](const std::string& column, const std::string& value) {
    std::string o;
    const auto h = split_csv_line(lines[0]);
    size_t c = 0;
    while (c < h.size() && h[c] != column) ++c;
    EXPECT_LT(c, h.size()) << column;
    for (size_t k = 0; k < lines.size(); ++k) {
      if (lines[k].empty()) continue;
      auto f = split_csv_line(lines[k]);
      if (k == 1 && c < f.size()) f[c] = value;
      std::string row;
      for (size_t i = 0; i < f.size(); ++i) row += (i ? "," : "") + f[i];
      o += row + "\n";
    }
    write_text(d + "/run/frames.csv", o);
  };
  with_value("shaded_samples", "-5");
  expect_user_error(run_cmd(bin + " predict --results " + d + "/run --gpu gtx1080"),
                    "/run/frames.csv:2:");
  expect_user_error(run_cmd(bin + " predict --results " + d + "/run --gpu gtx1080"),
                    "counter shaded_samples = -5 is negative (a counter is a finite number >= 0)");
  with_value("shaded_fraction", "nan");
  expect_user_error(run_cmd(bin + " predict --results " + d + "/run --gpu gtx1080"),
                    "counter shaded_fraction: non-finite value");
  with_value("prims_submitted", "inf");
  expect_user_error(run_cmd(bin + " budget --results " + d + "/run --gpu gtx1080"),
                    "counter prims_submitted: non-finite value");
}

TEST(Reliability, ControlBytesAreEscapedInOutputs) {
  const std::string d = temp_dir("rel_ctl"), bin = fovsim_bin();
  write_text(d + "/cfg.json", small_config());
  auto r =
      run_cmd(bin + " run " + d + "/cfg.json --out " + d +
              R"(/o --no-plots 'methods=[{"method": "full", "label": "a\u001b[31mred\u0007"}]')" +
              " outputs.print_summary=true");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output.find('\x1b'), std::string::npos);
  EXPECT_EQ(r.output.find('\x07'), std::string::npos);
  EXPECT_NE(r.output.find("a\\x1B[31mred\\x07"), std::string::npos) << r.output;
  for (const char* f : {"/o/summary.csv", "/o/frames.csv"}) {
    const std::string s = read_text(d + f);
    EXPECT_EQ(s.find('\x1b'), std::string::npos) << f;
    EXPECT_EQ(s.find('\x07'), std::string::npos) << f;
    EXPECT_NE(s.find("a\\x1B[31mred\\x07"), std::string::npos) << f;
  }
}

TEST(Reliability, OutOfMemoryNamesWhatWasAllocated) {
  // 256 cells of one reference group side by side under a 4 GB address-space limit: the
  // message names the cells, --memory-budget and --batch (not render.scale alone, not a bare
  // bad_alloc). (The default budget reads MemAvailable, which an address-space limit does not
  // lower.)
  const std::string d = temp_dir("rel_oom"), bin = fovsim_bin();
  auto r = run_cmd("ulimit -v 4000000; " + bin + " sweep configs/sweeps/rmfr_fx_fy.json --out " +
                   d + "/sw -q --no-plots");
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("out of memory while rendering and measuring 256 cells side by side "
                          "over one shared reference (run fewer cells at once with `fovsim sweep "
                          "--memory-budget GB` (or --batch N)"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.code, 2) << r.output;
}

// Check before working: `trace import` runs trace validate's checks on what it would write
// (a map's constant head position beyond the coordinate bound, a step below 1 us), and trace
// validate refuses steps a rate cannot describe (1e-12 s, a denormal step: "rate inf Hz").
TEST(Reliability, ImportWritesOnlyWhatValidateAccepts) {
  const std::string d = temp_dir("rel_import"), bin = fovsim_bin();
  write_text(d + "/map.json", R"({"delimiter": "comma", "header": true, "coordinates": "opengl",
    "time": {"column": "time", "unit": "s"}, "head_position": {"constant": [2e5, 1.6, 0]},
    "head_orientation": {"constant": [1, 0, 0, 0]},
    "gaze": {"type": "direction", "space": "head", "columns": ["x", "y", "z"]}})");
  write_text(d + "/rec.csv", "time,x,y,z\n0,0,0,-1\n0.01,0,0,-1\n0.02,0,0,-1\n");
  expect_user_error(
      run_cmd(bin + " trace import " + d + "/rec.csv --map " + d + "/map.json -o " + d + "/o.csv"),
      "/o.csv): column \"px\": head position 200000 m is beyond the coordinate bound +-1e5 m "
      "(trace validate would refuse the imported trace: nothing was written");
  EXPECT_NE(
      run_cmd(bin + " trace import " + d + "/rec.csv --map " + d + "/map.json -o " + d + "/o.csv")
          .output.find("rec.csv:2 (imported as row 1, column "),
      std::string::npos);
  EXPECT_FALSE(fs::exists(d + "/o.csv"));
  write_text(d + "/map2.json", R"({"delimiter": "comma", "header": true, "coordinates": "opengl",
    "time": {"column": "time", "unit": "s"}, "head_position": {"constant": [0, 1.6, 0]},
    "head_orientation": {"constant": [1, 0, 0, 0]},
    "gaze": {"type": "direction", "space": "head", "columns": ["x", "y", "z"]}})");
  write_text(d + "/fast.csv", "time,x,y,z\n0,0,0,-1\n0.01,0,0,-1\n0.0100001,0,0,-1\n");
  expect_user_error(
      run_cmd(bin + " trace import " + d + "/fast.csv --map " + d + "/map2.json -o " + d +
              "/o.csv"),
      "fast.csv:4 (imported as row 3, column 1 of " + d + "/o.csv): interval too short");
  EXPECT_FALSE(fs::exists(d + "/o.csv"));
  auto ok =
      run_cmd(bin + " trace import " + d + "/rec.csv --map " + d + "/map2.json -o " + d + "/o.csv");
  ASSERT_EQ(ok.code, 0) << ok.output;
  EXPECT_EQ(run_cmd(bin + " trace validate " + d + "/o.csv").code, 0);
  const std::string row = ",0,0,0,1,0,0,0,0,0,-1,1\n";
  write_text(d + "/tiny.csv", "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,valid\n0" + row + "1e-12" + row);
  expect_user_error(run_cmd(bin + " trace validate " + d + "/tiny.csv"),
                    "tiny.csv:3:1: interval too short: t=1e-12 after t=0 (line 2) is 1e-12 s (a "
                    "rate of 1e+12 Hz); samples must be at least 1e-06 s apart (at most 1 MHz)");
  write_text(d + "/denormal.csv",
             "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,valid\n0" + row + "4.9e-324" + row);
  expect_user_error(run_cmd(bin + " trace stats " + d + "/denormal.csv"), "a rate of inf Hz");
  // skip: the row is dropped and reported, as for a non-increasing time.
  auto sk = run_cmd(bin + " trace validate --on-bad skip " + d + "/tiny.csv");
  EXPECT_EQ(sk.code, 1) << sk.output;
  EXPECT_NE(sk.output.find("interval too short"), std::string::npos) << sk.output;
}

// Degenerate parameters and nesting are bounded before recursive or per-pixel code: RMFR's
// f below 1% of the width (fx = 1e-10 collapsed every sample onto the gaze: a one-colour image
// with a normal shaded fraction), and config paths (overrides, sweep axes) nesting a document
// deeper than JSON text may (each component is one level).
TEST(Reliability, DegenerateParametersAndDeepPathsAreRefused) {
  const std::string d = temp_dir("rel_depth"), bin = fovsim_bin();
  write_text(d + "/cfg.json", small_config());
  expect_user_error(run_cmd(bin + " run " + d + "/cfg.json --out " + d +
                            "/o 'methods=[{\"method\": \"rmfr\", \"fx\": 1e-10}]'"),
                    "methods[0].fx: value 1e-10 is out of range [0.01, ");
  expect_user_error(run_cmd(bin + " run " + d + "/cfg.json --out " + d +
                            "/o 'methods=[{\"method\": \"rmfr\", \"fy_px\": 0.5}]'"),
                    "methods[0].fy_px: value 0.5 is out of range [1, ");
  EXPECT_FALSE(fs::exists(d + "/o/manifest.json"));
  std::string path = "a";
  for (int i = 0; i < 100; ++i) path += ".a";
  expect_user_error(run_cmd(bin + " run " + d + "/cfg.json --out " + d + "/o " + path + "=1"),
                    "path nested deeper than 64 levels (the limit for any fovsim input)");
  std::string sw = small_config();
  sw.insert(sw.rfind('}'), ", \"sweep\": {\"grid\": {\"" + path + "\": [1]}}");
  write_text(d + "/sw.json", sw);
  expect_user_error(run_cmd(bin + " sweep expand " + d + "/sw.json"),
                    "path nested deeper than 64 levels");
}

// Memory within documented limits: `compare` reads both images' headers before decoding
// either; a pair over max_image_pixels (16 Mpx: about 140 bytes per pixel of working memory) is
// refused naming the file, its size and the limit. A 57-byte PNG whose header claims 6000x6000.
TEST(Reliability, CompareChecksHeadersBeforeDecoding) {
  const std::string d = temp_dir("rel_png"), bin = fovsim_bin();
  const std::string hex =
      "89504e470d0a1a0a0000000d49484452000017700000177008020000006c361014000000004944415435af061e"
      "0000000049454e44ae426082";
  std::string bytes;
  for (size_t i = 0; i + 1 < hex.size(); i += 2)
    bytes += char(std::stoi(hex.substr(i, 2), nullptr, 16));
  ASSERT_EQ(bytes.size(), 57u);
  write_text(d + "/big.png", bytes);
  expect_user_error(run_cmd(bin + " compare " + d + "/big.png " + d + "/big.png"),
                    d + "/big.png: image header claims 6000x6000x3 (36000000 pixels), over the "
                        "limit of 16777216 pixels (16 Mpx: comparing a pair takes about 140 bytes "
                        "per pixel; set FOVSIM_MAX_IMAGE_MPIXELS to raise it)");
  // TEST over the limit: refused before REF is decoded, naming TEST.
  const std::string png = std::string(FOVSIM_SOURCE_DIR) + "/tests/data/metrics/gray_a.png";
  ASSERT_TRUE(fs::exists(png));
  expect_user_error(run_cmd(bin + " compare " + png + " " + d + "/big.png"),
                    d + "/big.png: image header claims 6000x6000x3");
  expect_user_error(
      run_cmd("FOVSIM_MAX_IMAGE_MPIXELS=40 " + bin + " compare " + png + " " + d + "/big.png"),
      "compare: images differ in size: ");
}
