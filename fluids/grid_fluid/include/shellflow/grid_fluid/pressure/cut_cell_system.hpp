#pragma once
// CutCellSystem: the §4.3 projection's linear system on cut cells (issue #52,
// docs/cut-cells.md §2.4). Each part of a cell that shells cut has its own pressure: the
// cell's slot part keeps the cell's unknown, each extra part gets one after the cells. Each
// fragment of a split face (CellParts) is a face of its own with its aperture β and its own
// velocity; it joins its two parts (a structured face weight when both are the cells' slots,
// a link otherwise), or gives its liquid part the Dirichlet conductance β/θ towards an air
// part (ghost fluid, θ from the two parts' φ at their common centre). With u the face and
// fragment velocities and p' = p Δt/Δx, A p' = −Σ β u·n per unknown and u −= ∇p' make the
// flow through every part's faces balance; A is a graph Laplacian in the β-weighted norm, so
// the projection is orthogonal there and adds no kinetic energy. Across a shell there is no
// fragment: the two sides of a cut cell meet only through the water around the shell.
//
// A moving shell's flux out of each part (its pieces' normal velocity, ShellPieces) joins the
// part's divergence: the water fills the part as the shell sweeps it. Built on the whole grid.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/grid/uniform_grid.hpp"
#include "shellflow/grid_fluid/mac/cell_parts.hpp"
#include "shellflow/grid_fluid/mac/domain_boundary.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/linear/grid_laplacian.hpp"

namespace shellflow::grid_fluid {

class CutCellSystem {
 public:
  /// The liquid: φ at each whole cell's centre (φ <= 0: liquid), and at each part of
  /// CellParts::parts(), its virtual node (the centre; a slot's replaces its cell's).
  struct Liquid {
    std::span<const double> cell_phi;
    std::span<const double> part_phi;
    bool ghost_fluid = true;  ///< second-order θ; false: θ = 1
  };

  /// Builds the operator of `parts` (which must outlive this system) for `liquid` in a
  /// domain whose closed faces `boundary` names (walls, inflow sides, emitters: their
  /// velocities are prescribed, their weights 0). `shell_flux`: per part, the shells' flux out
  /// of it along each axis (shell_flux(); empty: the shells are still).
  void build(const grid::UniformGrid& grid, const CellParts& parts, const DomainBoundary& boundary,
             const Liquid& water, std::span<const Eigen::Vector3d> shell_flux = {});

  const linear::GridLaplacian& laplacian() const { return m_laplacian; }
  /// The unknown of part `part` (an index into CellParts::parts()).
  int unknown_of_part(int part) const { return m_part_unknown[part]; }
  /// Whether unknown u is liquid.
  bool liquid(int u) const { return m_phi[u] <= 0.0; }

  /// Per unknown, the flow out through its faces and fragments, Σ β u·n [m/s], and through
  /// its shells' pieces (air: 0).
  void outward_flux(const MacGrid& mac, const FragmentVelocities& fragments,
                    Eigen::VectorXd& flux) const;
  /// u −= ∇p' on every open face and fragment with a liquid side (ghost fluid towards air),
  /// `scaled` being p' = p Δt/Δx per unknown; the MAC keeps each split face's slot fragment.
  void apply_pressure(const Eigen::VectorXd& scaled, MacGrid& mac,
                      FragmentVelocities& fragments) const;

 private:
  /// The unknowns a fragment of face `face` (family `axis`) joins: −1 where none.
  std::pair<int, int> fragment_unknowns(int axis, std::int64_t face,
                                        const FaceFragment& fragment) const;
  double inverse_theta(int liquid, int air) const;

  grid::UniformGrid m_grid;
  const CellParts* m_parts = nullptr;
  bool m_ghost_fluid = true;
  std::vector<int> m_part_unknown;
  std::vector<double> m_phi;  ///< per unknown
  std::vector<std::pair<int, double>> m_shell_flux;  ///< (unknown, flux) where a shell moves
  /// Per face: 1 closed by the domain (prescribed), 2 split by shells (its fragments count).
  std::array<std::vector<std::uint8_t>, 3> m_face_kind;
  linear::GridLaplacian m_laplacian;
};

}  // namespace shellflow::grid_fluid
