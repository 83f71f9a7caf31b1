// Constructors of every method, referenced only by the factory table in factory.cpp.
#pragma once
#include <memory>
#include <vector>

#include "sim/foveation/method.h"

namespace fovsim {

std::unique_ptr<FoveationMethod> create_full(Params& p);
const std::vector<ParamInfo>& full_params();
std::unique_ptr<FoveationMethod> create_flc(Params& p);
const std::vector<ParamInfo>& flc_params();

}  // namespace fovsim
