#include "sim/experiment/cell_tracking.h"

#include "sim/core/params.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/lighting.h"

namespace fovsim {

FoveationMethod& TrackingSwap::full_method() {
  if (!full) {
    Params fp(Json::object(), "trace.on_invalid");
    full = make_method("full", fp);
  }
  return *full;
}

FoveationMethod& TrackingSwap::select(FoveationMethod& impl, const std::string& method,
                                      bool render_full) {
  if (render_full && method != "full") {
    was_full = true;
    return full_method();
  }
  if (was_full) {
    impl.restart();
    was_full = false;
  }
  return impl;
}

}  // namespace fovsim
