// test_app main: GoogleTest plus `--update-golden`, which rewrites the committed goldens
// from the current build instead of comparing (an explicit, reviewed step).
#include <gtest/gtest.h>

#include <cstring>

bool g_update_golden = false;

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--update-golden") == 0) g_update_golden = true;
  return RUN_ALL_TESTS();
}
