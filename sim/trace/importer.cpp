// Column-map importer (traces/README.md "Column maps"). The map's keys -- type, default,
// values, meaning -- are the table in sim/trace/map_keys.cpp; every typed key is read through
// it (map_string, map_number, ...), the column references through Resolver below.
#include "sim/trace/importer.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <map>
#include <regex>
#include <set>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/trace/convert.h"
#include "sim/trace/csv_table.h"
#include "sim/trace/issue_log.h"
#include "sim/trace/map_keys.h"

namespace fovsim {

namespace {

struct ColRef {
  int index = -1;  // 0-based field index
  std::string name;
};

struct Map {
  char delim = ',';
  bool header = true;
  int skip_lines = 0;
  char comment = 0;
  bool skip_bad = false;
  double max_skipped = 0.5;
  bool used_fields_only = false;
  AxisMap axes, gaze_axes;
  ColRef time;
  double time_scale = 1;
  bool rebase = true;
  int wrap_bits = 0;
  double max_step_s = 0;     // time.max_step_s (read from map_keys.cpp's table)
  double burst_below_s = 0;  // time.burst_below_s
  enum { BurstKeep, BurstDrop, BurstRetime } on_burst = BurstKeep;
  bool burst_pose_arrival = true;  // time.burst_pose: retimed samples keep the arrival pose
  bool pos_const = false;
  glm::dvec3 pos_value{0.0};
  std::vector<ColRef> pos;
  double pos_scale = 1;
  enum { Quat, Euler, Forward, ConstRot } rot_kind = Quat;
  std::vector<ColRef> rot, up;
  bool xyzw = false, intrinsic = false, inverse = false;
  std::string euler_order;
  glm::dvec3 euler_signs{1.0};
  double angle_scale = 1;
  glm::dquat rot_value{1, 0, 0, 0};
  bool interpolate_repeats = false;
  enum { DirHead, DirWorld, Screen, Point } gaze_kind = DirHead;
  std::vector<ColRef> gaze, left, right;
  std::string combine;
  bool screen_bottom_left = false;
  double point_scale = 1;
  bool gaze_orient = false, gaze_xyzw = false;  // gaze as an orientation quaternion
  bool gaze_angles = false;                     // gaze as azimuth/elevation in the head
  glm::dvec2 angle_signs{1.0};
  glm::dvec3 gaze_forward{0, 0, -1};  // its forward axis in source gaze axes
  struct Cond {
    ColRef col;
    enum { ValidList, InvalidList, AllBits, Min, Max } kind = ValidList;
    std::vector<std::string> values;
    long long bits = 0;
    double bound = 0;
    int eye = 0;  // 0 both, 1 left, 2 right
  };
  std::vector<Cond> valid;
  std::string recentre = "none";                  // head_position.recentre
  bool dequant_pos = false, dequant_rot = false;  // head_*.dequantise
  bool has_on_bad = false;
  BadSamplePolicy on_bad = BadSamplePolicy::Fail;  // the map's "on_bad"
  std::string on_invalid;                          // the map's "on_invalid"
  struct Fused {
    ColRef col;  // the first of the two fields that the export wrote as one
    std::vector<std::string> suffixes;
    bool use_pattern = false;
    std::regex pattern;
  };
  std::vector<Fused> fused;
};

// Splits `text` into the fused field's two parts; false when it is not fused.
bool split_fused(const Map::Fused& f, const std::string& text, std::string& a, std::string& b) {
  if (f.use_pattern) {
    std::smatch mt;
    if (!std::regex_match(text, mt, f.pattern) || mt.size() != 3) return false;
    a = mt[1].str();
    b = mt[2].str();
    return !a.empty() && !b.empty();
  }
  for (auto& sfx : f.suffixes)
    if (text.size() > sfx.size() && text.compare(text.size() - sfx.size(), sfx.size(), sfx) == 0) {
      a = text.substr(0, text.size() - sfx.size());
      b = sfx;
      return true;
    }
  return false;
}

// Dequantisation by run centres: a run of samples with an identical value is taken as that
// value at the run's middle time, and samples between two run middles are interpolated
// (`lerp(a, b, f)`); before the first and after the last middle the run's value is kept.
template <class T, class Get, class Set, class Lerp>
long dequantise_runs(std::vector<TraceSample>& x, Get get, Set set, Lerp lerp) {
  struct Knot {
    double t;
    T v;
  };
  std::vector<Knot> knots;
  for (size_t a = 0; a < x.size();) {
    size_t b = a;
    while (b + 1 < x.size() && get(x[b + 1]) == get(x[a])) ++b;
    knots.push_back({0.5 * (x[a].t + x[b].t), get(x[a])});
    a = b + 1;
  }
  if (knots.size() < 2) return 0;
  long changed = 0;
  size_t k = 0;
  for (auto& s : x) {
    while (k + 2 < knots.size() && knots[k + 1].t <= s.t) ++k;
    const Knot &A = knots[k], &B = knots[k + 1];
    if (s.t <= A.t || s.t >= B.t) continue;  // outside the knots: the run's own value
    T v = lerp(A.v, B.v, (s.t - A.t) / (B.t - A.t));
    if (!(v == get(s))) ++changed;
    set(s, v);
  }
  return changed;
}

// Column references are strings (header names) or 1-based integers (files without header).
struct Resolver {
  bool header;
  std::map<std::string, int> by_name;
  std::map<std::string, std::vector<int>>
      dup_cols;  // names that occur more than once: 1-based columns
  int nfields = 0;
  int max_index = -1;        // largest 0-based index the map uses
  std::vector<ColRef> used;  // every column the map refers to
  char delim = ',';
  std::string header_text;  // the header's only field, when it has one (wrong delimiter?)
  std::string in_file;
  long header_line = 0;
  ColRef get(Params& p, const std::string& key, const Json& v, const std::string& sub) {
    ColRef c;
    std::string where = p.where(key) + sub;
    if (v.is_string()) {
      c.name = v.get<std::string>();
      if (!header)
        throw Error(where, "column given by name \"" + c.name +
                               "\" but the map says header: false (use 1-based indices)");
      auto d = dup_cols.find(c.name);
      if (d != dup_cols.end()) {
        std::string cols;
        for (int k : d->second) cols += (cols.empty() ? "" : ", ") + std::to_string(k);
        throw Error(where, "column \"" + printable(c.name) +
                               "\" appears more than once in the header of " + in_file + " (line " +
                               std::to_string(header_line) + ", fields " + cols +
                               "): refer to the one meant by its 1-based index");
      }
      auto it = by_name.find(c.name);
      if (it == by_name.end()) {
        std::string hint;
        if (nfields == 1) {
          // One field: the delimiter is probably not the file's.
          std::string others;
          for (char d : {',', ';', '\t', ' '})
            if (d != delim && header_text.find(d) != std::string::npos)
              others += std::string(others.empty() ? "" : ", ") + (d == '\t'  ? "tab"
                                                                   : d == ' ' ? "space"
                                                                              : std::string(1, d));
          hint = ": the header is a single field (\"" + printable(header_text, 40) +
                 "\"), so the map's delimiter is probably wrong" +
                 (others.empty() ? std::string() : " (the header contains " + others + ")");
        }
        throw Error(where, "column \"" + printable(c.name) + "\" is not in the header of " +
                               in_file + " (line " + std::to_string(header_line) + ")" + hint);
      }
      c.index = it->second;
    } else if (v.is_number_integer()) {
      int i = v.get<int>();
      if (i < 1 || (nfields > 0 && i > nfields))
        throw Error(where, "column index " + std::to_string(i) + " is outside 1.." +
                               std::to_string(nfields));
      c.index = i - 1;
      c.name = "#" + std::to_string(i);
    } else {
      throw Error(where,
                  "expected a column name (string) or a 1-based index, got " + describe_json(v));
    }
    max_index = std::max(max_index, c.index);
    used.push_back(c);
    return c;
  }
  ColRef one(Params& p, const std::string& key) { return get(p, key, p.raw(key), ""); }
  std::vector<ColRef> many(Params& p, const std::string& key, size_t n) {
    const Json& v = p.raw(key);
    if (!v.is_array() || v.size() != n)
      p.fail(key,
             "expected an array of " + std::to_string(n) + " columns, got " + describe_json(v));
    std::vector<ColRef> out;
    for (size_t i = 0; i < n; ++i) out.push_back(get(p, key, v[i], "[" + std::to_string(i) + "]"));
    return out;
  }
};

double length_unit(Params& p, const std::string& path, const std::string& variant) {
  std::string u = map_string(p, path, variant);
  return u == "m" ? 1.0 : u == "cm" ? 0.01 : 0.001;
}

glm::dvec3 vec3_of(Params& p, const std::string& path, const std::string& variant) {
  std::vector<double> v = map_numbers(p, path, variant);
  if (v.size() != 3) p.fail(path.substr(path.rfind('.') + 1), "expected 3 numbers");
  return {v[0], v[1], v[2]};
}

// World-from-head rotation from a forward vector and an optional up vector, both in fovsim
// axes (the head looks down -Z with +Y up). Without an up vector, world +Y is used (no roll).
bool rotation_from_forward(glm::dvec3 f, glm::dvec3 u, glm::dquat& out) {
  double fn = glm::length(f);
  if (!(fn > 1e-9)) return false;
  f /= fn;
  glm::dvec3 r = glm::cross(f, u);
  double rn = glm::length(r);
  if (!(rn > 1e-6)) return false;
  r /= rn;
  glm::dvec3 up = glm::cross(r, f);
  out = glm::normalize(glm::quat_cast(glm::dmat3(r, up, -f)));
  return true;
}

bool same_pose(const TraceSample& a, const TraceSample& b) {
  return a.head_pos == b.head_pos && a.head_rot == b.head_rot;
}

bool parse_int64(const std::string& text, long long& v, bool& overflow) {
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+') ++b;
  auto r = std::from_chars(b, e, v);
  overflow = r.ec == std::errc::result_out_of_range && r.ptr == e;
  return r.ec == std::errc() && r.ptr == e && b != e;
}

Map::Cond read_cond(Params& c, Resolver& res, bool per_eye) {
  c.ignore("comment");
  Map::Cond cond;
  cond.col = res.one(c, "column");
  const char* kinds[] = {"valid_values", "invalid_values", "all_bits", "min", "max"};
  int n = 0;
  for (const char* k : kinds) n += c.has(k) ? 1 : 0;
  if (n != 1) c.fail("", "give exactly one of valid_values, invalid_values, all_bits, min or max");
  if (c.has("valid_values") || c.has("invalid_values")) {
    bool hv = c.has("valid_values");
    const std::string key = hv ? "valid_values" : "invalid_values";
    const Json& vals = c.raw(key);
    if (!vals.is_array() || vals.empty()) c.fail(key, "expected a non-empty array of strings");
    for (size_t i = 0; i < vals.size(); ++i) {
      if (!vals[i].is_string() && !vals[i].is_number())
        c.fail(key + "[" + std::to_string(i) + "]",
               "expected a string, got " + describe_json(vals[i]));
      cond.values.push_back(vals[i].is_string() ? vals[i].get<std::string>() : vals[i].dump());
    }
    cond.kind = hv ? Map::Cond::ValidList : Map::Cond::InvalidList;
  } else if (c.has("all_bits")) {
    cond.kind = Map::Cond::AllBits;
    cond.bits = map_integer(c, "valid[i].all_bits");
  } else {
    bool mn = c.has("min");
    cond.kind = mn ? Map::Cond::Min : Map::Cond::Max;
    cond.bound = map_number(c, mn ? "valid[i].min" : "valid[i].max");
  }
  std::string eye = map_string(c, "valid[i].eye");
  cond.eye = eye == "left" ? 1 : eye == "right" ? 2 : 0;
  if (cond.eye != 0 && !per_eye)
    c.fail("eye", "per-eye validity needs per-eye gaze (gaze.left and gaze.right)");
  return cond;
}

// True when the field satisfies the condition (an unparsable number fails it).
bool cond_holds(const Map::Cond& c, const std::string& f) {
  switch (c.kind) {
    case Map::Cond::ValidList:
    case Map::Cond::InvalidList: {
      bool listed = false;
      for (auto& v : c.values) listed = listed || v == f;
      return c.kind == Map::Cond::ValidList ? listed : !listed;
    }
    case Map::Cond::AllBits: {
      long long v = 0;
      bool of = false;
      if (!parse_int64(f, v, of)) {
        double d = 0;
        std::string why;
        if (!parse_number(f, d, why) || d != std::floor(d) || std::fabs(d) > 9e15) return false;
        v = (long long)d;
      }
      return (v & c.bits) == c.bits;
    }
    default: {
      double d = 0;
      std::string why;
      if (!parse_number(f, d, why)) return false;
      return c.kind == Map::Cond::Min ? d >= c.bound : d <= c.bound;
    }
  }
}

// ---- stage 1: the column map ------------------------------------------------------------------
// The map's layout: delimiter, header, skipped lines, bad-row policy, source axes.
Map read_map_layout(Params& p) {
  Map m;
  std::string d = map_string(p, "delimiter");
  m.delim = d == "comma" ? ',' : d == "tab" ? '\t' : d == "semicolon" ? ';' : ' ';
  m.header = map_boolean(p, "header");
  if (!p.has("header"))
    p.fail("header", "required: true if the first line names the columns, false otherwise");
  m.skip_lines = map_integer(p, "skip_lines");
  std::string cm = map_string(p, "comment_prefix");
  if (cm.size() > 1) p.fail("comment_prefix", "expected one character or \"\"");
  m.comment = cm.empty() ? 0 : cm[0];
  m.skip_bad = map_string(p, "on_bad_row") == "skip";
  m.max_skipped = map_number(p, "max_skipped_fraction");
  m.used_fields_only = map_string(p, "row_fields") == "used";
  m.interpolate_repeats = map_string(p, "repeated_pose") == "interpolate";
  if (!p.has("coordinates"))
    p.fail(
        "coordinates",
        "required: the source's axis convention (fovsim, opengl, unity, unreal or an axis object)");
  m.axes = axis_map_from(p.raw("coordinates"), p.where("coordinates"));
  m.gaze_axes = m.axes;
  return m;
}

// Skips to the header (or first row, without a header) and indexes its column names; the map's
// column references are resolved against it.
Resolver read_header(CsvReader& reader, const Map& m, const std::string& in, CsvRow& row0) {
  bool got = false;
  // skip_lines counts physical lines: drop rows whose line number is <= skip_lines.
  while ((got = reader.next(row0)) && row0.line <= m.skip_lines) {
  }
  if (!got) throw Error(in, "no data rows");
  Resolver res;
  res.header = m.header;
  res.in_file = in;
  if (m.header) {
    res.header_line = row0.line;
    // A name that occurs twice is an error only if the map refers to it (Resolver::get).
    for (size_t i = 0; i < row0.fields.size(); ++i) {
      const std::string& n = row0.fields[i].text;
      if (res.by_name.count(n)) {
        auto& dc = res.dup_cols[n];
        if (dc.empty()) dc.push_back(res.by_name[n] + 1);
        dc.push_back(int(i) + 1);
        continue;
      }
      res.by_name[n] = int(i);
    }
  }
  res.nfields = int(row0.fields.size());
  res.delim = m.delim;
  if (row0.fields.size() == 1) res.header_text = row0.fields[0].text;
  return res;
}

void read_time_keys(Params& p, Resolver& res, Map& m) {
  Params tp = p.child("time");
  m.time = res.one(tp, "column");
  std::string tu = map_string(tp, "time.unit");
  m.time_scale = tu == "s" ? 1.0 : tu == "ms" ? 1e-3 : tu == "us" ? 1e-6 : tu == "ns" ? 1e-9 : 1e-7;
  m.rebase = map_boolean(tp, "time.rebase");
  m.wrap_bits = map_integer(tp, "time.wrap_bits");
  if (m.wrap_bits != 0 && m.wrap_bits < 8)
    tp.fail("wrap_bits", "expected 0 (no wrap) or 8..62 bits of the counter");
  m.max_step_s = map_number(tp, "time.max_step_s");
  m.burst_below_s = map_number(tp, "time.burst_below_s");
  std::string ob = map_string(tp, "time.on_burst");
  m.on_burst = ob == "keep" ? Map::BurstKeep : ob == "drop" ? Map::BurstDrop : Map::BurstRetime;
  m.burst_pose_arrival = map_string(tp, "time.burst_pose") == "arrival";
  tp.ignore("comment");
}

void read_head_keys(Params& p, Resolver& res, Map& m) {
  if (!p.has("head_position"))
    p.fail("head_position",
           "required: {\"columns\": [x, y, z], \"unit\": \"m\"} or {\"constant\": [0, 1.6, 0]}");
  Params hp = p.child("head_position");
  hp.ignore("comment");
  if (hp.has("constant")) {
    m.pos_const = true;
    m.pos_value = vec3_of(hp, "head_position.constant", "constant");
  } else {
    m.pos = res.many(hp, "columns", 3);
    m.pos_scale = length_unit(hp, "head_position.unit", "columns");
    m.recentre = map_string(hp, "head_position.recentre", "columns");
    m.dequant_pos = map_boolean(hp, "head_position.dequantise", "columns");
  }

  if (!p.has("head_orientation"))
    p.fail("head_orientation",
           "required: quaternion, euler or forward columns, or {\"constant\": [1, 0, 0, 0]}");
  Params ho = p.child("head_orientation");
  ho.ignore("comment");
  m.inverse = map_boolean(ho, "head_orientation.inverse");
  m.dequant_rot = map_boolean(ho, "head_orientation.dequantise");
  if (m.dequant_rot && ho.has("constant"))
    ho.fail("dequantise", "a constant orientation has nothing to dequantise");
  if (ho.has("constant")) {
    std::vector<double> q = map_numbers(ho, "head_orientation.constant", "constant");
    if (q.size() != 4) ho.fail("constant", "expected 4 numbers (w, x, y, z) in fovsim coordinates");
    const double qn = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(qn > 1e-6) || !std::isfinite(qn))
      ho.fail("constant", "quaternion of norm " + std::to_string(qn) +
                              " is not a rotation (give a unit quaternion such as [1, 0, 0, 0])");
    m.rot_kind = Map::ConstRot;
    m.rot_value = glm::normalize(glm::dquat(q[0], q[1], q[2], q[3]));
  } else {
    std::string type = map_string(ho, "head_orientation.type");
    if (type == "quaternion") {
      m.rot_kind = Map::Quat;
      m.rot = res.many(ho, "columns", 4);
      m.xyzw = map_string(ho, "head_orientation.order", "quaternion") == "xyzw";
    } else if (type == "forward") {
      m.rot_kind = Map::Forward;
      m.rot = res.many(ho, "forward", 3);
      if (ho.has("up")) m.up = res.many(ho, "up", 3);
    } else {
      m.rot_kind = Map::Euler;
      m.rot = res.many(ho, "columns", 3);
      m.euler_order = map_string(ho, "head_orientation.order", "euler");
      bool okord = m.euler_order.size() == 3;
      for (char c : m.euler_order) okord = okord && (c == 'X' || c == 'Y' || c == 'Z');
      // Each axis once: "XXY" would ignore the Z column.
      okord = okord && m.euler_order[0] != m.euler_order[1] &&
              m.euler_order[1] != m.euler_order[2] && m.euler_order[0] != m.euler_order[2];
      if (!okord)
        ho.fail("order",
                "expected three of X, Y, Z, each once, such as \"ZXY\" (Unity) or \"ZYX\"");
      m.intrinsic = map_string(ho, "head_orientation.sequence", "euler") == "intrinsic";
      m.angle_scale = map_string(ho, "head_orientation.unit", "euler") == "deg" ? kPi / 180 : 1.0;
      std::vector<double> sg = map_numbers(ho, "head_orientation.signs", "euler");
      if (sg.size() != 3) ho.fail("signs", "expected 3 numbers, each 1 or -1");
      for (int i = 0; i < 3; ++i) {
        if (sg[size_t(i)] != 1 && sg[size_t(i)] != -1)
          ho.fail("signs", "expected 3 numbers, each 1 or -1");
        m.euler_signs[i] = sg[size_t(i)];
      }
    }
  }
}

void read_gaze_keys(Params& p, Resolver& res, Map& m) {
  Params gp = p.child("gaze");
  if (!p.has("gaze"))
    p.fail("gaze", "required: how the gaze is given (direction, screen or point)");
  gp.ignore("comment");
  std::string gt = map_string(gp, "gaze.type");
  if (gp.has("coordinates")) {
    if (gt == "screen")
      gp.fail("coordinates", "a screen gaze has no axes (only direction and point gaze do)");
    m.gaze_axes = axis_map_from(gp.raw("coordinates"), gp.where("coordinates"));
  }
  if (gt == "angles") {
    // Azimuth (positive to the right) and elevation (positive up) of the gaze in the head,
    // as world-camera eye trackers export them (Pupil Cloud gaze.csv).
    if (gp.has("coordinates"))
      gp.fail("coordinates", "angles have no axes: use \"signs\" to flip their sense");
    m.gaze_kind = Map::DirHead;
    m.gaze_angles = true;
    m.gaze_axes = AxisMap{};
    m.gaze = res.many(gp, "columns", 2);
    double sc = map_string(gp, "gaze.unit", "angles") == "deg" ? kPi / 180 : 1.0;
    std::vector<double> sg = map_numbers(gp, "gaze.signs", "angles");
    if (sg.size() != 2 || (sg[0] != 1 && sg[0] != -1) || (sg[1] != 1 && sg[1] != -1))
      gp.fail("signs", "expected 2 numbers (azimuth, elevation), each 1 or -1");
    m.angle_signs = glm::dvec2(sg[0], sg[1]) * sc;
  } else if (gt == "orientation") {
    // A gaze pose (OpenXR eye gaze): the gaze is the orientation's forward axis.
    m.gaze_kind = map_string(gp, "gaze.space", "direction, orientation") == "head" ? Map::DirHead
                                                                                   : Map::DirWorld;
    m.gaze_orient = true;
    m.gaze = res.many(gp, "columns", 4);
    m.gaze_xyzw = map_string(gp, "gaze.order", "orientation") == "xyzw";
    std::string fa = map_string(gp, "gaze.forward", "orientation");
    m.gaze_forward = glm::dvec3(0.0);
    m.gaze_forward[fa[1] - 'x'] = fa[0] == '-' ? -1.0 : 1.0;
  } else if (gt == "direction") {
    m.gaze_kind = map_string(gp, "gaze.space", "direction, orientation") == "head" ? Map::DirHead
                                                                                   : Map::DirWorld;
    bool per_eye = gp.has("left") || gp.has("right");
    if (per_eye == gp.has("columns"))
      gp.fail("", per_eye
                      ? "give either \"columns\" (combined gaze) or \"left\"/\"right\", not both"
                      : "needs \"columns\": [x, y, z] or per-eye \"left\" and \"right\"");
    if (per_eye) {
      m.left = res.many(gp, "left", 3);
      m.right = res.many(gp, "right", 3);
      m.combine = map_string(gp, "gaze.combine", "direction with left, right");
    } else {
      m.gaze = res.many(gp, "columns", 3);
    }
  } else if (gt == "screen") {
    m.gaze_kind = Map::Screen;
    m.gaze = res.many(gp, "columns", 2);
    m.screen_bottom_left = map_string(gp, "gaze.origin", "screen") == "bottom-left";
  } else {
    m.gaze_kind = Map::Point;
    m.gaze = res.many(gp, "columns", 3);
    m.point_scale = length_unit(gp, "gaze.unit", "point");
  }
}

// Validity conditions, the bad-sample and tracking-loss defaults, fused fields.
void read_row_keys(Params& p, Resolver& res, Map& m) {
  const bool per_eye = !m.left.empty();
  for (Params& c : p.children("valid")) m.valid.push_back(read_cond(c, res, per_eye));
  if (p.has("on_bad")) {
    m.has_on_bad = true;
    std::string ob = map_string(p, "on_bad");
    m.on_bad = ob == "fail"   ? BadSamplePolicy::Fail
               : ob == "skip" ? BadSamplePolicy::Skip
                              : BadSamplePolicy::Hold;
  }
  if (p.has("on_invalid")) m.on_invalid = map_string(p, "on_invalid");
  for (Params& f : p.children("fused")) {
    f.ignore("comment");
    Map::Fused fu;
    fu.col = res.one(f, "column");
    if (f.has("suffixes") == f.has("pattern"))
      f.fail("",
             "give exactly one of \"suffixes\": [\"True\", \"False\"] or \"pattern\": "
             "\"^(.*[0-9])(True|False)$\"");
    if (f.has("pattern")) {
      fu.use_pattern = true;
      std::string pat = map_string(f, "fused[i].pattern");
      try {
        fu.pattern = std::regex(pat);
      } catch (const std::regex_error& e) {
        f.fail("pattern", std::string("not a valid regular expression: ") + e.what());
      }
      if (fu.pattern.mark_count() != 2)
        f.fail("pattern", "needs exactly two groups, (first field)(second field)");
    } else {
      const Json& sj = f.raw("suffixes");
      if (!sj.is_array() || sj.empty()) f.fail("suffixes", "expected a non-empty array of strings");
      for (size_t i = 0; i < sj.size(); ++i) {
        if (!sj[i].is_string() || sj[i].get<std::string>().empty())
          f.fail("suffixes[" + std::to_string(i) + "]", "expected a non-empty string");
        fu.suffixes.push_back(sj[i].get<std::string>());
      }
    }
    if (fu.col.index + 1 >= res.nfields)
      f.fail("column", "the fused field must be followed by another header column");
    m.fused.push_back(std::move(fu));
  }
}

// ---- stage 2: the row decoder ----------------------------------------------------------------
// The imported samples and, per sample, its source line and its gaze in world axes (to re-derive
// the head-space gaze after a later stage moves the head pose).
struct Decoded {
  Trace tr;
  std::vector<long> lines;
  std::vector<glm::dvec3> world_gaze;
};

// Reads one row's numbers; the first unparsable field is remembered (`bad`, its message and
// column) and reported once the row's group of values is read.
struct RowReader {
  explicit RowReader(const CsvRow& r) : row(r) {}
  const CsvRow& row;
  bool bad = false;
  std::string err;
  int err_col = 1;
  double num(const ColRef& c) {
    double v = 0;
    std::string why;
    if (!bad && !parse_number(row.fields[size_t(c.index)].text, v, why)) {
      bad = true;
      err = "column \"" + printable(c.name) + "\": " + why;
      err_col = row.fields[size_t(c.index)].col;
    }
    return v;
  }
  glm::dvec3 vec(const std::vector<ColRef>& c) {
    return glm::dvec3(num(c[0]), num(c[1]), num(c[2]));
  }
};

// The time of one row, as read_time found it.
struct RowTime {
  const CsvField* tf = nullptr;  // the time field
  long long row_wrap = 0;        // wrap_add + wrap_span when this row wraps the counter
  double t = 0;                  // seconds (integer times already rebased)
  long long ti = 0;              // the raw integer time, when is_int
  bool is_int = false;
};

// One data row -> one sample in fovsim's conventions, or a skipped row (logged, counted), in
// file order: the time bookkeeping (exact integer rebasing, counter wraps, jumps, monotonic
// time) and the last valid gaze (held on invalid rows) need the rows in sequence.
struct RowDecoder {
  RowDecoder(const Map& m_, const Resolver& res_, const std::string& in_, const Display& display_,
             const ImportOptions& opt_, IssueLog& log_, ImportReport& rep_, Decoded& out_)
      : m(m_),
        res(res_),
        in(in_),
        display(display_),
        opt(opt_),
        eff(opt_),
        log(log_),
        rep(rep_),
        out(out_) {}
  const Map& m;
  const Resolver& res;
  const std::string& in;
  const Display& display;
  const ImportOptions& opt;  // the caller's options
  ImportOptions eff;         // with the map's on_bad unless the caller chose
  IssueLog& log;
  ImportReport& rep;
  Decoded& out;
  size_t nf = 0, need = 0;  // fields of the header; fields a row needs with row_fields = used
  bool per_eye = false;
  bool have_t0 = false, int_time = false;
  long long t0_int = 0, last_raw_int = 0, wrap_add = 0, wrap_span = 0;
  double t0 = 0, last_t = -INFINITY;
  long last_line = 0;
  std::string last_text;
  glm::dvec3 last_gaze{0, 0, -1};
  CsvRow prev_row;  // the last complete row (for a cut-off last line)
  bool have_prev_row = false;

  enum class Step { kept, skipped, stop };

  void fail_row_at(const CsvRow& row, int col, const std::string& kind, const std::string& msg) {
    std::string where = file_location(in, row.line, col);
    if (!m.skip_bad)
      throw Error(where, msg + " (set the map's on_bad_row to \"skip\" to drop such rows)");
    log.add("skipped", kind, where, msg);
    ++rep.skipped_rows;
  }

  void split_fused_fields(CsvRow& row) {
    // A fused field (`666.5324True`): split back into two, so later columns are in place.
    for (auto& f : m.fused) {
      if (row.fields.size() >= nf || size_t(f.col.index) >= row.fields.size()) break;
      std::string a, b;
      CsvField& fld = row.fields[size_t(f.col.index)];
      if (!split_fused(f, fld.text, a, b)) continue;
      CsvField second{b, fld.col + int(a.size())};
      fld.text = a;
      row.fields.insert(row.fields.begin() + f.col.index + 1, second);
      ++rep.fused_rows;
    }
  }

  // A cut-off last line, the field count.
  Step check_shape(const CsvRow& row) {
    auto fail_row = [&](int col, const std::string& kind, const std::string& msg) {
      fail_row_at(row, col, kind, msg);
    };
    Trace& tr = out.tr;
    // A last line cut off by an interrupted write (no final newline): dropped, and said so.
    {
      std::string why;
      if (looks_truncated(row, have_prev_row ? &prev_row : nullptr,
                          have_prev_row ? prev_row.fields.size() : nf, why)) {
        tr.warnings.push_back(file_location(in, row.line) + ": " + why + "; the line was dropped");
        ++rep.skipped_rows;
        return Step::stop;
      }
      if (!row.unterminated) {
        prev_row = row;
        have_prev_row = true;
      }
    }
    if (m.used_fields_only && row.fields.size() < need) {
      // Name the used column that is missing, not the field count (which row_fields = used
      // does not require).
      const ColRef* miss = nullptr;
      for (auto& c : res.used)
        if (size_t(c.index) >= row.fields.size() && (!miss || c.index > miss->index)) miss = &c;
      fail_row(row.fields.back().col, "used column missing",
               "column \"" + printable(miss ? miss->name : "?") + "\" (field " +
                   std::to_string(miss ? miss->index + 1 : 0) + ") is missing: the row has " +
                   std::to_string(row.fields.size()) +
                   " fields (a shorter row, or fields fused before it)");
      return Step::skipped;
    }
    if (row.fields.size() != nf && !(m.used_fields_only && row.fields.size() >= need)) {
      fail_row(row.fields.size() > nf ? row.fields[nf].col : row.fields.back().col,
               "wrong field count",
               "expected " + std::to_string(nf) + " fields" +
                   (m.header ? " as in the header" : " as in the first row") + ", got " +
                   std::to_string(row.fields.size()) +
                   (row.fields.size() < nf && !m.used_fields_only
                        ? " (if two fields are fused in the export, \"row_fields\": \"used\" "
                          "accepts rows whose used "
                          "columns are present)"
                        : ""));
      return Step::skipped;
    }
    return Step::kept;
  }

  void read_validity(const CsvRow& row, bool& valid, bool& left_ok, bool& right_ok) const {
    // Validity flags first: rows flagged invalid keep their pose but may carry any gaze.

    for (auto& c : m.valid) {
      bool ok = cond_holds(c, row.fields[size_t(c.col.index)].text);
      if (c.eye == 0)
        valid = valid && ok;
      else if (c.eye == 1)
        left_ok = left_ok && ok;
      else
        right_ok = right_ok && ok;
    }
    if (per_eye) {
      if (m.combine == "left")
        valid = valid && left_ok;
      else if (m.combine == "right")
        valid = valid && right_ok;
      else
        valid = valid && (left_ok || right_ok);
    }
  }

  bool read_time(const CsvRow& row, RowReader& rr, RowTime& rt) {
    bool& bad = rr.bad;
    std::string& err = rr.err;
    int& err_col = rr.err_col;
    auto num = [&](const ColRef& c) { return rr.num(c); };
    auto fail_row = [&](int col, const std::string& kind, const std::string& msg) {
      fail_row_at(row, col, kind, msg);
    };
    // Time (integers kept exact before rebasing, e.g. epoch nanoseconds).
    const CsvField& tf = row.fields[size_t(m.time.index)];
    long long row_wrap = wrap_add;  // wrap_add + wrap_span when this row wraps the counter
    double t = 0;
    long long ti = 0;
    bool overflow = false;
    bool is_int = parse_int64(tf.text, ti, overflow);
    if (overflow) {
      fail_row(tf.col, "bad time",
               "time value \"" + printable(tf.text) + "\" (" + std::to_string(tf.text.size()) +
                   " characters) does not fit a 64-bit integer: a corrupt or fused value?");
      return false;
    }
    if (!have_t0) int_time = is_int;
    if (int_time && is_int) {
      if (!have_t0) t0_int = ti;
      if (wrap_span) {
        if (ti < 0 || ti >= wrap_span) {
          fail_row(tf.col, "bad time",
                   "time value " + tf.text + " is outside the " + std::to_string(m.wrap_bits) +
                       "-bit counter range of time.wrap_bits");
          return false;
        }
        // A backward step of more than half the range is a wrap of the counter (counted when
        // the row is kept, so a dropped row does not unwrap twice).
        if (have_t0 && ti < last_raw_int && last_raw_int - ti > wrap_span / 2) {
          // Exact integer arithmetic: unwrapping past the 64-bit range is an error, not UB.
          if (__builtin_add_overflow(wrap_add, wrap_span, &row_wrap)) {
            fail_row(tf.col, "bad time",
                     "time value out of range: unwrapping " + tf.text + " (wrap " +
                         std::to_string(rep.time_wraps + 1) + " of a " +
                         std::to_string(m.wrap_bits) + "-bit counter) overflows a 64-bit integer");
            return false;
          }
        }
      }
      long long rel = 0, v = 0;
      if (__builtin_add_overflow(ti, row_wrap, &v) || __builtin_sub_overflow(v, t0_int, &rel)) {
        fail_row(tf.col, "bad time",
                 "time value out of range: " + tf.text + " minus the first time " +
                     std::to_string(t0_int) +
                     " overflows a 64-bit integer: a corrupt or sentinel value?");
        return false;
      }
      t = double(rel) * m.time_scale;
    } else {
      t = num(m.time) * m.time_scale;
      if (bad) {
        fail_row(err_col, "bad number", err);
        return false;
      }
      if (int_time) t -= double(t0_int) * m.time_scale;
    }
    if (have_t0 && t > last_t && t - last_t > m.max_step_s) {
      char b[64];
      std::snprintf(b, sizeof b, "%.6g", t - last_t);
      fail_row(tf.col, "time jump",
               "time \"" + printable(tf.text) + "\" jumps forward by " + b + " s from " +
                   printable(last_text) + " at line " + std::to_string(last_line) +
                   ", more than time.max_step_s = " + std::to_string(m.max_step_s) +
                   " s: a corrupt or sentinel time value?");
      return false;
    }
    rt.tf = &tf;
    rt.row_wrap = row_wrap;
    rt.t = t;
    rt.ti = ti;
    rt.is_int = is_int;
    return true;
  }

  bool read_pose(const CsvRow& row, RowReader& rr, TraceSample& s) {
    bool& bad = rr.bad;
    std::string& err = rr.err;
    int& err_col = rr.err_col;
    auto num = [&](const ColRef& c) { return rr.num(c); };
    auto vec = [&](const std::vector<ColRef>& c) { return rr.vec(c); };
    auto fail_row = [&](int col, const std::string& kind, const std::string& msg) {
      fail_row_at(row, col, kind, msg);
    };
    // Head pose.
    s.head_pos = m.pos_const ? m.pos_value : m.axes.vec(vec(m.pos) * m.pos_scale);
    if (m.rot_kind == Map::ConstRot) {
      s.head_rot = m.rot_value;
    } else if (m.rot_kind == Map::Quat) {
      double a = num(m.rot[0]), b = num(m.rot[1]), c = num(m.rot[2]), e = num(m.rot[3]);
      glm::dquat q = m.xyzw ? glm::dquat(e, a, b, c) : glm::dquat(a, b, c, e);
      double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
      if (!bad && std::fabs(n - 1) > 1e-2) {
        bad = true;
        err = "quaternion norm " + std::to_string(n) + " is not 1";
        err_col = row.fields[size_t(m.rot[0].index)].col;
      }
      if (!bad) s.head_rot = m.axes.rot(glm::mat3_cast(q / n));
    } else if (m.rot_kind == Map::Forward) {
      glm::dvec3 f = m.axes.vec(vec(m.rot));
      glm::dvec3 u = m.up.empty() ? glm::dvec3(0, 1, 0) : m.axes.vec(vec(m.up));
      if (!bad && !rotation_from_forward(f, u, s.head_rot)) {
        bad = true;
        err = m.up.empty() ? "head forward vector is zero or vertical (give \"up\" columns)"
                           : "head forward vector is zero or parallel to the up vector";
        err_col = row.fields[size_t(m.rot[0].index)].col;
      }
    } else {
      glm::dvec3 ang = vec(m.rot) * m.angle_scale * m.euler_signs;
      if (!bad) s.head_rot = m.axes.rot(euler_matrix(ang, m.euler_order, m.intrinsic));
    }
    if (m.inverse) s.head_rot = glm::conjugate(s.head_rot);
    if (bad) {
      fail_row(err_col, "bad number", err);
      return false;
    }
    return true;
  }

  bool read_gaze(const CsvRow& row, RowReader& rr, TraceSample& s, bool left_ok, bool right_ok,
                 bool& one_eye_out) {
    bool& bad = rr.bad;
    std::string& err = rr.err;
    int& err_col = rr.err_col;
    auto num = [&](const ColRef& c) { return rr.num(c); };
    auto vec = [&](const std::vector<ColRef>& c) { return rr.vec(c); };
    auto fail_row = [&](int col, const std::string& kind, const std::string& msg) {
      fail_row_at(row, col, kind, msg);
    };
    const bool valid = s.valid;
    // Gaze -> head space.
    glm::dvec3 g(0.0);
    std::string gerr;
    int gcol = row.fields[size_t((m.gaze.empty() ? m.left : m.gaze)[0].index)].col;
    bool one_eye = false;
    if (m.gaze_kind == Map::Screen) {
      double u = num(m.gaze[0]), v = num(m.gaze[1]);
      if (m.screen_bottom_left) v = 1 - v;
      if (!bad && (u < 0 || u > 1 || v < 0 || v > 1)) gerr = "gaze screen point outside [0,1]^2";
      g = gaze_dir_from_screen(display, u, v);  // already head space (fovsim)
    } else if (m.gaze_angles) {
      double az = num(m.gaze[0]) * m.angle_signs.x, el = num(m.gaze[1]) * m.angle_signs.y;
      g = glm::dvec3(std::cos(el) * std::sin(az), std::sin(el), -std::cos(el) * std::cos(az));
    } else if (m.gaze_orient) {
      double a = num(m.gaze[0]), b = num(m.gaze[1]), c = num(m.gaze[2]), e = num(m.gaze[3]);
      glm::dquat q = m.gaze_xyzw ? glm::dquat(e, a, b, c) : glm::dquat(a, b, c, e);
      double n = glm::length(q);
      g = n > 1e-9 ? (q / n) * m.gaze_forward : glm::dvec3(0.0);
    } else if (per_eye) {
      // An eye flagged invalid (valid conditions with "eye") is not read at all.
      glm::dvec3 l = left_ok ? vec(m.left) : glm::dvec3(0.0),
                 rr = right_ok ? vec(m.right) : glm::dvec3(0.0);
      double ln = glm::length(l), rn = glm::length(rr);
      if (m.combine == "left")
        g = l;
      else if (m.combine == "right")
        g = rr;
      else if (ln > 1e-9 && rn > 1e-9)
        g = l / ln + rr / rn;
      else {
        g = ln > 1e-9 ? l : rr;  // one eye lost: use the other
        one_eye = ln > 1e-9 || rn > 1e-9;
      }
    } else {
      g = vec(m.gaze);
    }
    if (bad) {
      if (valid) {
        fail_row(err_col, "bad number", err);
        return false;
      }
      g = glm::dvec3(0.0);
    }
    glm::dvec3 gh(0.0);
    if (m.gaze_kind == Map::Screen) {
      gh = g;
    } else if (m.gaze_kind == Map::DirHead) {
      gh = m.gaze_axes.vec(g);
    } else if (m.gaze_kind == Map::DirWorld) {
      gh = glm::conjugate(s.head_rot) * m.gaze_axes.vec(g);
    } else if (m.gaze_kind == Map::Point) {
      gh = glm::conjugate(s.head_rot) * (m.gaze_axes.vec(g * m.point_scale) - s.head_pos);
    }
    double gn = glm::length(gh);
    if (gerr.empty() && !(gn > 1e-9)) gerr = "zero-length gaze";
    if (gerr.empty() && !((gh / gn).z < 0))
      gerr = "gaze points behind the eye (not forward in head space: check coordinates)";
    if (!gerr.empty() && valid) {
      fail_row(gcol, gerr, gerr);
      return false;
    }
    // Rows flagged invalid show the last valid gaze (traces/README.md): their own gaze, even
    // when finite and inside the FOV, is what the tracker reported while it had lost the eye.
    s.gaze_dir = gerr.empty() && valid ? gh / gn : last_gaze;
    if (valid && opt.check_fov && !gaze_inside_fov(display, s.gaze_dir)) {
      double u = 0, w = 0;
      gaze_screen_from_dir(display, s.gaze_dir, u, w);
      char b[240];
      std::snprintf(b, sizeof b,
                    "gaze outside the display FOV (%s %.1fx%.1f deg): screen point (%.3f, %.3f) "
                    "not in [0,1]^2",
                    display.name.c_str(), display.fov_h_deg, display.fov_v_deg, u, w);
      std::string where = file_location(in, row.line, gcol);
      if (eff.on_fov == BadSamplePolicy::Fail)
        throw Error(where, std::string(b) +
                               " (check the gaze coordinates and --display; --on-bad / "
                               "trace.on_bad_sample skip or hold accept it)");
      if (eff.on_fov == BadSamplePolicy::Skip) {
        log.add("skipped", "gaze outside the display FOV", where, b);
        ++rep.skipped_rows;
        return false;
      }
      log.add("held", "gaze outside the display FOV", where, b);
      s.gaze_dir = last_gaze;
    }
    if (valid) last_gaze = s.gaze_dir;
    one_eye_out = one_eye;
    return true;
  }

  Step decode(CsvRow& cur) {
    split_fused_fields(cur);
    const CsvRow& row = cur;
    ++rep.data_rows;
    const Step shape = check_shape(row);
    if (shape != Step::kept) return shape;
    RowReader rr(row);
    bool valid = true, left_ok = true, right_ok = true;
    read_validity(row, valid, left_ok, right_ok);
    RowTime time;
    if (!read_time(row, rr, time)) return Step::skipped;
    TraceSample s;
    s.t = time.t;
    s.valid = valid;
    if (!read_pose(row, rr, s)) return Step::skipped;
    bool one_eye = false;
    if (!read_gaze(row, rr, s, left_ok, right_ok, one_eye)) return Step::skipped;
    return keep(row, time, s, one_eye);
  }

  // Monotonic time, then the sample is kept.
  Step keep(const CsvRow& row, const RowTime& time, const TraceSample& s, bool one_eye) {
    auto fail_row = [&](int col, const std::string& kind, const std::string& msg) {
      fail_row_at(row, col, kind, msg);
    };
    const CsvField& tf = *time.tf;
    const double t = time.t;
    const bool valid = s.valid, is_int = time.is_int;
    const long long ti = time.ti, row_wrap = time.row_wrap;
    Trace& tr = out.tr;
    std::vector<long>& lines = out.lines;
    std::vector<glm::dvec3>& world_gaze = out.world_gaze;
    if (!have_t0) {
      have_t0 = true;
      t0 = t;
    }
    // An equal time is a burst member when bursts are dropped or retimed (below).
    if (!(t > last_t) && !(t == last_t && m.on_burst != Map::BurstKeep)) {
      fail_row(tf.col, "non-monotonic time",
               "time not strictly increasing: " + printable(tf.text) + " after " +
                   printable(last_text) + " at line " + std::to_string(last_line));
      return Step::skipped;
    }
    if (!valid) ++rep.invalid_rows;
    if (valid && one_eye) ++rep.one_eye_rows;
    if (is_int) last_raw_int = ti;
    if (row_wrap != wrap_add) ++rep.time_wraps;
    wrap_add = row_wrap;
    last_t = t;
    last_line = row.line;
    last_text = tf.text;
    tr.samples.push_back(s);
    lines.push_back(row.line);
    world_gaze.push_back(s.head_rot * s.gaze_dir);
    if (t - t0 > opt.stop_after_s) {
      rep.stopped_early = true;
      return Step::stop;
    }
    return Step::kept;
  }
};

// ---- stage 3: time fix-ups ------------------------------------------------------------------
// Decimal times rebased (integer times were rebased exactly while decoding), then bursts of
// samples flushed after a stall kept, dropped or retimed (time.on_burst).
void fix_times(const Map& m, const std::string& in, const RowDecoder& dec, ImportReport& rep,
               Decoded& d) {
  Trace& tr = d.tr;
  std::vector<long>& lines = d.lines;
  std::vector<glm::dvec3>& world_gaze = d.world_gaze;
  const bool int_time = dec.int_time;
  const long long t0_int = dec.t0_int;
  const double t0 = dec.t0;
  // Integer times were rebased exactly on the fly; decimal times are rebased here.
  rep.time_offset_s = int_time ? double(t0_int) * m.time_scale : t0;
  for (auto& s : tr.samples) {
    if (m.rebase && !int_time) s.t -= t0;
    if (!m.rebase && int_time) s.t += rep.time_offset_s;
  }
  if (!m.rebase) rep.time_offset_s = 0;

  auto& x = tr.samples;
  // Bursts: samples delivered closer than burst_below_s (default: a quarter of the median
  // interval) after the previous one, typically buffered samples flushed after a stall.
  if (x.size() > 2) {
    std::vector<double> dts;
    for (size_t i = 1; i < x.size(); ++i) dts.push_back(x[i].t - x[i - 1].t);
    std::nth_element(dts.begin(), dts.begin() + long(dts.size() / 2), dts.end());
    double thr = m.burst_below_s > 0 ? m.burst_below_s : 0.25 * dts[dts.size() / 2];
    std::vector<char> burst(x.size(), 0);
    for (size_t i = 1; i < x.size(); ++i)
      if (x[i].t - x[i - 1].t < thr) burst[i] = 1;
    size_t first_b = 0;
    for (size_t i = 1; i < x.size(); ++i)
      if (burst[i]) {
        if (rep.burst_samples++ == 0) first_b = i;
      }
    if (rep.burst_samples > 0) {
      char b[200];
      std::snprintf(
          b, sizeof b,
          "%ld samples arrived less than %.3g ms after the previous one (bursts after a stall)",
          rep.burst_samples, thr * 1e3);
      std::string where = file_location(in, lines[first_b]);
      if (m.on_burst == Map::BurstKeep) {
        tr.warnings.push_back(in + ": " + b + "; kept (time.on_burst = keep); first at " + where);
      } else if (m.on_burst == Map::BurstDrop) {
        std::vector<TraceSample> kx;
        std::vector<long> kl;
        std::vector<glm::dvec3> kw;
        for (size_t i = 0; i < x.size(); ++i) {
          if (!kx.empty() && x[i].t - kx.back().t < thr) continue;
          kx.push_back(x[i]);
          kl.push_back(lines[i]);
          kw.push_back(world_gaze[i]);
        }
        tr.warnings.push_back(in + ": " + b + "; " + std::to_string(x.size() - kx.size()) +
                              " dropped (time.on_burst = drop); first at " + where);
        x.swap(kx);
        lines.swap(kl);
        world_gaze.swap(kw);
      } else {
        // Retime: a burst i..k was buffered during the stall before it; spread the samples
        // from the one that ended the stall (i-1) to k evenly after the sample before it (i-2).
        // The gaze was buffered, but the head pose of each sample is the one current when it
        // arrived (time.burst_pose = "arrival", the default): the retimed samples take the
        // pose interpolated on the arrival times, so the head does not turn by the whole
        // stall's motion in one retimed slot. "sample" moves the pose with the gaze.
        long retimed = 0;
        for (size_t i = 1; i < x.size();) {
          if (!burst[i]) {
            ++i;
            continue;
          }
          size_t k = i;
          while (k + 1 < x.size() && burst[k + 1]) ++k;
          if (i >= 2) {
            size_t a = i - 2;
            double ta = x[a].t, tk = x[k].t;
            std::vector<TraceSample> orig(x.begin() + long(a), x.begin() + long(k) + 1);
            for (size_t j = a + 1; j < k; ++j)
              x[j].t = ta + (tk - ta) * double(j - a) / double(k - a);
            if (m.burst_pose_arrival) {
              for (size_t j = a + 1; j < k; ++j) {
                // Bracket the new time on the arrival times orig[0..k-a] (non-decreasing).
                size_t q = 0;
                while (q + 2 < orig.size() && orig[q + 1].t <= x[j].t) ++q;
                const TraceSample &A = orig[q], &B = orig[q + 1];
                double f = B.t > A.t ? std::clamp((x[j].t - A.t) / (B.t - A.t), 0.0, 1.0) : 1.0;
                x[j].head_pos = A.head_pos + (B.head_pos - A.head_pos) * f;
                x[j].head_rot = glm::normalize(
                    glm::slerp(A.head_rot,
                               glm::dot(A.head_rot, B.head_rot) < 0 ? -B.head_rot : B.head_rot, f));
                if (m.gaze_kind == Map::DirWorld || m.gaze_kind == Map::Point)
                  x[j].gaze_dir = glm::normalize(glm::conjugate(x[j].head_rot) * world_gaze[j]);
              }
            }
            retimed += long(k - a - 1);
          }
          i = k + 1;
        }
        // A burst at the very start has no stall to spread over: equal times left are dropped.
        std::vector<TraceSample> kx;
        std::vector<long> kl;
        std::vector<glm::dvec3> kw;
        for (size_t i = 0; i < x.size(); ++i) {
          if (!kx.empty() && !(x[i].t > kx.back().t)) continue;
          kx.push_back(x[i]);
          kl.push_back(lines[i]);
          kw.push_back(world_gaze[i]);
        }
        std::string dropped = kx.size() < x.size() ? ", " + std::to_string(x.size() - kx.size()) +
                                                         " with equal times dropped"
                                                   : "";
        x.swap(kx);
        lines.swap(kl);
        world_gaze.swap(kw);
        tr.warnings.push_back(in + ": " + b + "; " + std::to_string(retimed) +
                              " retimed evenly over the preceding stall (time.on_burst = retime)" +
                              dropped + "; first at " + where);
      }
    }
  }
}

// ---- stage 4: the repeated-pose filter --------------------------------------------------------
// A head pose repeated exactly for several samples (pose updated per render frame, gaze per
// tracker sample): kept and reported, or interpolated (repeated_pose).
void filter_repeated_poses(const Map& m, const std::string& in, ImportReport& rep, Decoded& d) {
  Trace& tr = d.tr;
  auto& x = tr.samples;
  const std::vector<long>& lines = d.lines;
  const std::vector<glm::dvec3>& world_gaze = d.world_gaze;
  // With a constant head there is nothing to detect.
  if (!(m.pos_const && m.rot_kind == Map::ConstRot)) {
    long first_rep = 0;
    for (size_t i = 1; i < x.size(); ++i)
      if (same_pose(x[i], x[i - 1]) && rep.repeated_poses++ == 0) first_rep = lines[i];
    if (rep.repeated_poses > 0) {
      std::string msg =
          std::to_string(rep.repeated_poses) + " samples repeat the previous head pose exactly";
      if (!m.interpolate_repeats) {
        tr.warnings.push_back(
            in + ": " + msg +
            " (pose updated less often than the gaze); kept (repeated_pose = keep); "
            "first at " +
            file_location(in, first_rep));
      } else {
        // Interpolate each run a..b of one pose towards the next distinct pose n (slerp, lerp),
        // by time; gaze given in world keeps its world direction.
        long changed = 0;
        for (size_t a = 0; a < x.size();) {
          size_t b = a;
          while (b + 1 < x.size() && same_pose(x[b + 1], x[a])) ++b;
          if (b > a && b + 1 < x.size()) {
            size_t n = b + 1;
            const TraceSample A = x[a], N = x[n];
            for (size_t j = a + 1; j <= b; ++j) {
              double f = (x[j].t - A.t) / (N.t - A.t);
              x[j].head_pos = A.head_pos + (N.head_pos - A.head_pos) * f;
              x[j].head_rot = glm::normalize(glm::slerp(
                  A.head_rot, glm::dot(A.head_rot, N.head_rot) < 0 ? -N.head_rot : N.head_rot, f));
              if (m.gaze_kind == Map::DirWorld || m.gaze_kind == Map::Point)
                x[j].gaze_dir = glm::normalize(glm::conjugate(x[j].head_rot) * world_gaze[j]);
              ++changed;
            }
          }
          a = b + 1;
        }
        tr.warnings.push_back(
            in + ": " + msg + "; " + std::to_string(changed) +
            " interpolated between the poses around them (repeated_pose = interpolate); first at " +
            file_location(in, first_rep));
      }
    }
  }
}

// ---- stage 5: head-position recentring, dequantisation, and the notes of the earlier stages ----
void finish_poses(const Map& m, const std::string& in, const ImportReport& rep, Decoded& d) {
  Trace& tr = d.tr;
  auto& x = tr.samples;
  const std::vector<glm::dvec3>& world_gaze = d.world_gaze;
  if (rep.time_wraps > 0)
    tr.warnings.push_back(in + ": time counter wrapped " + std::to_string(rep.time_wraps) +
                          " times (" + std::to_string(m.wrap_bits) + " bits): unwrapped");
  if (rep.one_eye_rows > 0)
    tr.warnings.push_back(in + ": " + std::to_string(rep.one_eye_rows) +
                          (rep.one_eye_rows == 1 ? " row" : " rows") +
                          " had one valid eye: its gaze was used alone");
  // Recentring and dequantisation (traces/README.md "Column maps").
  if (m.recentre != "none" && !x.empty()) {
    glm::dvec3 c(0.0);
    if (m.recentre == "first") {
      c = x.front().head_pos;
    } else {
      for (auto& s : x) c += s.head_pos;
      c /= double(x.size());
    }
    for (auto& s : x) s.head_pos -= c;
    char b[160];
    std::snprintf(b, sizeof b, "head positions recentred by (%.4g, %.4g, %.4g) m (%s)", c.x, c.y,
                  c.z, m.recentre == "first" ? "first sample at the origin" : "mean at the origin");
    tr.warnings.push_back(in + ": " + b);
  }
  if (m.dequant_pos || m.dequant_rot) {
    long np = 0, nr = 0;
    if (m.dequant_pos)
      for (int k = 0; k < 3; ++k)
        np += dequantise_runs<double>(
            x, [k](const TraceSample& s) { return s.head_pos[k]; },
            [k](TraceSample& s, double v) { s.head_pos[k] = v; },
            [](double a, double b, double f) { return a + (b - a) * f; });
    if (m.dequant_rot)
      nr = dequantise_runs<glm::dquat>(
          x, [](const TraceSample& s) { return s.head_rot; },
          [](TraceSample& s, const glm::dquat& q) { s.head_rot = q; },
          [](const glm::dquat& a, const glm::dquat& b, double f) {
            return glm::normalize(glm::slerp(a, glm::dot(a, b) < 0 ? -b : b, f));
          });
    if (m.dequant_rot && (m.gaze_kind == Map::DirWorld || m.gaze_kind == Map::Point))
      for (size_t j = 0; j < x.size(); ++j)
        x[j].gaze_dir = glm::normalize(glm::conjugate(x[j].head_rot) * world_gaze[j]);
    tr.warnings.push_back(in + ": dequantised by run centres: " + std::to_string(np) +
                          " position components and " + std::to_string(nr) +
                          " orientations interpolated");
  }
  if (rep.fused_rows > 0)
    tr.warnings.push_back(in + ": " + std::to_string(rep.fused_rows) +
                          (rep.fused_rows == 1 ? " row had" : " rows had") +
                          " a fused field split back into two (the map's \"fused\")");
}

}  // namespace

// The stages in order: column map -> row decoder -> time fix-ups -> repeated-pose filter ->
// recentring/dequantisation (traces/README.md "Column maps").
Trace import_trace(const std::string& in, const std::string& map_path, const Display& display,
                   ImportReport* report, const ImportOptions& opt) {
  return import_trace(in, Params::parse_json_file(map_path), map_path, display, report, opt);
}

Trace import_trace(const std::string& in, const Json& map, const std::string& map_name,
                   const Display& display, ImportReport* report, const ImportOptions& opt) {
  Params p(map, map_name);
  p.ignore("comment");
  p.ignore("description");
  Map m = read_map_layout(p);
  // Rows are tokenized as they are imported, so a run that stops early (ImportOptions::
  // stop_after_s) never reads the rest of the file.
  CsvReader reader(in, m.delim, m.comment);
  CsvRow row0;
  Resolver res = read_header(reader, m, in, row0);
  read_time_keys(p, res, m);
  read_head_keys(p, res, m);
  read_gaze_keys(p, res, m);
  read_row_keys(p, res, m);
  p.finish();

  Decoded d;
  d.tr.source = in;
  IssueLog log;
  ImportReport rep;
  RowDecoder dec(m, res, in, display, opt, log, rep, d);
  if (m.has_on_bad && !opt.on_fov_explicit) dec.eff.on_fov = m.on_bad;
  dec.nf = size_t(res.nfields);
  dec.need = size_t(res.max_index + 1);
  dec.per_eye = !m.left.empty();
  dec.wrap_span = m.wrap_bits ? (1LL << m.wrap_bits) : 0;
  bool pending = !m.header;  // without a header the first row is data
  CsvRow cur;
  while (true) {
    if (pending) {
      cur = std::move(row0);
      pending = false;
    } else if (!reader.next(cur)) {
      break;
    }
    if (dec.decode(cur) == RowDecoder::Step::stop) break;
  }
  Trace& tr = d.tr;
  auto reasons = [&] {
    std::string w;
    for (auto& n : log.lines("on_bad_row=skip")) w += (w.empty() ? "" : "; ") + n;
    return w;
  };
  if (tr.samples.empty())
    throw Error(in, "no usable rows: all " + std::to_string(rep.data_rows) +
                        " data rows were dropped" + (log.total() ? ": " + reasons() : ""));
  if (m.skip_bad && rep.data_rows > 0 &&
      double(rep.skipped_rows) > m.max_skipped * double(rep.data_rows)) {
    char b[160];
    std::snprintf(
        b, sizeof b,
        "%ld of %ld data rows (%.1f %%) were skipped, more than max_skipped_fraction = %g: ",
        rep.skipped_rows, rep.data_rows, 100.0 * double(rep.skipped_rows) / double(rep.data_rows),
        m.max_skipped);
    throw Error(in, b + reasons());
  }
  fix_times(m, in, dec, rep, d);
  filter_repeated_poses(m, in, rep, d);
  finish_poses(m, in, rep, d);
  rep.on_invalid = m.on_invalid;
  tr.lines = d.lines;
  check_invalid_fraction(tr, m.valid.empty() ? ""
                                             : "check the map's valid conditions: a bitmask "
                                               "needs all_bits, a confidence a min");
  rep.notes = log.lines(m.skip_bad ? "on_bad_row=skip" : "on_bad_sample");
  for (auto& n : rep.notes) tr.warnings.push_back(in + ": " + n);
  if (report) *report = rep;
  return std::move(d.tr);
}

}  // namespace fovsim
