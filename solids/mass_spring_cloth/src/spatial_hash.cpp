#include "mass_spring_cloth/spatial_hash.hpp"

#include <algorithm>
#include <cmath>

namespace shellflow::cloth {

namespace {
constexpr long kMaxCellsPerBox = 512;
}

std::uint64_t SpatialHash::key(long ix, long iy, long iz) const {
  // Teschner et al. 2003 primes; a collision of keys only adds candidates.
  return (static_cast<std::uint64_t>(ix) * 73856093ULL) ^
         (static_cast<std::uint64_t>(iy) * 19349663ULL) ^
         (static_cast<std::uint64_t>(iz) * 83492791ULL);
}

void SpatialHash::build(std::vector<Box> boxes, double cell_size) {
  m_inverse_cell = 1.0 / cell_size;
  m_boxes = std::move(boxes);
  m_entries.clear();
  m_oversized.clear();
  m_entries.reserve(2 * m_boxes.size());
  for (int k = 0; k < static_cast<int>(m_boxes.size()); ++k) {
    const Eigen::Vector3d lo = (m_boxes[k].min() * m_inverse_cell).array().floor();
    const Eigen::Vector3d hi = (m_boxes[k].max() * m_inverse_cell).array().floor();
    const Eigen::Vector3d span = hi - lo + Eigen::Vector3d::Ones();
    if (span.prod() > kMaxCellsPerBox) {
      m_oversized.push_back(k);
      continue;
    }
    for (long i = static_cast<long>(lo.x()); i <= static_cast<long>(hi.x()); ++i)
      for (long j = static_cast<long>(lo.y()); j <= static_cast<long>(hi.y()); ++j)
        for (long l = static_cast<long>(lo.z()); l <= static_cast<long>(hi.z()); ++l)
          m_entries.emplace_back(key(i, j, l), k);
  }
  std::sort(m_entries.begin(), m_entries.end());
}

void SpatialHash::query(const Box& box, std::vector<int>& out) const {
  out.clear();
  const Eigen::Vector3d lo = (box.min() * m_inverse_cell).array().floor();
  const Eigen::Vector3d hi = (box.max() * m_inverse_cell).array().floor();
  const Eigen::Vector3d span = hi - lo + Eigen::Vector3d::Ones();
  if (span.prod() > kMaxCellsPerBox) {
    for (int k = 0; k < static_cast<int>(m_boxes.size()); ++k)
      if (m_boxes[k].intersects(box)) out.push_back(k);
    return;
  }
  for (long i = static_cast<long>(lo.x()); i <= static_cast<long>(hi.x()); ++i)
    for (long j = static_cast<long>(lo.y()); j <= static_cast<long>(hi.y()); ++j)
      for (long l = static_cast<long>(lo.z()); l <= static_cast<long>(hi.z()); ++l) {
        const std::uint64_t k = key(i, j, l);
        auto it = std::lower_bound(m_entries.begin(), m_entries.end(), std::make_pair(k, -1));
        for (; it != m_entries.end() && it->first == k; ++it)
          if (m_boxes[it->second].intersects(box)) out.push_back(it->second);
      }
  for (int k : m_oversized)
    if (m_boxes[k].intersects(box)) out.push_back(k);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

}  // namespace shellflow::cloth
