#pragma once
// How long OpenMP threads spin at a barrier before they sleep, chosen for the user.
//
// libgomp's default spins about 300,000 times (a few milliseconds) at every barrier. On a
// machine where another process holds a core, the spinning thread keeps its core from the
// thread it waits for, and a step takes many times longer (issue 17: a 6 s test ran for
// more than 4.5 minutes beside one busy process). OMP_WAIT_POLICY=PASSIVE cures that but
// costs the quiet machine a third of its speed (64^3 plume 0.055 against 0.080 s/step):
// waking a sleeping thread costs more than a short spin. A bounded spin keeps both.
//
// libgomp reads OMP_WAIT_POLICY and GOMP_SPINCOUNT once, when it is loaded, before main():
// so a program sets the bounded spin in its environment and executes itself again.

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace shellflow::runtime {

/// GOMP_SPINCOUNT that shellflow sets when the user chose no wait policy: about 10 us of
/// spinning (libgomp's estimate: 100,000 spins per ms) before a thread sleeps. Beside one
/// busy process 1,000 was as fast as PASSIVE, 3,000 and 10,000 up to 3x slower; README
/// "Measured figures" (OpenMP wait policy) has the figures.
inline constexpr const char* kBoundedSpinCount = "1000";

/// Set in the environment of the program executed again (and inherited by its children):
/// never execute twice. A user may set it to keep libgomp's own default.
inline constexpr const char* kWaitPolicyMarker = "SHELLFLOW_OPENMP_WAIT";

/// The environment as a program sees it: the value of a variable, or null when unset.
using EnvironmentLookup = std::function<const char*(const char* name)>;

/// What to do about the wait policy before OpenMP starts.
struct OpenmpWaitDecision {
  /// Set `environment` and execute the program again: the user chose no policy.
  bool execute_again = false;
  /// Variables (name, value) to set before executing again.
  std::vector<std::pair<std::string, std::string>> environment;
};

/// The user's OMP_WAIT_POLICY or GOMP_SPINCOUNT, when either is set, is kept; the marker
/// (set by an earlier execution or by the user) prevents a second one; otherwise the bounded
/// spin and the marker.
OpenmpWaitDecision decide_openmp_wait_policy(const EnvironmentLookup& lookup);

/// The wait policy in effect for a process with this environment, in words (run.json's plan
/// and the log).
std::string describe_openmp_wait_policy(const EnvironmentLookup& lookup);

/// Whether shellflow's bounded spin is the policy in effect.
bool bounded_spin_in_effect(const EnvironmentLookup& lookup);

/// The process environment (std::getenv).
EnvironmentLookup process_environment();

/// Call first thing in main(), before any OpenMP region: when the user chose no wait policy,
/// sets the bounded spin and executes /proc/self/exe again with the same arguments (it does
/// not return then). Returns when nothing is to be done, or when the execution fails (the
/// program then runs with libgomp's default; a note on stderr says so).
void execute_again_with_bounded_spin(char** argv);

}  // namespace shellflow::runtime
