// Column-map importer (traces/README.md "Column maps"). Map keys:
//   delimiter      "comma" | "tab" | "semicolon" | "space"            (required)
//   header         true: columns by name; false: by 1-based index   (required)
//   skip_lines     lines before the header / first row               (0)
//   comment_prefix prefix of comment lines, "" for none              ("")
//   on_bad_row     "fail" | "skip": wrong field count, bad numbers, non-monotonic time ("fail")
//   coordinates    "fovsim" | "unity" | "unreal" | {"x":"+x","y":"+y","z":"-z"}   (required)
//   time           {"column", "unit": s|ms|us|ns|100ns, "rebase": true}
//   head_position  {"columns": [x,y,z], "unit": m|cm|mm} | {"constant": [x,y,z]}   (required)
//   head_orientation {"type": "quaternion", "columns": [4], "order": "wxyz"|"xyzw"} |
//                  {"type": "euler", "columns": [about x, about y, about z], "order": "ZXY",
//                   "sequence": "extrinsic"|"intrinsic", "unit": "deg"|"rad", "signs": [1,1,1]} |
//                  {"constant": [w,x,y,z]};
//                  optional "inverse": true when the source stores head-from-world
//   gaze           {"type": "direction", "space": "head"|"world", "columns": [3]} |
//                  {"type": "direction", ..., "left": [3], "right": [3], "combine": "mean"|"left"|"right"} |
//                  {"type": "screen", "columns": [u,v], "origin": "top-left"|"bottom-left"} |
//                  {"type": "point", "columns": [x,y,z], "unit": "m"|"cm"|"mm"} (world point looked at)
//   valid          [{"column", "valid_values": [...]} | {"column", "invalid_values": [...]}]  ([])
#include "sim/trace/importer.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <map>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/trace/convert.h"
#include "sim/trace/csv_table.h"
#include "sim/trace/issue_log.h"

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
  AxisMap axes;
  ColRef time;
  double time_scale = 1;
  bool rebase = true;
  bool pos_const = false;
  glm::dvec3 pos_value{0.0};
  std::vector<ColRef> pos;
  double pos_scale = 1;
  enum { Quat, Euler, ConstRot } rot_kind = Quat;
  std::vector<ColRef> rot;
  bool xyzw = false, intrinsic = false, inverse = false;
  std::string euler_order;
  glm::dvec3 euler_signs{1.0};
  double angle_scale = 1;
  glm::dquat rot_value{1, 0, 0, 0};
  enum { DirHead, DirWorld, Screen, Point } gaze_kind = DirHead;
  std::vector<ColRef> gaze, left, right;
  std::string combine;
  bool screen_bottom_left = false;
  double point_scale = 1;
  struct Cond {
    ColRef col;
    std::vector<std::string> values;
    bool valid_list;
  };
  std::vector<Cond> valid;
};

// Column references are strings (header names) or 1-based integers (files without header).
struct Resolver {
  bool header;
  std::map<std::string, int> by_name;
  int nfields = 0;
  std::string in_file;
  long header_line = 0;
  ColRef get(Params& p, const std::string& key, const Json& v, const std::string& sub) {
    ColRef c;
    std::string where = p.where(key) + sub;
    if (v.is_string()) {
      c.name = v.get<std::string>();
      if (!header)
        throw Error(where, "column given by name \"" + c.name + "\" but the map says header: false (use 1-based indices)");
      auto it = by_name.find(c.name);
      if (it == by_name.end())
        throw Error(where, "column \"" + c.name + "\" is not in the header of " + in_file + " (line " +
                               std::to_string(header_line) + ")");
      c.index = it->second;
    } else if (v.is_number_integer()) {
      int i = v.get<int>();
      if (i < 1 || (nfields > 0 && i > nfields))
        throw Error(where, "column index " + std::to_string(i) + " is outside 1.." + std::to_string(nfields));
      c.index = i - 1;
      c.name = "#" + std::to_string(i);
    } else {
      throw Error(where, "expected a column name (string) or a 1-based index, got " + describe_json(v));
    }
    return c;
  }
  ColRef one(Params& p, const std::string& key) { return get(p, key, p.raw(key), ""); }
  std::vector<ColRef> many(Params& p, const std::string& key, size_t n) {
    const Json& v = p.raw(key);
    if (!v.is_array() || v.size() != n)
      p.fail(key, "expected an array of " + std::to_string(n) + " columns, got " + describe_json(v));
    std::vector<ColRef> out;
    for (size_t i = 0; i < n; ++i) out.push_back(get(p, key, v[i], "[" + std::to_string(i) + "]"));
    return out;
  }
};

double length_unit(Params& p, const std::string& key) {
  std::string u = p.string(key, {"m", "cm", "mm"});
  return u == "m" ? 1.0 : u == "cm" ? 0.01 : 0.001;
}

glm::dvec3 vec3_of(Params& p, const std::string& key) {
  std::vector<double> v = p.numbers(key, {});
  if (v.size() != 3) p.fail(key, "expected 3 numbers");
  return {v[0], v[1], v[2]};
}

}  // namespace

Trace import_trace(const std::string& in, const std::string& map_path, const Display& display,
                   ImportReport* report) {
  Params p = Params::from_file(map_path);
  p.ignore("comment");
  p.ignore("description");
  Map m;
  std::string d = p.string("delimiter", std::vector<std::string>{"comma", "tab", "semicolon", "space"});
  m.delim = d == "comma" ? ',' : d == "tab" ? '\t' : d == "semicolon" ? ';' : ' ';
  m.header = p.boolean("header", true);
  if (!p.has("header")) p.fail("header", "required: true if the first line names the columns, false otherwise");
  m.skip_lines = p.integer("skip_lines", 0, Range::closed(0, 1000000));
  std::string cm = p.string("comment_prefix", "");
  if (cm.size() > 1) p.fail("comment_prefix", "expected one character or \"\"");
  m.comment = cm.empty() ? 0 : cm[0];
  m.skip_bad = p.string("on_bad_row", "fail", {"fail", "skip"}) == "skip";
  if (!p.has("coordinates"))
    p.fail("coordinates", "required: the source's axis convention (fovsim, opengl, unity, unreal or an axis object)");
  m.axes = axis_map_from(p.raw("coordinates"), p.where("coordinates"));

  // Data rows (the map's column references are resolved against the header).
  std::vector<CsvRow> rows = read_csv_rows(in, m.delim, m.comment);
  {
    // skip_lines counts physical lines: drop rows whose line number is <= skip_lines.
    std::vector<CsvRow> kept;
    for (auto& r : rows)
      if (r.line > m.skip_lines) kept.push_back(std::move(r));
    rows.swap(kept);
  }
  if (rows.empty()) throw Error(in, "no data rows");
  Resolver res;
  res.header = m.header;
  res.in_file = in;
  size_t first = 0;
  if (m.header) {
    res.header_line = rows[0].line;
    for (size_t i = 0; i < rows[0].fields.size(); ++i) {
      const std::string& n = rows[0].fields[i].text;
      if (res.by_name.count(n))
        throw Error(file_location(in, rows[0].line, rows[0].fields[i].col), "duplicate column name \"" + n + "\"");
      res.by_name[n] = int(i);
    }
    res.nfields = int(rows[0].fields.size());
    first = 1;
  } else {
    res.nfields = int(rows[0].fields.size());
  }

  Params tp = p.child("time");
  m.time = res.one(tp, "column");
  std::string tu = tp.string("unit", std::vector<std::string>{"s", "ms", "us", "ns", "100ns"});
  m.time_scale = tu == "s" ? 1.0 : tu == "ms" ? 1e-3 : tu == "us" ? 1e-6 : tu == "ns" ? 1e-9 : 1e-7;
  m.rebase = tp.boolean("rebase", true);
  tp.ignore("comment");

  if (!p.has("head_position"))
    p.fail("head_position", "required: {\"columns\": [x, y, z], \"unit\": \"m\"} or {\"constant\": [0, 1.6, 0]}");
  Params hp = p.child("head_position");
  hp.ignore("comment");
  if (hp.has("constant")) {
    m.pos_const = true;
    m.pos_value = vec3_of(hp, "constant");
  } else {
    m.pos = res.many(hp, "columns", 3);
    m.pos_scale = length_unit(hp, "unit");
  }

  if (!p.has("head_orientation"))
    p.fail("head_orientation", "required: quaternion or euler columns, or {\"constant\": [1, 0, 0, 0]}");
  Params ho = p.child("head_orientation");
  ho.ignore("comment");
  m.inverse = ho.boolean("inverse", false);
  if (ho.has("constant")) {
    std::vector<double> q = ho.numbers("constant", {});
    if (q.size() != 4) ho.fail("constant", "expected 4 numbers (w, x, y, z) in fovsim coordinates");
    m.rot_kind = Map::ConstRot;
    m.rot_value = glm::normalize(glm::dquat(q[0], q[1], q[2], q[3]));
  } else {
    std::string type = ho.string("type", std::vector<std::string>{"quaternion", "euler"});
    if (type == "quaternion") {
      m.rot_kind = Map::Quat;
      m.rot = res.many(ho, "columns", 4);
      m.xyzw = ho.string("order", std::vector<std::string>{"wxyz", "xyzw"}) == "xyzw";
    } else {
      m.rot_kind = Map::Euler;
      m.rot = res.many(ho, "columns", 3);
      m.euler_order = ho.string("order");
      bool okord = m.euler_order.size() == 3;
      for (char c : m.euler_order) okord = okord && (c == 'X' || c == 'Y' || c == 'Z');
      if (!okord) ho.fail("order", "expected three of X, Y, Z such as \"ZXY\" (Unity) or \"ZYX\"");
      m.intrinsic = ho.string("sequence", std::vector<std::string>{"extrinsic", "intrinsic"}) == "intrinsic";
      m.angle_scale = ho.string("unit", std::vector<std::string>{"deg", "rad"}) == "deg" ? kPi / 180 : 1.0;
      std::vector<double> sg = ho.numbers("signs", {1, 1, 1});
      if (sg.size() != 3) ho.fail("signs", "expected 3 numbers, each 1 or -1");
      for (int i = 0; i < 3; ++i) {
        if (sg[size_t(i)] != 1 && sg[size_t(i)] != -1) ho.fail("signs", "expected 3 numbers, each 1 or -1");
        m.euler_signs[i] = sg[size_t(i)];
      }
    }
  }

  Params gp = p.child("gaze");
  if (!p.has("gaze")) p.fail("gaze", "required: how the gaze is given (direction, screen or point)");
  gp.ignore("comment");
  std::string gt = gp.string("type", std::vector<std::string>{"direction", "screen", "point"});
  if (gt == "direction") {
    m.gaze_kind = gp.string("space", std::vector<std::string>{"head", "world"}) == "head" ? Map::DirHead : Map::DirWorld;
    bool per_eye = gp.has("left") || gp.has("right");
    if (per_eye == gp.has("columns"))
      gp.fail("", per_eye ? "give either \"columns\" (combined gaze) or \"left\"/\"right\", not both"
                          : "needs \"columns\": [x, y, z] or per-eye \"left\" and \"right\"");
    if (per_eye) {
      m.left = res.many(gp, "left", 3);
      m.right = res.many(gp, "right", 3);
      m.combine = gp.string("combine", std::vector<std::string>{"mean", "left", "right"});
    } else {
      m.gaze = res.many(gp, "columns", 3);
    }
  } else if (gt == "screen") {
    m.gaze_kind = Map::Screen;
    m.gaze = res.many(gp, "columns", 2);
    m.screen_bottom_left = gp.string("origin", std::vector<std::string>{"top-left", "bottom-left"}) == "bottom-left";
  } else {
    m.gaze_kind = Map::Point;
    m.gaze = res.many(gp, "columns", 3);
    m.point_scale = length_unit(gp, "unit");
  }
  for (Params& c : p.children("valid")) {
    c.ignore("comment");
    Map::Cond cond;
    cond.col = res.one(c, "column");
    bool hv = c.has("valid_values"), hi = c.has("invalid_values");
    if (hv == hi) c.fail("", "give exactly one of valid_values or invalid_values");
    const std::string key = hv ? "valid_values" : "invalid_values";
    const Json& vals = c.raw(key);
    if (!vals.is_array() || vals.empty()) c.fail(key, "expected a non-empty array of strings");
    for (size_t i = 0; i < vals.size(); ++i) {
      if (!vals[i].is_string() && !vals[i].is_number())
        c.fail(key + "[" + std::to_string(i) + "]", "expected a string, got " + describe_json(vals[i]));
      cond.values.push_back(vals[i].is_string() ? vals[i].get<std::string>() : vals[i].dump());
    }
    cond.valid_list = hv;
    m.valid.push_back(cond);
  }
  p.finish();

  // ---- rows ---------------------------------------------------------------------------------
  Trace tr;
  tr.source = in;
  IssueLog log;
  ImportReport rep;
  const size_t nf = size_t(res.nfields);
  bool have_t0 = false, int_time = false;
  long long t0_int = 0;
  double t0 = 0, last_t = -INFINITY;
  glm::dvec3 last_gaze(0, 0, -1);
  for (size_t r = first; r < rows.size(); ++r) {
    const CsvRow& row = rows[r];
    ++rep.data_rows;
    std::string err;
    int err_col = 1;
    auto fail_row = [&](int col, const std::string& kind, const std::string& msg) {
      std::string where = file_location(in, row.line, col);
      if (!m.skip_bad) throw Error(where, msg + " (set the map's on_bad_row to \"skip\" to drop such rows)");
      log.add("skipped", kind, where, msg);
      ++rep.skipped_rows;
    };
    if (row.fields.size() != nf) {
      fail_row(row.fields.size() > nf ? row.fields[nf].col : row.fields.back().col, "wrong field count",
               "expected " + std::to_string(nf) + " fields" + (m.header ? " as in the header" : " as in the first row") +
                   ", got " + std::to_string(row.fields.size()));
      continue;
    }
    bool bad = false;
    auto num = [&](const ColRef& c) -> double {
      double v = 0;
      std::string why;
      if (!bad && !parse_number(row.fields[size_t(c.index)].text, v, why)) {
        bad = true;
        err = "column \"" + c.name + "\": " + why;
        err_col = row.fields[size_t(c.index)].col;
      }
      return v;
    };
    auto vec = [&](const std::vector<ColRef>& c) { return glm::dvec3(num(c[0]), num(c[1]), num(c[2])); };
    // Validity flags first: rows flagged invalid keep their pose but may carry any gaze.
    bool valid = true;
    for (auto& c : m.valid) {
      const std::string& f = row.fields[size_t(c.col.index)].text;
      bool listed = false;
      for (auto& v : c.values) listed = listed || v == f;
      if (c.valid_list ? !listed : listed) valid = false;
    }
    // Time (integers kept exact before rebasing, e.g. epoch nanoseconds).
    const CsvField& tf = row.fields[size_t(m.time.index)];
    double t = 0;
    long long ti = 0;
    auto tr_int = std::from_chars(tf.text.data(), tf.text.data() + tf.text.size(), ti);
    bool is_int = tr_int.ec == std::errc() && tr_int.ptr == tf.text.data() + tf.text.size() && !tf.text.empty();
    if (!have_t0) int_time = is_int;
    if (int_time && is_int) {
      if (!have_t0) t0_int = ti;
      t = double(ti - t0_int) * m.time_scale;
    } else {
      t = num(m.time) * m.time_scale;
      if (bad) {
        fail_row(err_col, "bad number", err);
        continue;
      }
      if (int_time) t -= double(t0_int) * m.time_scale;
    }
    TraceSample s;
    s.t = t;
    s.valid = valid;
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
    } else {
      glm::dvec3 ang = vec(m.rot) * m.angle_scale * m.euler_signs;
      if (!bad) s.head_rot = m.axes.rot(euler_matrix(ang, m.euler_order, m.intrinsic));
    }
    if (m.inverse) s.head_rot = glm::conjugate(s.head_rot);
    if (bad) {
      fail_row(err_col, "bad number", err);
      continue;
    }
    // Gaze -> head space.
    glm::dvec3 g(0.0);
    std::string gerr;
    int gcol = row.fields[size_t((m.gaze.empty() ? m.left : m.gaze)[0].index)].col;
    if (m.gaze_kind == Map::Screen) {
      double u = num(m.gaze[0]), v = num(m.gaze[1]);
      if (m.screen_bottom_left) v = 1 - v;
      if (!bad && (u < 0 || u > 1 || v < 0 || v > 1)) gerr = "gaze screen point outside [0,1]^2";
      g = gaze_dir_from_screen(display, u, v);  // already head space (fovsim)
    } else if (!m.left.empty()) {
      glm::dvec3 l = vec(m.left), rr = vec(m.right);
      double ln = glm::length(l), rn = glm::length(rr);
      if (m.combine == "left") g = l;
      else if (m.combine == "right") g = rr;
      else if (ln > 1e-9 && rn > 1e-9) g = l / ln + rr / rn;
      else g = ln > 1e-9 ? l : rr;  // one eye lost: use the other
    } else {
      g = vec(m.gaze);
    }
    if (bad) {
      if (valid) {
        fail_row(err_col, "bad number", err);
        continue;
      }
      g = glm::dvec3(0.0);
    }
    glm::dvec3 gh(0.0);
    if (m.gaze_kind == Map::Screen) {
      gh = g;
    } else if (m.gaze_kind == Map::DirHead) {
      gh = m.axes.vec(g);
    } else if (m.gaze_kind == Map::DirWorld) {
      gh = glm::conjugate(s.head_rot) * m.axes.vec(g);
    } else if (m.gaze_kind == Map::Point) {
      gh = glm::conjugate(s.head_rot) * (m.axes.vec(g * m.point_scale) - s.head_pos);
    }
    double gn = glm::length(gh);
    if (gerr.empty() && !(gn > 1e-9)) gerr = "zero-length gaze";
    if (gerr.empty() && !((gh / gn).z < 0))
      gerr = "gaze points behind the eye (not forward in head space: check coordinates)";
    if (!gerr.empty() && valid) {
      fail_row(gcol, gerr, gerr);
      continue;
    }
    s.gaze_dir = gerr.empty() ? gh / gn : last_gaze;
    if (valid) last_gaze = s.gaze_dir;
    if (!valid) ++rep.invalid_rows;
    if (!have_t0) {
      have_t0 = true;
      t0 = t;
    }
    if (!(t > last_t)) {
      fail_row(tf.col, "non-monotonic time", "time not strictly increasing: " + tf.text);
      if (!valid) --rep.invalid_rows;
      continue;
    }
    last_t = t;
    tr.samples.push_back(s);
  }
  if (tr.samples.empty()) throw Error(in, "no usable rows");
  // Integer times were rebased exactly on the fly; decimal times are rebased here.
  rep.time_offset_s = int_time ? double(t0_int) * m.time_scale : t0;
  for (auto& s : tr.samples) {
    if (m.rebase && !int_time) s.t -= t0;
    if (!m.rebase && int_time) s.t += rep.time_offset_s;
  }
  if (!m.rebase) rep.time_offset_s = 0;
  rep.notes = log.lines("on_bad_row=skip");
  for (auto& n : rep.notes) tr.warnings.push_back(in + ": " + n);
  if (report) *report = rep;
  return tr;
}

}  // namespace fovsim
