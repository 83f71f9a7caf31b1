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
  const MethodEntry* e = find_method(method);
  if (modelled) *modelled = !e || e->cost().widening_modelled;
  if (!(k > 1)) return p;
  // The method widens its own keys (FoveationMethod::widen_cost_keys, read from the same keys
  // with its defaults): a mapping method through its SamplingGeometry, rmfr_auto its sigma as
  // rmfr does, flc its log-polar lp_sigma. Invalid keys are left to the analytic parse that
  // follows, which reports them at their location.
  // The method's analytic-only keys (MethodCost::analytic_keys: filter_taps_per_pixel, ...) are
  // not its parser's: without them the method parses, so such a key does not silently stop the
  // widening; they stay in the returned keys for the analytic parse.
  Json method_keys = p;
  if (e)
    for (const std::string& key : e->cost().analytic_keys) method_keys.erase(key);
  try {
    Params mp(method_keys, "widen", "");
    const std::unique_ptr<FoveationMethod> inst = make_method(method, mp);
    // An iso-budget target on display d: a run widens the resolved geometry, so the widened
    // keys are the solution's and the target is dropped (else predict would solve it again).
    const MappingSpec* spec = inst->mapping_spec();
    if (d && spec && spec->target_shaded_fraction() > 0) {
      const MappingSpec resolved = resolved_mapping_spec(*spec, *d);
      p.erase("target_shaded_fraction");
      resolved.geometry().widen_keys(k, p);
    } else {
      inst->widen_cost_keys(k, p);
    }
  } catch (const Error&) {
    return p;  // left as given: the analytic parse that follows reports the key and location
  }
  return p;
}

std::string lost_frame_method(const std::string& method, OnInvalid p) {
  return p == OnInvalid::Full ? full_resolution_method() : method;
}

double expected_ms_with_loss(double valid_ms, double lost_ms, double fraction) {
  return (1.0 - fraction) * valid_ms + fraction * lost_ms;
}

}  // namespace fovsim
