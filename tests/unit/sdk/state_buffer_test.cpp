#include "shellflow/sdk/state_buffer.hpp"

#include <gtest/gtest.h>

#include <vector>

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

// A checkpoint measures its state (StateSizes) and then streams it: the streamed bytes are
// the buffered ones exactly, nested blocks included, and a save that writes a different
// length the second time is caught rather than written with a wrong length prefix.
TEST(StateBuffer, CountedThenStreamedBytesEqualTheBufferedOnes) {
  const std::vector<double> column = {1.5, -2.0, 3.25, 1e-300};
  Eigen::MatrixXd m(2, 3);
  m << 1, 2, 3, 4, 5, 6;
  int extra = 0;  // grows the inner block when set
  const auto save = [&](StateWriter& out) {
    out.write<int>(7);
    out.write_block([&](StateWriter& w) {
      w.write_matrix(m);
      w.write_block([&](StateWriter& inner) {
        inner.write_column(column.data(), static_cast<std::int64_t>(column.size()));
        for (int i = 0; i < extra; ++i) inner.write<double>(0.5);
      });
      w.write<std::uint8_t>(3);
    });
    out.write_bytes(StateBuffer{9, 8, 7});
  };
  StateBuffer buffered;
  StateWriter direct(buffered);
  save(direct);

  StateSizes sizes;
  StateWriter count(sizes);
  save(count);
  EXPECT_EQ(sizes.bytes, buffered.size());
  ASSERT_EQ(sizes.blocks.size(), 2u);
  EXPECT_EQ(sizes.blocks[1], 8u * 2 + 8u * column.size());  // the inner block: its column

  StateBuffer streamed;
  StateWriter out(
      [&](const std::uint8_t* p, size_t n) { streamed.insert(streamed.end(), p, p + n); }, sizes);
  save(out);
  EXPECT_EQ(streamed, buffered);

  // The column reads back as the matrix it is written as.
  StateReader r(buffered);
  EXPECT_EQ(r.read<int>(), 7);
  r.read<std::uint64_t>();
  Eigen::MatrixXd back;
  r.read_matrix(back);
  EXPECT_EQ(back, m);
  r.read<std::uint64_t>();
  Eigen::VectorXd col;
  r.read_matrix(col);
  EXPECT_EQ(col, Eigen::Map<const Eigen::VectorXd>(column.data(), 4));

  extra = 1;
  StateWriter changed([](const std::uint8_t*, size_t) {}, sizes);
  EXPECT_THROW(save(changed), Error);
}

}  // namespace shellflow::sdk
