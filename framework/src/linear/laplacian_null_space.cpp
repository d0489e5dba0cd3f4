#include "shellflow/linear/laplacian_null_space.hpp"

#include <numeric>
#include <vector>

namespace shellflow::linear {

ConstantNullSpace null_space_of(const GridLaplacian& a) {
  const int n = a.size();
  const Eigen::Vector3i cells = a.cells();
  std::vector<int> root(n);
  std::iota(root.begin(), root.end(), 0);
  const auto find = [&](int u) {
    while (root[u] != u) u = root[u] = root[root[u]];
    return u;
  };
  const auto join = [&](int u, int v) { root[find(u)] = find(v); };
  std::vector<std::uint8_t> grounded(n, 0);
  for (int u = 0; u < n; ++u)
    if (!a.dirichlet().empty() && a.dirichlet()[u] > 0.0) grounded[u] = 1;
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Vector3i faces = a.face_counts(axis);
    const auto& w = a.weights(axis);
    for (int k = 0; k < faces.z(); ++k)
      for (int j = 0; j < faces.y(); ++j)
        for (int i = 0; i < faces.x(); ++i) {
          const float weight = w[i + std::int64_t(faces.x()) * (j + std::int64_t(faces.y()) * k)];
          if (weight == 0.0f) continue;
          Eigen::Vector3i plus(i, j, k), minus(i, j, k);
          minus[axis] -= 1;
          const auto index = [&](const Eigen::Vector3i& c) {
            return c.x() + cells.x() * (c.y() + cells.y() * c.z());
          };
          const bool has_plus = plus[axis] < cells[axis], has_minus = minus[axis] >= 0;
          if (has_plus && has_minus) {
            join(index(plus), index(minus));
          } else {
            grounded[index(has_plus ? plus : minus)] = 1;  // a domain face: p = 0 beyond it
          }
        }
  }
  if (a.has_links())
    for (int u = 0; u < n; ++u)
      for (int l = a.link_start()[u]; l < a.link_start()[u + 1]; ++l)
        if (a.link_weight()[l] > 0.0f) join(u, a.link_to()[l]);
  for (int u = 0; u < n; ++u)
    if (grounded[u]) grounded[find(u)] = 1;
  std::vector<int> group(n, -1), number(n, -1);
  int groups = 0;
  for (int u = 0; u < n; ++u) {
    if (!(a.diagonal(u) > 0.0)) continue;  // isolated or inactive: no row to fix
    const int r = find(u);
    if (grounded[r]) continue;
    if (number[r] < 0) number[r] = groups++;
    group[u] = number[r];
  }
  return ConstantNullSpace(std::move(group), groups);
}

}  // namespace shellflow::linear
