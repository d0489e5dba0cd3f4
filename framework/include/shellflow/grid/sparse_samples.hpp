#pragma once
// SparseSamples: values of a grid field at a few of its samples (the nodes near a shell),
// addressed by the samples' flat grid indices like a full array, but stored compactly: a
// 4-byte slot per grid sample and one value per inserted sample. For the per-step
// scratch of work that only happens near shells (the swept-node refill, the §5.1 jumps
// spread to the nodes), where a full array of doubles per component costs memory in
// proportion to the whole grid (168 MB of node samples at Fig. 2's 4.2M nodes).

#include <cstdint>
#include <span>
#include <vector>

namespace shellflow::grid {

template <class T>
class SparseSamples {
 public:
  /// Makes room for grid indices [0, size) and forgets every sample when the size changes.
  void resize(std::int64_t size) {
    if (static_cast<std::int64_t>(m_slot.size()) == size) return;
    m_slot.assign(size, -1);
    m_values.clear();
    m_indices.clear();
  }
  std::int64_t size() const { return static_cast<std::int64_t>(m_slot.size()); }

  bool contains(std::int64_t index) const { return m_slot[index] >= 0; }
  /// The sample at `index`, inserted with `value` if absent (kept as it is otherwise).
  T& insert(std::int64_t index, const T& value = T{}) {
    std::int32_t& slot = m_slot[index];
    if (slot < 0) {
      slot = static_cast<std::int32_t>(m_values.size());
      m_values.push_back(value);
      m_indices.push_back(index);
    }
    return m_values[slot];
  }
  /// The sample at `index`, which must have been inserted.
  T& operator[](std::int64_t index) { return m_values[m_slot[index]]; }
  const T& operator[](std::int64_t index) const { return m_values[m_slot[index]]; }

  /// The inserted grid indices, in insertion order.
  std::span<const std::int64_t> indices() const { return m_indices; }
  /// Forgets every sample (touching only their slots).
  void clear() {
    for (const std::int64_t i : m_indices) m_slot[i] = -1;
    m_values.clear();
    m_indices.clear();
  }

 private:
  std::vector<std::int32_t> m_slot;  ///< per grid index: its value's slot, −1 when absent
  std::vector<T> m_values;
  std::vector<std::int64_t> m_indices;
};

}  // namespace shellflow::grid
