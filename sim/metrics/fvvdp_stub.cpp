#include <cmath>

#include "sim/metrics/fvvdp.h"

namespace fovsim {
double fvvdp_jod_from_q(double q) {
  return 10.0 - 0.0161713 * std::pow(q, std::pow(10.0, -0.228));
}
}  // namespace fovsim
