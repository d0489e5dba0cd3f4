#pragma once
// Opaque byte buffers for save()/restore(): the coupling loop looks ahead and rewinds
// (§4.3, §6), so every solver can copy its full state out and back, bit for bit.

#include <Eigen/Core>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "shellflow/sdk/error.hpp"

namespace shellflow::sdk {

using StateBuffer = std::vector<std::uint8_t>;

/// Appends plain values and Eigen matrices to a StateBuffer.
class StateWriter {
 public:
  explicit StateWriter(StateBuffer& buffer) : m_buffer(buffer) {}

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

  void write_bytes(const StateBuffer& bytes) {
    write<std::uint64_t>(bytes.size());
    append(bytes.data(), bytes.size());
  }
  /// The same length-prefixed block as write_bytes(), its bytes appended by `fill(*this)` in
  /// place: a solver's state is not built in a buffer of its own and then copied (a
  /// checkpoint of a large grid would hold its state twice).
  template <class Fill>
  void write_block(Fill&& fill) {
    const size_t at = m_buffer.size();
    write<std::uint64_t>(0);
    fill(*this);
    const std::uint64_t n = m_buffer.size() - at - sizeof(std::uint64_t);
    std::memcpy(m_buffer.data() + at, &n, sizeof n);
  }

 private:
  void append(const void* p, size_t n) {
    if (n == 0) return;
    const size_t old_size = m_buffer.size();
    m_buffer.resize(old_size + n);
    std::memcpy(m_buffer.data() + old_size, p, n);
  }
  StateBuffer& m_buffer;
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
