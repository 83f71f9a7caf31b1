#include "sim/trace/map_keys.h"

#include "sim/core/error.h"
#include "sim/core/param_table.h"
#include "sim/trace/tracking.h"

namespace fovsim {

namespace {

// Builds the rows in order; the modifiers change the last row.
class Rows {
 public:
  Rows& text(const char* path, const char* def, std::vector<std::string> allowed) {
    add(path, MapKeyType::String, def ? Json(def) : Json());
    v_.back().allowed = std::move(allowed);
    return *this;
  }
  Rows& boolean(const char* path, bool def) { return add(path, MapKeyType::Bool, Json(def)); }
  Rows& integer(const char* path, int def, Range r) {
    add(path, MapKeyType::Int, Json(def));
    v_.back().range = r;
    return *this;
  }
  Rows& number(const char* path, double def, Range r) {
    add(path, MapKeyType::Number, Json(def));
    v_.back().range = r;
    return *this;
  }
  Rows& numbers(const char* path, std::vector<double> def) {
    return add(path, MapKeyType::Numbers, Json(def));
  }
  // A key the importer reads with its own code (column references, axis objects, arrays of
  // conditions): documented here, `type` as the docs write it.
  Rows& other(const char* path, const char* type) {
    add(path, MapKeyType::Other, Json());
    v_.back().type_doc = type;
    return *this;
  }
  Rows& in(const char* variant) {
    v_.back().variant = variant;
    return *this;
  }
  // No default: the key must be given (in its variant).
  Rows& required() {
    v_.back().def = Json();
    v_.back().required = true;
    return *this;
  }
  // No default: read only when given.
  Rows& optional() {
    v_.back().def = Json();
    return *this;
  }
  Rows& shown(const char* def_doc, const char* values = "") {
    v_.back().def_doc = def_doc;
    v_.back().values = values;
    return *this;
  }
  Rows& doc(const char* d) {
    v_.back().doc = d;
    return *this;
  }
  std::vector<MapKey> rows() && { return std::move(v_); }

 private:
  Rows& add(const char* path, MapKeyType t, Json def) {
    MapKey k;
    k.path = path;
    k.type = t;
    k.def = std::move(def);
    v_.push_back(std::move(k));
    return *this;
  }
  std::vector<MapKey> v_;
};

void layout_keys(Rows& r) {
  r.text("delimiter", nullptr, {"comma", "tab", "semicolon", "space"})
      .required()
      .doc("the field separator")
      .boolean("header", true)
      .required()
      .doc(
          "true: columns referenced by header name (or 1-based index); false: by 1-based "
          "index")
      .integer("skip_lines", 0, Range::closed(0, 1000000))
      .doc("physical lines to drop before the header / first row")
      .text("comment_prefix", "", {})
      .shown("`\"\"`", "one character or `\"\"`")
      .doc("lines starting with it are ignored")
      .text("on_bad_row", "fail", {"fail", "skip"})
      .doc(
          "wrong field count, unparsable number, time overflowing 64 bits or jumping by more "
          "than `time.max_step_s`, non-monotonic time, zero/backward gaze on a valid row: an "
          "error, or the row is skipped; skipped rows are counted and the first location of "
          "each kind is printed")
      .number("max_skipped_fraction", 0.5, Range::closed(0, 1))
      .doc(
          "with `on_bad_row: skip`, skipping more than this fraction of the data rows is an "
          "error that lists the reasons (kind, count, first location). \"no usable rows\" "
          "also says why every row was dropped")
      .text("row_fields", "exact", {"exact", "used"})
      .doc(
          "`exact`: every row has as many fields as the header (or first row). `used`: a row "
          "of another length is accepted when every column the map uses exists in it (and "
          "parses); a row too short for a used column is an error naming that column and "
          "its 1-based field index. For exports that fuse two fields (`666.5324True`): safe "
          "only when the fusion lies after every used column, since later fields shift by "
          "one — check one fused row by eye")
      .text("repeated_pose", "keep", {"keep", "interpolate"})
      .doc(
          "samples whose head pose equals the previous one exactly (pose updated per render "
          "frame, gaze per tracker sample) are always reported; `interpolate` replaces each "
          "run by lerp/slerp in time between the run's first pose and the next different "
          "one (gaze given in world keeps its world direction). A constant head is not "
          "checked")
      .other("coordinates", "string or object")
      .required()
      .shown("required",
             "`fovsim`/`opengl`, `unity`, `unreal`, or "
             "`{\"x\": \"+x\", \"y\": \"+y\", \"z\": \"-z\"}`")
      .doc(
          "the source axes. `unity`: left-handed, +Y up, +Z forward (z flips); `unreal`: "
          "left-handed, +Z up, +X forward, +Y right. The object names, for each fovsim "
          "axis, the signed source axis. Positions and vectors map as v' = M v, rotations "
          "as R' = M R Mᵀ (this also converts handedness)");
}

void time_keys(Rows& r) {
  r.other("time.column", "column")
      .required()
      .doc("the time column: a header name, or a 1-based index")
      .text("time.unit", nullptr, {"s", "ms", "us", "ns", "100ns"})
      .required()
      .doc(
          "integer timestamps (epochs in ns or 100 ns ticks) are rebased exactly in 64-bit "
          "integers before conversion")
      .boolean("time.rebase", true)
      .doc("subtract the first time")
      .integer("time.wrap_bits", 0, Range::closed(0, 62))
      .shown("0", "0 or 8…62")
      .doc(
          "integer time is a counter of that many bits that wraps (a 32-bit millisecond "
          "tick wraps after 49.7 days): a backward step of more than half the range adds "
          "2^bits. 0 = no wrap")
      .number("time.max_step_s", 3600.0, Range::above(0))
      .doc(
          "a forward jump larger than this between consecutive rows is an error (or a "
          "skipped row) at its line: corrupt or sentinel times")
      .number("time.burst_below_s", 0.0, Range::at_least(0))
      .doc(
          "a sample closer than this to the previous one is part of a burst (0 = a quarter "
          "of the median interval)")
      .text("time.on_burst", "keep", {"keep", "drop", "retime"})
      .doc(
          "bursts (samples buffered during a stall and delivered < 1 ms apart) are always "
          "reported; `drop` removes samples within the burst interval of the previous kept "
          "one; `retime` spreads the sample that ended the stall and the burst after it "
          "evenly between the sample before the stall and the burst's last sample (a stall "
          "8 → 20 ms followed by three samples stamped 20 ms gives 12, 16, 20 ms). With "
          "`drop`/`retime`, equal consecutive times are accepted as burst members (with "
          "`keep` they are \"not strictly increasing\"); equal times left over (a burst at "
          "the very start) are dropped")
      .text("time.burst_pose", "arrival", {"arrival", "sample"})
      .doc(
          "with `retime`: which time a burst's head pose belongs to. `arrival`: the pose was "
          "attached when the buffered sample arrived, so each retimed sample takes the pose "
          "interpolated (lerp/slerp) on the arrival times, and the head does not make the "
          "whole stall's turn in the first retimed slot; world gaze keeps its world "
          "direction. `sample`: the pose was sampled with the gaze and moves with it");
}

void head_keys(Rows& r) {
  r.other("head_position.columns", "column[3]")
      .required()
      .in("columns")
      .doc(
          "head position x, y, z in source axes (a recording without position states a "
          "`constant`)")
      .text("head_position.unit", nullptr, {"m", "cm", "mm"})
      .required()
      .in("columns")
      .doc("unit of the position columns")
      .numbers("head_position.constant", {})
      .required()
      .in("constant")
      .shown("required", "3 numbers")
      .doc("a fixed head position, fovsim axes, metres")
      .text("head_position.recentre", "none", {"none", "first", "mean"})
      .in("columns")
      .doc(
          "subtract the first (or mean) head position, so world coordinates 20 m from the "
          "origin start at the origin; the offset is reported. A run places the trace at "
          "the scene's eye anyway (`trace_placement`); this is for the canonical file")
      .boolean("head_position.dequantise", false)
      .in("columns")
      .doc(
          "positions rounded in the export (0.1 m): each run of samples with an identical "
          "value (per component) is taken as that value at the run's middle time, and "
          "samples between two run middles are interpolated linearly; the first and last "
          "half-runs keep their value. World gaze keeps its world direction. Exact for "
          "motion slower than one step per run; it cannot recover motion within one step")
      .text("head_orientation.type", nullptr, {"quaternion", "euler", "forward"})
      .required()
      .doc(
          "world-from-head in source axes, as a quaternion, Euler angles or a forward "
          "vector (or a `constant`)")
      .other("head_orientation.columns", "column[4]")
      .required()
      .in("quaternion")
      .doc("the quaternion's four components")
      .text("head_orientation.order", nullptr, {"wxyz", "xyzw"})
      .required()
      .in("quaternion")
      .doc("the order of the quaternion columns")
      .other("head_orientation.columns", "column[3]")
      .required()
      .in("euler")
      .doc("the angles about X, Y, Z")
      .text("head_orientation.order", nullptr, {})
      .required()
      .in("euler")
      .shown("required", "three of `X`, `Y`, `Z`, each once")
      .doc(
          "the axes in the order the rotations act on a vector in the fixed frame "
          "(extrinsic). Unity's `eulerAngles` are `\"ZXY\"` extrinsic, degrees")
      .text("head_orientation.sequence", nullptr, {"extrinsic", "intrinsic"})
      .required()
      .in("euler")
      .doc("`intrinsic` reads `order` about the moving axes (intrinsic XYZ = extrinsic ZYX)")
      .text("head_orientation.unit", nullptr, {"deg", "rad"})
      .required()
      .in("euler")
      .doc("unit of the angles")
      .numbers("head_orientation.signs", {1, 1, 1})
      .in("euler")
      .shown("[1, 1, 1]", "3 numbers, each 1 or -1")
      .doc(
          "multiplies the angles about X, Y, Z by ±1 (sources whose positive sense is "
          "left-handed per axis)")
      .other("head_orientation.forward", "column[3]")
      .required()
      .in("forward")
      .doc(
          "head forward vector (source axes, any length); a forward that is zero, vertical "
          "without `up`, or parallel to `up` is a bad row")
      .other("head_orientation.up", "column[3]")
      .optional()
      .in("forward")
      .doc("head up vector; without it the head has no roll (world up is +Y in fovsim axes)")
      .numbers("head_orientation.constant", {})
      .required()
      .in("constant")
      .shown("required", "4 numbers, a unit quaternion")
      .doc("a fixed orientation, fovsim quaternion w, x, y, z")
      .boolean("head_orientation.inverse", false)
      .doc("the source stores head-from-world")
      .boolean("head_orientation.dequantise", false)
      .doc(
          "orientations rounded in the export (0.1°): runs of an identical orientation are "
          "taken at their middle times and interpolated by slerp, as "
          "`head_position.dequantise`");
}

void gaze_keys(Rows& r) {
  r.text("gaze.type", nullptr, {"direction", "orientation", "angles", "screen", "point"})
      .required()
      .doc("how the gaze is given")
      .other("gaze.coordinates", "string or object")
      .optional()
      .shown("`coordinates`", "as `coordinates`")
      .doc(
          "the gaze vectors' own axes when they differ from the head pose's (SRanipal's eye "
          "frame next to a Unity head pose); not for `screen` or `angles`")
      .text("gaze.space", nullptr, {"head", "world"})
      .required()
      .in("direction, orientation")
      .doc("the space the gaze vector or pose is given in")
      .other("gaze.columns", "column[3]")
      .required()
      .in("direction")
      .doc("combined gaze vector (any length)")
      .other("gaze.left, gaze.right", "column[3]")
      .in("direction")
      .shown("none", "")
      .doc("per-eye vectors instead of `columns`")
      .text("gaze.combine", nullptr, {"mean", "left", "right"})
      .required()
      .in("direction with left, right")
      .doc(
          "`mean` = normalized sum of the unit vectors, or the one eye with a non-zero "
          "vector")
      .other("gaze.columns", "column[4]")
      .required()
      .in("orientation")
      .doc("a gaze pose (OpenXR eye gaze): the gaze is the quaternion's `forward` axis")
      .text("gaze.order", nullptr, {"wxyz", "xyzw"})
      .required()
      .in("orientation")
      .doc("the order of the quaternion columns")
      .text("gaze.forward", "-z", {"+x", "-x", "+y", "-y", "+z", "-z"})
      .in("orientation")
      .doc("the signed source axis the gaze pose looks along (`-z` in OpenXR)")
      .other("gaze.columns", "column[2]")
      .required()
      .in("angles")
      .doc(
          "azimuth, positive to the right, and elevation, positive up, in the head "
          "(direction (cos e sin a, sin e, −cos e cos a)). Example: Pupil Cloud's "
          "`azimuth [deg]`, `elevation [deg]`")
      .text("gaze.unit", nullptr, {"deg", "rad"})
      .required()
      .in("angles")
      .doc("unit of the angles")
      .numbers("gaze.signs", {1, 1})
      .in("angles")
      .shown("[1, 1]", "2 numbers, each 1 or -1")
      .doc("flips the sense of the azimuth, the elevation")
      .other("gaze.columns", "column[2]")
      .required()
      .in("screen")
      .doc("normalized screen point u, v, converted with `--display`")
      .text("gaze.origin", nullptr, {"top-left", "bottom-left"})
      .required()
      .in("screen")
      .doc("the screen point's origin")
      .other("gaze.columns", "column[3]")
      .required()
      .in("point")
      .doc("world point looked at (direction from the head position)")
      .text("gaze.unit", nullptr, {"m", "cm", "mm"})
      .required()
      .in("point")
      .doc("unit of the point");
}

void row_keys(Rows& r) {
  r.other("valid", "array of conditions")
      .shown("[]", "")
      .doc(
          "all conditions must hold for valid=1. Invalid rows keep their pose; their gaze "
          "may be anything (held from the last valid sample). Exactly one of "
          "`valid_values`, `invalid_values`, `all_bits`, `min`, `max` per condition")
      .other("valid[i].column", "column")
      .required()
      .doc("the field the condition tests")
      .other("valid[i].valid_values, valid[i].invalid_values", "array of strings")
      .doc("valid when the field is (is not) one of the values, compared as trimmed strings")
      .integer("valid[i].all_bits", 0, Range::closed(1, 2147483647.0))
      .required()
      .shown("none", "int ≥ 1")
      .doc(
          "valid when every bit of the mask is set in the (integer) field: SRanipal "
          "`eye_valid_L` = 31 when all bits are set, `\"all_bits\": 2` requires bit 1 (gaze "
          "direction valid)")
      .number("valid[i].min", 0, Range::any())
      .required()
      .shown("none", "number")
      .doc(
          "valid when the field is ≥ min (tracker confidence ≥ 0.6); an unparsable field "
          "fails the condition")
      .number("valid[i].max", 0, Range::any())
      .required()
      .shown("none", "number")
      .doc("valid when the field is ≤ max; an unparsable field fails the condition")
      .text("valid[i].eye", "both", {"both", "left", "right"})
      .doc(
          "with per-eye gaze, the condition applies to that eye only. With `combine: mean`, "
          "a row with one valid eye uses that eye (counted in the report), with none it is "
          "invalid; `combine: left`/`right` needs that eye. Conditions with `both` must all "
          "hold")
      .other("fused", "array of objects")
      .shown("[]", "")
      .doc(
          "a field the export wrote fused with its neighbour (`666.5324True`): on a row one "
          "field short, that field is split and the fields after it are in place again. "
          "Rows of the right length are untouched; the count of split rows is reported")
      .other("fused[i].column", "column")
      .required()
      .doc("the first of the two header columns")
      .other("fused[i].suffixes", "array of strings")
      .doc(
          "split before the longest listed suffix that ends the field (`[\"True\", "
          "\"False\"]`); exactly one of `suffixes`, `pattern`")
      .text("fused[i].pattern", nullptr, {})
      .required()
      .shown("none", "a regular expression with two groups")
      .doc(
          "split into the pattern's two groups (`\"^(.*[0-9])(True|False)$\"`, ECMAScript "
          "syntax)")
      .text("on_bad", nullptr, {"fail", "skip", "hold"})
      .optional()
      .doc(
          "the map's policy for valid gaze outside the display FOV, used when the command "
          "line gives no `--on-bad` (and a run's trace block no `on_bad_sample`)")
      .text("on_invalid", nullptr, on_invalid_choices())
      .optional()
      .doc(
          "the tracking-loss policy a run uses when its `trace.on_invalid` is not given "
          "(docs/tracking.md)")
      .other("comment, description", "any")
      .doc(
          "ignored (also inside `time`, `head_position`, `head_orientation`, `gaze`, "
          "`valid` and `fused` entries)");
}

std::vector<MapKey> map_key_table() {
  Rows r;
  for (auto part : {layout_keys, time_keys, head_keys, gaze_keys, row_keys}) part(r);
  return std::move(r).rows();
}

const MapKey& typed_key(const std::string& path, const std::string& variant, MapKeyType t) {
  const MapKey& k = map_key(path, variant);
  FOVSIM_CHECK(k.type == t, "map key \"" + path + "\" is declared with another type");
  return k;
}

// The JSON key of a path: its last part.
std::string json_key(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

std::string cell(const std::string& s) {
  std::string r;
  for (char c : s) r += (c == '|') ? std::string("\\|") : std::string(1, c);
  return r.empty() ? std::string(" ") : r;
}

std::string type_text(const MapKey& k) {
  if (!k.type_doc.empty()) return k.type_doc;
  switch (k.type) {
    case MapKeyType::String:
      return "string";
    case MapKeyType::Bool:
      return "bool";
    case MapKeyType::Int:
      return "int";
    case MapKeyType::Number:
      return "number";
    case MapKeyType::Numbers:
      return "number[]";
    case MapKeyType::Other:
      break;
  }
  return "";
}

std::string values_text(const MapKey& k) {
  if (!k.values.empty()) return k.values;
  if (k.type == MapKeyType::String) {
    std::string s;
    for (const auto& a : k.allowed) s += (s.empty() ? "`" : ", `") + a + "`";
    return s;
  }
  if (k.type == MapKeyType::Bool) return "`true`, `false`";
  if ((k.type == MapKeyType::Int || k.type == MapKeyType::Number) &&
      !(k.range.lo <= -1e299 && k.range.hi >= 1e299))
    return param_doc_range(k.range);
  return "";
}

std::string default_text(const MapKey& k) {
  if (!k.def_doc.empty()) return k.def_doc;
  if (k.required) return "required";
  if (k.def.is_null()) return "none";
  if (k.def.is_string()) return "`" + k.def.get<std::string>() + "`";
  return "`" + param_def_text(k.def, false) + "`";
}

}  // namespace

const std::vector<MapKey>& map_keys() {
  static const std::vector<MapKey> keys = map_key_table();
  return keys;
}

const MapKey& map_key(const std::string& path, const std::string& variant) {
  for (const MapKey& k : map_keys())
    if (k.path == path && k.variant == variant) return k;
  FOVSIM_CHECK(false, "map key \"" + path + "\" (" + variant + ") is not in map_keys.cpp");
  return map_keys().front();
}

std::string map_string(Params& p, const std::string& path, const std::string& variant) {
  const MapKey& k = typed_key(path, variant, MapKeyType::String);
  const std::string key = json_key(path);
  return k.def.is_null() ? p.string(key, k.allowed)
                         : p.string(key, k.def.get<std::string>(), k.allowed);
}

bool map_boolean(Params& p, const std::string& path, const std::string& variant) {
  const MapKey& k = typed_key(path, variant, MapKeyType::Bool);
  // A required boolean is read for its type here; the caller says why it is required.
  return p.boolean(json_key(path), k.def.is_null() ? false : k.def.get<bool>());
}

int map_integer(Params& p, const std::string& path, const std::string& variant) {
  const MapKey& k = typed_key(path, variant, MapKeyType::Int);
  const std::string key = json_key(path);
  return k.required ? p.integer(key, k.range) : p.integer(key, k.def.get<int>(), k.range);
}

double map_number(Params& p, const std::string& path, const std::string& variant) {
  const MapKey& k = typed_key(path, variant, MapKeyType::Number);
  const std::string key = json_key(path);
  return k.required ? p.number(key, k.range) : p.number(key, k.def.get<double>(), k.range);
}

std::vector<double> map_numbers(Params& p, const std::string& path, const std::string& variant) {
  const MapKey& k = typed_key(path, variant, MapKeyType::Numbers);
  return p.numbers(json_key(path),
                   k.def.is_null() ? std::vector<double>{} : k.def.get<std::vector<double>>());
}

std::string map_keys_markdown() {
  std::string md = "| key | type | default | values | meaning |\n|---|---|---|---|---|\n";
  for (const MapKey& k : map_keys())
    md += "| `" + k.path + "`" + (k.variant.empty() ? "" : " (" + k.variant + ")") + " | " +
          cell(type_text(k)) + " | " + cell(default_text(k)) + " | " + cell(values_text(k)) +
          " | " + cell(k.doc) + " |\n";
  return md;
}

}  // namespace fovsim
