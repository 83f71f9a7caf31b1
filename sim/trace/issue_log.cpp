#include "sim/trace/issue_log.h"

namespace fovsim {

void IssueLog::add(const std::string& action, const std::string& kind, const std::string& where,
                   const std::string& msg) {
  for (auto& g : groups_)
    if (g.action == action && g.kind == kind) {
      ++g.count;
      return;
    }
  groups_.push_back({action, kind, where + ": " + msg, 1});
}

std::vector<std::string> IssueLog::lines(const std::string& policy_name) const {
  std::vector<std::string> out;
  for (auto& g : groups_)
    out.push_back(std::to_string(g.count) + (g.count == 1 ? " sample " : " samples ") + g.action +
                  " (" + g.kind + ", " + policy_name + "); first: " + g.first);
  return out;
}

long IssueLog::total() const {
  long n = 0;
  for (auto& g : groups_) n += g.count;
  return n;
}

}  // namespace fovsim
