#include "shellflow/runtime/openmp_wait_policy.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace shellflow::runtime {

namespace {

constexpr const char* kWaitPolicy = "OMP_WAIT_POLICY";
constexpr const char* kSpinCount = "GOMP_SPINCOUNT";
/// The marker's value when shellflow set the bounded spin (any other value: the user's).
constexpr const char* kMarkerBoundedSpin = "bounded-spin";

bool is_set(const EnvironmentLookup& lookup, const char* name) {
  return lookup(name) != nullptr;
}

}  // namespace

OpenmpWaitDecision decide_openmp_wait_policy(const EnvironmentLookup& lookup) {
  OpenmpWaitDecision decision;
  if (is_set(lookup, kWaitPolicy) || is_set(lookup, kSpinCount) ||
      is_set(lookup, kWaitPolicyMarker))
    return decision;
  decision.execute_again = true;
  decision.environment = {{kSpinCount, kBoundedSpinCount}, {kWaitPolicyMarker, kMarkerBoundedSpin}};
  return decision;
}

bool bounded_spin_in_effect(const EnvironmentLookup& lookup) {
  const char* marker = lookup(kWaitPolicyMarker);
  return marker != nullptr && std::strcmp(marker, kMarkerBoundedSpin) == 0 &&
         !is_set(lookup, kWaitPolicy) && is_set(lookup, kSpinCount);
}

std::string describe_openmp_wait_policy(const EnvironmentLookup& lookup) {
  if (bounded_spin_in_effect(lookup))
    return std::string("shellflow's bounded spin: ") + kSpinCount + "=" + lookup(kSpinCount) +
           " (threads spin briefly at barriers, then sleep; set " + kWaitPolicy + " or " +
           kSpinCount + " to choose another)";
  std::string chosen;
  for (const char* name : {kWaitPolicy, kSpinCount})
    if (const char* value = lookup(name))
      chosen += (chosen.empty() ? "" : ", ") + std::string(name) + "=" + value;
  if (!chosen.empty()) return chosen + " as set in the environment";
  return std::string(
             "libgomp's default (spins a few ms at barriers: slow beside other busy "
             "processes); ") +
         (is_set(lookup, kWaitPolicyMarker) ? std::string(kWaitPolicyMarker) + " is set"
                                            : "not started through the shellflow command");
}

EnvironmentLookup process_environment() {
  return [](const char* name) -> const char* { return std::getenv(name); };
}

void execute_again_with_bounded_spin(char** argv) {
  const auto decision = decide_openmp_wait_policy(process_environment());
  if (!decision.execute_again) return;
  for (const auto& [name, value] : decision.environment)
    ::setenv(name.c_str(), value.c_str(), /*overwrite=*/1);
  ::execv("/proc/self/exe", argv);
  // Still here: the run goes on with libgomp's default, which the marker now misnames.
  const int error = errno;
  ::unsetenv(kSpinCount);
  ::unsetenv(kWaitPolicyMarker);
  spdlog::warn(
      "could not execute /proc/self/exe again with {}={} ({}): OpenMP threads spin "
      "at barriers with libgomp's default; on a busy machine set "
      "OMP_WAIT_POLICY=PASSIVE",
      kSpinCount, kBoundedSpinCount, std::strerror(error));
}

}  // namespace shellflow::runtime
