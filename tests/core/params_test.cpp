#include "sim/core/params.h"

#include <gtest/gtest.h>

#include "sim/core/error.h"

using namespace fovsim;

TEST(Params, ReadsValuesAndRecordsDefaults) {
  Params p(Json::parse(R"({"sigma": 2.5, "sub": {"n": 3}})"), "cfg.json");
  EXPECT_DOUBLE_EQ(p.number("sigma", 1.8, Range::at_least(1)), 2.5);
  EXPECT_DOUBLE_EQ(p.number("alpha", 4.0, Range::above(0)), 4.0);
  Params s = p.child("sub");
  EXPECT_EQ(s.integer("n", 1, Range::closed(0, 10)), 3);
  EXPECT_NO_THROW(p.finish());
  EXPECT_DOUBLE_EQ(p.resolved()["alpha"].get<double>(), 4.0);
  EXPECT_EQ(p.resolved()["sub"]["n"].get<int>(), 3);
}

TEST(Params, UnknownKeyNamesPath) {
  Params p(Json::parse(R"({"methods": [{"sigma": 2, "sigmma": 3}]})"), "cfg.json");
  auto ms = p.children("methods");
  ms[0].number("sigma", 1.0);
  try {
    p.finish();
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "cfg.json: methods[0].sigmma: unknown key \"sigmma\" (did you mean \"sigma\"?)");
  }
  // No known key close to it: the old hint.
  Params q(Json{{"zzzzzz", 1}}, "cfg.json");
  q.number("sigma", 1.0);
  try {
    q.finish();
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "cfg.json: zzzzzz: unknown key \"zzzzzz\" (not a parameter here; check spelling)");
  }
}

TEST(Params, WrongTypeAndRange) {
  Params p(Json::parse(R"({"sigma": "big", "alpha": 0, "n": 2.5})"), "c.json");
  EXPECT_THROW(
      {
        try {
          p.number("sigma", 1.0, Range::at_least(1));
        } catch (const Error& e) {
          EXPECT_NE(std::string(e.what()).find(
                        "c.json: sigma: expected a number in [1, 1e+300], got a string \"big\""),
                    std::string::npos)
              << e.what();
          throw;
        }
      },
      Error);
  try {
    p.number("alpha", 1.0, Range::above(0));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "c.json: alpha: value 0 is out of range (0, 1e+300]");
  }
  EXPECT_THROW(p.integer("n", 1), Error);
}

TEST(Params, Overrides) {
  Json j = Json::parse(R"({"a": {"b": [ {"c": 1} ]}, "s": "x"})");
  apply_override(j, "a.b[0].c=2.5");
  apply_override(j, "s=hello");
  apply_override(j, "new.key=true");
  EXPECT_DOUBLE_EQ(j["a"]["b"][0]["c"].get<double>(), 2.5);
  EXPECT_EQ(j["s"], "hello");
  EXPECT_EQ(j["new"]["key"], true);
  EXPECT_THROW(apply_override(j, "a.b[3].c=1"), Error);
  EXPECT_THROW(apply_override(j, "novalue"), Error);
}

// Values written by a "base" file: errors name that file, relative paths resolve in its folder,
// and a command-line override of the same key is the user's again.
TEST(Params, InheritedValuesNameTheirFile) {
  Params p(Json{{"trace", {{"file", "t.csv"}}}, {"methods", Json::array({{{"sigma", -1}}})}},
           "dir/child.json");
  p.set_inherited({{"trace.file", "/repo/configs/base.json"}, {"methods", "../b.json"}});
  Params t = p.child("trace");
  EXPECT_EQ(t.where("file"), "dir/child.json: trace.file (inherited from /repo/configs/base.json)");
  EXPECT_EQ(t.source_dir("file"), "/repo/configs");
  auto ms = p.children("methods");
  EXPECT_EQ(ms[0].where("sigma"), "dir/child.json: methods[0].sigma (inherited from ../b.json)");
  EXPECT_EQ(p.source_dir("scene"), "");  // written by the config itself
  p.set_origins({{"trace.file", "trace.file=x.csv"}});
  EXPECT_EQ(t.source_dir("file"), "");
}
