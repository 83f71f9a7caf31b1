// A run's output folder (sim/experiment/engine.cpp start_output_folders): locked while the run
// writes (a second writer stops with an error), emptied of an earlier run's outputs (a finished
// folder holds only this run's files), and never written through a symbolic link inside it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/experiment/runner.h"

using namespace fovsim;
namespace fs = std::filesystem;

namespace {

std::string out_dir(const std::string& name) {
  return (fs::temp_directory_path() /
          ("fovsim_outfolder_" + name + "_" + std::to_string(::getpid())))
      .string();
}

RunResult run_into(const std::string& out, const Json& outputs = Json::object()) {
  LoadedConfig c;
  c.file = "outfolder.json";
  Json o = outputs;
  o["print_summary"] = false;
  c.doc =
      Json{{"name", "outfolder"},
           {"display", "htc_vive_pro_eye"},
           {"render", {{"scale", 0.03}, {"spp", 1}}},
           {"scene", {{"type", "patterns"}}},
           {"trace", {{"synthetic", {{"scenario", "fixate"}, {"seed", 1}, {"duration", 0.05}}}}},
           {"frames", {{"count", 1}}},
           {"methods", Json::array({Json{{"method", "full"}}})},
           {"outputs", o}};
  RunOptions ro;
  ro.out_dir = out;
  ro.models_dir = std::string(FOVSIM_SOURCE_DIR) + "/models";
  ro.print_summary = false;
  ro.use_cache = false;
  return run_experiment(c, ro);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "NO ERROR";
}

}  // namespace

TEST(OutputFolder, SecondWriterStopsAndRerunLeavesOnlyItsOwnOutputs) {
  const std::string out = out_dir("rerun");
  fs::remove_all(out);
  run_into(out);
  ASSERT_TRUE(fs::exists(out + "/manifest.json"));
  // What an earlier, different run left: images of another frame, a killed writer's temporary.
  write_file_atomic(out + "/images/frame_99/kfr.png", "stale");
  write_file_atomic(out + "/.tmp.4242.frames.csv", "stale");
  write_file_atomic(out + "/notes.txt", "the user's");
  run_into(out);
  EXPECT_FALSE(fs::exists(out + "/images/frame_99"));
  EXPECT_FALSE(fs::exists(out + "/.tmp.4242.frames.csv"));
  EXPECT_TRUE(fs::exists(out + "/frames.csv"));
  EXPECT_TRUE(fs::exists(out + "/notes.txt"));  // not a run's output: kept
  {
    DirLock other(out, ".lock", "another fovsim run");  // a run in progress
    const std::string e = error_of([&] { run_into(out); });
    EXPECT_NE(e.find("another fovsim run is writing to this folder"), std::string::npos) << e;
  }
  fs::remove_all(out);
}

TEST(OutputFolder, SymlinkedImagesFolderIsRefused) {
  const std::string out = out_dir("link"), outside = out_dir("link_outside");
  fs::remove_all(out);
  fs::remove_all(outside);
  fs::create_directories(out);
  fs::create_directories(outside + "/frame_0");
  std::ofstream(outside + "/frame_0/reference.png") << "precious";
  fs::create_symlink(outside, out + "/images");
  // Not an earlier run's folder (no manifest): the link stays and is refused when written.
  const std::string e = error_of([&] { run_into(out, {{"image_frames", Json::array({0})}}); });
  EXPECT_NE(e.find("is a symbolic link inside the output folder"), std::string::npos) << e;
  std::ifstream f(outside + "/frame_0/reference.png");
  std::string kept((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_EQ(kept, "precious");
  fs::remove_all(out);
  fs::remove_all(outside);
}
