// The one check of numeric flags (flags.h): the Range::contains and message of a config key
// (Params::number, check_number), with the unit and the meaning of 0 added.
#include "sim/app/flags.h"

#include <algorithm>
#include <cmath>

#include "sim/core/error.h"
#include "sim/core/message_text.h"

namespace fovsim::app {

namespace {
constexpr double kMaxExactInteger = 9007199254740992.0;  // 2^53
}

std::string number_flag_text(const NumberFlag& f) {
  Range r = f.range;
  if (f.integer) r.lo = std::max(r.lo, -kMaxExactInteger), r.hi = std::min(r.hi, kMaxExactInteger);
  std::string s = r.str() + (f.unit.empty() ? "" : " " + f.unit);
  if (!f.zero.empty()) s += " (0: " + f.zero + ")";
  return s;
}

std::string check_number_flag(std::string& text, const NumberFlag& f) {
  double v = 0;
  if (!CLI::detail::lexical_cast(text, v))
    return "value \"" + escape_control(text, 80) + "\" is not " +
           (f.integer ? "an integer" : "a number") + " in " + number_flag_text(f);
  if (!f.zero.empty() && v == 0) {
    text = "0";
    return "";
  }
  if (!f.range.contains(v))
    return "value " + shortest_number(v) + " is out of range " + number_flag_text(f);
  if (f.integer) {
    if (v != std::floor(v) || std::fabs(v) > kMaxExactInteger)
      return "value " + shortest_number(v) + " is not an integer in " + number_flag_text(f);
    text = std::to_string(static_cast<long long>(v));  // "1e3" -> "1000" for CLI11's int read
  }
  return "";
}

}  // namespace fovsim::app
