#include "shellflow/sdk/state_buffer.hpp"

#include <gtest/gtest.h>

#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::sdk {

TEST(StateBuffer, RoundTripsValuesAndMatricesBitForBit) {
  Positions p(3, 3);
  p << 0.1, 0.2, 0.3, 1e-300, -0.0, 7.0 / 3.0, 1, 2, 3;
  StateBuffer buffer;
  StateWriter w(buffer);
  w.write(42);
  w.write(0.1 + 0.2);
  w.write_matrix(p);

  StateReader r(buffer);
  EXPECT_EQ(r.read<int>(), 42);
  EXPECT_EQ(r.read<double>(), 0.1 + 0.2);  // exact: bytes are copied
  Positions q;
  r.read_matrix(q);
  ASSERT_EQ(q.rows(), 3);
  EXPECT_EQ(std::memcmp(p.data(), q.data(), sizeof(double) * 9), 0);
  EXPECT_TRUE(r.at_end());
  EXPECT_THROW(r.read<int>(), Error);  // reading past the end is an error, not garbage
}

}  // namespace shellflow::sdk
