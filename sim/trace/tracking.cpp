#include "sim/trace/tracking.h"

#include <iterator>

namespace fovsim {

namespace {
// The one list of policies, in the order of the enum (tracking.h).
constexpr OnInvalid kPolicies[] = {OnInvalid::Hold, OnInvalid::Centre, OnInvalid::Full,
                                   OnInvalid::Widen};
constexpr const char* kPolicyNames[] = {"hold", "centre", "full", "widen"};
static_assert(sizeof(kPolicies) / sizeof(kPolicies[0]) ==
              sizeof(kPolicyNames) / sizeof(kPolicyNames[0]));
}  // namespace

const std::vector<std::string>& on_invalid_choices() {
  static const std::vector<std::string> names(std::begin(kPolicyNames), std::end(kPolicyNames));
  return names;
}

bool parse_on_invalid(const std::string& s, OnInvalid& out) {
  for (size_t i = 0; i < std::size(kPolicies); ++i)
    if (s == kPolicyNames[i]) {
      out = kPolicies[i];
      return true;
    }
  return false;
}

const char* on_invalid_name(OnInvalid p) {
  for (size_t i = 0; i < std::size(kPolicies); ++i)
    if (p == kPolicies[i]) return kPolicyNames[i];
  return kPolicyNames[0];
}

TrackedGaze tracked_gaze(const Trace& trace, size_t i, const TrackingPolicy& p) {
  TrackedGaze g;
  const auto& x = trace.samples;
  if (i >= x.size()) return g;
  if (x[i].valid) {
    g.gaze_dir = x[i].gaze_dir;
    return g;
  }
  g.valid = false;
  // The last valid sample at or before i (a run is short: a backward scan is cheap enough,
  // and keeps the function free of state).
  size_t k = i;
  while (k > 0 && !x[k].valid) --k;
  const bool any = x[k].valid;
  g.since_valid_s = x[i].t - x[k].t;
  const glm::dvec3 held = any ? x[k].gaze_dir : glm::dvec3(0, 0, -1);
  switch (p.on_invalid) {
    case OnInvalid::Hold:
      g.gaze_dir = held;
      g.state = "held";
      break;
    case OnInvalid::Centre:
      g.gaze_dir = glm::dvec3(0, 0, -1);
      g.state = "lost";
      break;
    case OnInvalid::Full:
      g.gaze_dir = held;
      g.state = "held";
      g.render_full = true;
      break;
    case OnInvalid::Widen:
      g.gaze_dir = held;
      g.state = "held";
      g.widen = 1.0 + p.widen_per_s * g.since_valid_s;
      g.ecc_scale = 1.0 / g.widen;
      break;
  }
  return g;
}

}  // namespace fovsim
