#include "sim/trace/guess.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <vector>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/trace/csv_table.h"

namespace fovsim {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower((unsigned char)c));
  return s;
}

bool has(const std::string& s, std::initializer_list<const char*> words) {
  for (const char* w : words)
    if (s.find(w) != std::string::npos) return true;
  return false;
}

// "Head Position. x" -> ("head position.", 'x'); "gaze_direction_L.x [mm]" -> ("gaze_direction_l.",
// 'x').
bool split_component(const std::string& name, std::string& base, char& comp) {
  std::string n = lower(name);
  size_t b = n.find_first_of("[(");
  if (b != std::string::npos && b > 0) n = n.substr(0, b);
  while (!n.empty() && n.back() == ' ') n.pop_back();
  if (n.size() < 2) return false;
  char c = n.back();
  if (c != 'x' && c != 'y' && c != 'z' && c != 'w') return false;
  base = n.substr(0, n.size() - 1);
  comp = c;
  return true;
}

struct Group {
  std::string base;
  std::map<char, std::string> cols;  // component -> original column name
  int first = 0;                     // position of the first column
  char first_comp = 0;
};

double median_step(const std::vector<CsvRow>& rows, size_t col) {
  std::vector<double> d;
  double prev = NAN;
  for (size_t r = 1; r < rows.size() && d.size() < 200; ++r) {
    if (col >= rows[r].fields.size()) continue;
    double v = 0;
    std::string why;
    if (!parse_number(rows[r].fields[col].text, v, why)) continue;
    if (!std::isnan(prev) && v > prev) d.push_back(v - prev);
    prev = v;
  }
  if (d.empty()) return NAN;
  std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
  return d[d.size() / 2];
}

}  // namespace

Json guess_map(const std::string& in) {
  std::string text = read_file(in);
  size_t nl = text.find_first_of("\r\n");
  std::string line0 = text.substr(0, nl);
  std::vector<std::string> notes;
  auto assume = [&](const std::string& s) { notes.push_back("ASSUMPTION: " + s); };
  // Delimiter: tab, else the more frequent of ';' and ',', else space (names may contain spaces).
  auto count = [&](char c) { return long(std::count(line0.begin(), line0.end(), c)); };
  char delim = ' ';
  const char* dname = "space";
  if (count('\t') > 0)
    delim = '\t', dname = "tab";
  else if (count(';') > 0 && count(';') >= count(','))
    delim = ';', dname = "semicolon";
  else if (count(',') > 0)
    delim = ',', dname = "comma";
  assume(std::string("the delimiter is ") + dname);
  std::vector<CsvRow> rows = read_csv_rows(in, delim, 0);
  if (rows.size() < 2)
    throw Error(in, "too few rows to guess a map (need a header or first row and data)");
  Json m = Json::object();
  m["delimiter"] = dname;
  // Header: the first row has a non-numeric field.
  bool header = false;
  for (auto& f : rows[0].fields) {
    double v;
    std::string why;
    if (!parse_number(f.text, v, why)) header = true;
  }
  m["header"] = header;
  if (!header) {
    assume("no header row: columns are numbered; name them in the map by 1-based index");
    m["comment"] = notes;
    return m;
  }
  const auto& names = rows[0].fields;
  // Vector groups by common base name.
  std::vector<Group> groups;
  for (size_t i = 0; i < names.size(); ++i) {
    std::string base;
    char c;
    if (!split_component(names[i].text, base, c)) continue;
    auto it =
        std::find_if(groups.begin(), groups.end(), [&](const Group& g) { return g.base == base; });
    if (it == groups.end()) {
      groups.push_back({base, {}, int(i), c});
      it = groups.end() - 1;
    }
    if (!it->cols.count(c)) it->cols[c] = names[i].text;
  }
  auto xyz = [](const Group& g) {
    return Json::array({g.cols.at('x'), g.cols.at('y'), g.cols.at('z')});
  };
  auto is3 = [](const Group& g) {
    return g.cols.count('x') && g.cols.count('y') && g.cols.count('z');
  };
  bool unity_hint = false;
  for (auto& f : names)
    unity_hint = unity_hint || has(lower(f.text), {"unity", "euler", "eulerangles"});

  // Time.
  int tcol = -1;
  for (size_t i = 0; i < names.size() && tcol < 0; ++i) {
    std::string n = lower(names[i].text);
    if (n == "t" || has(n, {"timestamp", "time"})) tcol = int(i);
  }
  if (tcol >= 0) {
    std::string n = lower(names[size_t(tcol)].text);
    double step = median_step(rows, size_t(tcol));
    std::string unit = "s";
    if (has(n, {"[ns]", "_ns", "(ns)"}))
      unit = "ns";
    else if (has(n, {"[us]", "_us", "(us)"}))
      unit = "us";
    else if (has(n, {"[ms]", "_ms", "(ms)"}))
      unit = "ms";
    else if (std::isfinite(step))
      unit = step < 0.5 ? "s" : step < 500 ? "ms" : step < 5e5 ? "us" : "ns";
    m["time"] = {{"column", names[size_t(tcol)].text}, {"unit", unit}, {"rebase", true}};
    char b[200];
    std::snprintf(b, sizeof b, "time is column \"%s\" in %s (median step %.6g in the file)",
                  names[size_t(tcol)].text.c_str(), unit.c_str(), step);
    assume(b);
  } else {
    m["time"] = {{"column", "?"}, {"unit", "s"}};
    assume("no time column recognised: set time.column and time.unit");
  }

  // Head pose and gaze from the vector groups.
  bool pos = false, rot = false, gaze = false;
  Json left, right, point;
  for (auto& g : groups) {
    const std::string& b = g.base;
    bool headish = has(b, {"head", "hmd", "cam", "camera", "pose"});
    bool eyeish = has(b, {"gaze", "eye"});
    if (!pos && headish && is3(g) && !g.cols.count('w') && has(b, {"pos", "_p", "translation"})) {
      m["head_position"] = {{"columns", xyz(g)}, {"unit", "m"}};
      assume("head position from \"" + g.cols.at('x') + "\"...: metres");
      pos = true;
    } else if (!rot && headish && is3(g) && has(b, {"rot", "quat", "orient", "_q"})) {
      if (g.cols.count('w')) {
        bool wfirst = g.first_comp == 'w';
        Json cols =
            wfirst ? Json::array({g.cols.at('w'), g.cols.at('x'), g.cols.at('y'), g.cols.at('z')})
                   : Json::array({g.cols.at('x'), g.cols.at('y'), g.cols.at('z'), g.cols.at('w')});
        m["head_orientation"] = {
            {"type", "quaternion"}, {"columns", cols}, {"order", wfirst ? "wxyz" : "xyzw"}};
        assume("head orientation is a world-from-head quaternion (not head-from-world)");
      } else {
        m["head_orientation"] = {{"type", "euler"},
                                 {"columns", xyz(g)},
                                 {"order", "ZXY"},
                                 {"sequence", "extrinsic"},
                                 {"unit", "deg"}};
        assume("head orientation is Euler angles in degrees applied Z, X, Y (Unity eulerAngles)");
        unity_hint = true;
      }
      rot = true;
    } else if (headish && is3(g) && has(b, {"forward", "fwd"}) && !rot) {
      m["head_orientation"] = {{"type", "forward"}, {"forward", xyz(g)}};
      assume("head orientation from the forward vector \"" + g.cols.at('x') + "\"..., no roll");
      rot = true;
    } else if (eyeish && is3(g) && has(b, {"dir", "vector", "forward", "normal"}) &&
               !has(b, {"origin"})) {
      bool l = has(b, {"left", "_l.", "_l_", " l."}) && !has(b, {"right"});
      bool r = has(b, {"right", "_r.", "_r_", " r."}) && !l;
      if (l && left.is_null())
        left = xyz(g);
      else if (r && right.is_null())
        right = xyz(g);
      else if (!l && !r && !gaze) {
        m["gaze"] = {{"type", "direction"}, {"space", "head"}, {"columns", xyz(g)}};
        gaze = true;
      }
    } else if (eyeish && is3(g) && has(b, {"point"}) && point.is_null()) {
      point = {{"type", "point"}, {"columns", xyz(g)}, {"unit", has(b, {"3d"}) ? "mm" : "m"}};
    }
  }
  if (!gaze && !left.is_null() && !right.is_null()) {
    m["gaze"] = {{"type", "direction"},
                 {"space", "head"},
                 {"left", left},
                 {"right", right},
                 {"combine", "mean"}};
    gaze = true;
  }
  if (!gaze && !point.is_null()) {
    // Only when no gaze direction is given: a point may be in head space rather than world.
    m["gaze"] = point;
    assume("gaze is a world point looked at (\"" + point["columns"][0].get<std::string>() +
           "\"...), in " + point["unit"].get<std::string>());
    gaze = true;
  }
  if (gaze && m["gaze"]["type"] == "direction")
    assume(
        "gaze direction is in head space (set gaze.space to \"world\" if it follows the head's "
        "turns)");
  if (!pos) {
    m["head_position"] = {{"constant", {0, 1.6, 0}}};
    assume("no head position columns: constant (0, 1.6, 0) m");
  }
  if (!rot) {
    m["head_orientation"] = {{"constant", {1, 0, 0, 0}}};
    assume("no head orientation columns: constant identity");
  }
  if (!gaze) {
    m["gaze"] = {{"type", "direction"}, {"space", "head"}, {"columns", {"?", "?", "?"}}};
    assume("no gaze columns recognised: set gaze");
  }
  m["coordinates"] = unity_hint ? "unity" : "opengl";
  assume(unity_hint ? "coordinates are Unity's (left-handed, +Y up, +Z forward)"
                    : "coordinates are OpenGL/OpenXR (right-handed, +Y up, -Z forward): check a "
                      "frame where the user "
                      "looks right (fovsim gx > 0)");

  // Validity columns.
  Json valid = Json::array();
  for (auto& f : names) {
    std::string n = lower(f.text);
    if (has(n, {"blink"})) {
      valid.push_back({{"column", f.text}, {"valid_values", {"False", "false", "0"}}});
      assume("\"" + f.text + "\" True/1 means blinking (invalid)");
    } else if (has(n, {"confidence"})) {
      valid.push_back({{"column", f.text}, {"min", 0.6}});
      assume("\"" + f.text + "\" >= 0.6 is a valid sample");
    } else if (has(n, {"valid"})) {
      valid.push_back({{"column", f.text}, {"valid_values", {"1", "True", "true"}}});
      assume("\"" + f.text + "\" = 1/True is valid (a bitmask needs all_bits instead)");
    }
  }
  if (!valid.empty()) m["valid"] = valid;
  m["on_bad_row"] = "fail";
  Json c = Json::array();
  c.push_back("Guessed by fovsim trace import --guess from " + in +
              ": check every ASSUMPTION, then run "
              "fovsim trace import with this map and read its summary (eccentricity, eye speed)");
  for (auto& n : notes) c.push_back(n);
  m["comment"] = c;
  return m;
}

}  // namespace fovsim
