#pragma once
// Opaque byte buffers for save()/restore(): the coupling loop looks ahead and rewinds
// (§4.3, §6), so every solver can copy its full state out and back, bit for bit.

#include <Eigen/Core>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include "shellflow/sdk/error.hpp"

namespace shellflow::sdk {

using StateBuffer = std::vector<std::uint8_t>;

/// What a save() writes, measured without writing it: its length and the length of each
/// of its write_block()s, in call order (the first pass of a streamed write).
struct StateSizes {
  std::uint64_t bytes = 0;
  std::vector<std::uint64_t> blocks;
};

/// Appends plain values and Eigen matrices to a StateBuffer — or, for a checkpoint of a
/// large grid, measures them (StateSizes) and then streams them to a sink in a second,
/// identical pass, so that the state is never held in memory a second time.
class StateWriter {
 public:
  using Sink = std::function<void(const std::uint8_t*, size_t)>;

  explicit StateWriter(StateBuffer& buffer) : m_buffer(&buffer) {}
  /// Writes nothing; records the lengths a later streamed pass needs.
  explicit StateWriter(StateSizes& sizes) : m_sizes(&sizes) {}
  /// Hands every byte to `sink` in order, each block's length taken from `sizes` (the
  /// counting pass of the same save()); throws if the save writes other lengths.
  StateWriter(Sink sink, const StateSizes& sizes) : m_sink(std::move(sink)), m_known(&sizes) {}

  template <class T>
    requires std::is_trivially_copyable_v<T>
  void write(const T& value) {
    append(&value, sizeof(T));
  }

  template <class Derived>
  void write_matrix(const Eigen::PlainObjectBase<Derived>& m) {
    write<std::int64_t>(m.rows());
    write<std::int64_t>(m.cols());
    append(m.data(), sizeof(typename Derived::Scalar) * static_cast<size_t>(m.size()));
  }

  /// The bytes write_matrix() writes for an n x 1 column, from memory the caller keeps
  /// (no Eigen copy of a grid-sized array).
  template <class T>
  requires std::is_arithmetic_v<T>
  void write_column(const T* values, std::int64_t n) {
    write<std::int64_t>(n);
    write<std::int64_t>(1);
    append(values, sizeof(T) * static_cast<size_t>(n));
  }

  void write_bytes(const StateBuffer& bytes) {
    write<std::uint64_t>(bytes.size());
    append(bytes.data(), bytes.size());
  }
  /// The same length-prefixed block as write_bytes(), its bytes appended by `fill(*this)` in
  /// place: a solver's state is not built in a buffer of its own and then copied (a
  /// checkpoint of a large grid would hold its state twice).
  template <class Fill>
  void write_block(Fill&& fill) {
    if (m_buffer != nullptr) {
      const size_t at = m_buffer->size();
      write<std::uint64_t>(0);
      fill(*this);
      const std::uint64_t n = m_buffer->size() - at - sizeof(std::uint64_t);
      std::memcpy(m_buffer->data() + at, &n, sizeof n);
    } else if (m_sizes != nullptr) {
      const size_t index = m_sizes->blocks.size();
      m_sizes->blocks.push_back(0);
      write<std::uint64_t>(0);
      const std::uint64_t start = m_count;
      fill(*this);
      m_sizes->blocks[index] = m_count - start;
    } else {
      if (m_next_block >= m_known->blocks.size())
        throw Error("save(): more blocks in the streamed pass than in the counting pass");
      const std::uint64_t n = m_known->blocks[m_next_block++];
      write<std::uint64_t>(n);
      const std::uint64_t start = m_count;
      fill(*this);
      if (m_count - start != n)
        throw Error(
            "save(): a block changed length between the counting and the streamed "
            "pass (" +
            std::to_string(n) + " then " + std::to_string(m_count - start) + " bytes)");
    }
  }

  /// Bytes written (or counted) so far.
  std::uint64_t size() const { return m_buffer != nullptr ? m_buffer->size() : m_count; }

 private:
  void append(const void* p, size_t n) {
    if (n == 0) return;
    if (m_buffer != nullptr) {
      const size_t old_size = m_buffer->size();
      m_buffer->resize(old_size + n);
      std::memcpy(m_buffer->data() + old_size, p, n);
      return;
    }
    if (m_sink) m_sink(static_cast<const std::uint8_t*>(p), n);
    m_count += n;
    if (m_sizes != nullptr) m_sizes->bytes = m_count;
  }
  StateBuffer* m_buffer = nullptr;
  StateSizes* m_sizes = nullptr;
  Sink m_sink;
  const StateSizes* m_known = nullptr;
  std::uint64_t m_count = 0;
  size_t m_next_block = 0;
};

/// Reads back what a StateWriter wrote, in the same order; throws on a short buffer.
class StateReader {
 public:
  explicit StateReader(const StateBuffer& buffer) : m_buffer(buffer) {}

  template <class T>
    requires std::is_trivially_copyable_v<T>
  T read() {
    T value;
    take(&value, sizeof(T));
    return value;
  }

  template <class Derived>
  void read_matrix(Eigen::PlainObjectBase<Derived>& m) {
    const auto rows = read<std::int64_t>();
    const auto cols = read<std::int64_t>();
    m.resize(rows, cols);
    take(m.data(), sizeof(typename Derived::Scalar) * static_cast<size_t>(m.size()));
  }

  StateBuffer read_bytes() {
    const auto n = read<std::uint64_t>();
    StateBuffer out(n);
    take(out.data(), n);
    return out;
  }

  bool at_end() const { return m_offset == m_buffer.size(); }

 private:
  void take(void* p, size_t n) {
    if (m_offset + n > m_buffer.size())
      throw Error("restore(): state buffer is shorter than the state it should hold (" +
                  std::to_string(m_buffer.size()) + " bytes); it was saved by another solver");
    if (n > 0) std::memcpy(p, m_buffer.data() + m_offset, n);
    m_offset += n;
  }
  const StateBuffer& m_buffer;
  size_t m_offset = 0;
};

}  // namespace shellflow::sdk
