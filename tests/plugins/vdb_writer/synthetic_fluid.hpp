#pragma once
// A FluidSolver test double for the writer tests: it owns a few grid fields filled by
// the test and shows them through fields(), and a domain box if the test gives one
// (domain()); the solver calls do nothing.

#include <algorithm>
#include <array>
#include <deque>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "shellflow/sdk/fluid_solver.hpp"

namespace shellflow::writer_testing {

class SyntheticFluid final : public sdk::FluidSolver {
 public:
  struct Field {
    sdk::FieldView::Location location = sdk::FieldView::Location::Cell;
    std::string name;
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    double dx = 1.0;
    std::array<int, 3> dims{0, 0, 0};
    int components = 1;
    std::array<std::vector<double>, 3> data;

    size_t index(int i, int j, int k) const {
      return static_cast<size_t>(i) +
             static_cast<size_t>(dims[0]) *
                 (static_cast<size_t>(j) + static_cast<size_t>(dims[1]) * k);
    }
    Eigen::Vector3d position(int i, int j, int k) const {
      return origin + dx * Eigen::Vector3d(i, j, k);
    }
    /// Sets every sample of component c to f(position).
    template <class F>
    void fill(int c, F&& f) {
      for (int k = 0; k < dims[2]; ++k)
        for (int j = 0; j < dims[1]; ++j)
          for (int i = 0; i < dims[0]; ++i) data[c][index(i, j, k)] = f(position(i, j, k));
    }
  };

  /// Adds a zero field; returns it for filling (stays valid for the double's lifetime).
  Field& add(const std::string& name, sdk::FieldView::Location location,
             const Eigen::Vector3d& origin, double dx, std::array<int, 3> dims, int components) {
    Field f;
    f.name = name;
    f.location = location;
    f.origin = origin;
    f.dx = dx;
    f.dims = dims;
    f.components = components;
    for (int c = 0; c < components; ++c)
      f.data[c].assign(static_cast<size_t>(dims[0]) * dims[1] * dims[2], 0.0);
    m_fields.push_back(std::move(f));
    return m_fields.back();
  }

  /// The field added under `name` (the first one).
  const Field& field(const std::string& name) const {
    for (const auto& f : m_fields)
      if (f.name == name) return f;
    throw std::out_of_range("SyntheticFluid: no field " + name);
  }

  /// What domain() reports from now on (nothing until set).
  void set_domain(const sdk::DomainView& domain) { m_domain = domain; }
  std::optional<sdk::DomainView> domain() const override { return m_domain; }

  double stable_dt(double /*cfl*/) const override {
    return std::numeric_limits<double>::infinity();
  }
  void advect(double, double, sdk::ShellSet, sdk::ShellSet) override {}
  void coupling_forces(double, sdk::ShellSet, std::span<sdk::TriangleVectors>) override {}
  void project(double, sdk::ShellSet, std::span<const sdk::Positions>) override {}
  void save(sdk::StateWriter&) const override {}
  void restore(sdk::StateReader&) override {}

  std::vector<sdk::FieldView> fields() const override {
    std::vector<sdk::FieldView> views;
    for (const auto& f : m_fields) {
      sdk::FieldView v;
      v.name = f.name;
      v.location = f.location;
      v.origin = f.origin;
      v.dx = f.dx;
      v.dims = f.dims;
      v.components = f.components;
      for (int c = 0; c < f.components; ++c) v.data[c] = f.data[c].data();
      views.push_back(v);
    }
    return views;
  }

 private:
  std::deque<Field> m_fields;  // a deque: add() keeps earlier references valid
  std::optional<sdk::DomainView> m_domain;
};

/// The water level set a fluid shows writers: node field "phi" (φ ≤ 0 water), the signed
/// distance to a sphere of `radius` about `centre`, clamped to ±band as the fluid clamps
/// it beyond its band.
inline SyntheticFluid::Field& add_sphere_phi(SyntheticFluid& fluid, const Eigen::Vector3d& origin,
                                             double dx, std::array<int, 3> dims,
                                             const Eigen::Vector3d& centre, double radius,
                                             double band) {
  auto& phi = fluid.add("phi", sdk::FieldView::Location::Node, origin, dx, dims, 1);
  phi.fill(0, [&](const Eigen::Vector3d& x) {
    return std::clamp((x - centre).norm() - radius, -band, band);
  });
  return phi;
}

}  // namespace shellflow::writer_testing
