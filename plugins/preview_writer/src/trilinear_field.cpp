#include "shellflow/preview_writer/trilinear_field.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace shellflow::preview_writer {

TrilinearField::TrilinearField(const sdk::FieldView& field, const std::string& role)
    : m_data(field.data[0]), m_dims(field.dims), m_origin(field.origin), m_dx(field.dx) {
  if (field.components != 1 || m_data == nullptr)
    throw std::invalid_argument("the " + role + " field \"" + field.name +
                                "\" is not a scalar field");
  if (m_dims[0] <= 0 || m_dims[1] <= 0 || m_dims[2] <= 0 || !(m_dx > 0.0))
    throw std::invalid_argument("the " + role + " field \"" + field.name + "\" is empty");
  const Eigen::Vector3d last =
      m_origin + m_dx * Eigen::Vector3d(m_dims[0] - 1, m_dims[1] - 1, m_dims[2] - 1);
  const double pad = field.location == sdk::FieldView::Location::Cell ? 0.5 * m_dx : 0.0;
  m_lower = m_origin.array() - pad;
  m_upper = last.array() + pad;
}

bool TrilinearField::contains(const Eigen::Vector3d& x) const {
  return (x.array() >= m_lower.array()).all() && (x.array() <= m_upper.array()).all();
}

TrilinearField::Stencil TrilinearField::stencil(const Eigen::Vector3d& x) const {
  Stencil st;
  for (int a = 0; a < 3; ++a) {
    // Grid coordinate, clamped to the outer samples (constant beyond them).
    const double g =
        std::clamp((x[a] - m_origin[a]) / m_dx, 0.0, static_cast<double>(m_dims[a] - 1));
    st.base[a] = std::min(static_cast<int>(g), std::max(m_dims[a] - 2, 0));
    st.w[a] = m_dims[a] > 1 ? g - st.base[a] : 0.0;
  }
  return st;
}

double TrilinearField::value(const Eigen::Vector3d& x) const {
  return value(stencil(x));
}

double TrilinearField::value(const Stencil& st) const {
  // Sample (i,j,k) at i + nx (j + ny k) (sdk::FieldView).
  const size_t sx = 1;
  const size_t sy = static_cast<size_t>(m_dims[0]);
  const size_t sz = sy * static_cast<size_t>(m_dims[1]);
  const size_t step[3] = {m_dims[0] > 1 ? sx : 0, m_dims[1] > 1 ? sy : 0, m_dims[2] > 1 ? sz : 0};
  const double* p = m_data + st.base[0] * sx + st.base[1] * sy + st.base[2] * sz;
  auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
  const double c00 = lerp(p[0], p[step[0]], st.w[0]);
  const double c10 = lerp(p[step[1]], p[step[1] + step[0]], st.w[0]);
  const double c01 = lerp(p[step[2]], p[step[2] + step[0]], st.w[0]);
  const double c11 = lerp(p[step[2] + step[1]], p[step[2] + step[1] + step[0]], st.w[0]);
  return lerp(lerp(c00, c10, st.w[1]), lerp(c01, c11, st.w[1]), st.w[2]);
}

std::array<int, 3> TrilinearField::cells() const {
  return {std::max(m_dims[0] - 1, 1), std::max(m_dims[1] - 1, 1), std::max(m_dims[2] - 1, 1)};
}

std::int64_t TrilinearField::cell_index(const Stencil& st) const {
  const std::array<int, 3> n = cells();
  return st.base[0] + std::int64_t(n[0]) * (st.base[1] + std::int64_t(n[1]) * st.base[2]);
}

double TrilinearField::value_seen(
    const Stencil& st, const Eigen::Vector3d& x,
    const std::function<bool(const Eigen::Vector3d&, const Eigen::Vector3d&)>& seen,
    double fallback) const {
  double value[8], weight[8];
  bool kept[8];
  double sum = 0.0;
  int count = 0;
  for (int c = 0; c < 8; ++c) {
    int ijk[3];
    weight[c] = 1.0;
    for (int a = 0; a < 3; ++a) {
      const int bit = (c >> a) & 1;
      ijk[a] = std::min(st.base[a] + bit, m_dims[a] - 1);
      weight[c] *= bit ? st.w[a] : 1.0 - st.w[a];
    }
    value[c] = m_data[ijk[0] + static_cast<size_t>(m_dims[0]) *
                                   (ijk[1] + static_cast<size_t>(m_dims[1]) * ijk[2])];
    const Eigen::Vector3d sample = m_origin + m_dx * Eigen::Vector3d(ijk[0], ijk[1], ijk[2]);
    kept[c] = seen(x, sample);
    if (kept[c]) {
      sum += value[c];
      ++count;
    }
  }
  if (count == 0) return fallback;
  double result = 0.0;
  for (int c = 0; c < 8; ++c) result += weight[c] * (kept[c] ? value[c] : sum / count);
  return result;
}

bool TrilinearField::clip(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                          double& s_in, double& s_out, int* entry_axis) const {
  // Slab test (Kay–Kajiya 1986).
  s_in = -std::numeric_limits<double>::infinity();
  s_out = std::numeric_limits<double>::infinity();
  int axis = -1;
  for (int a = 0; a < 3; ++a) {
    if (direction[a] == 0.0) {
      if (origin[a] < m_lower[a] || origin[a] > m_upper[a]) return false;
      continue;
    }
    double t0 = (m_lower[a] - origin[a]) / direction[a];
    double t1 = (m_upper[a] - origin[a]) / direction[a];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > s_in) {
      s_in = t0;
      axis = a;
    }
    s_out = std::min(s_out, t1);
  }
  if (entry_axis != nullptr) *entry_axis = axis;
  return s_in <= s_out;
}

}  // namespace shellflow::preview_writer
