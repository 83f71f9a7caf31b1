// Hypothesis search for `--guess` (traces/README.md "--guess"): the name-based starting map
// varied along each convention the names cannot decide, every variant scored by importing a
// sample of the rows through the real importer.
#include "sim/trace/map_search.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <set>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/text.h"
#include "sim/trace/csv_table.h"
#include "sim/trace/guess.h"
#include "sim/trace/stats.h"

namespace fovsim {

namespace {

constexpr size_t kSampleRows = 1500;  // data rows each hypothesis imports

// Up to four numbers through one printf format.
std::string fmt_n(const char* f, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}
double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// The first rows of IN in a temporary file (removed with the object): what every hypothesis
// imports, so that a long recording costs no more than a short one.
struct Sample {
  std::string path;
  bool whole = false;  // the sample is the whole file
  explicit Sample(const std::string& in) {
    const std::string text = read_file(in);
    size_t pos = 0, lines = 0;
    while (pos < text.size() && lines < kSampleRows + 20) {
      size_t e = text.find_first_of("\r\n", pos);
      if (e == std::string::npos) {
        pos = text.size();
        break;
      }
      if (text[e] == '\r' && e + 1 < text.size() && text[e + 1] == '\n') ++e;
      pos = e + 1;
      ++lines;
    }
    whole = pos >= text.size();
    static std::atomic<int> counter{0};
    path = (std::filesystem::temp_directory_path() / ("fovsim_guess." + std::to_string(getpid()) +
                                                      "." + std::to_string(++counter) + ".sample"))
               .string();
    write_file_atomic(path, text.substr(0, pos));
  }
  ~Sample() {
    std::error_code ec;
    std::filesystem::remove(path, ec);
  }
  Sample(const Sample&) = delete;
  Sample& operator=(const Sample&) = delete;
};

char delimiter_char(const Json& m) {
  const std::string d = m.value("delimiter", "comma");
  return d == "tab" ? '\t' : d == "semicolon" ? ';' : d == "space" ? ' ' : ',';
}

// The sample's raw fields, for the evidence the hypotheses are built from.
struct Data {
  std::vector<CsvRow> rows;  // data rows only
  std::vector<std::string> names;
  std::string all_names;  // lower-case, for name hints
  Data(const std::string& path, const Json& m) {
    const std::string cp = m.value("comment_prefix", "");
    rows = read_csv_rows(path, delimiter_char(m), cp.empty() ? 0 : cp[0]);
    const int skip = m.value("skip_lines", 0);
    // read_csv_rows drops blank lines: skip_lines counts physical lines.
    while (!rows.empty() && rows.front().line <= skip) rows.erase(rows.begin());
    if (m.value("header", true) && !rows.empty()) {
      for (auto& f : rows.front().fields) names.push_back(f.text);
      rows.erase(rows.begin());
    }
    for (auto& n : names) all_names += ascii_lower(n) + "|";
  }
  int col(const Json& ref) const {
    if (ref.is_number_integer()) return ref.get<int>() - 1;
    if (!ref.is_string()) return -1;
    for (size_t i = 0; i < names.size(); ++i)
      if (names[i] == ref.get<std::string>()) return int(i);
    return -1;
  }
  const std::string* text(size_t r, int c) const {
    if (c < 0 || size_t(c) >= rows[r].fields.size()) return nullptr;
    return &rows[r].fields[size_t(c)].text;
  }
  bool num(size_t r, int c, double& v) const {
    const std::string* t = text(r, c);
    std::string why;
    return t && parse_number(*t, v, why);
  }
  std::vector<double> values(int c) const {
    std::vector<double> out;
    double v;
    for (size_t r = 0; r < rows.size(); ++r)
      if (num(r, c, v)) out.push_back(v);
    return out;
  }
  bool increasing(int c) const {
    std::vector<double> v = values(c);
    if (v.size() < 3 || v.size() < rows.size() * 9 / 10) return false;
    for (size_t k = 1; k < v.size(); ++k)
      if (!(v[k] > v[k - 1])) return false;
    return true;
  }
  double median_step(int c) const {
    std::vector<double> v = values(c), d;
    for (size_t k = 1; k < v.size(); ++k)
      if (v[k] > v[k - 1]) d.push_back(v[k] - v[k - 1]);
    return median(d);
  }
};

// ---- scoring ----------------------------------------------------------------------------------

struct Score {
  std::string fingerprint;  // the import's statistics and mean gaze: equal for equivalent maps
  double total = 1e9;
  bool imported = false;
  std::string error;  // why the import failed
  TraceStats st;
  double skipped = 0, outside = 0, upside_down = 0;
  std::string first_skip;             // the importer's first note on skipped rows
  std::vector<std::string> problems;  // implausible values, for the evidence
};

constexpr double kFailed = 100;  // the score of a hypothesis the importer refuses

// How far the import of the sample under `map` is from a human recording: every term is 0
// inside the human range (traces/README.md "--guess", the plausibility bounds of stats.h).
Score score_map(const Json& map, const Sample& s, const Display& d) {
  Score sc;
  Json m = map;
  m["on_bad_row"] = "skip";
  m["max_skipped_fraction"] = 1.0;
  m.erase("on_bad");
  ImportOptions io;
  io.check_fov = false;
  ImportReport rep;
  Trace tr;
  try {
    tr = import_trace(s.path, m, "(hypothesis)", d, &rep, io);
  } catch (const Error& e) {
    sc.error = e.message();
    sc.total = kFailed;
    return sc;
  }
  sc.imported = true;
  sc.st = trace_stats(tr);
  const TraceStats& st = sc.st;
  sc.skipped = rep.data_rows > 0 ? double(rep.skipped_rows) / double(rep.data_rows) : 0;
  if (!rep.notes.empty()) sc.first_skip = rep.notes.front();
  long valid = 0, out = 0, down = 0;
  for (auto& x : tr.samples) {
    if (x.valid) {
      ++valid;
      out += gaze_inside_fov(d, x.gaze_dir) ? 0 : 1;
    }
    down += (x.head_rot * glm::dvec3(0, 1, 0)).y < 0.3 ? 1 : 0;
  }
  glm::dvec3 mean(0.0);
  for (auto& x : tr.samples)
    if (x.valid) mean += x.gaze_dir;
  if (valid) mean /= double(valid);
  char fp[200];
  std::snprintf(fp, sizeof fp, "%zu %.4f %.3f %.3f %.1f %.1f %.3f %.3f %.3f", tr.samples.size(),
                sc.st.invalid_fraction, sc.st.ecc_p50, sc.st.ecc_p95, sc.st.speed_p99,
                sc.st.head_speed_max, mean.x, mean.y, mean.z);
  sc.fingerprint = fp;
  sc.outside = valid ? double(out) / double(valid) : 0;
  sc.upside_down = tr.samples.empty() ? 0 : double(down) / double(tr.samples.size());
  double t = 6 * sc.skipped;
  if (sc.skipped > 0.01) sc.problems.push_back(fmt_n("%.0f %% of rows refused", 100 * sc.skipped));
  const double f = st.invalid_fraction;
  t += 0.5 * f + 4 * std::max(0.0, f - 0.25) + 10 * std::max(0.0, f - 0.9);
  if (f > 0.25) sc.problems.push_back(fmt_n("%.0f %% invalid", 100 * f));
  t += st.ecc_p50 / 90;
  if (st.ecc_p95 > kPlausibleEccP95) {
    t += 1 + (st.ecc_p95 - kPlausibleEccP95) / 10;
    sc.problems.push_back(fmt_n("eccentricity p95 %.0f deg", st.ecc_p95));
  }
  if (st.speed_p99 > kPlausibleSpeedP99) {
    t += 1 + std::log2(st.speed_p99 / kPlausibleSpeedP99);
    sc.problems.push_back(fmt_n("eye speed p99 %.0f deg/s", st.speed_p99));
  }
  if (!(st.rate_hz >= 10 && st.rate_hz <= 5000)) {
    t += 3 + std::fabs(std::log10(std::max(st.rate_hz, 1e-9) / (st.rate_hz < 10 ? 10 : 5000)));
    sc.problems.push_back(fmt_n("rate %.3g Hz", st.rate_hz));
  }
  if (st.head_speed_max > kPlausibleHeadSpeed) {
    t += 1 + 0.5 * std::log2(st.head_speed_max / kPlausibleHeadSpeed);
    sc.problems.push_back(fmt_n("head speed max %.0f deg/s", st.head_speed_max));
  }
  if (st.head_speed_p50 > kPlausibleHeadSpeedP50) t += 1;
  // Tracker noise alone moves the gaze by several deg/s between samples: a gaze that hardly
  // moves is a column that is not the gaze (or angles read in the wrong unit).
  if (st.samples >= 10 && st.speed_p50 < 0.5) {
    t += 0.3;
    sc.problems.push_back(fmt_n("eye speed p50 %.2g deg/s", st.speed_p50));
  }
  t += 3 * sc.outside + 3 * sc.upside_down;
  if (sc.outside > 0.05) sc.problems.push_back(fmt_n("%.0f %% outside the FOV", 100 * sc.outside));
  if (sc.upside_down > 0.05)
    sc.problems.push_back(fmt_n("head upside down on %.0f %%", 100 * sc.upside_down));
  if (st.samples < 10) t += 5;
  sc.total = t;
  return sc;
}

std::string evidence(const Score& sc) {
  if (!sc.imported) return "import fails: " + sc.error;
  const TraceStats& st = sc.st;
  std::string e = fmt_n("invalid %.1f %%, eccentricity p95 %.1f deg, eye speed p99 %.0f deg/s",
                        100 * st.invalid_fraction, st.ecc_p95, st.speed_p99) +
                  fmt_n(", head speed max %.0f deg/s, rate %.4g Hz", st.head_speed_max, st.rate_hz);
  if (sc.skipped > 0) e += fmt_n(", %.1f %% of rows refused", 100 * sc.skipped);
  if (!sc.problems.empty()) {
    e += " (implausible:";
    for (auto& p : sc.problems) e += " " + p + (&p == &sc.problems.back() ? ")" : ";");
  }
  return e;
}

// ---- hypotheses -------------------------------------------------------------------------------

struct Option {
  std::string what;  // "coordinates unity, gaze.space world"
  double prior = 0;  // a small cost: what the names or conventions make less likely
  std::function<void(Json&)> apply;
};
struct Dimension {
  std::string name;
  std::vector<Option> options;
};

// Signed dominant component of the gaze columns: 'x', 'y' or 'z' and its sign (the axis a
// tracker's gaze points along is its forward axis). `dom` = 0 when there is no gaze vector.
void dominant_axis(const Data& D, const Json& m, char& dom, int& sign) {
  dom = 0;
  sign = 0;
  if (!m.contains("gaze")) return;
  const Json& g = m["gaze"];
  const Json cols = g.contains("columns") ? g["columns"] : g.value("left", Json());
  const std::string type = g.value("type", "");
  if ((type != "direction" && type != "point") || !cols.is_array() || cols.size() != 3) return;
  int c[3];
  for (int k = 0; k < 3; ++k)
    if ((c[k] = D.col(cols[size_t(k)])) < 0) return;
  glm::dvec3 sum(0.0);
  for (size_t r = 0; r < D.rows.size(); ++r) {
    glm::dvec3 v;
    if (!D.num(r, c[0], v.x) || !D.num(r, c[1], v.y) || !D.num(r, c[2], v.z)) continue;
    if (glm::length(v) > 1e-9) sum += v / glm::length(v);
  }
  const glm::dvec3 a = glm::abs(sum);
  if (a.x + a.y + a.z == 0) return;
  dom = a.z >= a.x && a.z >= a.y ? 'z' : a.x >= a.y ? 'x' : 'y';
  const double s = dom == 'z' ? sum.z : dom == 'x' ? sum.x : sum.y;
  sign = s > 0 ? 1 : -1;
}

// The fraction of rows whose raw gaze `axis` component is > 0 (for the hints).
double fraction_positive(const Data& D, const Json& m, int axis) {
  const Json& g = m["gaze"];
  const Json cols = g.contains("columns") ? g["columns"] : g.value("left", Json());
  if (!cols.is_array() || cols.size() != 3) return NAN;
  const int c = D.col(cols[size_t(axis)]);
  long n = 0, pos = 0;
  for (size_t r = 0; r < D.rows.size(); ++r) {
    double v;
    if (!D.num(r, c, v) || v == 0) continue;
    ++n;
    pos += v > 0 ? 1 : 0;
  }
  return n ? double(pos) / double(n) : NAN;
}

Json axes_object(const std::string& c) {
  if (c == "unity") return {{"x", "+x"}, {"y", "+y"}, {"z", "-z"}};
  if (c == "unreal") return {{"x", "+y"}, {"y", "+z"}, {"z", "-x"}};
  if (c == "opencv") return {{"x", "+x"}, {"y", "-y"}, {"z", "-z"}};
  return {{"x", "+x"}, {"y", "+y"}, {"z", "+z"}};
}
// The same axes with the source x mirrored (SRanipal's and Tobii's eye frames: +x left).
Json mirrored_x(const std::string& c) {
  Json a = axes_object(c);
  std::string x = a["x"];
  x[0] = x[0] == '+' ? '-' : '+';
  a["x"] = x;
  return a;
}

// Axis convention, gaze space, head quaternion order and direction or Euler unit: one
// dimension, since they only make sense together.
Dimension frame_dimension(const Data& D, const Json& base) {
  char dom;
  int sign;
  dominant_axis(D, base, dom, sign);
  const std::string& nm = D.all_names;
  const bool pupil = contains_any(nm, {"norm_pos", "gaze_normal", "gaze_point_3d"});
  std::string expect = dom == 'x' ? "unreal" : sign > 0 ? (pupil ? "opencv" : "unity") : "opengl";
  if (dom == 0) expect = base.value("coordinates", "opengl");
  std::vector<std::string> coords = {"opengl", "unity"};
  if (dom == 'x' || expect == "unreal") coords.push_back("unreal");
  if (pupil) coords.push_back("opencv");
  const Json& g = base["gaze"];
  const std::string gtype = g.value("type", "");
  const Json& ho = base["head_orientation"];
  const bool head_rot = !ho.contains("constant");
  const bool dir = gtype == "direction" || gtype == "orientation";
  const bool mirror_hint =
      contains_any(nm, {"validata", "gaze_direction_normalized", "gaze direction"});
  std::vector<std::pair<std::string, double>> spaces = {{g.value("space", "head"), 0}};
  if (dir && head_rot) spaces.push_back({spaces[0].first == "head" ? "world" : "head", 0.08});
  std::vector<int> mirrors = {0};
  if (gtype == "direction") mirrors.push_back(1);
  std::vector<std::pair<std::string, double>> orders = {{"", 0}}, units = {{"", 0}};
  if (ho.value("type", "") == "quaternion") {
    const std::string o = ho.value("order", "wxyz");
    orders = {{o, 0}, {o == "wxyz" ? "xyzw" : "wxyz", 0.08}};
  }
  if (ho.value("type", "") == "euler") {
    // Angles that never leave [-pi, pi] but do vary are radians (read as degrees they would
    // be a head that hardly moves, which the scores cannot tell from a still head).
    bool within = true;
    double lo = INFINITY, hi = -INFINITY;
    for (auto& ref : ho.value("columns", Json::array()))
      for (double v : D.values(D.col(ref))) {
        within = within && std::fabs(v) <= kPi + 1e-3;
        lo = std::min(lo, v), hi = std::max(hi, v);
      }
    const bool rad = within && hi - lo > 0.05;
    units = {{"deg", rad ? 0.1 : 0}, {"rad", rad ? 0 : 0.05}};
  }
  std::vector<int> inverses = {0};
  if (ho.value("type", "") == "quaternion") inverses.push_back(1);
  Dimension dim{"frame", {}};
  for (auto& c : coords)
    for (int mir : mirrors)
      for (auto& sp : spaces)
        for (auto& od : orders)
          for (auto& un : units)
            for (int inv : inverses) {
              Option o;
              o.what = "coordinates: " + c;
              o.prior = (c == expect                          ? 0
                         : c == base.value("coordinates", "") ? 0.05
                                                              : 0.15) +
                        (mir ? (mirror_hint ? 0 : 0.12) : (mirror_hint ? 0.02 : 0)) + sp.second +
                        od.second + un.second + (inv ? 0.1 : 0);
              if (mir) o.what += ", gaze.coordinates: " + mirrored_x(c).dump();
              if (dir) o.what += ", gaze.space: " + sp.first;
              if (!od.first.empty()) o.what += ", head_orientation.order: " + od.first;
              if (!un.first.empty()) o.what += ", head_orientation.unit: " + un.first;
              if (inv) o.what += ", head_orientation.inverse: true";
              o.apply = [=](Json& m) {
                m["coordinates"] = c == "opencv" ? axes_object(c) : Json(c);  // no name
                m["gaze"].erase("coordinates");
                // The gaze form dimension may have replaced the gaze: only its own keys.
                const std::string t = m["gaze"].value("type", "");
                if (mir && t == "direction") m["gaze"]["coordinates"] = mirrored_x(c);
                if (dir && (t == "direction" || t == "orientation")) m["gaze"]["space"] = sp.first;
                if (!od.first.empty()) m["head_orientation"]["order"] = od.first;
                if (!un.first.empty()) m["head_orientation"]["unit"] = un.first;
                m["head_orientation"].erase("inverse");
                if (inv) m["head_orientation"]["inverse"] = true;
              };
              dim.options.push_back(o);
            }
  return dim;
}

// Step unit: < 0.5 s, < 500 ms, < 5e5 us, else ns.
std::string unit_from_step(double step) {
  if (!std::isfinite(step)) return "s";
  return step < 0.5 ? "s" : step < 500 ? "ms" : step < 5e5 ? "us" : "ns";
}

// Time column and unit: the starting map's, the unit its median step suggests, and other
// strictly increasing columns when the names found none.
Dimension time_dimension(const Data& D, const Json& base) {
  Dimension dim{"time", {}};
  const Json& t = base["time"];
  const int bc = D.col(t.value("column", Json()));
  auto add = [&](int c, const std::string& unit, double prior) {
    const Json ref = D.names.empty() ? Json(c + 1) : Json(D.names[size_t(c)]);
    Option o;
    o.what = "time.column: " + ref.dump() + ", time.unit: " + unit;
    o.prior = prior;
    o.apply = [=](Json& m) {
      m["time"]["column"] = ref;
      m["time"]["unit"] = unit;
      if (!m["time"].contains("rebase")) m["time"]["rebase"] = true;
    };
    dim.options.push_back(o);
  };
  if (bc >= 0) {
    const std::string u = t.value("unit", "s"), us = unit_from_step(D.median_step(bc));
    add(bc, u, 0);
    if (us != u) add(bc, us, 0.1);
  }
  int found = 0;
  const size_t ncols = D.rows.empty() ? 0 : D.rows[0].fields.size();
  for (size_t c = 0; c < ncols && found < 3; ++c)
    if (int(c) != bc && D.increasing(int(c))) {
      add(int(c), unit_from_step(D.median_step(int(c))), bc >= 0 ? 0.3 : 0.01 * found);
      ++found;
    }
  return dim;
}

Json enc(const char* key, const Json& v) {
  Json j = Json::object();
  j[key] = v;
  return j;
}

// The validity encodings a column's values allow, each a condition without "column".
std::vector<std::pair<Json, double>> encodings(const Data& D, int c, const std::string& name) {
  std::vector<std::pair<Json, double>> out;
  std::set<std::string> texts;
  std::vector<double> v;
  bool ints = true;
  for (size_t r = 0; r < D.rows.size(); ++r) {
    const std::string* t = D.text(r, c);
    if (!t) continue;
    texts.insert(*t);
    double x;
    std::string why;
    if (parse_number(*t, x, why)) {
      v.push_back(x);
      ints = ints && x == std::floor(x) && std::fabs(x) < 2147483648.0;
    }
  }
  if (texts.empty()) return out;
  const bool neg_name = contains_any(name, {"blink", "invalid", "lost", "missing", "closed"});
  if (v.size() < texts.size() / 2 + 1 || v.empty()) {  // words: True/False, Valid/Invalid
    if (texts.size() > 6) return out;
    for (auto& t : texts) {
      const std::string lt = ascii_lower(t);
      const bool good =
          (lt == "true" || lt == "valid" || lt == "1") != neg_name || (neg_name && lt == "false");
      out.push_back({enc("valid_values", Json::array({t})), good ? 0.0 : 0.1});
    }
    return out;
  }
  if (texts.count("")) {  // a numeric column empty on some rows ("blink id": set in blinks)
    out.push_back({enc("valid_values", Json::array({""})), neg_name ? 0.0 : 0.08});
    out.push_back({enc("invalid_values", Json::array({""})), neg_name ? 0.08 : 0.03});
  }
  const double mx = *std::max_element(v.begin(), v.end());
  const double mn = *std::min_element(v.begin(), v.end());
  if (ints && mn >= 0 && mx <= 1) {
    out.push_back({enc("valid_values", Json::array({"1"})), neg_name ? 0.1 : 0.0});
    out.push_back({enc("valid_values", Json::array({"0"})), neg_name ? 0.0 : 0.1});
  } else if (ints && mx > 1) {
    long long all = 0;
    std::map<long long, long> count;
    for (double x : v) {
      if (x > 0) all |= (long long)x;
      ++count[(long long)x];
    }
    for (long long b = 1; b <= all; b <<= 1)
      if (all & b) out.push_back({enc("all_bits", b), 0.04});
    if ((all & (all + 1)) == 0) out.push_back({enc("all_bits", all), 0.02});
    long long mode = 0;
    for (auto& [k, n] : count)
      if (n > count[mode]) mode = k;
    out.push_back({enc("valid_values", Json::array({std::to_string((long long)mx)})), 0.05});
    if (mode != (long long)mx)
      out.push_back({enc("valid_values", Json::array({std::to_string(mode)})), 0.06});
    out.push_back({enc("invalid_values", Json::array({"0"})), 0.05});
  } else if (!ints && mn >= 0 && mx <= 1.0001) {
    out.push_back({enc("min", 0.6), 0.0});
    out.push_back({enc("min", 0.8), 0.03});
    out.push_back({enc("min", 0.3), 0.03});
  }
  if (mn < 0) {
    Json neg = Json::array();
    for (auto& t : texts) {
      double x;
      std::string why;
      if (parse_number(t, x, why) && x < 0 && x == std::floor(x)) neg.push_back(t);
    }
    if (!neg.empty() && neg.size() <= 3) out.push_back({enc("invalid_values", neg), 0.03});
  }
  return out;
}

// Columns of the map's gaze, time and head pose (not candidates for validity).
std::set<int> used_columns(const Data& D, const Json& m) {
  std::set<int> used;
  std::function<void(const Json&)> walk = [&](const Json& j) {
    if (!j.is_object()) return;
    for (auto& [k, v] : j.items()) {
      const bool ref = k == "column" || k == "columns" || k == "left" || k == "right" ||
                       k == "forward" || k == "up";
      if (ref && v.is_array())
        for (auto& x : v) used.insert(D.col(x));
      else if (ref)
        used.insert(D.col(v));
      else if (k != "valid")
        walk(v);
    }
  };
  walk(m);
  return used;
}

// Validity: no condition, or one encoding for the validity-like columns (names with valid,
// confidence, blink, status, mask, quality, tracked), left/right by name with per-eye gaze.
Dimension validity_dimension(const Data& D, const Json& base) {
  Dimension dim{"validity", {}};
  const std::set<int> used = used_columns(D, base);
  const bool per_eye = base["gaze"].contains("left");
  struct Col {
    int c;
    std::string name, eye;
    std::vector<std::pair<Json, double>> enc;
  };
  std::vector<Col> cols;
  for (size_t i = 0; i < D.names.size(); ++i) {
    const std::string n = ascii_lower(D.names[i]);
    const bool val = n == "val" || n.rfind("val_", 0) == 0 || contains_any(n, {"_val"});
    if (used.count(int(i)) || !(val || contains_any(n, {"valid", "confidence", "blink", "status",
                                                        "mask", "quality", "tracked"})))
      continue;
    Col col{int(i), D.names[i], "", encodings(D, int(i), n)};
    if (per_eye && (contains_any(n, {"left", "_l", " l", "l_"}) && !contains_any(n, {"right"})))
      col.eye = "left";
    if (per_eye && col.eye.empty() && contains_any(n, {"right", "_r", " r", "r_"}))
      col.eye = "right";
    if (!col.enc.empty()) cols.push_back(col);
  }
  Option none;
  none.what = "valid: []";
  none.prior = cols.empty() ? 0 : 0.3;
  none.apply = [](Json& m) { m.erase("valid"); };
  dim.options.push_back(none);
  if (base.contains("valid")) {  // the starting map's conditions, as they are
    Option o;
    o.what = "valid: " + base["valid"].dump();
    o.prior = 0.01;
    const Json v = base["valid"];
    o.apply = [v](Json& m) { m["valid"] = v; };
    dim.options.push_back(o);
  }
  auto cond = [](const Col& col, const Json& e) {
    Json c = e;
    c["column"] = col.name;
    if (!col.eye.empty()) c["eye"] = col.eye;
    return c;
  };
  // One column at a time, and every column with the same encoding (per-eye masks).
  for (auto& col : cols)
    for (auto& [e1, prior] : col.enc) {
      Json v = Json::array({cond(col, e1)});
      for (auto& other : cols)
        if (&other != &col && other.eye != col.eye && !other.eye.empty())
          for (auto& [e2, p2] : other.enc)
            if (e2 == e1) v.push_back(cond(other, e2));
      std::sort(v.begin(), v.end(),
                [](const Json& a, const Json& b) { return a.dump() < b.dump(); });
      Option o;
      o.what = "valid: " + v.dump();
      o.prior = prior + (v.size() > 1 ? 0 : 0.01 * double(cols.size() - 1));
      o.apply = [v](Json& m) { m["valid"] = v; };
      dim.options.push_back(o);
    }
  return dim;
}

// Gaze sentinels: rows whose gaze vector is all zeros or all -1 (trackers write these when
// they lose the eye) made invalid by a condition on the vector's z column.
Dimension sentinel_dimension(const Data& D, const Json& base) {
  Dimension dim{"sentinel", {}};
  const Json& g = base["gaze"];
  std::vector<std::pair<Json, std::string>> vecs;
  if (g.contains("columns") && g["columns"].size() == 3 && g.value("type", "") == "direction")
    vecs.push_back({g["columns"], ""});
  if (g.contains("left")) vecs = {{g["left"], "left"}, {g["right"], "right"}};
  Json add = Json::array();
  std::string seen;
  for (auto& [cols, eye] : vecs) {
    int c[3];
    bool ok = true;
    for (int k = 0; k < 3; ++k) ok = ok && (c[k] = D.col(cols[size_t(k)])) >= 0;
    if (!ok) continue;
    std::set<std::string> texts;
    for (size_t r = 0; r < D.rows.size(); ++r) {
      glm::dvec3 v;
      if (!D.num(r, c[0], v.x) || !D.num(r, c[1], v.y) || !D.num(r, c[2], v.z)) continue;
      if (v == glm::dvec3(0.0) || v == glm::dvec3(-1.0)) texts.insert(*D.text(r, c[2]));
    }
    if (texts.empty() || texts.size() > 4) continue;
    Json cond = {{"column", cols[2]}, {"invalid_values", Json(texts)}};
    if (!eye.empty()) cond["eye"] = eye;
    add.push_back(cond);
    seen += (seen.empty() ? "" : ", ") + cols[2].dump();
  }
  if (add.empty()) return dim;
  Option off{"no gaze sentinel", 0.05, [](Json&) {}};
  Option on{"valid += " + add.dump(), 0, [add](Json& m) {
              if (!m.contains("valid")) m["valid"] = Json::array();
              for (auto& c : add) m["valid"].push_back(c);
            }};
  dim.options = {on, off};
  return dim;
}

// Head position from the columns the names suggested, or constant (a triple that is not a
// position: gyroscope rates, empty on most rows).
Dimension position_dimension(const Json& base) {
  Dimension dim{"position", {}};
  if (!base["head_position"].contains("columns")) return dim;
  const Json hp = base["head_position"];
  dim.options.push_back(
      {"head_position: " + hp.dump(), 0, [hp](Json& m) { m["head_position"] = hp; }});
  dim.options.push_back({"head_position.constant: [0, 1.6, 0]", 0.2, [](Json& m) {
                           m["head_position"] = {{"constant", {0, 1.6, 0}}};
                         }});
  return dim;
}

// When the names found no gaze: adjacent numeric columns read as gaze -- a unit-norm triple as a
// direction, a pair as angles (deg or rad) or, with values in [0, 1], a screen point.
Dimension gaze_form_dimension(const Data& D, const Json& base) {
  Dimension dim{"gaze form", {}};
  if (base["gaze"].value("type", "") == "point" && base["gaze"].contains("columns")) {
    // A point looked at (world), or the same columns as a direction (head or world): a
    // head-relative point and a direction read the same once normalised.
    const Json pt = base["gaze"];
    dim.options.push_back({"gaze: " + pt.dump(), 0, [pt](Json& m) { m["gaze"] = pt; }});
    for (const char* sp : {"head", "world"}) {
      const Json g = {{"type", "direction"}, {"space", sp}, {"columns", pt["columns"]}};
      dim.options.push_back({"gaze: " + g.dump(), 0.05, [g](Json& m) { m["gaze"] = g; }});
    }
    return dim;
  }
  if (base["gaze"].dump().find("\"?\"") == std::string::npos) return dim;
  const std::set<int> used = used_columns(D, base);
  const size_t ncols = D.rows.empty() ? 0 : D.rows[0].fields.size();
  auto numeric = [&](size_t c) {
    if (used.count(int(c)) || D.increasing(int(c))) return false;
    std::vector<double> v = D.values(int(c));
    return v.size() >= D.rows.size() / 2 + 1;
  };
  auto varies = [&](size_t c) {
    std::vector<double> v = D.values(int(c));
    return *std::max_element(v.begin(), v.end()) > *std::min_element(v.begin(), v.end());
  };
  auto ref = [&](size_t c) { return D.names.empty() ? Json(c + 1) : Json(D.names[c]); };
  int pairs = 0;
  for (size_t c = 0; c + 1 < ncols && pairs < 4; ++c) {
    if (!numeric(c) || !numeric(c + 1) || !(varies(c) || varies(c + 1))) continue;
    // "x"/"y", "gaze_x"/"gaze_y", "X [deg]"/"Y [deg]": named as a pair.
    bool named = false;
    if (!D.names.empty()) {
      std::string a = ascii_lower(D.names[c]), b = ascii_lower(D.names[c + 1]);
      const size_t k = a.rfind('x');
      named = k != std::string::npos && (a[k] = 'y', a == b);
    }
    const double pr = 0.02 * pairs++ + (named ? 0 : 0.1);
    const Json cols = {ref(c), ref(c + 1)};
    if (c + 2 < ncols && numeric(c + 2)) {
      long unit = 0, n = 0;
      for (size_t r = 0; r < D.rows.size(); ++r) {
        glm::dvec3 v;
        if (!D.num(r, int(c), v.x) || !D.num(r, int(c + 1), v.y) || !D.num(r, int(c + 2), v.z))
          continue;
        ++n;
        unit += std::fabs(glm::length(v) - 1) < 0.05 ? 1 : 0;
      }
      if (n > 0 && unit * 10 > n * 8) {
        const Json g = {{"type", "direction"},
                        {"space", "head"},
                        {"columns", {ref(c), ref(c + 1), ref(c + 2)}}};
        dim.options.push_back({"gaze: " + g.dump(), pr, [g](Json& m) { m["gaze"] = g; }});
        c += 2;  // its columns are not also a pair
        continue;
      }
    }
    std::vector<double> a = D.values(int(c)), b = D.values(int(c + 1));
    const bool unit_box = *std::min_element(a.begin(), a.end()) >= -0.05 &&
                          *std::max_element(a.begin(), a.end()) <= 1.05 &&
                          *std::min_element(b.begin(), b.end()) >= -0.05 &&
                          *std::max_element(b.begin(), b.end()) <= 1.05;
    std::vector<Json> forms = {{{"type", "angles"}, {"columns", cols}, {"unit", "deg"}},
                               {{"type", "angles"}, {"columns", cols}, {"unit", "rad"}}};
    if (unit_box) {
      forms.push_back({{"type", "screen"}, {"columns", cols}, {"origin", "top-left"}});
      forms.push_back({{"type", "screen"}, {"columns", cols}, {"origin", "bottom-left"}});
    }
    for (size_t k = 0; k < forms.size(); ++k) {
      const Json g = forms[k];
      dim.options.push_back(
          {"gaze: " + g.dump(), pr + 0.01 * double(k), [g](Json& m) { m["gaze"] = g; }});
    }
  }
  return dim;
}

// Gaze angles in degrees or radians.
Dimension angle_dimension(const Json& base) {
  Dimension dim{"angles", {}};
  if (base["gaze"].value("type", "") != "angles") return dim;
  for (const char* u : {"deg", "rad"}) {
    const std::string us = u;
    dim.options.push_back({"gaze.unit: " + us, us == base["gaze"].value("unit", "deg") ? 0 : 0.05,
                           [us](Json& m) { m["gaze"]["unit"] = us; }});
  }
  return dim;
}

// Head positions in m, cm or mm from their spread: a head moves within a few metres.
void position_unit(const Data& D, Json& m, std::vector<std::string>& notes) {
  const Json& hp = m["head_position"];
  if (!hp.contains("columns")) return;
  double spread = 0, far = 0;
  for (auto& ref : hp["columns"]) {
    std::vector<double> v = D.values(D.col(ref));
    if (v.size() < 2) return;
    std::sort(v.begin(), v.end());
    spread = std::max(spread, v[v.size() * 99 / 100] - v[v.size() / 100]);
    far = std::max(far, std::fabs(v[v.size() / 2]));
  }
  const double s = std::max(spread, far / 10);
  const std::string unit = s > 300 ? "mm" : s > 30 ? "cm" : "m";
  m["head_position"]["unit"] = unit;
  notes.push_back("head_position.unit: " + unit +
                  fmt_n(" from the positions' spread (%.3g; median |x| %.3g)", spread, far));
}

struct Tested {
  Json map;
  Score score;
};

// Coordinate descent over the dimensions (two passes; every map imported once).
std::vector<Tested> search(const Json& base, const std::vector<Dimension>& dims, const Sample& s,
                           const Display& d, std::vector<size_t>& choice) {
  std::map<std::string, size_t> seen;
  std::vector<Tested> all;
  auto build = [&](const std::vector<size_t>& ch) {
    Json m = base;
    double prior = 0;
    for (size_t k = 0; k < dims.size(); ++k) {
      dims[k].options[ch[k]].apply(m);
      prior += dims[k].options[ch[k]].prior;
    }
    return std::make_pair(m, prior);
  };
  auto eval = [&](const std::vector<size_t>& ch) {
    auto [m, prior] = build(ch);
    const std::string key = m.dump();
    auto it = seen.find(key);
    if (it != seen.end()) return all[it->second].score.total;
    Score sc = score_map(m, s, d);
    sc.total += prior;
    seen[key] = all.size();
    all.push_back({m, sc});
    return sc.total;
  };
  choice.assign(dims.size(), 0);
  for (size_t k = 0; k < dims.size(); ++k)
    for (size_t o = 1; o < dims[k].options.size(); ++o)
      if (dims[k].options[o].prior < dims[k].options[choice[k]].prior) choice[k] = o;
  double best = eval(choice);
  for (int pass = 0; pass < 2; ++pass)
    for (size_t k = 0; k < dims.size(); ++k)
      for (size_t o = 0; o < dims[k].options.size(); ++o) {
        std::vector<size_t> ch = choice;
        ch[k] = o;
        const double sc = eval(ch);
        if (sc < best) best = sc, choice = ch;
      }
  return all;
}

// "gaze.space: world, coordinates: \"unity\"": the keys where `b` differs from `a`.
std::string map_diff(const Json& a, const Json& b) {
  std::string out;
  auto add = [&](const std::string& k, const Json& v) {
    std::string s = v.is_null() ? "(absent)" : v.is_string() ? v.get<std::string>() : v.dump();
    if (s.size() > 90) s = s.substr(0, 87) + "...";
    out += (out.empty() ? "" : ", ") + k + ": " + s;
  };
  std::set<std::string> keys;
  for (auto& [k, v] : a.items()) keys.insert(k);
  for (auto& [k, v] : b.items()) keys.insert(k);
  for (auto& k : keys) {
    if (k == "comment" || (a.contains(k) && b.contains(k) && a[k] == b[k])) continue;
    const Json va = a.value(k, Json()), vb = b.value(k, Json());
    if (va.is_object() && vb.is_object()) {
      std::set<std::string> sub;
      for (auto& [s, v] : va.items()) sub.insert(s);
      for (auto& [s, v] : vb.items()) sub.insert(s);
      for (auto& s : sub)
        if (va.value(s, Json()) != vb.value(s, Json())) add(k + "." + s, vb.value(s, Json()));
    } else {
      add(k, vb);
    }
  }
  return out;
}

std::vector<Dimension> dimensions(const Data& D, const Json& base) {
  std::vector<Dimension> dims = {gaze_form_dimension(D, base), position_dimension(base),
                                 frame_dimension(D, base),     validity_dimension(D, base),
                                 sentinel_dimension(D, base),  time_dimension(D, base),
                                 angle_dimension(base)};
  dims.erase(std::remove_if(dims.begin(), dims.end(),
                            [](const Dimension& x) { return x.options.empty(); }),
             dims.end());
  return dims;
}

// The full file with `m` and the options a plain `trace import --map` uses; on a refusal,
// the policy keys that make it import (bad rows skipped, out-of-FOV gaze held), if any.
bool verify(const std::string& in, Json& m, const Display& d, std::string& why,
            std::vector<std::string>& notes) {
  for (int attempt = 0; attempt < 3; ++attempt) {
    try {
      ImportReport rep;
      import_trace(in, m, in + " (guessed map)", d, &rep);
      return true;
    } catch (const Error& e) {
      why = e.what();
      const std::string w = e.message();
      if (w.find("outside the display FOV") != std::string::npos && !m.contains("on_bad")) {
        m["on_bad"] = "hold";
        notes.push_back("on_bad: hold, since some valid gaze lies outside the display FOV (" + w +
                        ")");
      } else if (m.value("on_bad_row", "fail") != "skip" &&
                 w.find("no usable rows") == std::string::npos &&
                 w.find("flagged invalid") == std::string::npos) {
        m["on_bad_row"] = "skip";
        notes.push_back("on_bad_row: skip, since some rows are refused (" + w + ")");
      } else {
        return false;
      }
    }
  }
  return false;
}

}  // namespace

// Long because: the search's stages in order (start map, dimensions, search, ranking,
// verification, report) read best as one sequence.
MapSearchResult search_map(const std::string& in, const Display& display) {
  MapSearchResult res;
  Json base = guess_map(in);
  const Json start_notes = base.value("comment", Json::array());
  // Without a header the names say nothing: placeholders the time and gaze-form dimensions
  // fill from the values.
  if (!base.contains("time")) base["time"] = {{"column", "?"}, {"unit", "s"}};
  if (!base.contains("gaze"))
    base["gaze"] = {{"type", "direction"}, {"space", "head"}, {"columns", {"?", "?", "?"}}};
  if (!base.contains("head_position")) base["head_position"] = {{"constant", {0, 1.6, 0}}};
  if (!base.contains("head_orientation")) base["head_orientation"] = {{"constant", {1, 0, 0, 0}}};
  if (!base.contains("coordinates")) base["coordinates"] = "opengl";
  Sample sample(in);
  Data D(sample.path, base);
  std::vector<std::string> notes;
  position_unit(D, base, notes);
  const std::vector<Dimension> dims = dimensions(D, base);
  std::vector<size_t> choice;
  std::vector<Tested> all = search(base, dims, sample, display, choice);
  res.hypotheses = int(all.size());
  std::stable_sort(all.begin(), all.end(),
                   [](const Tested& a, const Tested& b) { return a.score.total < b.score.total; });
  // The best hypothesis the full file imports with.
  size_t chosen = all.size();
  std::string why;
  for (size_t k = 0; k < all.size() && k < 6 && chosen == all.size(); ++k) {
    if (!all[k].score.imported) break;
    Json m = all[k].map;
    std::vector<std::string> vnotes;
    if (verify(in, m, display, why, vnotes)) {
      chosen = k;
      all[k].map = m;
      for (auto& n : vnotes) notes.push_back(n);
    }
  }
  if (chosen == all.size()) {
    std::string e = "no column map imports this file: tested " + std::to_string(all.size()) +
                    " hypotheses; the best " + evidence(all.front().score);
    if (!why.empty()) e += "; with it the full import says: " + why;
    throw Error(in, e);
  }
  const Tested& best = all[chosen];
  res.map = best.map;
  res.plausible = best.score.problems.empty();
  char b[200];
  std::snprintf(
      b, sizeof b,
      "guess: tested %d hypotheses on the first %zu rows%s; chosen (score %.3f): ", res.hypotheses,
      D.rows.size(), sample.whole ? " (the whole file)" : "", best.score.total);
  res.report.push_back(b + evidence(best.score));
  // The runner-up: the best map whose import differs (maps that import the same trace, such
  // as a validity condition on either of two columns that agree, are one hypothesis).
  const Tested* runner = nullptr;
  int same = 0;
  for (size_t k = 0; k < all.size() && !runner; ++k) {
    if (k == chosen) continue;
    if (all[k].score.imported && all[k].score.fingerprint == best.score.fingerprint)
      ++same;
    else
      runner = &all[k];
  }
  if (same > 0)
    res.report.push_back("guess: " + std::to_string(same) +
                         " other maps import the same trace (equivalent choices)");
  if (runner) {
    const double margin = runner->score.total - best.score.total;
    res.ambiguous = margin < kAmbiguousMargin && runner->score.imported;
    std::snprintf(b, sizeof b, "guess: runner-up (score %.3f, margin %.3f) differs in ",
                  runner->score.total, margin);
    res.report.push_back(b + map_diff(best.map, runner->map) + ": " + evidence(runner->score));
    if (res.ambiguous)
      res.report.push_back(
          "guess: ambiguous: the data cannot tell the chosen map from the runner-up (equally "
          "plausible imports); check those keys on a frame where the user looks right and up "
          "(fovsim gx > 0, gy > 0)");
  }
  if (!res.plausible)
    res.report.push_back("guess: no hypothesis is plausible; the best still has: " +
                         evidence(best.score));
  for (auto& n : notes)
    if (n.rfind("head_position.unit", 0) != 0 || res.map["head_position"].contains("columns"))
      res.report.push_back("guess: " + n);
  Json c = Json::array();
  c.push_back("Chosen by fovsim trace import --guess from " + in + " by importing " +
              std::to_string(res.hypotheses) + " hypotheses and scoring them (" +
              evidence(best.score) + ")");
  for (auto& l : res.report) c.push_back(l);
  for (auto& n : start_notes) c.push_back("starting guess from the names: " + n.get<std::string>());
  res.map["comment"] = c;
  return res;
}

// Long because: one pass over single-dimension changes, then the evidence for the best one.
std::string import_failure_hint(const std::string& in, const Json& map, const Display& display) {
  Sample sample(in);
  Data D(sample.path, map);
  if (D.rows.empty() || !map.contains("gaze") || !map["gaze"].is_object()) return "";
  const Score now = score_map(map, sample, display);
  const std::vector<Dimension> dims = dimensions(D, map);
  const Tested* best = nullptr;
  std::vector<Tested> tried;
  tried.reserve(64);
  for (auto& dim : dims)
    for (auto& o : dim.options) {
      Json m = map;
      try {
        o.apply(m);
      } catch (const std::exception&) {
        continue;
      }
      if (m == map) continue;
      Score sc = score_map(m, sample, display);
      sc.total += o.prior;
      tried.push_back({m, sc});
    }
  for (auto& t : tried)
    if (t.score.imported && (!best || t.score.total < best->score.total)) best = &t;
  // Only a clear improvement is worth naming (a small one is a matter of priors).
  constexpr double kHintMargin = 0.2;
  if (!best || best->score.total > now.total - kHintMargin) return "";
  std::string ev;
  const std::string diff = map_diff(map, best->map);
  if (diff.find("coordinates") != std::string::npos) {
    const double zpos = fraction_positive(D, map, 2);
    if (std::isfinite(zpos)) ev = fmt_n("gaze z > 0 on %.0f %% of rows", 100 * zpos);
  } else if (diff.find("valid") != std::string::npos && now.imported) {
    ev = fmt_n("the map's valid conditions leave %.0f %% of the sample invalid",
               100 * now.st.invalid_fraction);
  } else if (diff.find("valid") != std::string::npos) {
    ev = "the map's valid conditions flag every sampled row invalid";
  }
  if (ev.empty()) ev = now.imported ? evidence(now) : "the import fails";
  return ev + ": try `" + diff + "` (then " + evidence(best->score) + ")";
}

Trace import_trace_hinted(const std::string& in, const std::string& map_path,
                          const Display& display, ImportReport* report, const ImportOptions& opt) {
  try {
    return import_trace(in, map_path, display, report, opt);
  } catch (const Error& e) {
    std::string hint;
    try {
      hint = import_failure_hint(in, Params::parse_json_file(map_path), display);
    } catch (const std::exception&) {
      hint.clear();  // no hint when the map or the file cannot be read: the original error
    }
    if (hint.empty()) throw;
    throw Error(e.where(), e.message() + " (hint: " + hint + ")");
  }
}

}  // namespace fovsim
