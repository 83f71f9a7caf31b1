#include "sim/trace/guess.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <vector>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/text.h"
#include "sim/trace/csv_table.h"

namespace fovsim {

namespace {

// "Head Position. x" -> ("head position.", 'x'); "gaze_direction_L.x [mm]" -> ("gaze_direction_l.",
// 'x').
bool split_component(const std::string& name, std::string& base, char& comp) {
  std::string n = ascii_lower(name);
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
  std::string n = ascii_lower(name);
  if (contains_any(n, {"tick"})) return "100ns";
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
  std::string n = ascii_lower(name);
  if (n == "t" || contains_any(n, {"timestamp", "time", "tick"})) return true;
  if (n.size() > 2 && n[0] == 't' && std::string("_ [(").find(n[1]) != std::string::npos)
    return true;  // "t_ns", "t [s]"

  if (name.size() > 2 && name.compare(name.size() - 2, 2, "TS") == 0) return true;
  return n.size() > 3 && n.compare(n.size() - 3, 3, "_ts") == 0;
}

// One guess in progress: the rows read, the map being written and its ASSUMPTION notes.
struct MapGuess {
  std::string in;
  std::vector<CsvRow> rows;
  Json m = Json::object();
  std::vector<std::string> notes;
  std::map<std::string, int> name_count;
  bool dup_noted = false;

  const std::vector<CsvField>& names() const { return rows[0].fields; }
  void assume(const std::string& s) { notes.push_back("ASSUMPTION: " + s); }
  // A column reference: its name, or its 1-based index when the name occurs twice in the
  // header (the importer refuses a duplicated name).
  Json ref(int i) {
    const std::string& n = names()[size_t(i)].text;
    if (name_count[n] < 2) return n;
    if (!dup_noted) {
      assume("column \"" + n +
             "\" appears more than once in the header: referred to by its "
             "1-based index");
      dup_noted = true;
    }
    return i + 1;
  }
  Json xyz(const Group& g) {
    return Json::array({ref(g.idx.at('x')), ref(g.idx.at('y')), ref(g.idx.at('z'))});
  }
  // A quaternion's columns in the file's order (w first or last).
  Json quat(const Group& g) {
    return g.first_comp == 'w' ? Json::array({ref(g.idx.at('w')), ref(g.idx.at('x')),
                                              ref(g.idx.at('y')), ref(g.idx.at('z'))})
                               : Json::array({ref(g.idx.at('x')), ref(g.idx.at('y')),
                                              ref(g.idx.at('z')), ref(g.idx.at('w'))});
  }
};

bool is3(const Group& g) {
  return g.cols.count('x') && g.cols.count('y') && g.cols.count('z');
}

// Tab, else the more frequent of ';' and ',', else space (names may contain spaces).
char guess_delimiter(const std::string& line0, const char*& dname) {
  auto count = [&](char c) { return long(std::count(line0.begin(), line0.end(), c)); };
  char delim = ' ';
  dname = "space";
  if (count('\t') > 0)
    delim = '\t', dname = "tab";
  else if (count(';') > 0 && count(';') >= count(','))
    delim = ';', dname = "semicolon";
  else if (count(',') > 0)
    delim = ',', dname = "comma";
  return delim;
}

// Vector groups by common base name ("head_pos.x", "head_pos.y", ...).
std::vector<Group> vector_groups(const std::vector<CsvField>& names) {
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
  return groups;
}

// Time: the first time-like column whose values increase (an eye-tracker clock next to an
// engine clock: the first one); its unit from the name, else from the median step.
void guess_time(MapGuess& G) {
  const auto& names = G.names();
  int tcol = -1;
  for (size_t i = 0; i < names.size() && tcol < 0; ++i) {
    if (!timeish(names[i].text)) continue;
    std::vector<double> v = column_values(G.rows, i, 50);
    bool inc = v.size() >= 2;
    for (size_t k = 1; k < v.size() && inc; ++k) inc = v[k] >= v[k - 1];
    if (inc) tcol = int(i);
  }
  if (tcol < 0) {
    G.m["time"] = {{"column", "?"}, {"unit", "s"}};
    G.assume("no time column recognised: set time.column and time.unit");
    return;
  }
  const std::string& tn = names[size_t(tcol)].text;
  double step = median_step(G.rows, size_t(tcol));
  std::string unit = unit_from_name(tn);
  char b[300];
  if (!unit.empty()) {
    std::snprintf(b, sizeof b, "time is column \"%s\" in %s (from its name; median step %.6g)",
                  tn.c_str(), unit.c_str(), step);
  } else {
    unit = "s";
    if (std::isfinite(step)) unit = step < 0.5 ? "s" : step < 500 ? "ms" : step < 5e5 ? "us" : "ns";
    std::snprintf(b, sizeof b,
                  "time is column \"%s\" in %s, guessed from its median step %.6g (no unit in "
                  "the name: check the rate in the summary)",
                  tn.c_str(), unit.c_str(), step);
  }
  G.m["time"] = {{"column", G.ref(tcol)}, {"unit", unit}, {"rebase", true}};
  G.assume(b);
}

// What the vector groups and named columns say about head pose and gaze so far.
struct PoseGuess {
  bool pos = false, rot = false, gaze = false, unity_hint = false;
  Json left, right, point, combined;
  VecStats combined_st;
  std::string combined_name;
  std::vector<const Group*> other;  // x/y/z triples no name hint classifies ("C_x", "F_x")
  bool per_eye() const { return !left.is_null() && !right.is_null(); }
};

// Head position, head orientation and gaze from the groups' names.
void classify_groups(MapGuess& G, const std::vector<Group>& groups, PoseGuess& P) {
  Json& m = G.m;
  for (auto& g : groups) {
    const std::string& b = g.base;
    bool headish = contains_any(b, {"head", "hmd", "cam", "camera", "pose"});
    bool eyeish = contains_any(b, {"gaze", "eye"});
    if (!P.pos && headish && is3(g) && !g.cols.count('w') &&
        contains_any(b, {"pos", "_p", "translation"})) {
      m["head_position"] = {{"columns", G.xyz(g)}, {"unit", "m"}};
      G.assume("head position from \"" + g.cols.at('x') + "\"...: metres");
      P.pos = true;
    } else if (!P.gaze && eyeish && is3(g) && g.cols.count('w')) {
      // A gaze pose (OpenXR eye gaze): its -Z axis.
      m["gaze"] = {{"type", "orientation"},
                   {"space", "world"},
                   {"columns", G.quat(g)},
                   {"order", g.first_comp == 'w' ? "wxyz" : "xyzw"},
                   {"forward", "-z"}};
      G.assume("gaze is the -Z axis of the world-space gaze pose \"" + g.cols.at('x') + "\"...");
      P.gaze = true;
    } else if (!P.rot && headish && is3(g) &&
               contains_any(b, {"rot", "quat", "orient", "_q", "_r", "euler"})) {
      if (g.cols.count('w')) {
        m["head_orientation"] = {{"type", "quaternion"},
                                 {"columns", G.quat(g)},
                                 {"order", g.first_comp == 'w' ? "wxyz" : "xyzw"}};
        G.assume("head orientation is a world-from-head quaternion (not head-from-world)");
      } else {
        m["head_orientation"] = {{"type", "euler"},
                                 {"columns", G.xyz(g)},
                                 {"order", "ZXY"},
                                 {"sequence", "extrinsic"},
                                 {"unit", "deg"}};
        G.assume("head orientation is Euler angles in degrees applied Z, X, Y (Unity eulerAngles)");
        P.unity_hint = true;
      }
      P.rot = true;
    } else if (headish && is3(g) && contains_any(b, {"forward", "fwd"}) && !P.rot) {
      m["head_orientation"] = {{"type", "forward"}, {"forward", G.xyz(g)}};
      G.assume("head orientation from the forward vector \"" + g.cols.at('x') + "\"..., no roll");
      P.rot = true;
    } else if (eyeish && is3(g) && contains_any(b, {"dir", "vector", "forward", "normal"}) &&
               !contains_any(b, {"origin"})) {
      bool l = contains_any(b, {"left", "_l.", "_l_", " l."}) && !contains_any(b, {"right"});
      bool r = contains_any(b, {"right", "_r.", "_r_", " r."}) && !l;
      if (l && P.left.is_null())
        P.left = G.xyz(g);
      else if (r && P.right.is_null())
        P.right = G.xyz(g);
      else if (!l && !r && P.combined.is_null()) {
        P.combined = {{"type", "direction"}, {"space", "head"}, {"columns", G.xyz(g)}};
        P.combined_st = vec_stats(G.rows, g.idx.at('x'), g.idx.at('y'), g.idx.at('z'));
        P.combined_name = g.cols.at('x');
      }
    } else if (eyeish && is3(g) && contains_any(b, {"point"}) && P.point.is_null()) {
      P.point = {
          {"type", "point"}, {"columns", G.xyz(g)}, {"unit", contains_any(b, {"3d"}) ? "mm" : "m"}};
    } else if (is3(g) && !g.cols.count('w') && !eyeish) {
      P.other.push_back(&g);
    }
  }
}

// Gaze angles (Pupil Cloud): "azimuth [deg]", "elevation [deg]".
void guess_gaze_angles(MapGuess& G, PoseGuess& P) {
  if (P.gaze) return;
  const auto& names = G.names();
  int az = -1, el = -1;
  for (size_t i = 0; i < names.size(); ++i) {
    std::string n = ascii_lower(names[i].text);
    if (az < 0 && contains_any(n, {"azimuth"})) az = int(i);
    if (el < 0 && contains_any(n, {"elevation"})) el = int(i);
  }
  if (az < 0 || el < 0) return;
  bool rad = contains_any(ascii_lower(names[size_t(az)].text), {"rad"});
  G.m["gaze"] = {{"type", "angles"},
                 {"columns", {G.ref(az), G.ref(el)}},
                 {"unit", rad ? "rad" : "deg"},
                 {"signs", {1, 1}}};
  G.assume(std::string("gaze is azimuth (right +) and elevation (up +) in ") +
           (rad ? "radians" : "degrees") + " in the head");
  P.gaze = true;
}

// A combined gaze whose values are not directions (zero, sentinel or broken in most rows)
// loses to per-eye directions.
void choose_combined_gaze(MapGuess& G, PoseGuess& P) {
  if (P.combined.is_null()) return;
  const bool per_eye = P.per_eye();
  const VecStats& st = P.combined_st;
  bool plausible = st.unit_frac >= 0.5 ||
                   (st.median_len > 1e-6 && st.median_len < 1e3 && st.unit_frac > 0 && !per_eye);
  if (plausible || !per_eye) {
    G.m["gaze"] = P.combined;
    P.gaze = true;
    if (!plausible) {
      char b[200];
      std::snprintf(b, sizeof b,
                    "the combined gaze \"%s\"... is a unit vector in only %.0f %% of the first "
                    "rows: check it",
                    P.combined_name.c_str(), 100.0 * st.unit_frac);
      G.assume(b);
    }
  } else {
    char b[240];
    std::snprintf(b, sizeof b,
                  "the combined gaze \"%s\"... is a unit vector in only %.0f %% of the first "
                  "rows: the per-eye directions are used instead",
                  P.combined_name.c_str(), 100.0 * st.unit_frac);
    G.assume(b);
  }
}

// Triples named only by an x/y/z suffix: unit vectors are directions, others positions.
void guess_unnamed_triples(MapGuess& G, PoseGuess& P) {
  if (P.other.empty()) return;
  Json& m = G.m;
  std::vector<std::pair<const Group*, VecStats>> dirs, poss;
  for (const Group* g : P.other) {
    VecStats st = vec_stats(G.rows, g->idx.at('x'), g->idx.at('y'), g->idx.at('z'));
    if (st.rows == 0) continue;
    (st.unit_frac >= 0.9 ? dirs : poss).push_back({g, st});
  }
  for (auto& [g, st] : poss) {
    if (P.pos) break;
    m["head_position"] = {{"columns", G.xyz(*g)}, {"unit", "m"}};
    char b[260];
    std::snprintf(b, sizeof b,
                  "head position from \"%s\"... (not unit vectors: median distance from the "
                  "origin %.3g), in metres",
                  g->cols.at('x').c_str(), st.median_len);
    G.assume(b);
    P.pos = true;
  }
  if (!P.rot && dirs.size() >= 2) {
    // Head forward: named so ("F_", "forward"), else the direction that turns slower (the
    // gaze moves with the head and the eye).
    size_t f = 0;
    bool named = false;
    for (size_t k = 0; k < dirs.size(); ++k) {
      const std::string& b = dirs[k].first->base;
      if (contains_any(b, {"forward", "fwd"}) || b == "f_" || b == "f" || b == "f.") {
        f = k;
        named = true;
      }
    }
    if (!named)
      for (size_t k = 1; k < dirs.size(); ++k)
        if (dirs[k].second.median_step_deg < dirs[f].second.median_step_deg) f = k;
    size_t gk = f == 0 ? 1 : 0;
    m["head_orientation"] = {{"type", "forward"}, {"forward", G.xyz(*dirs[f].first)}};
    G.assume("head orientation from the unit vectors \"" + dirs[f].first->cols.at('x') + "\"... (" +
             (named ? "named forward" : "the slower-turning direction") + "), no roll");
    P.rot = true;
    if (!P.gaze) {
      m["gaze"] = {{"type", "direction"}, {"space", "world"}, {"columns", G.xyz(*dirs[gk].first)}};
      G.assume("gaze is the world direction \"" + dirs[gk].first->cols.at('x') +
               "\"... (unit vectors, turning faster than the head forward)");
      P.gaze = true;
    }
  } else if (!P.gaze && !dirs.empty()) {
    m["gaze"] = {{"type", "direction"}, {"space", "head"}, {"columns", G.xyz(*dirs[0].first)}};
    G.assume("gaze is the unit vector \"" + dirs[0].first->cols.at('x') + "\"...");
    P.gaze = true;
  }
}

// What is still missing: per-eye or one-eye directions, a gaze point, then constants and
// placeholders; the coordinate convention.
void guess_fallbacks(MapGuess& G, PoseGuess& P) {
  Json& m = G.m;
  if (!P.gaze && P.per_eye()) {
    m["gaze"] = {{"type", "direction"},
                 {"space", "head"},
                 {"left", P.left},
                 {"right", P.right},
                 {"combine", "mean"}};
    P.gaze = true;
  }
  if (!P.gaze && P.left.is_null() != P.right.is_null()) {
    // One eye's direction only (a monocular tracker, or an export of one eye): that eye.
    const Json& one = P.left.is_null() ? P.right : P.left;
    m["gaze"] = {{"type", "direction"}, {"space", "head"}, {"columns", one}};
    G.assume(std::string("gaze is the ") + (P.left.is_null() ? "right" : "left") +
             " eye's direction " + one[0].dump() + "... (the only per-eye direction in the file)");
    P.gaze = true;
  }
  if (!P.gaze && !P.point.is_null()) {
    // Only when no gaze direction is given: a point may be in head space rather than world.
    m["gaze"] = P.point;
    G.assume("gaze is a world point looked at (" + P.point["columns"][0].dump() + "...), in " +
             P.point["unit"].get<std::string>());
    P.gaze = true;
  }
  if (P.gaze && m["gaze"]["type"] == "direction" && m["gaze"]["space"] == "head")
    G.assume(
        "gaze direction is in head space (set gaze.space to \"world\" if it follows the head's "
        "turns)");
  if (!P.pos) {
    // A gaze point without a head pose is in the eye camera's frame: the head at the origin.
    const bool pt = P.gaze && m["gaze"]["type"] == "point";
    m["head_position"] = {{"constant", pt ? Json::array({0, 0, 0}) : Json::array({0, 1.6, 0})}};
    G.assume(pt ? "no head position columns: the gaze point is relative to the eye, head at the "
                  "origin"
                : "no head position columns: constant (0, 1.6, 0) m");
  }
  if (!P.rot) {
    m["head_orientation"] = {{"constant", {1, 0, 0, 0}}};
    G.assume("no head orientation columns: constant identity");
  }
  if (!P.gaze) {
    m["gaze"] = {{"type", "direction"}, {"space", "head"}, {"columns", {"?", "?", "?"}}};
    G.assume("no gaze columns recognised: set gaze");
  }
  m["coordinates"] = P.unity_hint ? "unity" : "opengl";
  G.assume(P.unity_hint ? "coordinates are Unity's (left-handed, +Y up, +Z forward)"
                        : "coordinates are OpenGL/OpenXR (right-handed, +Y up, -Z forward): "
                          "check a frame where the user "
                          "looks right (fovsim gx > 0)");
}

// Validity columns: blink flags, confidences, valid flags, bitmasks and status codes.
void guess_validity(MapGuess& G, bool per_eye) {
  const auto& names = G.names();
  Json& m = G.m;
  Json valid = Json::array();
  for (auto& f : names) {
    std::string n = ascii_lower(f.text);
    if (contains_any(n, {"blink"})) {
      valid.push_back(
          {{"column", G.ref(int(&f - &names[0]))}, {"valid_values", {"False", "false", "0"}}});
      G.assume("\"" + f.text + "\" True/1 means blinking (invalid)");
    } else if (contains_any(n, {"confidence"})) {
      valid.push_back({{"column", G.ref(int(&f - &names[0]))}, {"min", 0.6}});
      G.assume("\"" + f.text + "\" >= 0.6 is a valid sample");
    } else if (contains_any(n, {"valid"})) {
      // A bitmask (SRanipal eye_valid = 31 with every bit set) has integer values above 1.
      const int ci = int(&f - &names[0]);
      std::vector<double> v = column_values(G.rows, size_t(ci));
      double mx = 0;
      bool ints = !v.empty();
      for (double x : v) {
        ints = ints && x == std::floor(x) && x >= 0 && x < 2147483648.0;
        mx = std::max(mx, x);
      }
      Json cond = {{"column", G.ref(ci)}};
      if (per_eye && m["gaze"].contains("left")) {
        bool l = contains_any(n, {"left", "_l"}) && !contains_any(n, {"right"});
        bool r = contains_any(n, {"right", "_r"}) && !l;
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
          G.assume(b);
        } else {
          cond["valid_values"] = {std::to_string(all)};
          G.assume("\"" + f.text + "\" is a status code: " + std::to_string(all) +
                   " (its largest value) is valid");
        }
      } else {
        cond["valid_values"] = {"1", "True", "true"};
        G.assume("\"" + f.text + "\" = 1/True is valid");
      }
      valid.push_back(cond);
    }
  }
  if (!valid.empty()) m["valid"] = valid;
}

}  // namespace

// Stages: the delimiter and header, vector groups, time, head pose and gaze by name
// (classify_groups), gaze angles, the combined-versus-per-eye gaze choice, unnamed triples,
// fallbacks, validity columns; each assumption is a note in the map's "comment".
Json guess_map(const std::string& in) {
  std::string text = read_file(in);
  // Metadata lines starting with '#' before the header (SMI, Tobii Studio, loggers' notes).
  const bool hash_comments = !text.empty() && text[0] == '#';
  size_t start = 0;
  while (hash_comments && start < text.size() && text[start] == '#') {
    size_t e = text.find_first_of("\r\n", start);
    start = e == std::string::npos ? text.size() : text.find_first_not_of("\r\n", e);
    if (start == std::string::npos) start = text.size();
  }
  size_t nl = text.find_first_of("\r\n", start);
  std::string line0 = text.substr(start, nl == std::string::npos ? std::string::npos : nl - start);
  MapGuess G;
  G.in = in;
  const char* dname = "space";
  const char delim = guess_delimiter(line0, dname);
  G.assume(std::string("the delimiter is ") + dname);
  G.rows = read_csv_rows(in, delim, hash_comments ? '#' : 0);
  if (G.rows.size() < 2)
    throw Error(in, "too few rows to guess a map (need a header or first row and data)");
  Json& m = G.m;
  m["delimiter"] = dname;
  if (hash_comments) {
    m["comment_prefix"] = "#";
    G.assume("lines starting with # are comments (the file starts with one)");
  }
  // Header: the first row has a non-numeric field.
  bool header = false;
  for (auto& f : G.rows[0].fields) {
    double v;
    std::string why;
    if (!parse_number(f.text, v, why)) header = true;
  }
  m["header"] = header;
  if (!header) {
    G.assume("no header row: columns are numbered; name them in the map by 1-based index");
    m["comment"] = G.notes;
    return m;
  }
  const std::vector<Group> groups = vector_groups(G.names());
  for (auto& f : G.names()) ++G.name_count[f.text];
  PoseGuess P;
  for (auto& f : G.names())
    P.unity_hint =
        P.unity_hint || contains_any(ascii_lower(f.text), {"unity", "euler", "eulerangles"});
  guess_time(G);
  classify_groups(G, groups, P);
  guess_gaze_angles(G, P);
  choose_combined_gaze(G, P);
  guess_unnamed_triples(G, P);
  guess_fallbacks(G, P);
  guess_validity(G, P.per_eye());
  m["on_bad_row"] = "fail";
  Json c = Json::array();
  c.push_back("Guessed by fovsim trace import --guess from " + in +
              ": check every ASSUMPTION, then run "
              "fovsim trace import with this map and read its summary (eccentricity, eye speed)");
  for (auto& n : G.notes) c.push_back(n);
  m["comment"] = c;
  return m;
}

}  // namespace fovsim
