// The main() of every test binary. ctest starts test binaries directly, not through the
// shellflow command, so they take its OpenMP wait policy themselves: a bounded spin unless
// the user chose one (ctest -j2 on two cores runs two tests of two threads each, and
// libgomp's default spin made the coupling tests many times slower).

#include <gtest/gtest.h>

#include "shellflow/runtime/openmp_wait_policy.hpp"

int main(int argc, char** argv) {
  shellflow::runtime::execute_again_with_bounded_spin(argv);
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
