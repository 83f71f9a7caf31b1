// Collects sample problems that a skip/hold policy handled, so they are reported (as
// Trace::warnings) instead of silently changing the data.
#pragma once
#include <string>
#include <vector>

namespace fovsim {

class IssueLog {
 public:
  // `action` is what was done ("skipped", "held"), `kind` a short category used for grouping
  // ("not a number"), `where` the first location (file:line:col), `msg` the full message.
  void add(const std::string& action, const std::string& kind, const std::string& where,
           const std::string& msg);
  // One line per (action, kind): "12 samples skipped (not a number); first: f.csv:3:7: ...".
  std::vector<std::string> lines(const std::string& policy_name) const;
  long total() const;

 private:
  struct Group {
    std::string action, kind, first;
    long count = 0;
  };
  std::vector<Group> groups_;
};

}  // namespace fovsim
