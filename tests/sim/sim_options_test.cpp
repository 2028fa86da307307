// rigid-sim's command line: accepted forms and one-line errors naming the argument and value.
#include "sim/sim_options.hpp"

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "physics/integrator.hpp"

namespace rigid::sim {
namespace {

SimOptions parse(std::initializer_list<std::string_view> args) {
  const std::vector<std::string_view> v(args);
  return parse_options(v);
}

void expect_usage_error(std::initializer_list<std::string_view> args,
                        std::initializer_list<std::string_view> fragments) {
  try {
    parse(args);
    ADD_FAILURE() << "no error";
  } catch (const UsageError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    for (std::string_view f : fragments) {
      EXPECT_NE(what.find(f), std::string::npos) << "'" << f << "' not in: " << what;
    }
  }
}

TEST(SimOptions, Defaults) {
  const SimOptions o = parse({"scene.pbtxt"});
  EXPECT_EQ(o.scene, "scene.pbtxt");
  EXPECT_EQ(o.duration, 10.0);
  EXPECT_FALSE(o.integrator);
  EXPECT_FALSE(o.dt);
  EXPECT_FALSE(o.csv);
  EXPECT_FALSE(o.every);
  EXPECT_FALSE(o.help);
  EXPECT_FALSE(o.list_integrators);
}

TEST(SimOptions, EveryOptionInBothForms) {
  const std::string name(physics::all_integrators().front().name);
  for (bool with_equals : {false, true}) {
    std::vector<std::string> storage;
    const auto opt = [&](const std::string& name, const std::string& value) {
      if (with_equals) {
        storage.push_back(name + "=" + value);
      } else {
        storage.push_back(name);
        storage.push_back(value);
      }
    };
    opt("--duration", "2.5");
    opt("--integrator", name);
    opt("--dt", "1e-4");
    opt("--csv", "out.csv");
    opt("--every", "7");
    storage.push_back("s.pbtxt");
    const std::vector<std::string_view> args(storage.begin(), storage.end());
    const SimOptions o = parse_options(args);
    EXPECT_EQ(o.scene, "s.pbtxt");
    EXPECT_EQ(o.duration, 2.5);
    EXPECT_EQ(o.integrator, name);
    EXPECT_EQ(o.dt, 1e-4);
    EXPECT_EQ(o.csv, "out.csv");
    EXPECT_EQ(o.every, 7);
  }
}

TEST(SimOptions, HelpAndListNeedNoScene) {
  EXPECT_TRUE(parse({"--help"}).help);
  EXPECT_TRUE(parse({"-h"}).help);
  EXPECT_TRUE(parse({"--list-integrators"}).list_integrators);
}

TEST(SimOptions, DoubleDashEndsOptions) {
  EXPECT_EQ(parse({"--", "--weird-name.pbtxt"}).scene, "--weird-name.pbtxt");
}

TEST(SimOptions, DurationZeroIsAllowed) {
  EXPECT_EQ(parse({"s", "--duration", "0"}).duration, 0.0);
}

TEST(SimOptions, Errors) {
  expect_usage_error({}, {"scene"});
  expect_usage_error({"a.pbtxt", "b.pbtxt"}, {"'b.pbtxt'", "'a.pbtxt'"});
  expect_usage_error({"s", "--frobnicate"}, {"'--frobnicate'"});
  expect_usage_error({"s", "--frobnicate=3"}, {"'--frobnicate'"});
  expect_usage_error({"s", "--duration"}, {"--duration", "value"});
  expect_usage_error({"s", "--duration", "ten"}, {"--duration", "'ten'"});
  expect_usage_error({"s", "--duration", "-1"}, {"--duration", "'-1'"});
  expect_usage_error({"s", "--duration", "inf"}, {"--duration", "'inf'"});
  expect_usage_error({"s", "--duration", "nan"}, {"--duration", "'nan'"});
  expect_usage_error({"s", "--duration=1s"}, {"--duration", "'1s'"});
  expect_usage_error({"s", "--duration="}, {"--duration", "''"});
  expect_usage_error({"s", "--dt", "0"}, {"--dt", "'0'"});
  expect_usage_error({"s", "--dt", "-1e-3"}, {"--dt", "'-1e-3'"});
  expect_usage_error({"s", "--every", "0"}, {"--every", "'0'"});
  expect_usage_error({"s", "--every", "2.5"}, {"--every", "'2.5'"});
  expect_usage_error({"s", "--every", "99999999999999999999"}, {"--every"});
  expect_usage_error({"s", "--csv="}, {"--csv"});
  const std::string def(physics::default_integrator().name);
  expect_usage_error({"s", "--integrator", "euler-magic"}, {"--integrator", "'euler-magic'", def});
}

TEST(SimOptions, UsageMentionsEveryOption) {
  const std::string u = usage();
  for (const char* o :
       {"--duration", "--integrator", "--dt", "--csv", "--every", "--list-integrators", "--help"}) {
    EXPECT_NE(u.find(o), std::string::npos) << o;
  }
}

}  // namespace
}  // namespace rigid::sim
