#include "sim/cost/tracking_cost.h"

#include <algorithm>

namespace fovsim {

Json widened_method_params(const std::string& method, const Json& params, double k,
                           bool* modelled) {
  Json p = params.is_object() ? params : Json::object();
  if (modelled) *modelled = method != "twfr";
  if (!(k > 1)) return p;
  auto num = [&](const char* key, double def) {
    return p.contains(key) && p[key].is_number() ? p[key].get<double>() : def;
  };
  if (method == "kfr" || method == "rmfr") {
    p["sigma"] = std::max(1.0, num("sigma", method == "kfr" ? 1.8 : 2.6) / k);
    if (method == "rmfr") {
      for (const char* f : {"fx_px", "fy_px"})
        if (p.contains(f) && p[f].is_number()) p[f] = p[f].get<double>() * k;
      if (!p.contains("fx_px")) p["fx"] = num("fx", 0.38) * k;
      if (!p.contains("fy_px")) p["fy"] = num("fy", 0.38) * k;
    }
  } else if (method == "hyperbolic" || method == "linear" || method == "fvrs") {
    p["radius_scale"] = num("radius_scale", 1.0) * k;
  } else if (method == "flc") {
    if (p.contains("log_polar") && p["log_polar"].is_boolean() && p["log_polar"].get<bool>())
      p["lp_sigma"] = std::max(1.0, num("lp_sigma", 2.0) / k);
  }
  return p;
}

std::string lost_frame_method(const std::string& method, OnInvalid p) {
  return p == OnInvalid::Full ? std::string("full") : method;
}

double expected_ms_with_loss(double valid_ms, double lost_ms, double fraction) {
  return (1.0 - fraction) * valid_ms + fraction * lost_ms;
}

}  // namespace fovsim
