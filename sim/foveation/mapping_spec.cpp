#include "sim/foveation/mapping_spec.h"

#include "sim/core/error.h"

namespace fovsim {

bool is_mapping_method(const std::string& n) {
  return n == "kfr" || n == "rmfr" || n == "hyperbolic" || n == "linear" || n == "fvrs";
}

namespace {
void read_radii(MappingSpec& s, Params& p) {
  s.r1 = p.number("r1", 10.0, Range::closed(0, 180));
  s.r2 = p.number("r2", 20.0, Range::closed(0, 180));
  if (s.r2 < s.r1) p.fail("r2", "must be >= r1 (" + std::to_string(s.r1) + ")");
  s.radius_scale = p.number("radius_scale", 1.0, Range::above(0));
}
void read_target(MappingSpec& s, Params& p) {
  if (p.has("target_shaded_fraction"))
    s.target_shaded_fraction = p.number("target_shaded_fraction", Range::above(0, 1));
}
}  // namespace

MappingSpec MappingSpec::from_params(const std::string& method, Params& p) {
  MappingSpec s;
  s.method = method;
  if (method == "kfr") {
    s.sigma = p.number("sigma", 1.8, Range::at_least(1));
    s.kernel.kind = KernelFn::parse(p.string("kernel", "power", {"power", "sine", "exp"}));
    s.kernel.alpha = p.number("alpha", 4.0, Range::closed(1e-3, 1e3));
    s.internal_aa = p.boolean("internal_aa", true);
    s.internal_aa_start = p.number("internal_aa_start", 0.5, Range::closed(0, 1));
    s.post_aa = p.boolean("post_aa", true);
    read_target(s, p);
  } else if (method == "rmfr") {
    s.sigma = p.number("sigma", 2.6, Range::at_least(1));
    if (p.has("fx") && p.has("fx_px"))
      p.fail("fx_px", "give either fx (fraction of W) or fx_px, not both");
    if (p.has("fy") && p.has("fy_px"))
      p.fail("fy_px", "give either fy (fraction of H) or fy_px, not both");
    if (p.has("fx_px"))
      s.fx_px = p.number("fx_px", Range::above(0));
    else
      s.fx = p.number("fx", 0.38, Range::above(0));
    if (p.has("fy_px"))
      s.fy_px = p.number("fy_px", Range::above(0));
    else
      s.fy = p.number("fy", 0.38, Range::above(0));
    read_target(s, p);
  } else if (method == "hyperbolic") {
    read_radii(s, p);
    s.s1 = p.number("s1", 1.0, Range::closed(1, 1e4));
    s.s2 = p.number("s2", 2.0, Range::closed(1, 1e4));
    s.s3 = p.number("s3", 12.35, Range::closed(1, 1e4));
    s.blend_deg = p.number("blend_deg", 1.0, Range::closed(0, 90));
    read_target(s, p);
  } else if (method == "linear") {
    read_radii(s, p);
    s.p_min = p.number("p_min", 0.047, Range::above(0, 1));
    s.seed = uint64_t(p.integer("seed", 0, Range::closed(0, 2147483647)));
    read_target(s, p);
  } else if (method == "fvrs") {
    read_radii(s, p);
    s.edge_aware = p.boolean("edge_aware", true);
    read_target(s, p);
  } else {
    p.fail("method", "not a mapping method: \"" + method + "\"");
  }
  return s;
}

std::vector<std::pair<std::string, std::string>> MappingSpec::text_columns() const {
  if (method == "kfr") return {{"kernel", KernelFn::name(kernel.kind)}};
  return {};
}

std::vector<std::pair<std::string, double>> MappingSpec::columns() const {
  std::vector<std::pair<std::string, double>> c;
  if (method == "kfr") {
    c = {{"sigma", sigma}, {"alpha", kernel.alpha}};  // kernel: text_columns()
  } else if (method == "rmfr") {
    c = {{"sigma", sigma}};
    // fx, fy always as fractions of W / H; fx_px, fy_px only when given in pixels.
    if (fx_px > 0)
      c.push_back({"fx_px", fx_px});
    else
      c.push_back({"fx", fx});
    if (fy_px > 0)
      c.push_back({"fy_px", fy_px});
    else
      c.push_back({"fy", fy});
  } else {
    c = {{"r1", r1_eff()}, {"r2", r2_eff()}, {"radius_scale", radius_scale}};
    if (method == "hyperbolic") {
      c.push_back({"s1", s1});
      c.push_back({"s2", s2});
      c.push_back({"s3", s3});
    } else if (method == "linear") {
      c.push_back({"p_min", p_min});
    }
  }
  if (target_shaded_fraction > 0) c.push_back({"target_shaded_fraction", target_shaded_fraction});
  return c;
}

}  // namespace fovsim
