// The one explicit factory (DESIGN §5: no static self-registration).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "sim/foveation/method.h"

namespace fovsim {

struct MethodEntry {
  const char* name;
  const char* summary;
  std::unique_ptr<FoveationMethod> (*create)(Params& p);
  const std::vector<ParamInfo>& (*params)();
};

const std::vector<MethodEntry>& method_table();
// Creates a method by name from its parameter block; unknown names and keys are errors.
std::unique_ptr<FoveationMethod> make_method(const std::string& name, Params& p);

}  // namespace fovsim
