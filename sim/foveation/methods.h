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
std::unique_ptr<FoveationMethod> create_kfr(Params& p);
const std::vector<ParamInfo>& kfr_params();
std::unique_ptr<FoveationMethod> create_rmfr(Params& p);
const std::vector<ParamInfo>& rmfr_params();
std::unique_ptr<FoveationMethod> create_hyperbolic(Params& p);
const std::vector<ParamInfo>& hyperbolic_params();
std::unique_ptr<FoveationMethod> create_linear(Params& p);
const std::vector<ParamInfo>& linear_params();
std::unique_ptr<FoveationMethod> create_fvrs(Params& p);
const std::vector<ParamInfo>& fvrs_params();
std::unique_ptr<FoveationMethod> create_twfr(Params& p);
const std::vector<ParamInfo>& twfr_params();

}  // namespace fovsim
