// Helpers for tests that run the fovsim binary as a user would.
#pragma once
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fovsim_test {

struct CmdResult {
  int code = -1;
  std::string output;  // stdout + stderr
};

inline CmdResult run_cmd(const std::string& cmd) {
  CmdResult r;
  std::string full = "cd '" FOVSIM_SOURCE_DIR "' && " + cmd + " 2>&1";
  FILE* p = popen(full.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  int st = pclose(p);
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

inline std::string fovsim_bin() {
  return FOVSIM_BINARY;
}

inline std::string temp_dir(const std::string& name) {
  auto d = std::filesystem::temp_directory_path() /
           ("fovsim_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d.string();
}

inline void write_text(const std::string& path, const std::string& s) {
  std::ofstream f(path);
  f << s;
}

inline std::string read_text(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// Makes one `name` file below `dir` (a sweep's cell.json, a search's done.json) look as if another
// build of fovsim wrote it: its git_commit gets the prefix "older-". Returns the file, or "" when
// none has a git_commit.
inline std::string stamp_other_build(const std::string& dir, const std::string& name) {
  for (auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (e.path().filename() != name) continue;
    std::string text = read_text(e.path().string());
    const size_t key = text.find("\"git_commit\"");
    if (key == std::string::npos) continue;
    const size_t value = text.find('"', text.find(':', key));
    if (value == std::string::npos) continue;
    text.insert(value + 1, "older-");
    write_text(e.path().string(), text);
    return e.path().string();
  }
  return "";
}

// Parses a CSV with a header into columns (no quoted commas expected in numeric files).
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  int col(const std::string& name) const {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return int(i);
    return -1;
  }
};

inline std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool q = false;
  for (char c : line) {
    if (c == '"')
      q = !q;
    else if (c == ',' && !q) {
      out.push_back(cur);
      cur.clear();
    } else
      cur += c;
  }
  out.push_back(cur);
  return out;
}

inline Csv read_csv(const std::string& path) {
  Csv c;
  std::ifstream f(path);
  std::string line;
  bool first = true;
  while (std::getline(f, line)) {
    if (line.empty()) continue;
    if (first) {
      c.header = split_csv_line(line);
      first = false;
    } else {
      c.rows.push_back(split_csv_line(line));
    }
  }
  return c;
}

}  // namespace fovsim_test
