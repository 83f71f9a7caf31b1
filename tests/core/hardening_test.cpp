// Every input-caused failure is a located fovsim::Error (never an exception that
// ends as "internal error"), input sizes are bounded before reading, names become file names
// only through safe_file_name, images are never left truncated under their final name.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/image.h"
#include "sim/core/params.h"
#include "sim/core/rng.h"

using namespace fovsim;
namespace fs = std::filesystem;

namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("NOT A fovsim::Error: ") + e.what();
  }
  return "NO ERROR";
}

std::string tmp(const std::string& name) {
  auto d = fs::temp_directory_path() / ("fovsim_harden_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return (d / name).string();
}

void write(const std::string& p, const std::string& s) {
  std::ofstream(p, std::ios::binary) << s;
}

// Sets an environment variable for one scope.
struct ScopedEnv {
  std::string name;
  ScopedEnv(const char* n, const char* v) : name(n) { ::setenv(n, v, 1); }
  ~ScopedEnv() { ::unsetenv(name.c_str()); }
};

}  // namespace

TEST(Hardening, NumberOutOfDoubleRangeIsLocated) {
  std::string e = error_of([] { parse_json_text("{\n  \"name\": 1e400\n}", "n.json"); });
  EXPECT_EQ(e.rfind("n.json:2:11: malformed JSON: number overflow parsing '1e400'", 0), 0u) << e;
  e = error_of([] { parse_json_text("[-1e999]", "m.json"); });
  EXPECT_EQ(e.rfind("m.json:1:", 0), 0u) << e;
  // Syntax errors keep file:line:column.
  e = error_of([] { parse_json_text("{\"a\": 1,,}", "s.json"); });
  EXPECT_EQ(e.rfind("s.json:1:9: malformed JSON: parse error", 0), 0u) << e;
  // Largest doubles and comments are fine.
  EXPECT_DOUBLE_EQ(parse_json_text("// c\n{\"a\": 1.7e308 /* x */}", "ok.json")["a"].get<double>(),
                   1.7e308);
}

TEST(Hardening, NestingDepthLimitCheckedBeforeParsing) {
  std::string ok = std::string(kMaxJsonDepth, '[') + std::string(kMaxJsonDepth, ']');
  EXPECT_NO_THROW(parse_json_text(ok, "ok.json"));
  // One level deeper: error at the first bracket over the limit (line 2 here).
  std::string deep =
      "{\"comment\":\n" + std::string(kMaxJsonDepth, '[') + std::string(kMaxJsonDepth, ']') + "}";
  std::string e = error_of([&] { parse_json_text(deep, "d.json"); });
  EXPECT_EQ(e, "d.json:2:" + std::to_string(kMaxJsonDepth) + ": JSON nested deeper than " +
                   std::to_string(kMaxJsonDepth) + " levels (the limit for any fovsim input)");
  // 200 KB of nesting: one clear error, no recursion.
  std::string huge(200000, '[');
  e = error_of([&] { parse_json_text(huge, "h.json"); });
  EXPECT_NE(e.find("h.json:1:65: JSON nested deeper"), std::string::npos) << e;
  // Brackets inside strings and comments do not count; escaped quotes are handled.
  std::string s =
      "{\"a\": \"" + std::string(500, '[') + "\\\"[[\", // [[[[[[\n /* {{{{ */ \"b\": 1}";
  EXPECT_NO_THROW(parse_json_text(s, "s.json"));
}

TEST(Hardening, OverridePathsAreValidated) {
  Json doc = Json::parse(R"({"render": {"scale": 1}, "methods": [{"sigma": 1}]})");
  for (const auto& tc : std::vector<std::pair<std::string, std::string>>{
           {".=1", "empty key"},
           {"render.=1", "trailing '.'"},
           {"render..scale=1", "empty key"},
           {"[0]=1", "must start with a key"},
           {"methods[99999999999999999999999].sigma=1", "bad array index"},
           {"methods[5].sigma=1", "has no element [5]"},
           {"methods[-1].sigma=1", "bad array index"},
           {"methods[0]x=1", "expected '.' or '['"},
           {"render.scale=1e400", "bad value"},
           {"render.scale=" + std::string(100, '['), "nested deeper"},
       }) {
    // Not a structured binding: clang 14 (the sanitizer build) cannot capture one.
    const std::string &ov = tc.first, &expect = tc.second;
    Json d = doc;
    std::string e = error_of([&] { apply_override(d, ov); });
    EXPECT_EQ(e.rfind("override ", 0), 0u) << ov << " -> " << e;
    EXPECT_NE(e.find(expect), std::string::npos) << ov << " -> " << e;
    EXPECT_EQ(d, doc) << ov;  // a refused override changes nothing
  }
  apply_override(doc, "methods[0].sigma=2.5");
  EXPECT_DOUBLE_EQ(doc["methods"][0]["sigma"].get<double>(), 2.5);
}

TEST(Hardening, ReadFileRefusesNonRegularAndOversizedFiles) {
  EXPECT_NE(error_of([] { read_file("/dev/zero"); }).find("/dev/zero: not a regular file"),
            std::string::npos);
  EXPECT_NE(error_of([] { read_file(fs::temp_directory_path().string()); }).find("is a directory"),
            std::string::npos);
  EXPECT_NE(error_of([] { read_file("/nonexistent/x.json"); }).find("cannot read file"),
            std::string::npos);
  std::string p = tmp("big.json");
  write(p, std::string((1 << 20) + 1, ' '));  // 1 MiB + 1 byte
  EXPECT_EQ(read_file(p).size(), size_t((1 << 20) + 1));
  {
    ScopedEnv env("FOVSIM_MAX_INPUT_MB", "1");
    std::string e = error_of([&] { read_file(p); });
    EXPECT_NE(e.find("over the input limit of 1 MiB (set FOVSIM_MAX_INPUT_MB"), std::string::npos)
        << e;
  }
  {
    ScopedEnv env("FOVSIM_MAX_INPUT_MB", "1x");
    std::string e = error_of([&] { read_file(p); });
    EXPECT_EQ(e, "environment FOVSIM_MAX_INPUT_MB=\"1x\": expected an integer in [1, 1048576]");
  }
  EXPECT_EQ(max_input_bytes(), uint64_t(256) << 20);
}

TEST(Hardening, StrictIntegers) {
  long v = 0;
  EXPECT_TRUE(parse_integer("42", 0, 100, v));
  EXPECT_EQ(v, 42);
  EXPECT_TRUE(parse_integer("-3", -5, 5, v));
  EXPECT_EQ(v, -3);
  for (const char* bad :
       {"", "abc", "4x", " 4", "4 ", "+4", "101", "-", "99999999999999999999999", "1e3", "0x10"})
    EXPECT_FALSE(parse_integer(bad, 0, 100, v)) << bad;
  EXPECT_FALSE(env_integer("FOVSIM_TEST_UNSET_VARIABLE", 0, 1).has_value());
  ScopedEnv env("FOVSIM_TEST_INT", "abc");
  EXPECT_EQ(error_of([] { env_integer("FOVSIM_TEST_INT", 0, 9); }),
            "environment FOVSIM_TEST_INT=\"abc\": expected an integer in [0, 9]");
}

TEST(Hardening, SafeFileNameIsOneComponent) {
  EXPECT_EQ(safe_file_name("kfr_s1.8-a+4"), "kfr_s1.8-a+4");
  EXPECT_EQ(safe_file_name("../../../../escaped_label"), "_._.._.._.._escaped_label");
  EXPECT_EQ(safe_file_name(".."), "_.");
  EXPECT_EQ(safe_file_name("."), "_");
  EXPECT_EQ(safe_file_name(""), "_");
  EXPECT_EQ(safe_file_name("a/b\\c\nd\te f"), "a_b_c_d_e_f");
  EXPECT_EQ(safe_file_name(std::string("x\0y", 3)), "x_y");
  EXPECT_EQ(safe_file_name(std::string(500, 'a')).size(), 120u);
  // Whatever the input: no separator, not "." or "..", no control character.
  Rng rng(7, 1);
  for (int i = 0; i < 2000; ++i) {
    std::string s;
    int n = int(rng.below(12));
    for (int k = 0; k < n; ++k) s += char(rng.below(256));
    std::string f = safe_file_name(s);
    EXPECT_FALSE(f.empty());
    EXPECT_EQ(f.find('/'), std::string::npos);
    EXPECT_NE(f[0], '.');
    for (char c : f) EXPECT_GE((unsigned char)c, 0x20);
    EXPECT_EQ(fs::path(f).filename().string(), f);
  }
}

TEST(Hardening, DirLockIsExclusive) {
  std::string d = tmp("locked");
  {
    DirLock a(d, ".lock", "another fovsim sweep");
    std::string e = error_of([&] { DirLock b(d, ".lock", "another fovsim sweep"); });
    EXPECT_NE(e.find("another fovsim sweep is writing to this folder"), std::string::npos) << e;
    EXPECT_NO_THROW(DirLock c(d, ".lock.shard-1-of-2", "x"));  // another lock name: independent
  }
  EXPECT_NO_THROW(DirLock again(d, ".lock", "x"));  // released with its owner
}

TEST(Hardening, FullDiskLeavesNoTruncatedImage) {
  // A file-size limit makes writes fail like a full disk (EFBIG instead of ENOSPC).
  std::string dir = tmp("fulldisk");
  fs::remove_all(dir);
  fs::create_directories(dir);
  Image img(256, 256, 3);
  Rng rng(3, 3);
  for (auto& v : img.data) v = float(rng.uniform());  // noise: a PNG far above the limit
  struct rlimit old {};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  auto prev = ::signal(SIGXFSZ, SIG_IGN);
  struct rlimit lim = old;
  lim.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &lim), 0);
  std::string e = error_of([&] { write_image(dir + "/reference.png", img); });
  ::setrlimit(RLIMIT_FSIZE, &old);
  ::signal(SIGXFSZ, prev);
  EXPECT_EQ(e.rfind(dir + "/reference.png: ", 0), 0u) << e;
  EXPECT_FALSE(fs::exists(dir + "/reference.png"));
  EXPECT_TRUE(fs::is_empty(dir)) << "temporary file left behind";
  // Without the limit the same image is written completely.
  write_image(dir + "/reference.png", img);
  Image back = read_image(dir + "/reference.png");
  EXPECT_EQ(back.width, 256);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);
}

TEST(Hardening, CommandLineValues) {
  EXPECT_EQ(parse_value_or_string("2.5", "--param kfr.alpha=2.5"), Json(2.5));
  EXPECT_EQ(parse_value_or_string("fove_1280x1440", "x"), Json("fove_1280x1440"));
  EXPECT_EQ(parse_value_or_string("[1, 2]", "x"), Json::parse("[1, 2]"));
  EXPECT_EQ(error_of([] {
              parse_value_or_string("1e400", "--method kfr:sigma=1e400");
            }).rfind("--method kfr:sigma=1e400: bad value: ", 0),
            0u);
  // Found by fuzz_params: a non-JSON value that is not UTF-8 ended in "internal error" when
  // an error message or manifest.json serialised it.
  EXPECT_EQ(error_of([] {
              parse_value_or_string(
                  "1\xe5"
                  "400",
                  "override x");
            }),
            "override x: value is not valid UTF-8 text");
  EXPECT_EQ(describe_json(Json(std::string("a\xe5"))), "a string \"a\xef\xbf\xbd\"");
  EXPECT_NE(error_of([] {
              parse_value_or_string(std::string(100000, '['), "--param kfr.alpha");
            }).find("--param kfr.alpha:1:65: JSON nested deeper than 64 levels"),
            std::string::npos);
}

// Label paths work in overrides as in sweep axes: methods[kfr].sigma.
TEST(Override, MethodLabelPaths) {
  Json doc = Json::parse(
      R"({"methods": [{"method": "full"}, {"method": "kfr"}, {"method": "rmfr", "label": "r2"}]})");
  apply_override(doc, "methods[kfr].sigma=2.2");
  EXPECT_EQ(doc["methods"][1]["sigma"], 2.2);
  apply_override(doc, "methods[r2].fx=0.3");
  EXPECT_EQ(doc["methods"][2]["fx"], 0.3);
  try {
    apply_override(doc, "methods[twfr].epsilon=0.1");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "no entry of \"methods\" has label \"twfr\" (labels: full, kfr, r2)"),
              std::string::npos)
        << e.what();
  }
  Json two = Json::parse(R"({"methods": [{"method": "kfr"}, {"method": "kfr"}]})");
  EXPECT_THROW(apply_override(two, "methods[kfr].sigma=2"), Error);
}

// An override's mistake names the command line, not the config file it lands in.
TEST(Override, ErrorsNameTheCommandLine) {
  Json doc = Json::parse(R"({"render": {"scale": 1}, "methods": [{"method": "kfr", "sigma": 1}]})");
  std::vector<std::pair<std::string, std::string>> origins;
  for (std::string ov : {"rendr.scale=1", "methods[kfr].sigma=-3"})
    origins.emplace_back(apply_override(doc, ov), ov);
  EXPECT_EQ(origins[0].first, "rendr");             // the subtree the override created
  EXPECT_EQ(origins[1].first, "methods[0].sigma");  // labels resolve to indices
  Params p(doc, "configs/x.json");
  p.set_origins(origins);
  (void)p.child("render").number("scale");
  auto ms = p.children("methods");
  EXPECT_EQ(error_of([&] {
              (void)ms[0].number("sigma", 1.8, Range::at_least(1));
            }).rfind("override 'methods[kfr].sigma=-3': methods[0].sigma: ", 0),
            0u);
  (void)ms[0].string("method");
  ms[0].ignore("sigma");  // the failed read above did not mark it
  EXPECT_EQ(error_of([&] { p.finish(); }),
            "override 'rendr.scale=1': rendr: unknown key \"rendr\" (did you mean \"render\"?)");
  // Keys the command line did not touch still name the file.
  EXPECT_EQ(error_of([&] {
              (void)p.child("render").string("scale");
            }).rfind("configs/x.json: render.scale: ", 0),
            0u);
  // Bad override paths name the whole assignment; "render..scale" is rejected.
  EXPECT_EQ(error_of([&] {
              apply_override(doc, "render..scale=1");
            }).rfind("override 'render..scale=1': empty key", 0),
            0u);
}

TEST(Hardening, ClosestNameForDidYouMean) {
  std::vector<std::string> cmds{"run", "sweep", "merge", "trace", "density", "predict"};
  EXPECT_EQ(closest_name("rn", cmds), "run");
  EXPECT_EQ(closest_name("swep", cmds), "sweep");
  EXPECT_EQ(closest_name("mereg", cmds), "merge");  // transposition
  EXPECT_EQ(closest_name("xyzzy", cmds), "");
  EXPECT_EQ(closest_name("", cmds), "");
  EXPECT_EQ(closest_name(std::string(1000, 'r'), cmds), "");
}

// One writer for every output (files.h write_atomic): a failed check or write leaves neither
// the final name nor a temporary; an old file under the name is kept.
TEST(Hardening, WriteAtomicChecksBeforeRenaming) {
  std::string p = tmp("atomic/out.csv");
  write_file_atomic(p, "a,b\n1,2\n");
  EXPECT_EQ(read_file(p), "a,b\n1,2\n");
  std::string e = error_of([&] {
    write_atomic(
        p, [](const std::string& t) { write(t, "a,b\n1,"); },
        [](const std::string&) { return std::string("truncated"); });
  });
  EXPECT_EQ(e, p + ": truncated; nothing written under this name");
  EXPECT_EQ(read_file(p), "a,b\n1,2\n");  // the previous complete file stays
  for (auto& f : fs::directory_iterator(fs::path(p).parent_path()))
    EXPECT_FALSE(is_temporary_name(f.path().filename().string())) << f.path();
  EXPECT_TRUE(is_temporary_name(".tmp.123.frames.csv"));
  EXPECT_TRUE(is_temporary_name("00003.merge-tmp"));
  EXPECT_FALSE(is_temporary_name("frames.csv"));
}
