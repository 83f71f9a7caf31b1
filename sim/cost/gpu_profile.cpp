// GPU profile files (models/gpus/*.json). Their keys are gpu_profile_keys() (docs/cost_model.md
// "GPU profile" is generated from it; `spec` keys are gpu_spec_table()).
#include "sim/cost/gpu_profile.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/param_table.h"
#include "sim/cost/passes.h"

namespace fovsim {

const char* model_name(CostModelKind k) {
  return k == CostModelKind::Roofline ? "roofline" : "linear";
}

const char* resource_name(Resource r) {
  switch (r) {
    case Resource::Geometry:
      return "geometry";
    case Resource::Raster:
      return "raster";
    case Resource::Shading:
      return "shading";
    case Resource::Memory:
      return "memory";
    case Resource::Fixed:
      return "fixed";
  }
  return "?";
}

Resource resource_from_name(const std::string& s, const std::string& where) {
  for (Resource r :
       {Resource::Geometry, Resource::Raster, Resource::Shading, Resource::Memory, Resource::Fixed})
    if (s == resource_name(r)) return r;
  throw Error(where,
              "unknown resource '" + s + "' (known: geometry, raster, shading, memory, fixed)");
}

double l2_miss_fraction(const GpuSpec& s, double working_set_bytes) {
  if (!(s.l2_mb > 0) || !(working_set_bytes > 0)) return 1.0;
  return std::max(0.0, 1.0 - s.l2_mb * 1024.0 * 1024.0 / working_set_bytes);
}

const ParamTable<GpuSpec>& gpu_spec_table() {
  using S = GpuSpec;
  // A new spec field: its member in GpuSpec and one row here (parsing, docs, profile files).
  static const auto t =
      ParamTable<S>()
          .number("fp32_gflops", 0, Range::above(0, 1e7), &S::fp32_gflops)
          .required()
          .doc("vendor spec sheet", "FP32 throughput, GFLOP/s (shading)")
          .number("mem_gbps", 0, Range::above(0, 1e6), &S::mem_gbps)
          .required()
          .doc("vendor spec sheet", "memory bandwidth, GB/s")
          .number("fill_gpix", 0, Range::above(0, 1e5), &S::fill_gpix)
          .required()
          .doc("vendor spec sheet", "ROP fill rate, Gpixel/s (raster)")
          .number("tri_gtris", 0, Range::above(0, 1e5), &S::tri_gtris)
          .required()
          .doc("vendor spec sheet", "primitive rate, Gtriangles/s (geometry)")
          .number("boost_mhz", 0, Range::closed(0, 1e5), &S::boost_mhz)
          .doc("vendor spec sheet", "boost clock, MHz (0: unknown)")
          .number("l2_mb", 0, Range::closed(0, 1e5), &S::l2_mb)
          .doc("vendor spec sheet", "last-level (L2) cache, MB (0: unknown: no working-set effect)")
          .text("source", "", {}, &S::source)
          .doc("", "where the numbers come from");
  return t;
}

namespace {

// Builds the rows in order; the modifiers change the last row.
class ProfileRows {
 public:
  ProfileRows& text(const char* path, const char* def, std::vector<std::string> allowed = {}) {
    add(path, ProfileKeyType::String, def ? Json(def) : Json());
    v_.back().allowed = std::move(allowed);
    return *this;
  }
  ProfileRows& boolean(const char* path, bool def) {
    return add(path, ProfileKeyType::Bool, Json(def));
  }
  ProfileRows& integer(const char* path, int def, Range r) {
    add(path, ProfileKeyType::Int, Json(def));
    v_.back().range = r;
    return *this;
  }
  ProfileRows& number(const char* path, double def, Range r) {
    add(path, ProfileKeyType::Number, Json(def));
    v_.back().range = r;
    return *this;
  }
  ProfileRows& numbers(const char* path, Range r) {
    add(path, ProfileKeyType::Numbers, Json::array());
    v_.back().range = r;
    return *this;
  }
  ProfileRows& strings(const char* path) { return add(path, ProfileKeyType::Strings, Json()); }
  ProfileRows& object(const char* path) { return add(path, ProfileKeyType::Object, Json()); }
  // No default: the key must be given (where its parent is).
  ProfileRows& required() {
    v_.back().def = Json();
    v_.back().required = true;
    return *this;
  }
  // No default: read only when given.
  ProfileRows& optional() {
    v_.back().def = Json();
    return *this;
  }
  ProfileRows& doc(const char* d) {
    v_.back().doc = d;
    return *this;
  }
  std::vector<ProfileKey> rows() && { return std::move(v_); }

 private:
  ProfileRows& add(const char* path, ProfileKeyType t, Json def) {
    ProfileKey k;
    k.path = path;
    k.type = t;
    k.def = std::move(def);
    v_.push_back(std::move(k));
    return *this;
  }
  std::vector<ProfileKey> v_;
};

// The interval factors of `prefix` ("interval", "interval.total", "interval.passes.{pass}").
void factor_keys(ProfileRows& r, const std::string& prefix, const char* what) {
  const std::string lo = prefix + ".lo_factor", hi = prefix + ".hi_factor", n = prefix + ".n";
  r.number(lo.c_str(), 0, Range::above(0, 1))
      .required()
      .doc((std::string("lower multiplicative factor (") + what + ")").c_str())
      .number(hi.c_str(), 0, Range::closed(1, 1e3))
      .required()
      .doc((std::string("upper multiplicative factor (") + what + ")").c_str())
      .integer(n.c_str(), 0, Range::at_least(0))
      .doc("held-out rows the factors came from");
}

std::vector<ProfileKey> gpu_profile_key_table() {
  ProfileRows r;
  r.text("name", nullptr)
      .required()
      .doc("profile name")
      .text("description", "")
      .doc("what the profile is")
      .boolean("calibrated", false)
      .doc("false: coefficients transferred through spec ratios only")
      .text("architecture", nullptr)
      .optional()
      .doc("what a spec transfer assumes (uncalibrated profiles)")
      .text("model", "linear", {"linear", "roofline"})
      .doc("how a pass combines its terms (docs/architecture.md \"Cost model\")")
      .text("comment", nullptr)
      .optional()
      .doc("free text, ignored")
      .object("interval")
      .optional()
      .doc("prediction interval (optional; none: point estimates only)")
      .number("interval.level", 0, Range::above(0, 1))
      .required()
      .doc("coverage the factors were made for");
  factor_keys(r, "interval", "pooled over every held-out row");
  r.text("interval.method", "")
      .doc("how the factors were made")
      .number("interval.widen", 1.0, Range::closed(1, 10))
      .doc("extrapolation: log-widths are multiplied by this")
      .object("interval.total")
      .optional()
      .doc("split-conformal factors of the frame total (none: its passes' intervals combine)");
  factor_keys(r, "interval.total", "frame total");
  r.numbers("interval.total_scores", Range::closed(-20, 20))
      .doc("held-out log(published / model) of frame totals (sorted when read)")
      .object("interval.passes")
      .optional()
      .doc("pass -> factors (optional; a pass not listed takes the pooled factors)");
  factor_keys(r, "interval.passes.{pass}", "that pass");
  r.object("spec")
      .required()
      .doc("spec-sheet rates: every key is in configs/README.md \"GPU spec\" (gpu_spec_table())")
      .object("passes")
      .required()
      .doc("per-pass coefficients; every pass the costed method declares")
      .number("passes.{pass}.overhead_ms", 0.0, Range::closed(0, 1e4))
      .doc("fixed time of the pass, ms")
      .object("passes.{pass}.terms")
      .required()
      .doc("term -> coefficient; the terms of docs/cost_model.md")
      .number("passes.{pass}.terms.{term}", 0, Range::closed(0, 1e3))
      .required()
      .doc("ms per counter unit")
      .object("calibration")
      .optional()
      .doc("how the coefficients were fitted (`fovsim calibrate`)")
      .text("calibration.comment", "")
      .doc("free text")
      .object("calibration.fit")
      .optional()
      .doc("fit diagnostics, ignored when read")
      .strings("calibration.tables")
      .optional()
      .doc("\"id: source\" of the tables fitted")
      .object("calibration.residuals")
      .optional()
      .doc("array, one entry per calibration row")
      .text("calibration.residuals[i].id", nullptr)
      .required()
      .doc("calibration entry id")
      .boolean("calibration.residuals[i].fitted", true)
      .doc("false: a check row (compared, not fitted)")
      .number("calibration.residuals[i].published_ms", 0, Range::closed(0, 1e6))
      .required()
      .doc("published time, ms")
      .number("calibration.residuals[i].model_ms", 0, Range::closed(0, 1e6))
      .required()
      .doc("model time, ms")
      .number("calibration.residuals[i].rel_err", 0, Range::closed(-1e6, 1e6))
      .required()
      .doc("(model - published) / published");
  return std::move(r).rows();
}

// The JSON key of a path: its last part.
std::string json_key(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

const ProfileKey& typed_key(const std::string& path, ProfileKeyType t) {
  const ProfileKey& k = gpu_profile_key(path);
  FOVSIM_CHECK(k.type == t, "GPU profile key \"" + path + "\" read with the wrong type");
  return k;
}

std::string cell(const std::string& s) {
  std::string r;
  for (char c : s) r += (c == '|') ? std::string("\\|") : std::string(1, c);
  return r.empty() ? std::string(" ") : r;
}

std::string type_text(const ProfileKey& k) {
  switch (k.type) {
    case ProfileKeyType::String:
      return "string";
    case ProfileKeyType::Bool:
      return "bool";
    case ProfileKeyType::Int:
      return "int";
    case ProfileKeyType::Number:
      return "number";
    case ProfileKeyType::Numbers:
      return "number[]";
    case ProfileKeyType::Strings:
      return "string[]";
    case ProfileKeyType::Object:
      return k.path == "calibration.residuals" ? "object[]" : "object";
  }
  return "";
}

std::string values_text(const ProfileKey& k) {
  if (k.type == ProfileKeyType::String) {
    std::string s;
    for (const auto& a : k.allowed) s += (s.empty() ? "`" : ", `") + a + "`";
    return s;
  }
  if (k.type == ProfileKeyType::Bool) return "`true`, `false`";
  if ((k.type == ProfileKeyType::Int || k.type == ProfileKeyType::Number ||
       k.type == ProfileKeyType::Numbers) &&
      !(k.range.lo <= -1e299 && k.range.hi >= 1e299))
    return param_doc_range(k.range) + (k.type == ProfileKeyType::Numbers ? " each" : "");
  return "";
}

std::string default_text(const ProfileKey& k) {
  if (k.required) return "required";
  if (k.def.is_null()) return "none";
  if (k.def.is_string())
    return k.def.get<std::string>().empty() ? "`\"\"`" : "`" + k.def.get<std::string>() + "`";
  return "`" + param_def_text(k.def, false) + "`";
}

}  // namespace

const std::vector<ProfileKey>& gpu_profile_keys() {
  static const std::vector<ProfileKey> keys = gpu_profile_key_table();
  return keys;
}

const ProfileKey& gpu_profile_key(const std::string& path) {
  for (const ProfileKey& k : gpu_profile_keys())
    if (k.path == path) return k;
  FOVSIM_CHECK(false, "GPU profile key \"" + path + "\" is not in gpu_profile.cpp");
  return gpu_profile_keys().front();
}

std::string profile_string(Params& p, const std::string& path) {
  const ProfileKey& k = typed_key(path, ProfileKeyType::String);
  const std::string key = json_key(path);
  return k.def.is_null() ? p.string(key, k.allowed)
                         : p.string(key, k.def.get<std::string>(), k.allowed);
}

bool profile_boolean(Params& p, const std::string& path) {
  const ProfileKey& k = typed_key(path, ProfileKeyType::Bool);
  return p.boolean(json_key(path), k.def.get<bool>());
}

int profile_integer(Params& p, const std::string& path) {
  const ProfileKey& k = typed_key(path, ProfileKeyType::Int);
  const std::string key = json_key(path);
  return k.required ? p.integer(key, k.range) : p.integer(key, k.def.get<int>(), k.range);
}

double profile_number(Params& p, const std::string& path, const std::string& key) {
  const ProfileKey& k = typed_key(path, ProfileKeyType::Number);
  const std::string jk = key.empty() ? json_key(path) : key;
  return k.required ? p.number(jk, k.range) : p.number(jk, k.def.get<double>(), k.range);
}

std::vector<double> profile_numbers(Params& p, const std::string& path) {
  const ProfileKey& k = typed_key(path, ProfileKeyType::Numbers);
  return p.numbers(json_key(path), k.def.get<std::vector<double>>(), k.range);
}

std::string gpu_profile_keys_markdown() {
  std::string md = "| key | type | default | values | meaning |\n|---|---|---|---|---|\n";
  for (const ProfileKey& k : gpu_profile_keys())
    md += "| `" + k.path + "` | " + cell(type_text(k)) + " | " + cell(default_text(k)) + " | " +
          cell(values_text(k)) + " | " + cell(k.doc) + " |\n";
  return md;
}

double GpuSpec::rate_per_ms(Resource r) const {
  switch (r) {
    case Resource::Geometry:
      return tri_gtris * 1e6;
    case Resource::Raster:
      return fill_gpix * 1e6;
    case Resource::Shading:
      return fp32_gflops * 1e6;
    case Resource::Memory:
      return mem_gbps * 1e6;
    case Resource::Fixed:
      return 1.0;
  }
  return 1.0;
}

static bool looks_like_path(const std::string& s) {
  return s.find('/') != std::string::npos ||
         (s.size() > 5 && s.compare(s.size() - 5, 5, ".json") == 0);
}

std::vector<std::string> GpuProfile::available(const std::string& models_dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (auto& e : std::filesystem::directory_iterator(models_dir + "/gpus", ec))
    if (e.path().extension() == ".json") out.push_back(e.path().stem().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> GpuProfile::names_from_config(Params& root) {
  if (!root.has("gpus")) return {kDefaultGpu};
  std::vector<std::string> names;
  const Json& gj = root.raw("gpus");
  if (!gj.is_array() || gj.empty())
    root.fail("gpus", "expected a non-empty array of GPU profile names");
  for (size_t i = 0; i < gj.size(); ++i) {
    if (!gj[i].is_string())
      root.fail("gpus[" + std::to_string(i) + "]",
                "expected a profile name, got " + describe_json(gj[i]));
    for (size_t k = 0; k < names.size(); ++k)
      if (names[k] == gj[i].get<std::string>())
        root.fail("gpus[" + std::to_string(i) + "]",
                  "\"" + names[k] + "\" is also gpus[" + std::to_string(k) +
                      "] (each GPU once: a repeat would count every frame twice)");
    names.push_back(gj[i].get<std::string>());
  }
  return names;
}

GpuProfile GpuProfile::load(const std::string& name_or_path, const std::string& models_dir) {
  std::string file =
      looks_like_path(name_or_path) ? name_or_path : models_dir + "/gpus/" + name_or_path + ".json";
  if (!file_exists(file)) {
    std::string av;
    for (auto& n : available(models_dir)) av += (av.empty() ? "" : ", ") + n;
    throw Error(file, "unknown GPU profile '" + name_or_path + "' (available in " + models_dir +
                          "/gpus: " + (av.empty() ? "none" : av) + ")");
  }
  return from_json(Params::parse_json_file(file), file);
}

GpuProfile GpuProfile::from_json(const Json& j, const std::string& file) {
  Params p(j, file);
  GpuProfile g;
  g.file = file;
  g.data = j;
  g.name = profile_string(p, "name");
  g.description = profile_string(p, "description");
  g.calibrated = profile_boolean(p, "calibrated");
  g.model =
      profile_string(p, "model") == "roofline" ? CostModelKind::Roofline : CostModelKind::Linear;
  if (p.has("interval")) {
    Params iv = p.child("interval");
    g.interval.level = profile_number(iv, "interval.level");
    // Multiplicative factors around the estimate: lo <= 1 <= hi (gpu_profile.h).
    auto factors = [](Params& f, IntervalFactors& out, const std::string& prefix) {
      out.lo_factor = profile_number(f, prefix + ".lo_factor");
      out.hi_factor = profile_number(f, prefix + ".hi_factor");
      out.n = profile_integer(f, prefix + ".n");
    };
    IntervalFactors pooled;
    factors(iv, pooled, "interval");
    g.interval.lo_factor = pooled.lo_factor;
    g.interval.hi_factor = pooled.hi_factor;
    g.interval.n = pooled.n;
    g.interval.method = profile_string(iv, "interval.method");
    g.interval.widen = profile_number(iv, "interval.widen");
    if (iv.has("total")) {
      Params t = iv.child("total");
      factors(t, g.interval.total, "interval.total");
      t.finish();
    }
    if (iv.has("total_scores")) {
      g.interval.total_scores = profile_numbers(iv, "interval.total_scores");
      std::sort(g.interval.total_scores.begin(), g.interval.total_scores.end());
    }
    if (iv.has("passes")) {
      Params ps = iv.child("passes");
      if (!ps.json().is_object())
        ps.fail("", "must be an object pass -> {lo_factor, hi_factor, n}");
      for (auto it = ps.json().begin(); it != ps.json().end(); ++it) {
        if (!is_known_pass(it.key())) ps.fail(it.key(), "unknown pass '" + it.key() + "'");
        Params f = ps.child(it.key());
        factors(f, g.interval.passes[it.key()], "interval.passes.{pass}");
        f.finish();
      }
    }
    iv.finish();
  }
  {
    Params s = p.child("spec");
    gpu_spec_table().read_into(s, g.spec);
  }
  if (!p.has("passes")) p.fail("passes", "missing required key (per-pass coefficients)");
  Params ps = p.child("passes");
  if (!ps.json().is_object()) ps.fail("", "must be an object of passes");
  for (auto it = ps.json().begin(); it != ps.json().end(); ++it) {
    const std::string pass = it.key();
    Params pp = ps.child(pass);
    if (!is_known_pass(pass)) {
      std::string all;
      for (auto& k : known_passes()) all += (all.empty() ? "" : ", ") + k;
      ps.fail(pass, "unknown pass '" + pass + "' (known: " + all + ")");
    }
    PassCoef pc;
    pc.overhead_ms = profile_number(pp, "passes.{pass}.overhead_ms");
    Params terms = pp.child("terms");
    if (!terms.json().is_object()) terms.fail("", "must be an object term -> ms per unit");
    for (auto t = terms.json().begin(); t != terms.json().end(); ++t) {
      term_resource(pass, t.key(), terms.where(t.key()));
      pc.terms[t.key()] = profile_number(terms, "passes.{pass}.terms.{term}", t.key());
    }
    // Every term of the pass is required: a profile written before a term existed (e.g. the
    // reprojection's sprites) would otherwise charge nothing for its work.
    std::string all, missing;
    for (const std::string& term : term_names())
      if (find_term_resource(pass, term)) {
        all += (all.empty() ? "" : ", ") + term;
        if (!pc.terms.count(term)) missing += (missing.empty() ? "" : ", ") + term;
      }
    if (!missing.empty())
      terms.fail("", "missing term(s) " + missing + " of pass '" + pass + "' (its terms: " + all +
                         "; write 0 for work that costs nothing on this GPU, or recalibrate with "
                         "`fovsim calibrate`)");
    g.passes[pass] = pc;
  }
  if (p.has("calibration")) {
    Params cal = p.child("calibration");
    g.calibration_comment = profile_string(cal, "calibration.comment");
    cal.ignore("fit");
    if (cal.has("tables"))
      for (auto& t : cal.raw("tables")) g.calibration_tables.push_back(t.get<std::string>());
    for (Params r : cal.children("residuals")) {
      CalibrationResidual cr;
      cr.id = profile_string(r, "calibration.residuals[i].id");
      cr.published_ms = profile_number(r, "calibration.residuals[i].published_ms");
      cr.model_ms = profile_number(r, "calibration.residuals[i].model_ms");
      cr.rel_err = profile_number(r, "calibration.residuals[i].rel_err");
      cr.fitted = profile_boolean(r, "calibration.residuals[i].fitted");
      g.residuals.push_back(cr);
    }
  }
  p.ignore("comment");
  if (p.has("architecture")) g.architecture = profile_string(p, "architecture");
  p.finish();
  return g;
}

Json GpuProfile::to_json() const {
  Json j = data.is_object() ? data : Json::object();
  j["name"] = name;
  j["description"] = description;
  j["calibrated"] = calibrated;
  if (!architecture.empty()) j["architecture"] = architecture;
  j["model"] = model_name(model);
  j.erase("interval");
  if (interval.level > 0) {
    Json iv = {{"level", interval.level},
               {"lo_factor", interval.lo_factor},
               {"hi_factor", interval.hi_factor},
               {"n", interval.n}};
    if (!interval.method.empty()) iv["method"] = interval.method;
    if (interval.widen != 1.0) iv["widen"] = interval.widen;
    if (interval.total.n > 0)
      iv["total"] = {{"lo_factor", interval.total.lo_factor},
                     {"hi_factor", interval.total.hi_factor},
                     {"n", interval.total.n}};
    if (!interval.total_scores.empty()) iv["total_scores"] = interval.total_scores;
    if (!interval.passes.empty()) {
      Json ps = Json::object();
      for (auto& [pass, f] : interval.passes)
        ps[pass] = {{"lo_factor", f.lo_factor}, {"hi_factor", f.hi_factor}, {"n", f.n}};
      iv["passes"] = ps;
    }
    j["interval"] = iv;
  }
  Json sp = Json::object();
  for (const auto& row : gpu_spec_table().rows()) sp[row.key] = row.get(spec);
  j["spec"] = sp;
  Json ps = Json::object();
  for (auto& [pass, pc] : passes) {
    Json t = Json::object();
    for (auto& [k, v] : pc.terms) t[k] = v;
    ps[pass] = {{"overhead_ms", pc.overhead_ms}, {"terms", t}};
  }
  j["passes"] = ps;
  if (!residuals.empty() || !calibration_tables.empty() || !calibration_comment.empty()) {
    Json cal = Json::object();
    if (!calibration_comment.empty()) cal["comment"] = calibration_comment;
    cal["tables"] = calibration_tables;
    Json res = Json::array();
    for (auto& r : residuals)
      res.push_back({{"id", r.id},
                     {"fitted", r.fitted},
                     {"published_ms", r.published_ms},
                     {"model_ms", r.model_ms},
                     {"rel_err", r.rel_err}});
    cal["residuals"] = res;
    j["calibration"] = cal;
  }
  return j;
}

std::string GpuProfile::to_file_text() const {
  const Json j = to_json();
  nlohmann::ordered_json o;
  for (const char* k :
       {"name", "description", "calibrated", "architecture", "model", "interval", "spec"})
    if (j.contains(k)) o[k] = j.at(k);
  if (o.contains("interval")) {  // level, factors, n, method, passes (as documented)
    nlohmann::ordered_json iv;
    for (const char* k : {"level", "lo_factor", "hi_factor", "n", "method", "widen", "total",
                          "total_scores", "passes"})
      if (j.at("interval").contains(k)) iv[k] = j.at("interval").at(k);
    o["interval"] = iv;
  }
  if (o.contains("spec")) {
    nlohmann::ordered_json sp;
    for (const auto& row : gpu_spec_table().rows())  // in the declaration's order
      if (j.at("spec").contains(row.key)) sp[row.key] = j.at("spec").at(row.key);
    o["spec"] = sp;
  }
  nlohmann::ordered_json ps = nlohmann::ordered_json::object();
  for (const std::string& pass : known_passes())
    if (j.at("passes").contains(pass)) ps[pass] = j.at("passes").at(pass);
  o["passes"] = ps;
  for (auto it = j.begin(); it != j.end(); ++it)  // calibration and any other key, after
    if (!o.contains(it.key())) o[it.key()] = it.value();
  if (o.contains("calibration")) {
    nlohmann::ordered_json cal;
    for (const char* k : {"comment", "tables", "residuals"})
      if (j.at("calibration").contains(k)) cal[k] = j.at("calibration").at(k);
    nlohmann::ordered_json res = nlohmann::ordered_json::array();
    for (auto& r : j.at("calibration").value("residuals", Json::array())) {
      nlohmann::ordered_json x;
      for (const char* k : {"id", "fitted", "published_ms", "model_ms", "rel_err"})
        if (r.contains(k)) x[k] = r.at(k);
      res.push_back(x);
    }
    cal["residuals"] = res;
    o["calibration"] = cal;
  }
  return o.dump(2) + "\n";
}

namespace {
IntervalFactors widened(IntervalFactors f, double widen) {
  if (widen != 1.0) {
    f.lo_factor = std::exp(widen * std::log(f.lo_factor));
    f.hi_factor = std::exp(widen * std::log(f.hi_factor));
  }
  return f;
}
}  // namespace

IntervalFactors PredictionInterval::for_pass(const std::string& pass) const {
  auto it = passes.find(pass);
  if (it != passes.end()) return widened(it->second, widen);
  return widened({lo_factor, hi_factor, n}, widen);
}

IntervalFactors PredictionInterval::for_total() const {
  if (total.n <= 0) return {1, 1, 0};
  return widened(total, widen);
}

double fit_probability(const PredictionInterval& iv, double ms, double budget_ms) {
  if (!(ms > 0)) return 1.0;
  if (!std::isfinite(ms)) return 0.0;
  const double need = std::log(budget_ms / ms);  // the score at which the frame just fits
  if (!iv.total_scores.empty()) {
    const double n = double(iv.total_scores.size());
    double k = 0;
    for (double s : iv.total_scores) k += iv.widen * s <= need ? 1.0 : 0.0;
    return (k + 0.5) / (n + 1);
  }
  if (iv.level <= 0) return ms <= budget_ms ? 1.0 : 0.0;
  // Only the level's factors: a log-uniform spread between them carrying `level` of the mass.
  const IntervalFactors f = iv.for_total().n > 0 ? iv.for_total() : iv.for_pass("");
  const double a = std::log(f.lo_factor), b = std::log(f.hi_factor), tail = (1 - iv.level) / 2;
  if (!(b > a)) return ms <= budget_ms ? 1.0 : 0.0;
  if (need < a) return tail * std::exp((need - a) / (b - a));
  if (need > b) return 1 - tail * std::exp((b - need) / (b - a));
  return tail + iv.level * (need - a) / (b - a);
}

void combine_pass_intervals(const std::vector<PassSpan>& parts, double* lo_ms, double* hi_ms) {
  double total = 0, below = 0, above = 0;
  for (auto& p : parts) {
    total += p.ms;
    below += (p.ms - p.lo_ms) * (p.ms - p.lo_ms);
    above += (p.hi_ms - p.ms) * (p.hi_ms - p.ms);
  }
  *lo_ms = std::max(0.0, total - std::sqrt(below));
  *hi_ms = total + std::sqrt(above);
}

GpuProfile GpuProfile::scaled(Resource r, double factor) const {
  if (!(factor > 0) || !std::isfinite(factor))
    throw Error("what-if",
                std::string("throughput factor for ") + resource_name(r) + " must be > 0");
  GpuProfile g = *this;
  for (auto& [pass, pc] : g.passes) {
    if (r == Resource::Fixed) pc.overhead_ms /= factor;
    for (auto& [term, v] : pc.terms)
      if (term_resource(pass, term, "") == r) v /= factor;
  }
  switch (r) {
    case Resource::Geometry:
      g.spec.tri_gtris *= factor;
      break;
    case Resource::Raster:
      g.spec.fill_gpix *= factor;
      break;
    case Resource::Shading:
      g.spec.fp32_gflops *= factor;
      break;
    case Resource::Memory:
      g.spec.mem_gbps *= factor;
      break;
    case Resource::Fixed:
      break;
  }
  return g;
}

double GpuProfile::coef(const std::string& pass, const std::string& term) const {
  auto it = passes.find(pass);
  if (it == passes.end()) return 0;
  auto t = it->second.terms.find(term);
  return t == it->second.terms.end() ? 0 : t->second;
}

}  // namespace fovsim
