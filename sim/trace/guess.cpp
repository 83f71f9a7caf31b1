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
  std::map<char, int> idx;           // component -> 0-based field index
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

// Numeric values of a column over the first rows (unparsable fields skipped).
std::vector<double> column_values(const std::vector<CsvRow>& rows, size_t col,
                                  size_t max_rows = 400) {
  std::vector<double> out;
  for (size_t r = 1; r < rows.size() && r <= max_rows; ++r) {
    if (col >= rows[r].fields.size()) continue;
    double v = 0;
    std::string why;
    if (parse_number(rows[r].fields[col].text, v, why)) out.push_back(v);
  }
  return out;
}

// Statistics of a 3-column group over the first rows: the fraction of rows that are unit
// vectors (| |v| - 1 | < 0.05), the median length, and the median angle between consecutive
// rows' directions (deg).
struct VecStats {
  double unit_frac = 0, median_len = 0, median_step_deg = 0;
  long rows = 0;
};
VecStats vec_stats(const std::vector<CsvRow>& rows, int ix, int iy, int iz) {
  VecStats st;
  std::vector<double> lens, steps;
  long unit = 0;
  double px = NAN, py = NAN, pz = NAN;
  for (size_t r = 1; r < rows.size() && r <= 400; ++r) {
    const auto& f = rows[r].fields;
    if (size_t(std::max({ix, iy, iz})) >= f.size()) continue;
    double x, y, z;
    std::string why;
    if (!parse_number(f[size_t(ix)].text, x, why) || !parse_number(f[size_t(iy)].text, y, why) ||
        !parse_number(f[size_t(iz)].text, z, why))
      continue;
    double n = std::sqrt(x * x + y * y + z * z);
    ++st.rows;
    lens.push_back(n);
    if (std::fabs(n - 1) < 0.05) ++unit;
    if (n > 1e-9 && std::isfinite(px)) {
      double pn = std::sqrt(px * px + py * py + pz * pz);
      if (pn > 1e-9) {
        double c = (x * px + y * py + z * pz) / (n * pn);
        steps.push_back(std::acos(std::clamp(c, -1.0, 1.0)) * 180 / 3.14159265358979323846);
      }
    }
    px = x, py = y, pz = z;
  }
  auto med = [](std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  st.unit_frac = st.rows ? double(unit) / double(st.rows) : 0;
  st.median_len = med(lens);
  st.median_step_deg = med(steps);
  return st;
}

// Time unit named in a column name: "time(100ns)", "timestamp [ms]", "t_us", "time_s",
// "ticks" (100 ns, .NET DateTime ticks). Empty when none.
std::string unit_from_name(const std::string& name) {
  std::string n = lower(name);
  if (has(n, {"tick"})) return "100ns";
  // Inside brackets or parentheses.
  size_t b = n.find_first_of("[(");
  if (b != std::string::npos) {
    size_t e = n.find_first_of("])", b);
    std::string u = n.substr(b + 1, e == std::string::npos ? std::string::npos : e - b - 1);
    while (!u.empty() && u.front() == ' ') u.erase(u.begin());
    while (!u.empty() && u.back() == ' ') u.pop_back();
    if (u == "100ns" || u == "100 ns") return "100ns";
    if (u == "ns" || u == "us" || u == "ms" || u == "s") return u;
    if (u == "\xc2\xb5s" || u == "usec") return "us";
    if (u == "sec" || u == "seconds") return "s";
    if (u == "msec") return "ms";
  }
  // A suffix after a separator: "_100ns", "_ns", " ms", ".us", "_s".
  for (const char* u : {"100ns", "ns", "us", "ms", "s"}) {
    std::string su(u);
    if (n.size() > su.size() + 1 && n.compare(n.size() - su.size(), su.size(), su) == 0) {
      char sep = n[n.size() - su.size() - 1];
      if (sep == '_' || sep == ' ' || sep == '.' || sep == '-') return su;
    }
  }
  return "";
}

// A time column by name: "t", "...time...", "...timestamp...", "...TS" (oculoTS, unityTS),
// "..._ts", "ticks".
bool timeish(const std::string& name) {
  std::string n = lower(name);
  if (n == "t" || has(n, {"timestamp", "time", "tick"})) return true;
  if (n.size() > 2 && n[0] == 't' && std::string("_ [(").find(n[1]) != std::string::npos)
    return true;  // "t_ns", "t [s]"

  if (name.size() > 2 && name.compare(name.size() - 2, 2, "TS") == 0) return true;
  return n.size() > 3 && n.compare(n.size() - 3, 3, "_ts") == 0;
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
      groups.push_back({base, {}, {}, int(i), c});
      it = groups.end() - 1;
    }
    if (!it->cols.count(c)) {
      it->cols[c] = names[i].text;
      it->idx[c] = int(i);
    }
  }
  // A column reference: its name, or its 1-based index when the name occurs twice in the
  // header (the importer refuses a duplicated name).
  std::map<std::string, int> name_count;
  for (auto& f : names) ++name_count[f.text];
  bool dup_noted = false;
  auto ref = [&](int i) -> Json {
    const std::string& n = names[size_t(i)].text;
    if (name_count[n] < 2) return n;
    if (!dup_noted) {
      assume("column \"" + n +
             "\" appears more than once in the header: referred to by its "
             "1-based index");
      dup_noted = true;
    }
    return i + 1;
  };
  auto xyz = [&](const Group& g) {
    return Json::array({ref(g.idx.at('x')), ref(g.idx.at('y')), ref(g.idx.at('z'))});
  };
  auto is3 = [](const Group& g) {
    return g.cols.count('x') && g.cols.count('y') && g.cols.count('z');
  };
  bool unity_hint = false;
  for (auto& f : names)
    unity_hint = unity_hint || has(lower(f.text), {"unity", "euler", "eulerangles"});

  // Time: the first time-like column whose values increase (an eye-tracker clock next to an
  // engine clock: the first one).
  int tcol = -1;
  for (size_t i = 0; i < names.size() && tcol < 0; ++i) {
    if (!timeish(names[i].text)) continue;
    std::vector<double> v = column_values(rows, i, 50);
    bool inc = v.size() >= 2;
    for (size_t k = 1; k < v.size() && inc; ++k) inc = v[k] >= v[k - 1];
    if (inc) tcol = int(i);
  }
  if (tcol >= 0) {
    const std::string& tn = names[size_t(tcol)].text;
    double step = median_step(rows, size_t(tcol));
    std::string unit = unit_from_name(tn);
    char b[300];
    if (!unit.empty()) {
      std::snprintf(b, sizeof b, "time is column \"%s\" in %s (from its name; median step %.6g)",
                    tn.c_str(), unit.c_str(), step);
    } else {
      unit = "s";
      if (std::isfinite(step))
        unit = step < 0.5 ? "s" : step < 500 ? "ms" : step < 5e5 ? "us" : "ns";
      std::snprintf(b, sizeof b,
                    "time is column \"%s\" in %s, guessed from its median step %.6g (no unit in "
                    "the name: check the rate in the summary)",
                    tn.c_str(), unit.c_str(), step);
    }
    m["time"] = {{"column", ref(tcol)}, {"unit", unit}, {"rebase", true}};
    assume(b);
  } else {
    m["time"] = {{"column", "?"}, {"unit", "s"}};
    assume("no time column recognised: set time.column and time.unit");
  }

  // Head pose and gaze from the vector groups.
  bool pos = false, rot = false, gaze = false;
  Json left, right, point, combined;
  VecStats combined_st;
  std::string combined_name;
  std::vector<const Group*> other;  // x/y/z triples no name hint classifies ("C_x", "F_x")
  for (auto& g : groups) {
    const std::string& b = g.base;
    bool headish = has(b, {"head", "hmd", "cam", "camera", "pose"});
    bool eyeish = has(b, {"gaze", "eye"});
    if (!pos && headish && is3(g) && !g.cols.count('w') && has(b, {"pos", "_p", "translation"})) {
      m["head_position"] = {{"columns", xyz(g)}, {"unit", "m"}};
      assume("head position from \"" + g.cols.at('x') + "\"...: metres");
      pos = true;
    } else if (!gaze && eyeish && is3(g) && g.cols.count('w')) {
      // A gaze pose (OpenXR eye gaze): its -Z axis.
      bool wfirst = g.first_comp == 'w';
      Json cols = wfirst ? Json::array({ref(g.idx.at('w')), ref(g.idx.at('x')), ref(g.idx.at('y')),
                                        ref(g.idx.at('z'))})
                         : Json::array({ref(g.idx.at('x')), ref(g.idx.at('y')), ref(g.idx.at('z')),
                                        ref(g.idx.at('w'))});
      m["gaze"] = {{"type", "orientation"},
                   {"space", "world"},
                   {"columns", cols},
                   {"order", wfirst ? "wxyz" : "xyzw"},
                   {"forward", "-z"}};
      assume("gaze is the -Z axis of the world-space gaze pose \"" + g.cols.at('x') + "\"...");
      gaze = true;
    } else if (!rot && headish && is3(g) &&
               has(b, {"rot", "quat", "orient", "_q", "_r", "euler"})) {
      if (g.cols.count('w')) {
        bool wfirst = g.first_comp == 'w';
        Json cols = wfirst ? Json::array({ref(g.idx.at('w')), ref(g.idx.at('x')),
                                          ref(g.idx.at('y')), ref(g.idx.at('z'))})
                           : Json::array({ref(g.idx.at('x')), ref(g.idx.at('y')),
                                          ref(g.idx.at('z')), ref(g.idx.at('w'))});
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
      else if (!l && !r && combined.is_null()) {
        combined = {{"type", "direction"}, {"space", "head"}, {"columns", xyz(g)}};
        combined_st = vec_stats(rows, g.idx.at('x'), g.idx.at('y'), g.idx.at('z'));
        combined_name = g.cols.at('x');
      }
    } else if (eyeish && is3(g) && has(b, {"point"}) && point.is_null()) {
      point = {{"type", "point"}, {"columns", xyz(g)}, {"unit", has(b, {"3d"}) ? "mm" : "m"}};
    } else if (is3(g) && !g.cols.count('w') && !eyeish) {
      other.push_back(&g);
    }
  }
  // Gaze angles (Pupil Cloud): "azimuth [deg]", "elevation [deg]".
  if (!gaze) {
    int az = -1, el = -1;
    for (size_t i = 0; i < names.size(); ++i) {
      std::string n = lower(names[i].text);
      if (az < 0 && has(n, {"azimuth"})) az = int(i);
      if (el < 0 && has(n, {"elevation"})) el = int(i);
    }
    if (az >= 0 && el >= 0) {
      bool rad = has(lower(names[size_t(az)].text), {"rad"});
      m["gaze"] = {{"type", "angles"},
                   {"columns", {ref(az), ref(el)}},
                   {"unit", rad ? "rad" : "deg"},
                   {"signs", {1, 1}}};
      assume(std::string("gaze is azimuth (right +) and elevation (up +) in ") +
             (rad ? "radians" : "degrees") + " in the head");
      gaze = true;
    }
  }
  // A combined gaze whose values are not directions (zero, sentinel or broken in most rows)
  // loses to per-eye directions.
  const bool per_eye = !left.is_null() && !right.is_null();
  if (!combined.is_null()) {
    bool plausible = combined_st.unit_frac >= 0.5 ||
                     (combined_st.median_len > 1e-6 && combined_st.median_len < 1e3 &&
                      combined_st.unit_frac > 0 && !per_eye);
    if (plausible || !per_eye) {
      m["gaze"] = combined;
      gaze = true;
      if (!plausible) {
        char b[200];
        std::snprintf(b, sizeof b,
                      "the combined gaze \"%s\"... is a unit vector in only %.0f %% of the first "
                      "rows: check it",
                      combined_name.c_str(), 100.0 * combined_st.unit_frac);
        assume(b);
      }
    } else {
      char b[240];
      std::snprintf(b, sizeof b,
                    "the combined gaze \"%s\"... is a unit vector in only %.0f %% of the first "
                    "rows: the per-eye directions are used instead",
                    combined_name.c_str(), 100.0 * combined_st.unit_frac);
      assume(b);
    }
  }
  // Triples named only by an x/y/z suffix: unit vectors are directions, others positions.
  if (!other.empty()) {
    std::vector<std::pair<const Group*, VecStats>> dirs, poss;
    for (const Group* g : other) {
      VecStats st = vec_stats(rows, g->idx.at('x'), g->idx.at('y'), g->idx.at('z'));
      if (st.rows == 0) continue;
      (st.unit_frac >= 0.9 ? dirs : poss).push_back({g, st});
    }
    for (auto& [g, st] : poss) {
      if (pos) break;
      m["head_position"] = {{"columns", xyz(*g)}, {"unit", "m"}};
      char b[260];
      std::snprintf(b, sizeof b,
                    "head position from \"%s\"... (not unit vectors: median distance from the "
                    "origin %.3g), in metres",
                    g->cols.at('x').c_str(), st.median_len);
      assume(b);
      pos = true;
    }
    if (!rot && dirs.size() >= 2) {
      // Head forward: named so ("F_", "forward"), else the direction that turns slower (the
      // gaze moves with the head and the eye).
      size_t f = 0;
      bool named = false;
      for (size_t k = 0; k < dirs.size(); ++k) {
        const std::string& b = dirs[k].first->base;
        if (has(b, {"forward", "fwd"}) || b == "f_" || b == "f" || b == "f.") {
          f = k;
          named = true;
        }
      }
      if (!named)
        for (size_t k = 1; k < dirs.size(); ++k)
          if (dirs[k].second.median_step_deg < dirs[f].second.median_step_deg) f = k;
      size_t gk = f == 0 ? 1 : 0;
      m["head_orientation"] = {{"type", "forward"}, {"forward", xyz(*dirs[f].first)}};
      assume("head orientation from the unit vectors \"" + dirs[f].first->cols.at('x') + "\"... (" +
             (named ? "named forward" : "the slower-turning direction") + "), no roll");
      rot = true;
      if (!gaze) {
        m["gaze"] = {{"type", "direction"}, {"space", "world"}, {"columns", xyz(*dirs[gk].first)}};
        assume("gaze is the world direction \"" + dirs[gk].first->cols.at('x') +
               "\"... (unit vectors, turning faster than the head forward)");
        gaze = true;
      }
    } else if (!gaze && !dirs.empty()) {
      m["gaze"] = {{"type", "direction"}, {"space", "head"}, {"columns", xyz(*dirs[0].first)}};
      assume("gaze is the unit vector \"" + dirs[0].first->cols.at('x') + "\"...");
      gaze = true;
    }
  }
  if (!gaze && per_eye) {
    m["gaze"] = {{"type", "direction"},
                 {"space", "head"},
                 {"left", left},
                 {"right", right},
                 {"combine", "mean"}};
    gaze = true;
  }
  if (!gaze && left.is_null() != right.is_null()) {
    // One eye's direction only (a monocular tracker, or an export of one eye): that eye.
    const Json& one = left.is_null() ? right : left;
    m["gaze"] = {{"type", "direction"}, {"space", "head"}, {"columns", one}};
    assume(std::string("gaze is the ") + (left.is_null() ? "right" : "left") + " eye's direction " +
           one[0].dump() + "... (the only per-eye direction in the file)");
    gaze = true;
  }
  if (!gaze && !point.is_null()) {
    // Only when no gaze direction is given: a point may be in head space rather than world.
    m["gaze"] = point;
    assume("gaze is a world point looked at (" + point["columns"][0].dump() + "...), in " +
           point["unit"].get<std::string>());
    gaze = true;
  }
  if (gaze && m["gaze"]["type"] == "direction" && m["gaze"]["space"] == "head")
    assume(
        "gaze direction is in head space (set gaze.space to \"world\" if it follows the head's "
        "turns)");
  if (!pos) {
    // A gaze point without a head pose is in the eye camera's frame: the head at the origin.
    const bool pt = gaze && m["gaze"]["type"] == "point";
    m["head_position"] = {{"constant", pt ? Json::array({0, 0, 0}) : Json::array({0, 1.6, 0})}};
    assume(pt ? "no head position columns: the gaze point is relative to the eye, head at the "
                "origin"
              : "no head position columns: constant (0, 1.6, 0) m");
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
      valid.push_back(
          {{"column", ref(int(&f - &names[0]))}, {"valid_values", {"False", "false", "0"}}});
      assume("\"" + f.text + "\" True/1 means blinking (invalid)");
    } else if (has(n, {"confidence"})) {
      valid.push_back({{"column", ref(int(&f - &names[0]))}, {"min", 0.6}});
      assume("\"" + f.text + "\" >= 0.6 is a valid sample");
    } else if (has(n, {"valid"})) {
      // A bitmask (SRanipal eye_valid = 31 with every bit set) has integer values above 1.
      const int ci = int(&f - &names[0]);
      std::vector<double> v = column_values(rows, size_t(ci));
      double mx = 0;
      bool ints = !v.empty();
      for (double x : v) {
        ints = ints && x == std::floor(x) && x >= 0 && x < 2147483648.0;
        mx = std::max(mx, x);
      }
      Json cond = {{"column", ref(ci)}};
      if (per_eye && m["gaze"].contains("left")) {
        bool l = has(n, {"left", "_l"}) && !has(n, {"right"});
        bool r = has(n, {"right", "_r"}) && !l;
        if (l) cond["eye"] = "left";
        if (r) cond["eye"] = "right";
      }
      if (ints && mx > 1) {
        long long all = (long long)mx;
        bool full = (all & (all + 1)) == 0;  // 2^k - 1: every bit set
        if (full) {
          cond["all_bits"] = all;
          char b[240];
          std::snprintf(b, sizeof b,
                        "\"%s\" is a bitmask: valid when all bits of %lld are set (the largest "
                        "value in the file; SRanipal's gaze-direction bit alone is all_bits 2)",
                        f.text.c_str(), all);
          assume(b);
        } else {
          cond["valid_values"] = {std::to_string(all)};
          assume("\"" + f.text + "\" is a status code: " + std::to_string(all) +
                 " (its largest value) is valid");
        }
      } else {
        cond["valid_values"] = {"1", "True", "true"};
        assume("\"" + f.text + "\" = 1/True is valid");
      }
      valid.push_back(cond);
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
