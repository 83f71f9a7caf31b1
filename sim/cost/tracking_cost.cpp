#include "sim/cost/tracking_cost.h"

#include <algorithm>

#include "sim/core/error.h"
#include "sim/cost/analytic.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/mapping_spec.h"
#include "sim/foveation/method.h"

namespace fovsim {

Json widened_method_params(const std::string& method, const Json& params, double k, bool* modelled,
                           const Display* d) {
  Json p = params.is_object() ? params : Json::object();
  if (modelled) *modelled = method != "twfr";
  if (!(k > 1)) return p;
  auto num = [&](const char* key, double def) {
    return p.contains(key) && p[key].is_number() ? p[key].get<double>() : def;
  };
  if (method == "flc") {
    if (p.contains("log_polar") && p["log_polar"].is_boolean() && p["log_polar"].get<bool>())
      p["lp_sigma"] = std::max(1.0, num("lp_sigma", 2.0) / k);
    return p;
  }
  // A mapping method widens its own keys (its SamplingGeometry, read from the same keys with
  // its defaults). A method whose geometry is another's (rmfr_auto renders through rmfr, which
  // widens in a run) takes the widened keys it declares itself (rmfr_auto: sigma; its f_x, f_y
  // are chosen per frame and do not change the RS-buffer's shaded samples). Invalid keys are
  // left to the analytic parse that follows, which reports them at their location.
  try {
    Params mp(p, "widen", "");
    const std::unique_ptr<FoveationMethod> inst = make_method(method, mp);
    if (!inst->mapping_spec()) return p;
    // An iso-budget target on display d: a run widens the resolved geometry, so the widened
    // keys are the solution's and the target is dropped (else predict would solve it again).
    const bool target = d && inst->mapping_spec()->target_shaded_fraction() > 0;
    const MappingSpec spec =
        target ? resolved_mapping_spec(*inst->mapping_spec(), *d) : *inst->mapping_spec();
    if (target) p.erase("target_shaded_fraction");
    if (spec.method() == method) {
      spec.geometry().widen_keys(k, p);
    } else {
      Json w = Json::object();
      spec.geometry().widen_keys(k, w);
      const MethodEntry* e = find_method(method);
      for (const ParamInfo& pi : e->params())
        if (w.contains(pi.name)) p[pi.name] = w[pi.name];
    }
  } catch (const Error&) {
    return p;  // left as given: the analytic parse that follows reports the key and location
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
