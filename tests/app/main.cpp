// test_app main: GoogleTest plus `--update-golden`, which rewrites the committed goldens
// from the current build instead of comparing (an explicit, reviewed step).
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

bool g_update_golden = false;

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  // `fovsim run` makes plots by default when matplotlib is present; the CLI tests do not need
  // them (sim/experiment/plots.h). Tests of the plots unset it for their own command.
  setenv("FOVSIM_NO_PLOTS", "1", 0);
  // Nor do they read or write the user's reference cache (sim/experiment/reference_cache.h);
  // the tests of the cache give their own folder and unset this for their command.
  setenv("FOVSIM_NO_CACHE", "1", 0);
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--update-golden") == 0) g_update_golden = true;
  return RUN_ALL_TESTS();
}
