#pragma once
#include <string>

namespace fovsim {
std::string version_string();  // e.g. "0.1.0"
// Short commit hash at build time ("-dirty-<8 hex of the diff>": local changes), or "unknown".
std::string git_commit();
}  // namespace fovsim
