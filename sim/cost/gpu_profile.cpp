// GPU profile files (models/gpus/*.json). Format in docs/cost_model.md.
#include "sim/cost/gpu_profile.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "sim/core/error.h"
#include "sim/core/files.h"
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
  g.data = j;
  g.name = p.string("name");
  g.description = p.string("description", "");
  g.calibrated = p.boolean("calibrated", false);
  g.model = p.string("model", "linear", {"linear", "roofline"}) == "roofline"
                ? CostModelKind::Roofline
                : CostModelKind::Linear;
  if (p.has("interval")) {
    Params iv = p.child("interval");
    g.interval.level = iv.number("level", Range::above(0, 1));
    g.interval.lo_factor = iv.number("lo_factor", Range::above(0));
    g.interval.hi_factor = iv.number("hi_factor", Range::above(0));
    g.interval.n = iv.integer("n", 0, Range::at_least(0));
    iv.ignore("method");
    if (g.interval.lo_factor > g.interval.hi_factor)
      iv.fail("hi_factor", "must be >= lo_factor (" + std::to_string(g.interval.lo_factor) + ")");
    iv.finish();
  }
  {
    Params s = p.child("spec");
    auto pos = Range::above(0);
    g.spec.fp32_gflops = s.number("fp32_gflops", pos);
    g.spec.mem_gbps = s.number("mem_gbps", pos);
    g.spec.fill_gpix = s.number("fill_gpix", pos);
    g.spec.tri_gtris = s.number("tri_gtris", pos);
    g.spec.boost_mhz = s.number("boost_mhz", 0, Range::at_least(0));
    g.spec.l2_mb = s.number("l2_mb", 0, Range::at_least(0));
    g.spec.source = s.string("source", "");
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
    pc.overhead_ms = pp.number("overhead_ms", 0.0, Range::at_least(0));
    Params terms = pp.child("terms");
    if (!terms.json().is_object()) terms.fail("", "must be an object term -> ms per unit");
    for (auto t = terms.json().begin(); t != terms.json().end(); ++t) {
      term_resource(pass, t.key(), terms.where(t.key()));
      pc.terms[t.key()] = terms.number(t.key(), Range::at_least(0));
    }
    g.passes[pass] = pc;
  }
  if (p.has("calibration")) {
    Params cal = p.child("calibration");
    cal.ignore("comment");
    cal.ignore("fit");
    cal.ignore("tables");
    for (Params r : cal.children("residuals")) {
      CalibrationResidual cr;
      cr.id = r.string("id");
      cr.published_ms = r.number("published_ms");
      cr.model_ms = r.number("model_ms");
      cr.rel_err = r.number("rel_err");
      r.ignore("fitted");
      g.residuals.push_back(cr);
    }
  }
  p.ignore("comment");
  p.finish();
  return g;
}

Json GpuProfile::to_json() const {
  Json j = data.is_object() ? data : Json::object();
  j["name"] = name;
  j["description"] = description;
  j["calibrated"] = calibrated;
  j["model"] = model_name(model);
  if (interval.level > 0)
    j["interval"] = {{"level", interval.level},
                     {"lo_factor", interval.lo_factor},
                     {"hi_factor", interval.hi_factor},
                     {"n", interval.n}};
  j["spec"] = {{"fp32_gflops", spec.fp32_gflops},
               {"mem_gbps", spec.mem_gbps},
               {"fill_gpix", spec.fill_gpix},
               {"tri_gtris", spec.tri_gtris},
               {"boost_mhz", spec.boost_mhz},
               {"l2_mb", spec.l2_mb},
               {"source", spec.source}};
  Json ps = Json::object();
  for (auto& [pass, pc] : passes) {
    Json t = Json::object();
    for (auto& [k, v] : pc.terms) t[k] = v;
    ps[pass] = {{"overhead_ms", pc.overhead_ms}, {"terms", t}};
  }
  j["passes"] = ps;
  return j;
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
