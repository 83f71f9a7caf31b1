// A GPU profile's `spec` block reads its own declared defaults and ranges (required keys need
// a value; the others default), and profile files write the declared keys.
#include <gtest/gtest.h>

#include "sim/cost/gpu_profile.h"
#include "tests/common/param_table_check.h"

TEST(GpuSpecDecl, TableReadsItsOwnDefaults) {
  fovsim::table_check::expect_table_reads_own_defaults(fovsim::gpu_spec_table(), "spec");
  fovsim::Params p(fovsim::Json::object(), "gpu.json", "spec");
  try {
    fovsim::gpu_spec_table().read(p);
    ADD_FAILURE() << "a spec without fp32_gflops was accepted";
  } catch (const fovsim::Error& e) {
    EXPECT_NE(std::string(e.what()).find("spec.fp32_gflops"), std::string::npos) << e.what();
  }
}
