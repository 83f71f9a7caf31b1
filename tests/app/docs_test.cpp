// The method tables in docs/methods.md and configs/README.md are the ones generated from the
// methods' declarations (`fovsim methods --markdown`); regenerate with `make docs`.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "sim/foveation/factory.h"

namespace {
std::string generated_section(const std::string& rel) {
  std::ifstream f(std::string(FOVSIM_SOURCE_DIR) + "/" + rel);
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string s = ss.str();
  auto b = s.find(fovsim::kMethodDocsBegin);
  auto e = s.find(fovsim::kMethodDocsEnd);
  if (b == std::string::npos || e == std::string::npos || e < b)
    return "<markers missing in " + rel + ">";
  b = s.find('\n', b) + 1;
  return s.substr(b, e - b);
}
}  // namespace

TEST(Docs, MethodTablesMatchDeclarations) {
  const std::string want = "\n" + fovsim::methods_markdown();
  for (const char* f : {"docs/methods.md", "configs/README.md"})
    EXPECT_EQ(generated_section(f), want) << f << " differs from the declarations: run `make docs`";
}
