// The `trace` and `trace.synthetic` tables read their own declared defaults and ranges.
#include "sim/trace/trace_keys.h"

#include <gtest/gtest.h>

#include "sim/trace/synth.h"
#include "tests/common/param_table_check.h"

using namespace fovsim;

TEST(TraceKeys, EveryTableReadsItsOwnDefaults) {
  TraceBlock b;
  b.rate_hz = 72;  // the display's refresh rate, set by load_trace
  table_check::expect_table_reads_own_defaults(trace_block_table(), "trace", b);
  SynthBlock s;
  s.duration = 3;  // trace.start + trace.duration, set by load_trace
  table_check::expect_table_reads_own_defaults(synth_block_table(), "trace.synthetic", s);
}

// The eye model (trace.synthetic.params): one table per section of models/eyemodel/default.json.
TEST(TraceKeys, EyeModelTablesReadTheirOwnDefaults) {
  for (auto& sec : eye_model_tables()) {
    std::string path = std::string("trace.synthetic.params.") + sec.path;
    for (char& ch : path)
      if (ch == '/') ch = '.';
    table_check::expect_table_reads_own_defaults(sec.table, path, EyeModel{});
  }
}

TEST(TraceKeys, DefaultsTheCallerSetsAreKept) {
  Params p(Json::object(), "run.json", "");
  TraceBlock b;
  b.rate_hz = 72;
  trace_block_table().read_into(p, b);
  EXPECT_EQ(b.rate_hz, 72);
  EXPECT_EQ(p.resolved()["rate_hz"], 72);
}

TEST(TraceKeys, SyntheticSeedMustBeAnInteger) {
  Params p(Json{{"scenario", "reading"}, {"seed", 1.5}}, "run.json", "trace.synthetic");
  try {
    synth_block_table().read(p);
    ADD_FAILURE() << "seed 1.5 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("run.json: trace.synthetic.seed"), std::string::npos)
        << e.what();
  }
}

TEST(TraceKeys, MapIsReadOnlyWithAFile) {
  // With `synthetic`, a `map` is not read, so Params::finish() reports it as unknown.
  Params p(Json{{"synthetic", Json::object()}, {"map", "m.json"}}, "run.json", "trace");
  TraceBlock b;
  trace_block_table().read_into(p, b);
  EXPECT_TRUE(b.map.empty());
  p.ignore("synthetic");
  EXPECT_THROW(p.finish(), Error);
}
