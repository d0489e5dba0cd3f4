#include "shellflow/runtime/openmp_wait_policy.hpp"

#include <gtest/gtest.h>

#include <map>

namespace shellflow::runtime {

namespace {

/// An environment made of the given variables only.
EnvironmentLookup environment(std::map<std::string, std::string> variables) {
  return [variables = std::move(variables)](const char* name) -> const char* {
    const auto it = variables.find(name);
    return it == variables.end() ? nullptr : it->second.c_str();
  };
}

}  // namespace

TEST(OpenmpWaitPolicy, NoChoiceGetsTheBoundedSpinAndTheMarker) {
  const auto decision = decide_openmp_wait_policy(environment({}));
  EXPECT_TRUE(decision.execute_again);
  std::map<std::string, std::string> set(decision.environment.begin(), decision.environment.end());
  EXPECT_EQ(set["GOMP_SPINCOUNT"], kBoundedSpinCount);
  EXPECT_TRUE(set.count(kWaitPolicyMarker));
  // What the program executed again sees: the bounded spin, and no second execution.
  const auto again = environment(set);
  EXPECT_FALSE(decide_openmp_wait_policy(again).execute_again);
  EXPECT_TRUE(bounded_spin_in_effect(again));
  EXPECT_NE(describe_openmp_wait_policy(again).find("bounded spin"), std::string::npos);
}

TEST(OpenmpWaitPolicy, TheUsersChoiceIsKept) {
  for (const auto& user :
       std::vector<std::map<std::string, std::string>>{{{"OMP_WAIT_POLICY", "PASSIVE"}},
                                                       {{"OMP_WAIT_POLICY", "active"}},
                                                       {{"GOMP_SPINCOUNT", "infinite"}}}) {
    const auto env = environment(user);
    EXPECT_FALSE(decide_openmp_wait_policy(env).execute_again) << user.begin()->first;
    EXPECT_FALSE(bounded_spin_in_effect(env));
    const std::string said = user.begin()->first + "=" + user.begin()->second;
    EXPECT_NE(describe_openmp_wait_policy(env).find(said), std::string::npos);
  }
}

TEST(OpenmpWaitPolicy, TheMarkerAlonePreventsExecutingAgain) {
  // A user who wants libgomp's own default sets the marker to anything.
  const auto env = environment({{kWaitPolicyMarker, "off"}});
  EXPECT_FALSE(decide_openmp_wait_policy(env).execute_again);
  EXPECT_FALSE(bounded_spin_in_effect(env));
  EXPECT_NE(describe_openmp_wait_policy(env).find("libgomp's default"), std::string::npos);
}

TEST(OpenmpWaitPolicy, AUserPolicyBesideAnInheritedMarkerIsTheUsers) {
  // A child of a re-executed shellflow whose user then set OMP_WAIT_POLICY.
  auto variables = std::map<std::string, std::string>{};
  for (const auto& [name, value] : decide_openmp_wait_policy(environment({})).environment)
    variables[name] = value;
  variables["OMP_WAIT_POLICY"] = "PASSIVE";
  const auto env = environment(variables);
  EXPECT_FALSE(decide_openmp_wait_policy(env).execute_again);
  EXPECT_FALSE(bounded_spin_in_effect(env));
}

}  // namespace shellflow::runtime
