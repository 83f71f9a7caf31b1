// Helpers shared by the trace tests.
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/display/display.h"

namespace fovsim::test {

inline std::string src(const std::string& rel) {
  return std::string(FOVSIM_SOURCE_DIR) + "/" + rel;
}
inline Display vive() {
  return Display::load("htc_vive_pro_eye", src("models"));
}

// A per-test temporary directory.
inline std::string tmpdir() {
  auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string d = (std::filesystem::temp_directory_path() /
                   ("fovsim_trace_" + std::string(info->test_suite_name()) + "_" + info->name()))
                      .string();
  std::filesystem::create_directories(d);
  return d;
}
inline std::string write_tmp(const std::string& name, const std::string& content) {
  std::string p = tmpdir() + "/" + name;
  write_file_atomic(p, content);
  return p;
}

// Runs f, expects fovsim::Error whose text contains every needle; returns the message.
inline std::string expect_error(const std::function<void()>& f,
                                std::initializer_list<std::string> needles) {
  try {
    f();
  } catch (const Error& e) {
    std::string w = e.what();
    for (auto& n : needles)
      EXPECT_NE(w.find(n), std::string::npos) << "missing \"" << n << "\" in: " << w;
    return w;
  }
  ADD_FAILURE() << "expected fovsim::Error";
  return "";
}

}  // namespace fovsim::test
