// The renderer's keys of the `render` block read their own declared defaults and ranges.
#include <gtest/gtest.h>

#include "sim/render/renderer.h"
#include "tests/common/param_table_check.h"

TEST(RenderSettingsDecl, TableReadsItsOwnDefaults) {
  fovsim::table_check::expect_table_reads_own_defaults(fovsim::render_settings_table(), "render");
}
