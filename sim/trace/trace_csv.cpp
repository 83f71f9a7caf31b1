// Canonical trace CSV (docs/architecture.md "Inputs: displays, traces, scenes, configs",
// traces/README.md): reading with validation and a bad-sample policy, and writing.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/limits.h"
#include "sim/trace/csv_table.h"
#include "sim/trace/issue_log.h"
#include "sim/trace/trace.h"

namespace fovsim {

bool gaze_inside_fov(const Display& display, const glm::dvec3& dir) {
  double u = 0, v = 0;
  if (!gaze_screen_from_dir(display, dir, u, v)) return false;
  return u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0;
}

namespace {

const char* kCols[] = {"t",  "px", "py", "pz", "qw",     "qx",     "qy",
                       "qz", "gx", "gy", "gz", "gaze_u", "gaze_v", "valid"};
enum Col { T, PX, PY, PZ, QW, QX, QY, QZ, GX, GY, GZ, GU, GV, VALID, NCOL };

// Which part of a sample a problem touches: a time/row problem cannot be held.
enum class Part { Row, Pose, Gaze };

struct Problem {
  Part part;
  int col;
  std::string kind, msg;
};

const char* policy_name(BadSamplePolicy p) {
  return p == BadSamplePolicy::Fail   ? "on_bad_sample=fail"
         : p == BadSamplePolicy::Skip ? "on_bad_sample=skip"
                                      : "on_bad_sample=hold";
}

// The header: which field holds each canonical column, and whether gaze is a direction
// (gx,gy,gz) or a screen point (gaze_u,gaze_v).
struct Header {
  int idx[NCOL];
  bool dir_gaze = false;
};

Header read_header(const std::string& path, const CsvRow& head) {
  Header h;
  int* idx = h.idx;
  for (int k = 0; k < NCOL; ++k) idx[k] = -1;
  for (size_t f = 0; f < head.fields.size(); ++f) {
    const std::string& name = head.fields[f].text;
    int c = -1;
    for (int k = 0; k < NCOL; ++k)
      if (name == kCols[k]) c = k;
    auto loc = file_location(path, head.line, head.fields[f].col);
    if (c < 0 && head.fields.size() == 1 && name.find_first_of(";\t ") != std::string::npos)
      throw Error(loc, "the header is a single field (\"" + printable(name, 40) +
                           "\"): the canonical trace CSV is comma-separated (t,px,py,...), "
                           "this file seems to use another delimiter");
    if (c < 0)
      throw Error(
          loc,
          "unknown column \"" + printable(name) +
              "\" (canonical columns: t,px,py,pz,qw,qx,qy,qz, gx,gy,gz or gaze_u,gaze_v, optional "
              "valid; see traces/README.md)");
    if (idx[c] >= 0) throw Error(loc, "duplicate column \"" + printable(name) + "\"");
    idx[c] = int(f);
  }
  auto header_loc = file_location(path, head.line);
  for (int k = T; k <= QZ; ++k)
    if (idx[k] < 0)
      throw Error(header_loc, std::string("missing column \"") + kCols[k] + "\" in the header");
  bool dir_gaze = idx[GX] >= 0 || idx[GY] >= 0 || idx[GZ] >= 0;
  bool scr_gaze = idx[GU] >= 0 || idx[GV] >= 0;
  if (dir_gaze && scr_gaze)
    throw Error(header_loc, "gaze given both as gx,gy,gz and as gaze_u,gaze_v: keep exactly one");
  if (!dir_gaze && !scr_gaze)
    throw Error(header_loc,
                "missing gaze columns: give gx,gy,gz (head-space direction) or gaze_u,gaze_v");
  for (int k : dir_gaze ? std::vector<int>{GX, GY, GZ} : std::vector<int>{GU, GV})
    if (idx[k] < 0)
      throw Error(header_loc, std::string("missing column \"") + kCols[k] + "\" in the header");
  h.dir_gaze = dir_gaze;
  return h;
}

// One row's fields parsed as numbers, with the problems each part of the sample has.
struct RowFields {
  const CsvRow& row;
  const Header& h;
  double v[NCOL] = {};
  bool ok[NCOL] = {};
  std::string why[NCOL];
  RowFields(const CsvRow& r, const Header& hd) : row(r), h(hd) {
    for (int k = 0; k < NCOL; ++k)
      if (h.idx[k] >= 0) ok[k] = parse_number(row.fields[size_t(h.idx[k])].text, v[k], why[k]);
  }
  int col_of(int k) const { return row.fields[size_t(h.idx[k])].col; }
  const std::string& text(int k) const { return row.fields[size_t(h.idx[k])].text; }
  Problem bad_number(int k, Part part) const {
    return {part, col_of(k), why[k].rfind("empty", 0) == 0 ? "empty field" : "bad number",
            std::string("column \"") + kCols[k] + "\": " + why[k]};
  }
};

// Time (finite, within the exact range, strictly increasing after `last_t`) and the validity
// flag: problems of the whole row, which cannot be held.
void decode_time_and_valid(const RowFields& f, double last_t, const std::string& last_t_text,
                           long last_t_line, TraceSample& s, std::vector<Problem>& probs) {
  if (!f.ok[T]) {
    probs.push_back(f.bad_number(T, Part::Row));
  } else if (!(std::fabs(f.v[T]) <= kMaxTraceTimeS)) {
    probs.push_back({Part::Row, f.col_of(T), "time out of range",
                     "time value out of range: t=" + printable(f.text(T)) +
                         " is beyond +-9.007e9 s (2^53 us), where times are no longer exact "
                         "to the microsecond and nanosecond integers overflow"});
  } else if (!(f.v[T] > last_t)) {
    probs.push_back({Part::Row, f.col_of(T), "non-monotonic time",
                     "time not strictly increasing: t=" + printable(f.text(T)) + " after t=" +
                         printable(last_t_text) + " (line " + std::to_string(last_t_line) + ")"});
  } else if (!(f.v[T] - last_t >= kMinTraceIntervalS)) {
    char b[96];
    std::snprintf(b, sizeof b, "%.6g s (a rate of %.6g Hz)", f.v[T] - last_t,
                  1.0 / (f.v[T] - last_t));
    probs.push_back({Part::Row, f.col_of(T), "interval too short",
                     "interval too short: t=" + printable(f.text(T)) + " after t=" +
                         printable(last_t_text) + " (line " + std::to_string(last_t_line) +
                         ") is " + b + "; samples must be at least 1e-06 s apart (at most 1 MHz)"});
  }
  s.t = f.v[T];
  if (f.h.idx[VALID] >= 0) {
    const std::string& t = f.text(VALID);
    if (t == "1" || t == "true")
      s.valid = true;
    else if (t == "0" || t == "false")
      s.valid = false;
    else
      probs.push_back({Part::Row, f.col_of(VALID), "bad valid flag",
                       "column \"valid\": expected 0 or 1, got \"" + escape_control(t, 80) + "\""});
  }
}

// Head position (within the coordinate bound) and a unit quaternion.
void decode_pose(const RowFields& f, const TraceReadOptions& opt, TraceSample& s,
                 std::vector<Problem>& probs) {
  bool pose_ok = true;
  for (int k = PX; k <= QZ; ++k)
    if (!f.ok[k]) {
      probs.push_back(f.bad_number(k, Part::Pose));
      pose_ok = false;
    }
  if (pose_ok) {
    for (int k = PX; k <= PZ; ++k)
      if (!(std::fabs(f.v[k]) <= kMaxCoordinateM)) {
        probs.push_back({Part::Pose, f.col_of(k), "head position out of range",
                         std::string("column \"") + kCols[k] + "\": head position " +
                             printable(f.text(k)) + " m is beyond the coordinate bound +-1e5 m"});
        pose_ok = false;
        break;
      }
  }
  if (!pose_ok) return;
  const double* v = f.v;
  s.head_pos = {v[PX], v[PY], v[PZ]};
  glm::dquat q(v[QW], v[QX], v[QY], v[QZ]);
  double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (std::fabs(n - 1.0) > opt.quat_tolerance) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "quaternion (qw,qx,qy,qz) has norm %.6g, not unit within %.3g",
                  n, opt.quat_tolerance);
    probs.push_back({Part::Pose, f.col_of(QW), "non-unit quaternion", buf});
  } else {
    s.head_rot = q / n;
  }
}

// The gaze direction in head space (a unit direction, or a screen point), inside the display's
// FOV. Returns false with the problems in `gprobs` when the row's gaze is unusable.
bool decode_gaze(const RowFields& f, const Display& display, const TraceReadOptions& opt,
                 glm::dvec3& g, std::vector<Problem>& gprobs) {
  const double* v = f.v;
  const bool dir_gaze = f.h.dir_gaze;
  bool gaze_ok = true;
  for (int k : dir_gaze ? std::vector<int>{GX, GY, GZ} : std::vector<int>{GU, GV})
    if (!f.ok[k]) {
      gprobs.push_back({Part::Gaze, f.col_of(k),
                        f.why[k] == "empty field" ? "empty field" : "bad number",
                        std::string("column \"") + kCols[k] + "\": " + f.why[k]});
      gaze_ok = false;
    }
  if (!gaze_ok) return false;
  if (dir_gaze) {
    g = {v[GX], v[GY], v[GZ]};
    double n = glm::length(g);
    if (std::fabs(n - 1.0) > opt.quat_tolerance) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "gaze direction (gx,gy,gz) has length %.6g, not unit within %.3g", n,
                    opt.quat_tolerance);
      gprobs.push_back({Part::Gaze, f.col_of(GX), "non-unit gaze", buf});
      return false;
    }
    g /= n;
  } else {
    if (v[GU] < 0 || v[GU] > 1 || v[GV] < 0 || v[GV] > 1) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "gaze outside the display FOV: screen point (%.4g, %.4g) not in [0,1]^2", v[GU],
                    v[GV]);
      gprobs.push_back({Part::Gaze, f.col_of(GU), "gaze outside the display FOV", buf});
      return false;
    }
    g = gaze_dir_from_screen(display, v[GU], v[GV]);
  }
  if (dir_gaze && !gaze_inside_fov(display, g)) {
    double u = 0, w = 0;
    bool front = gaze_screen_from_dir(display, g, u, w);
    char buf[200];
    if (front)
      std::snprintf(buf, sizeof buf,
                    "gaze outside the display FOV (%s %.1fx%.1f deg): screen point (%.3f, %.3f) "
                    "not in [0,1]^2",
                    display.name.c_str(), display.fov_h_deg, display.fov_v_deg, u, w);
    else
      std::snprintf(buf, sizeof buf,
                    "gaze outside the display FOV: direction points behind the eye (gz >= 0)");
    gprobs.push_back({Part::Gaze, f.col_of(GX), "gaze outside the display FOV", buf});
    return false;
  }
  return true;
}

// Where a problem of a row is reported: file:line:column of the file read, by default.
using RowLocation = std::function<std::string(long line, long col)>;

// Stages: the header (read_header), each row decoded (decode_time_and_valid, decode_pose,
// decode_gaze), the bad-sample policy (fail, skip, hold the last good part), gap statistics.
// Rows stream from `rd` (one row and the one before it held at a time): a trace costs its
// samples, not its parsed text (traces/README.md, "Memory:" under "Commands").
Trace read_trace_rows(CsvReader& rd, const std::string& path, const Display& display,
                      const TraceReadOptions& opt, const RowLocation& row_location,
                      const std::string& fail_hint) {
  CsvRow head;
  if (!rd.next(head))
    throw Error(path, "empty trace file: expected a header row (see traces/README.md)");
  const Header h = read_header(path, head);

  Trace tr;
  tr.source = path;
  IssueLog log;
  const size_t ncols = head.fields.size();
  bool have_last = false;
  TraceSample last_good;                       // last accepted sample (for hold)
  glm::dvec3 last_valid_gaze(0.0, 0.0, -1.0);  // gaze shown while valid=0
  double last_t = -INFINITY;
  long last_t_line = 0;
  std::string last_t_text;  // the previous time as written in the file
  long gaps = 0;            // intervals longer than opt.max_gap_s
  double longest_gap = 0;
  std::string first_gap;

  {
    const size_t rows = rd.lines_left();  // the header is read: at most the rows left
    tr.samples.reserve(rows);
    tr.lines.reserve(rows);
  }
  CsvRow row, prev;  // the row and the one before it (the truncation check compares them)
  bool have_prev = false;
  for (; rd.next(row); std::swap(prev, row), have_prev = true) {
    std::string cut;
    // Only the file's last line can be unterminated.
    if (row.unterminated && looks_truncated(row, have_prev ? &prev : nullptr, ncols, cut)) {
      tr.warnings.push_back(file_location(path, row.line) + ": " + cut + "; the line was dropped");
      break;
    }
    if (row.fields.size() != ncols) {
      int col = row.fields.size() > ncols ? row.fields[ncols].col : row.fields.back().col;
      throw Error(file_location(path, row.line, col), "expected " + std::to_string(ncols) +
                                                          " fields as in the header, got " +
                                                          std::to_string(row.fields.size()));
    }
    const RowFields f(row, h);
    std::vector<Problem> probs;
    TraceSample s;
    decode_time_and_valid(f, last_t, last_t_text, last_t_line, s, probs);
    decode_pose(f, opt, s, probs);
    // Gaze. Rows flagged valid=0 may carry any gaze (or none): the last valid gaze is shown.
    std::vector<Problem> gprobs;
    glm::dvec3 g(0.0);
    const bool gaze_ok = decode_gaze(f, display, opt, g, gprobs);
    if (s.valid) {
      for (auto& p : gprobs) probs.push_back(p);
      if (gaze_ok) s.gaze_dir = g;
    } else {
      // Flagged invalid: the last valid gaze, whatever this row carries (traces/README.md).
      s.gaze_dir = last_valid_gaze;
    }

    if (!probs.empty()) {
      const Problem& p = probs.front();
      std::string where = row_location(row.line, p.col);
      if (opt.on_bad == BadSamplePolicy::Fail) throw Error(where, p.msg + " (" + fail_hint + ")");
      bool can_hold = opt.on_bad == BadSamplePolicy::Hold && have_last;
      for (auto& q : probs) can_hold = can_hold && q.part != Part::Row;
      if (!can_hold) {
        log.add(opt.on_bad == BadSamplePolicy::Hold ? "skipped (cannot hold)" : "skipped", p.kind,
                where, p.msg);
        continue;
      }
      for (auto& q : probs) {
        if (q.part == Part::Pose) {
          s.head_pos = last_good.head_pos;
          s.head_rot = last_good.head_rot;
        } else if (q.part == Part::Gaze) {
          s.gaze_dir = last_good.gaze_dir;
        }
      }
      log.add("held", p.kind, where, p.msg);
    }
    if (s.valid) last_valid_gaze = s.gaze_dir;
    if (have_last && s.t - last_t > opt.max_gap_s) {
      ++gaps;
      if (gaps == 1) {
        char b[200];
        std::snprintf(b, sizeof b, "t=%.9g after t=%.9g (line %ld): a gap of %.6g s", s.t, last_t,
                      last_t_line, s.t - last_t);
        first_gap = file_location(path, row.line, f.col_of(T)) + ": " + b;
      }
      longest_gap = std::max(longest_gap, s.t - last_t);
    }
    last_t = s.t;
    last_t_line = row.line;
    last_t_text = f.text(T);
    last_good = s;
    have_last = true;
    tr.samples.push_back(s);
    tr.lines.push_back(row.line);
  }
  if (tr.samples.empty()) throw Error(path, "trace has no usable samples");
  check_invalid_fraction(tr);
  for (auto& l : log.lines(policy_name(opt.on_bad))) tr.warnings.push_back(path + ": " + l);
  if (gaps > 0) {
    char b[160];
    std::snprintf(b, sizeof b, "%ld gap%s longer than max_gap %g s (longest %.6g s); first: ", gaps,
                  gaps == 1 ? "" : "s", opt.max_gap_s, longest_gap);
    tr.warnings.push_back(path + ": " + b + first_gap);
  }
  return tr;
}

std::string trace_csv_text(const Trace& trace);

}  // namespace

Trace read_trace_csv(const std::string& path, const Display& display, const TraceReadOptions& opt) {
  CsvReader rd(path, ',', '#');
  return read_trace_rows(
      rd, path, display, opt, [&](long line, long col) { return file_location(path, line, col); },
      "set the trace's on_bad_sample to skip or hold to continue past it");
}

void check_trace_as_written(const Trace& trace, const Display& display, const std::string& source,
                            const std::string& out) {
  CsvReader rd = CsvReader::from_text(trace_csv_text(trace), out, ',', '#');
  TraceReadOptions opt;  // trace validate's defaults: the first problem is an error
  read_trace_rows(
      rd, out, display, opt,
      [&](long line, long col) {
        // Line 1 is the header: line L holds sample L - 2, which came from trace.lines[L - 2].
        const size_t i = size_t(line - 2);
        const std::string at = i < trace.lines.size() ? file_location(source, trace.lines[i])
                                                      : source + ": sample " + std::to_string(i);
        return at + " (imported as row " + std::to_string(line - 1) + ", column " +
               std::to_string(col) + " of " + out + ")";
      },
      "trace validate would refuse the imported trace: nothing was written; check the map's units "
      "and constants");
}

void check_invalid_fraction(Trace& tr, const std::string& hint) {
  long invalid = 0;
  for (auto& s : tr.samples) invalid += s.valid ? 0 : 1;
  const long n = long(tr.samples.size());
  if (n > 0 && invalid == n)
    throw Error(tr.source, "all " + std::to_string(n) + (n == 1 ? " sample is" : " samples are") +
                               " flagged invalid: the trace has no gaze to foveate on" +
                               (hint.empty() ? "" : " (" + hint + ")"));
  double f = n > 0 ? double(invalid) / double(n) : 0.0;
  if (f > kWarnInvalidFraction) {
    char b[200];
    std::snprintf(b, sizeof b,
                  "%.1f %% of samples (%ld of %ld) are flagged invalid, more than %.0f %%: check "
                  "the validity flags",
                  100.0 * f, invalid, n, 100.0 * kWarnInvalidFraction);
    tr.warnings.push_back(tr.source + ": " + b + (hint.empty() ? "" : " (" + hint + ")"));
  }
}

namespace {

// "+ 0.0" turns -0 into 0 so files do not show "-0".
std::string trace_csv_text(const Trace& trace) {
  std::string out = "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,valid\n";
  char buf[512];
  for (const TraceSample& s : trace.samples) {
    std::snprintf(buf, sizeof buf, "%.9f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n",
                  s.t + 0.0, s.head_pos.x + 0.0, s.head_pos.y + 0.0, s.head_pos.z + 0.0,
                  s.head_rot.w + 0.0, s.head_rot.x + 0.0, s.head_rot.y + 0.0, s.head_rot.z + 0.0,
                  s.gaze_dir.x + 0.0, s.gaze_dir.y + 0.0, s.gaze_dir.z + 0.0, s.valid ? 1 : 0);
    out += buf;
  }
  return out;
}

}  // namespace

void write_trace_csv(const std::string& path, const Trace& trace) {
  write_file_atomic(path, trace_csv_text(trace));
}

}  // namespace fovsim
