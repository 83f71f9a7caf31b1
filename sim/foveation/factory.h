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

// A method with parameters on the command line, in the one syntax every command accepts:
// "kfr", "kfr:sigma=1.8,alpha=4" (the keys of the method's config block; values are JSON,
// else strings). The name is checked against the factory table; keys are checked by whoever
// builds the method from `params` (make_method, analytic_counters). `flag` names the option
// in errors (e.g. "--method").
struct MethodArg {
  std::string text, name;
  Json params = Json::object();
};
MethodArg parse_method_arg(const std::string& text, const std::string& flag);

}  // namespace fovsim
