// As a user meets them: numeric flags refuse NaN, 0 and values past their range with one line
// naming the flag, range and unit (flags_test.cpp walks every command); cost inputs that would
// overflow, and a profile without the passes a method declares, are errors naming the file;
// messages print bounds as given, echo at most 80 characters of a value, name the right key,
// never show the JSON library's text, and escape control characters in tables.
#include <gtest/gtest.h>
#include <unistd.h>

#include "sim/core/params.h"
#include "tests/app/app_util.h"

using namespace fovsim_test;
namespace fs = std::filesystem;

namespace {

const std::string kTrace = std::string(FOVSIM_SOURCE_DIR) + "/tests/golden/golden_trace.csv";
const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";

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
  EXPECT_EQ(r.output.find("json.exception"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(expect), std::string::npos) << r.output;
}

std::string small_config(const std::string& scene = R"({"type": "atrium", "complexity": 1})",
                         const std::string& methods = R"([{"method": "full"}])",
                         const std::string& outputs = R"({"print_summary": false})") {
  return R"({"name": "v4", "render": {"scale": 0.05}, "scene": )" + scene +
         R"(, "trace": {"file": ")" + kTrace + R"("}, "frames": {"count": 1}, "methods": )" +
         methods + R"(, "outputs": )" + outputs + "}";
}

}  // namespace

TEST(FlagsCli, ReportedFlagValuesAreErrorsNamingRangeAndUnit) {
  const std::string bin = fovsim_bin(), d = temp_dir("v4_flags");
  const std::string png = std::string(FOVSIM_SOURCE_DIR) + "/tests/data/metrics/gray_a.png";
  expect_user_error(run_cmd(bin + " budget --gpu gtx1080 --workload kfr_bistro --p nan"),
                    "--p: value nan is out of range [0.5, 0.99] probability");
  expect_user_error(run_cmd(bin + " converge configs/convergence.json --tol-jod nan"),
                    "--tol-jod: value nan is out of range [1e-06, 10] JOD");
  for (const char* fps : {"nan", "0", "-5"})
    expect_user_error(run_cmd(bin + " compare " + png + " " + png + " --fvvdp --fps=" + fps),
                      std::string("--fps: value ") + fps + " is out of range (4, 10000] Hz");
  expect_user_error(run_cmd(bin + " run configs/quickstart.json --plot-dpi nan"),
                    "--plot-dpi: value nan is out of range [10, 2400] dpi");
  expect_user_error(run_cmd(bin + " compare " + png + " " + png + " --ppd 1e-300"),
                    "--ppd: value 1e-300 is out of range [0.01, 1e+06] px/deg");
  expect_user_error(run_cmd(bin + " run configs/quickstart.json --watchdog 1e-300"),
                    "--watchdog: value 1e-300 is out of range [1, 86400] s (0: off)");
  expect_user_error(run_cmd(bin + " converge configs/convergence.json --spp 1,4.5"),
                    "--spp: value 4.5 is not an integer in [1, 1024]");
  expect_user_error(run_cmd(bin + " sweep configs/quickstart.json --batch=-1"),
                    "--batch: value -1 is out of range [0, 1e+06] cells");
  expect_user_error(run_cmd(bin + " density --directions 1e9 --out " + d + "/x"),
                    "--directions: value 1e+09 is out of range [1, 360] directions");
  expect_user_error(run_cmd(bin + " density --samples nan --out " + d + "/x"),
                    "--samples: value nan is out of range [1, 1e+05] samples");
  expect_user_error(run_cmd(bin + " run configs/quickstart.json -j 1e9"),
                    "--threads: value 1e+09 is out of range [0, 4096] threads");
  // A bound prints as given: 36000.0001 is not "36000".
  expect_user_error(
      run_cmd(bin + " trace synth --scenario fixate --duration 36000.0001 -o " + d + "/t.csv"),
      "--duration: value 36000.0001 is out of range (0, 36000] s");
  // --help shows each numeric flag's range and unit.
  const CmdResult h = run_cmd(bin + " budget --help");
  EXPECT_NE(h.output.find("--p FLOAT in [0.5, 0.99] probability"), std::string::npos) << h.output;
  EXPECT_NE(run_cmd(bin + " run --help").output.find("--watchdog FLOAT in [1, 86400] s (0: off)"),
            std::string::npos);
}

TEST(FlagsCli, OverflowingWorkloadsAndIncompleteProfilesAreErrorsNamingTheFile) {
  const std::string bin = fovsim_bin(), d = temp_dir("v4_cost");
  write_text(d + "/lights.json", R"({"name": "big", "lights": 1e300})");
  expect_user_error(run_cmd(bin + " predict --gpu gtx1080 --workload " + d + "/lights.json"),
                    "lights.json: lights: value 1e+300 is out of range [-1, 1e+06]");
  write_text(d + "/shadow.json", R"({"name": "big", "shadow_map_res": 1e155})");
  expect_user_error(run_cmd(bin + " predict --gpu gtx1080 --workload " + d + "/shadow.json"),
                    "shadow.json: shadow_map_res: value 1e+155 is out of range [0, 65536]");
  // "passes": {} used to cost every method 0 ms and fit every budget.
  fovsim::Json g = fovsim::Params::parse_json_file(kModels + "/gpus/gtx1080.json");
  fovsim::Json empty = g;
  empty["passes"] = fovsim::Json::object();
  write_text(d + "/empty.json", empty.dump(2));
  expect_user_error(
      run_cmd(bin + " budget --gpu " + d + "/empty.json --workload kfr_bistro -m full"),
      "empty.json: GPU profile 'gtx1080' has no coefficients for pass 'depth', which method "
      "'full' declares");
  expect_user_error(
      run_cmd(bin + " predict --gpu " + d + "/empty.json --workload kfr_bistro -m kfr"),
      "has no coefficients for pass 'depth'");
  // Control characters of a GPU name are escaped in the table.
  fovsim::Json evil = g;
  evil["name"] = "gtx\x1b[31m1080";
  write_text(d + "/evil.json", evil.dump(2));
  const CmdResult t = run_cmd(bin + " predict --gpu " + d + "/evil.json --workload kfr_bistro");
  EXPECT_EQ(t.code, 0) << t.output;
  EXPECT_EQ(t.output.find('\x1b'), std::string::npos) << t.output;
  EXPECT_NE(t.output.find("gtx\\x1B[31m1080"), std::string::npos) << t.output;
  // A symbolic link loop is not "not found".
  fs::create_symlink(d + "/loop.json", d + "/loop.json");
  expect_user_error(run_cmd(bin + " predict --gpu " + d + "/loop.json --workload kfr_bistro"),
                    "symbolic link loop");
}

TEST(FlagsCli, MessagesNameTheKeyAndStayShort) {
  const std::string bin = fovsim_bin(), d = temp_dir("v4_msgs");
  // A pattern plane of 1e300 m blames scene.size, not scene.type.
  write_text(d + "/size.json", small_config(R"({"type": "patterns", "size": 1e300})"));
  expect_user_error(run_cmd(bin + " run " + d + "/size.json --out " + d + "/o1"),
                    "scene.size: value 1e+300 is out of range [0, 1e+05]");
  write_text(d + "/label.json", small_config(R"({"type": "atrium", "complexity": 1})",
                                             R"([{"method": "full", "label": ""}])"));
  expect_user_error(run_cmd(bin + " run " + d + "/label.json --out " + d + "/o2"),
                    "methods[0].label: empty label");
  write_text(d + "/frames.json",
             small_config(R"({"type": "atrium", "complexity": 1})", R"([{"method": "full"}])",
                          R"({"print_summary": false, "image_frames": [0.5]})"));
  expect_user_error(run_cmd(bin + " run " + d + "/frames.json --out " + d + "/o3"),
                    "outputs.image_frames[0]: expected a frame index (an integer), got 0.5");
  // `fovsim merge` of a sweep record {}: a located error, not the JSON library's text.
  fs::create_directories(d + "/sw");
  write_text(d + "/sw/sweep.json", "{}");
  expect_user_error(run_cmd(bin + " merge " + d + "/sw"), "sweep.json: config: missing");
  // A 1 MB `valid` field is echoed to 80 characters at most.
  write_text(d + "/big.csv", "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,valid\n0,0,1.6,0,1,0,0,0,0,0,-1," +
                                 std::string(1 << 20, 'x') + "\n");
  const CmdResult v = run_cmd(bin + " trace validate " + d + "/big.csv");
  EXPECT_EQ(v.code, 2) << v.output.substr(0, 300);
  EXPECT_LT(v.output.size(), 600u) << v.output.substr(0, 300);
}
