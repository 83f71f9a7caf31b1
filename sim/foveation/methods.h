// Constructors and parameter declarations of every method (method_list.h), referenced only
// by the factory table in factory.cpp.
#pragma once
#include <memory>
#include <vector>

#include "sim/foveation/method.h"
#include "sim/foveation/method_cost.h"
#include "sim/foveation/method_ids.h"

namespace fovsim {

#define FOVSIM_METHOD(name, summary)                         \
  std::unique_ptr<FoveationMethod> create_##name(Params& p); \
  const std::vector<ParamInfo>& name##_params();             \
  const MethodCost& name##_cost();
#include "sim/foveation/method_list.h"
#undef FOVSIM_METHOD

}  // namespace fovsim
