// Every method's name as a constant, generated from the registration list (method_list.h):
// a method's file names itself with `method_id::<name>` (KfrGeometry::kMethod =
// method_id::kfr), so each name is spelled once, in method_list.h.
#pragma once

namespace fovsim::method_id {

#define FOVSIM_METHOD(name, summary) inline constexpr const char name[] = #name;
#include "sim/foveation/method_list.h"
#undef FOVSIM_METHOD

}  // namespace fovsim::method_id
