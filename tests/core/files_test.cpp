// Inputs and outputs are regular files reached without leaving the folder fovsim was pointed
// at (sim/core/files.h): a FIFO or link at a cache entry is ignored without waiting on it, a
// symbolic link inside an output folder is never written through, a link loop says so, a
// rerun's folder is emptied of the earlier run's outputs, and every JSON text and every file
// open in the sources goes through the checked helpers (the scans below fail on a new one).
#include "sim/core/files.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <set>

#include "sim/core/disk_cache.h"
#include "sim/core/error.h"
#include "sim/core/image.h"
#include "sim/core/params.h"

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

std::string fresh(const std::string& name) {
  fs::path d =
      fs::temp_directory_path() / ("fovsim_files_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

std::string slurp(const std::string& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

// Every source file of sim/ and python/ (C++), relative to the repository.
std::vector<std::string> sources() {
  std::vector<std::string> out;
  for (const char* top : {"sim", "python"})
    for (auto& e : fs::recursive_directory_iterator(std::string(FOVSIM_SOURCE_DIR) + "/" + top)) {
      const std::string ext = e.path().extension().string();
      if (e.is_regular_file() && (ext == ".cpp" || ext == ".h"))
        out.push_back(fs::relative(e.path(), FOVSIM_SOURCE_DIR).string());
    }
  std::sort(out.begin(), out.end());
  return out;
}

// "file:line: text" of each line of the sources matching `re` outside `allowed` files.
std::vector<std::string> uses(const std::regex& re, const std::set<std::string>& allowed) {
  std::vector<std::string> hits;
  for (const std::string& f : sources()) {
    if (allowed.count(f)) continue;
    std::ifstream in(std::string(FOVSIM_SOURCE_DIR) + "/" + f);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      const size_t c = line.find("//");
      if (std::regex_search(c == std::string::npos ? line : line.substr(0, c), re))
        hits.push_back(f + ":" + std::to_string(n) + ": " + line);
    }
  }
  return hits;
}

}  // namespace

TEST(Files, FifoOrLinkAtACacheEntryIsIgnoredWithoutWaiting) {
  const std::string d = fresh("cache");
  DiskCache c(d, "refs", 1 << 30);
  CacheItem it;
  it.arrays.emplace_back("a", std::vector<float>{1.f, 2.f});
  c.put("fifo", it);
  c.put("link", it);
  const std::string fifo = c.path_of("fifo"), link = c.path_of("link");
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);  // no writer: an open without O_NONBLOCK blocks
  EXPECT_FALSE(c.get("fifo").has_value());
  ASSERT_FALSE(c.warnings().empty());
  EXPECT_NE(c.warnings().back().find("is not a regular file"), std::string::npos)
      << c.warnings().back();
  const std::string outside = d + "/outside.fce";
  fs::rename(link, outside);
  fs::create_symlink(outside, link);
  EXPECT_FALSE(c.get("link").has_value());
  EXPECT_NE(c.warnings().back().find("is a symbolic link"), std::string::npos)
      << c.warnings().back();
  c.put("fifo", it);  // replaced by a real entry
  EXPECT_TRUE(c.get("fifo").has_value());
  fs::remove_all(d);
}

TEST(Files, SymlinkedFolderInsideAnOutputFolderIsNotWrittenThrough) {
  const std::string d = fresh("out"), outside = fresh("outside");
  write_file_atomic(outside + "/frame.png", "precious");
  fs::create_directories(d + "/run");
  fs::create_symlink(outside, d + "/run/images");
  {
    OutputRoot root(d + "/run");
    const std::string e = error_of([&] { write_file_atomic(d + "/run/images/frame.png", "x"); });
    EXPECT_NE(e.find(d + "/run/images: is a symbolic link inside the output folder " + d + "/run"),
              std::string::npos)
        << e;
    // A link deeper down (images/frame_3/) and make_dirs alike.
    fs::remove(d + "/run/images");
    fs::create_directories(d + "/run/images");
    fs::create_symlink(outside, d + "/run/images/frame_3");
    EXPECT_NE(error_of([&] {
                make_dirs(d + "/run/images/frame_3/debug");
              }).find("is a symbolic link inside the output folder"),
              std::string::npos);
    EXPECT_NO_THROW(write_file_atomic(d + "/run/images/frame_4/x.txt", "ok"));  // real folders
    // A lock makes its folder an output folder too.
    DirLock lock(d + "/run", ".lock", "another fovsim run");
    EXPECT_EQ(error_of([&] {
                DirLock b(d + "/run", ".lock", "another fovsim run");
              }).find("another fovsim run is writing to this folder") != std::string::npos,
              true);
  }
  EXPECT_EQ(slurp(outside + "/frame.png"), "precious");
  EXPECT_FALSE(fs::exists(outside + "/debug"));
  // Outside any output folder a link above the file is the user's business (results/ on
  // another disk): followed.
  EXPECT_NO_THROW(write_file_atomic(d + "/run/images/frame_3/y.txt", "ok"));
  EXPECT_EQ(slurp(outside + "/y.txt"), "ok");
  fs::remove_all(d);
  fs::remove_all(outside);
}

TEST(Files, SymlinkLoopSaysSoAndLinksOutOfAFolderAreRefused) {
  const std::string d = fresh("loop");
  fs::create_symlink(d + "/b", d + "/a");
  fs::create_symlink(d + "/a", d + "/b");
  for (auto f : std::vector<std::function<void()>>{
           [&] { read_file(d + "/a"); }, [&] { check_input_file(d + "/a", "scene.path"); },
           [&] { path_kind(d + "/a", "texture"); }})
    EXPECT_NE(error_of(f).find("symbolic link loop"), std::string::npos) << error_of(f);
  EXPECT_EQ(path_kind(d + "/none"), PathKind::missing);
  const std::string model = fresh("model"), outside = fresh("model_outside");
  write_file_atomic(outside + "/secret.mtl", "newmtl x\n");
  fs::create_symlink(outside + "/secret.mtl", model + "/m.mtl");
  write_file_atomic(model + "/inside.mtl", "newmtl y\n");
  fs::create_symlink(model + "/inside.mtl", model + "/ok.mtl");
  EXPECT_NE(error_of([&] {
              check_inside(model, model + "/m.mtl", "scene.path", "material library");
            }).find("outside the model's folder"),
            std::string::npos);
  EXPECT_NO_THROW(check_inside(model, model + "/ok.mtl", "scene.path", "material library"));
  fs::remove_all(d);
  fs::remove_all(model);
  fs::remove_all(outside);
}

TEST(Files, ClearRunOutputsLeavesOnlyWhatIsNotARunsOutput) {
  const std::string d = fresh("rerun"), outside = fresh("rerun_outside");
  for (const char* f : {"frames.csv", "summary.csv", ".tmp.123.frames.csv", "notes.txt"})
    write_file_atomic(d + "/" + f, "x");
  write_file_atomic(d + "/images/frame_0/kfr.png", "x");
  write_file_atomic(outside + "/keep.png", "keep");
  fs::create_symlink(outside, d + "/plots");
  clear_run_outputs(d, false);  // not a run folder: only temporaries go
  EXPECT_FALSE(fs::exists(d + "/.tmp.123.frames.csv"));
  EXPECT_TRUE(fs::exists(d + "/frames.csv"));
  clear_run_outputs(d, true);
  EXPECT_FALSE(fs::exists(d + "/frames.csv"));
  EXPECT_FALSE(fs::exists(d + "/images"));
  EXPECT_FALSE(fs::exists(fs::symlink_status(d + "/plots")));
  EXPECT_TRUE(fs::exists(d + "/notes.txt"));
  EXPECT_EQ(slurp(outside + "/keep.png"), "keep");  // the link went, not what it points to
  fs::remove_all(d);
  fs::remove_all(outside);
}

TEST(Files, OrderedParserChecksDepth) {
  const std::string deep = std::string(100, '[') + std::string(100, ']');
  EXPECT_NE(error_of([&] {
              parse_json_text_ordered(deep, "w.json");
            }).find("w.json:1:65: JSON nested deeper than 64 levels"),
            std::string::npos);
  EXPECT_EQ(parse_json_text_ordered("{\"b\": 1, \"a\": 2}", "w.json").begin().key(), "b");
}

// Class-wide guards: a new JSON parse or a new raw file open outside the checked helpers fails
// here, naming the line.
TEST(SourceScan, EveryJsonTextGoesThroughTheCheckedParser) {
  const auto hits =
      uses(std::regex(R"((json|Json)::parse\s*\(|json::accept\s*\()"), {"sim/core/params.cpp"});
  EXPECT_TRUE(hits.empty()) << "parse JSON with parse_json_text (sim/core/params.h):\n"
                            << [&] {
                                 std::string s;
                                 for (auto& h : hits) s += h + "\n";
                                 return s;
                               }();
}

TEST(SourceScan, FilesAreOpenedOnlyThroughTheCoreHelpers) {
  // The helpers themselves, and the decoders handed a path the helpers checked first
  // (check_input_file / confined_path): textures, compare's images; the kernel's /proc
  // counters (memory_info.cpp: fixed paths, not input).
  const std::set<std::string> allowed = {"sim/core/core.cpp",        "sim/core/disk_cache.cpp",
                                         "sim/core/memory_info.cpp", "sim/core/image.cpp",
                                         "sim/scene/import.cpp",     "sim/metrics/compare.cpp"};
  const auto hits = uses(std::regex(R"(std::[io]?fstream\b|\bfopen\s*\(|::open\s*\(|)"
                                    R"(create_director(y|ies)\s*\(|ImageInput::open|)"
                                    R"(ImageOutput::create)"),
                         allowed);
  std::string s;
  for (auto& h : hits) s += h + "\n";
  EXPECT_TRUE(hits.empty())
      << "open files with read_file / check_input_file / write_atomic / make_dirs "
         "(sim/core/files.h):\n"
      << s;
}

TEST(Images, NonFiniteValueIsAnErrorNamingThePixel) {
  Image img(4, 3, 3, 0.5f);
  EXPECT_NO_THROW(check_finite_image(img, "frame 0: reference"));
  img.at(2, 1)[1] = std::nanf("");
  EXPECT_NE(error_of([&] {
              check_finite_image(img, "frame 7: method \"kfr\" (label \"k\")");
            }).find("frame 7: method \"kfr\" (label \"k\"): pixel (2, 1) channel 1 is NaN"),
            std::string::npos);
  img.at(2, 1)[1] = 0.f;
  img.at(0, 2)[0] = INFINITY;
  EXPECT_NE(error_of([&] {
              check_finite_image(img, "frame 0: reference");
            }).find("pixel (0, 2) channel 0 is infinite"),
            std::string::npos);
}
