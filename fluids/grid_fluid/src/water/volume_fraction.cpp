#include "shellflow/grid_fluid/water/volume_fraction.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/mac/ordered_sum.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

namespace {

/// F this close to 0 or 1 counts as empty or full: no plane is fitted to it.
constexpr double kFullOrEmpty = 1e-9;
/// The most parts a step's sweeps are split into (a face far faster than the step's CFL
/// speed, θ near 0, would otherwise split every step of the whole grid: its excess Courant
/// number is then clipped at the donor's water, and counted).
constexpr int kMostParts = 16;
/// A cut cell's part smaller than this share of its cell may be filled past its volume in a
/// sweep (the excess carried on as a full cell's) rather than split the step further.
constexpr double kSmallPart = 0.1;

}  // namespace

double VolumeFraction::box_fraction_below(const Eigen::Vector3d& normal, double d,
                                          const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  // Scardovelli and Zaleski 2000 (J. Comput. Phys. 164): with the box moved to [0, c] and
  // each axis turned so that m_i = |n_i| >= 0, the region Σ m_i z_i <= α is a corner
  // simplex less the parts beyond each face, by inclusion and exclusion. An axis the plane
  // runs along (m_i ≈ 0) drops out: its extent times the lower-dimensional measure. Below
  // 1e-5 of the largest the sums cancel (two axes at 1e-7 read a cell 0.64 full as empty),
  // while the tilt moves the fraction by less than that.
  const Eigen::Vector3d c = hi - lo;
  double alpha = d - normal.dot(lo);
  std::array<double, 3> m{}, extent{};
  int used = 0;
  double across = 1.0;  // the extents of the axes the plane runs along
  const double largest = normal.cwiseAbs().maxCoeff();
  for (int a = 0; a < 3; ++a) {
    if (normal[a] < 0.0) alpha -= normal[a] * c[a];
    if (std::abs(normal[a]) <= 1e-5 * largest) {
      across *= c[a];
      continue;
    }
    m[used] = std::abs(normal[a]);
    extent[used++] = c[a];
  }
  const double volume = c.prod();
  if (volume <= 0.0) return 0.0;
  const auto pos = [](double x, int power) {
    return x > 0.0 ? (power == 3 ? x * x * x : power == 2 ? x * x : x) : 0.0;
  };
  double measure = 0.0;  // of the used axes' box below the plane
  if (used == 0) {
    measure = alpha >= 0.0 ? 1.0 : 0.0;
  } else if (used == 1) {
    measure = std::clamp(alpha / m[0], 0.0, extent[0]);
  } else if (used == 2) {
    const double a1 = m[0] * extent[0], a2 = m[1] * extent[1];
    measure = (pos(alpha, 2) - pos(alpha - a1, 2) - pos(alpha - a2, 2) + pos(alpha - a1 - a2, 2)) /
              (2.0 * m[0] * m[1]);
  } else {
    const double a1 = m[0] * extent[0], a2 = m[1] * extent[1], a3 = m[2] * extent[2];
    measure = (pos(alpha, 3) - pos(alpha - a1, 3) - pos(alpha - a2, 3) - pos(alpha - a3, 3) +
               pos(alpha - a1 - a2, 3) + pos(alpha - a1 - a3, 3) + pos(alpha - a2 - a3, 3) -
               pos(alpha - a1 - a2 - a3, 3)) /
              (6.0 * m[0] * m[1] * m[2]);
  }
  return std::clamp(measure * across / volume, 0.0, 1.0);
}

double VolumeFraction::plane_height(const Eigen::Vector3d& normal, double fraction) {
  const Eigen::Vector3d lo = Eigen::Vector3d::Constant(-0.5), hi = Eigen::Vector3d::Constant(0.5);
  // The fraction grows with d from 0 to 1 over [−reach, reach], smoothly (a cubic per
  // piece): regula falsi with the Illinois step keeps the root bracketed and converges
  // superlinearly, to 1e-13 of the cube in about ten evaluations.
  const double reach = 0.5 * normal.cwiseAbs().sum();
  double a = -reach, b = reach, fa = -fraction, fb = 1.0 - fraction;
  int side = 0;
  for (int n = 0; n < 100 && b - a > 1e-13; ++n) {
    const double c = (a * fb - b * fa) / (fb - fa);
    const double fc = box_fraction_below(normal, c, lo, hi) - fraction;
    if (fc == 0.0) return c;
    if ((fc < 0.0) == (fa < 0.0)) {
      a = c, fa = fc;
      if (side == -1) fb *= 0.5;
      side = -1;
    } else {
      b = c, fb = fc;
      if (side == 1) fa *= 0.5;
      side = 1;
    }
    if (std::abs(fc) < 1e-15) return c;
  }
  return 0.5 * (a + b);
}

namespace {

/// The water fraction of the cell of `grid` centred at `centre` where `distance` is below
/// zero, from 4³ points (each a plane's share of its sub-cell, |∇d| = 1: exact for a
/// plane along the grid).
template <class Distance>
double sampled_fraction(const grid::UniformGrid& grid, const Eigen::Vector3d& centre,
                        const Distance& distance) {
  constexpr int kPoints = 4;
  const double dx = grid.dx(), h = dx / kPoints;
  const Eigen::Vector3d low = centre - Eigen::Vector3d::Constant(0.5 * dx);
  double water = 0.0;
  for (int k = 0; k < kPoints; ++k)
    for (int j = 0; j < kPoints; ++j)
      for (int i = 0; i < kPoints; ++i)
        water += std::clamp(
            0.5 - distance(Eigen::Vector3d(low + h * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5))) / h,
            0.0, 1.0);
  return water / (kPoints * kPoints * kPoints);
}

}  // namespace

VolumeFraction::VolumeFraction(const LevelSet& level_set) : m_mac(level_set.mac_grid()) {
  const std::int64_t count = m_mac.size(Location::Cell);
  if (count > std::numeric_limits<std::int32_t>::max())  // m_plane_of's entries
    throw Error("grid_fluid: a volume fraction takes at most 2^31 cells");
  m_fraction.assign(count, 0.0);
#pragma omp parallel for schedule(static)
  for (std::int64_t cell = 0; cell < count; ++cell)
    m_fraction[cell] = sampled_fraction(m_mac, m_mac.position(Location::Cell, cell),
                                        [&](const Eigen::Vector3d& q) { return level_set.sample(q); });
}

double VolumeFraction::fill(const std::function<double(const Eigen::Vector3d&)>& distance,
                            const grid::IndexBox& cells) {
  if (cells.empty()) return 0.0;
  double added = 0.0;
  for (int k = cells.lo.z(); k <= cells.hi.z(); ++k)
    for (int j = cells.lo.y(); j <= cells.hi.y(); ++j)
      for (int i = cells.lo.x(); i <= cells.hi.x(); ++i) {
        const std::int64_t c = m_mac.index(Location::Cell, i, j, k);
        const double shape =
            sampled_fraction(m_mac, m_mac.position(Location::Cell, c), distance);
        if (shape > m_fraction[c]) {
          added += shape - m_fraction[c];
          m_fraction[c] = shape;
        }
      }
  const double dx = m_mac.dx();
  return added * dx * dx * dx;
}

double VolumeFraction::volume() const {
  double sum = ordered_sum(static_cast<std::int64_t>(m_fraction.size()),
                           [&](std::int64_t c) { return m_fraction[c]; });
  if (m_parts != nullptr) {
    const auto parts = m_parts->parts();
    sum += ordered_sum(static_cast<std::int64_t>(parts.size()),
                       [&](std::int64_t p) { return parts[p].slot ? 0.0 : m_part_fraction[p]; });
  }
  const double dx = m_mac.dx();
  return sum * dx * dx * dx;
}

double VolumeFraction::volume_in(const grid::IndexBox& cells) const {
  if (cells.empty()) return 0.0;
  double sum = 0.0;
  for (int k = cells.lo.z(); k <= cells.hi.z(); ++k)
    for (int j = cells.lo.y(); j <= cells.hi.y(); ++j)
      for (int i = cells.lo.x(); i <= cells.hi.x(); ++i)
        sum += m_fraction[m_mac.index(Location::Cell, i, j, k)];
  if (m_parts != nullptr) {
    const auto parts = m_parts->parts();
    for (size_t p = 0; p < parts.size(); ++p)
      if (!parts[p].slot && cells.contains(m_mac.coordinates(Location::Cell, parts[p].cell)))
        sum += m_part_fraction[p];
  }
  const double dx = m_mac.dx();
  return sum * dx * dx * dx;
}

Eigen::Vector3d VolumeFraction::normal_at(const LevelSet& level_set, const Eigen::Vector3i& c) const {
  const Eigen::Vector3i n = m_mac.cells();
  const auto& phi = level_set.phi();
  const auto gradient = [&](const std::vector<double>& field) {
    Eigen::Vector3d g;
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3i lo = c, hi = c;
      lo[a] = std::max(c[a] - 1, 0);
      hi[a] = std::min(c[a] + 1, n[a] - 1);
      g[a] = hi[a] == lo[a] ? 0.0
                            : (field[m_mac.index(Location::Cell, hi)] -
                               field[m_mac.index(Location::Cell, lo)]) /
                                  (hi[a] - lo[a]);
    }
    return g;
  };
  Eigen::Vector3d g = gradient(phi);
  if (g.norm() < 1e-12 * m_mac.dx()) g = -gradient(m_fraction);
  if (g.norm() == 0.0) return Eigen::Vector3d::UnitZ();
  return g.normalized();
}

std::vector<std::pair<std::int64_t, double>> VolumeFraction::moved_faces(int axis,
                                                                         const MacGrid& mac) const {
  // The kept projection's values, then a cut face's share of what it holds.
  std::vector<std::pair<std::int64_t, double>> faces;
  if (!m_faces_kept) return faces;
  const auto& u = mac.face_velocity(axis);
  faces = m_kept[axis];  // in face order
  for (const CutFace& cut : m_cut[axis]) {
    const auto at =
        std::lower_bound(faces.begin(), faces.end(), cut.face,
                         [](const auto& entry, std::int64_t face) { return entry.first < face; });
    const bool kept = at != faces.end() && at->first == cut.face;
    const double base = kept ? at->second : u[cut.face];
    const double shared = cut.fraction * base + (1.0 - cut.fraction) * cut.shell_velocity;
    if (kept)
      at->second = shared;
    else
      faces.insert(at, {cut.face, shared});
  }
  return faces;
}

void VolumeFraction::faces_along(int axis, const MacGrid& mac, std::vector<double>& out) const {
  out = mac.face_velocity(axis);
  for (const auto& [face, u] : moved_faces(axis, mac)) out[face] = u;
}

void VolumeFraction::save(sdk::StateWriter& out, const MacGrid& mac) const {
  out.write_column(m_fraction.data(), static_cast<std::int64_t>(m_fraction.size()));
  out.write(m_steps);
  out.write(m_clipped_total);
  out.write(m_faces_kept);
  if (!m_faces_kept) return;
  std::vector<double> u;
  for (int a = 0; a < 3; ++a) {
    faces_along(a, mac, u);
    out.write_column(u.data(), static_cast<std::int64_t>(u.size()));
  }
  out.write(static_cast<std::int64_t>(m_faces_sources.size()));
  for (const grid::IndexBox& box : m_faces_sources)
    for (const Eigen::Vector3i* corner : {&box.lo, &box.hi})
      for (int a = 0; a < 3; ++a) out.write(static_cast<std::int64_t>((*corner)[a]));
}

void VolumeFraction::restore(sdk::StateReader& in, const MacGrid& mac) {
  const auto read = [&](std::vector<double>& v, std::int64_t size) {
    Eigen::VectorXd m;
    in.read_matrix(m);
    if (m.size() != size)
      throw Error("grid_fluid restore(): the saved water fraction is for another grid");
    v.assign(m.data(), m.data() + m.size());
  };
  read(m_fraction, m_mac.size(Location::Cell));
  m_steps = in.read<std::int64_t>();
  m_clipped_total = in.read<double>();
  m_faces_sources.clear();
  for (int a = 0; a < 3; ++a) {
    m_kept[a].clear();
    m_cut[a].clear();
  }
  m_faces_kept = in.read<bool>();
  if (!m_faces_kept) return;
  // Kept: where the saved faces differ from the restored MAC's (the same faces F moves with).
  std::vector<double> saved;
  for (int a = 0; a < 3; ++a) {
    read(saved, m_mac.size(face_location(a)));
    const auto& u = mac.face_velocity(a);
    for (std::int64_t f = 0; f < static_cast<std::int64_t>(saved.size()); ++f)
      if (std::bit_cast<std::uint64_t>(saved[f]) != std::bit_cast<std::uint64_t>(u[f]))
        m_kept[a].push_back({f, saved[f]});
  }
  const std::int64_t boxes = in.read<std::int64_t>();
  for (std::int64_t b = 0; b < boxes; ++b) {
    grid::IndexBox box;
    for (Eigen::Vector3i* corner : {&box.lo, &box.hi})
      for (int a = 0; a < 3; ++a) (*corner)[a] = static_cast<int>(in.read<std::int64_t>());
    m_faces_sources.push_back(box);
  }
}

void VolumeFraction::gather_line_faces(const MacGrid& mac) {
  for (int a = 0; a < 3; ++a) {
    const Location loc = face_location(a);
    const std::vector<std::pair<std::int64_t, double>> faces = moved_faces(a, mac);
    const Eigen::Vector3i n = m_mac.cells();
    const int b = (a + 1) % 3, e = (a + 2) % 3;
    const std::int64_t lines = std::int64_t(n[b]) * n[e];
    auto& start = m_line_start[a];
    auto& entries = m_line_faces[a];
    start.assign(lines + 1, 0);
    entries.resize(faces.size());
    const auto line_of = [&](const Eigen::Vector3i& f) { return f[b] + std::int64_t(n[b]) * f[e]; };
    for (const auto& [face, value] : faces) ++start[line_of(m_mac.coordinates(loc, face)) + 1];
    for (std::int64_t l = 0; l < lines; ++l) start[l + 1] += start[l];
    std::vector<std::int64_t> next(start.begin(), start.end() - 1);
    for (const auto& [face, value] : faces) {
      const Eigen::Vector3i f = m_mac.coordinates(loc, face);
      entries[next[line_of(f)]++] = {f[a], value};
    }
  }
}

void VolumeFraction::advect(const MacGrid& mac, const LevelSet& level_set, double dt,
                            double max_speed, const std::vector<grid::IndexBox>& on,
                            std::span<const std::uint8_t> cut) {
  const std::vector<grid::IndexBox>& sources = m_faces_kept ? m_faces_sources : on;
  const std::int64_t step = m_steps++;
  m_stats = VolumeFractionStats{};
  gather_line_faces(mac);
  // Weymouth and Yue's sweeps keep F in [0, 1] up to a Courant number of ½ per sweep: the
  // step is split to stay within it (the faces next to liquid cells carry the projection's
  // values, which may outrun the step's CFL speed where θ is small), up to kMostParts.
  double fastest = max_speed;  // the MAC's faces, and those F moves with instead
  for (const auto& faces : m_line_faces)
    for (const LineFace& face : faces) fastest = std::max(fastest, std::abs(face.u));
  // A fragment fills the smaller of its parts as fast as its flux over that part's volume.
  if (m_parts != nullptr)
    fastest = std::max(fastest, m_parts->max_filling_speed(*m_fragment_velocity, kSmallPart));
  const int parts =
      std::clamp(static_cast<int>(std::ceil(fastest * dt / m_mac.dx() / 0.5)), 1, kMostParts);
  // The dilation term's cells: the liquid cells of φ^n, whose faces the projection made
  // divergence free, so that the terms add up to nothing (Weymouth and Yue take F > ½,
  // which φ^n's liquid cells are once correct() has moved φ to F) but in the emitters'
  // cells, whose held faces push water out.
  const auto& phi = level_set.phi();
  const std::int64_t count = m_mac.size(Location::Cell);
  // In the liquid cells a shell cuts, where φ is left to the level set, F itself: φ may
  // read a film liquid there that F holds a tenth of, and a whole cell's dilation overdrew
  // it (any weight constant over the step adds up to nothing on divergence-free faces).
  m_cut_weights.clear();
  if (!cut.empty())
    for (std::int64_t c = 0; c < count; ++c)
      if (cut[c] != 0 && phi[c] <= 0.0) m_cut_weights.push_back({c, m_fraction[c]});
  // The cells the sweeps may change: those with water or φ <= 0 (their bounding box, which
  // each pass grows by a cell along its axis), and the cells F cuts now.
  const Eigen::Vector3i n = m_mac.cells();
  m_wet = {n, Eigen::Vector3i::Constant(-1)};
  m_plane_of.resize(count, -1);  // −1 everywhere between steps
  m_planes.clear();
  std::vector<std::vector<std::int64_t>> mixed_per_slab(n.z());
  std::vector<grid::IndexBox> wet_per_slab(n.z(), m_wet);
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        const std::int64_t c = m_mac.index(Location::Cell, i, j, k);
        if (!(m_fraction[c] > kFullOrEmpty || phi[c] <= 0.0)) continue;
        grid::IndexBox& box = wet_per_slab[k];
        box.lo = box.lo.cwiseMin(Eigen::Vector3i(i, j, k));
        box.hi = box.hi.cwiseMax(Eigen::Vector3i(i, j, k));
        if (m_fraction[c] < 1.0 - kFullOrEmpty && m_fraction[c] > kFullOrEmpty)
          mixed_per_slab[k].push_back(c);
      }
  for (int k = 0; k < n.z(); ++k) {
    m_wet.lo = m_wet.lo.cwiseMin(wet_per_slab[k].lo);
    m_wet.hi = m_wet.hi.cwiseMax(wet_per_slab[k].hi);
    for (const std::int64_t c : mixed_per_slab[k]) add_plane(c);
  }
  // Cut cells: each part's fill at the step's start (its dilation weight); a part with water
  // is wet.
  m_part_fill.clear();
  if (m_parts != nullptr) {
    const auto all = m_parts->parts();
    m_part_fill.resize(all.size());
    m_part_room.resize(all.size());
    for (size_t p = 0; p < all.size(); ++p) {
      m_part_room[p] = all[p].volume;
      const double water = all[p].slot ? m_fraction[all[p].cell] : m_part_fraction[p];
      m_part_fill[p] = all[p].volume > 0.0 ? std::clamp(water / all[p].volume, 0.0, 1.0) : 0.0;
      if (water > kFullOrEmpty) {
        const Eigen::Vector3i c = m_mac.coordinates(Location::Cell, all[p].cell);
        m_wet.lo = m_wet.lo.cwiseMin(c);
        m_wet.hi = m_wet.hi.cwiseMax(c);
      }
    }
  }
  double clipped = 0.0, outflow = 0.0, dilated = 0.0, divergence = 0.0;
  for (int part = 0; part < parts && !m_wet.empty(); ++part) {
    sweeps(mac, level_set, cut, sources, dt / parts, step * 3 + part);
    clipped += m_stats.clipped;
    outflow += m_stats.outflow;
    dilated += m_stats.dilated;
    divergence += m_stats.divergence;
  }
  for (const Plane& plane : m_planes) m_plane_of[plane.cell] = -1;
  m_stats.clipped = clipped;
  m_stats.outflow = outflow;
  m_stats.dilated = dilated;
  m_stats.divergence = divergence;
  m_stats.parts = parts;
  m_clipped_total += clipped;
}

void VolumeFraction::add_plane(std::int64_t cell) {
  m_plane_of[cell] = static_cast<std::int32_t>(m_planes.size());
  m_planes.push_back({cell, Eigen::Vector3d::Zero(), 0.0});
}

void VolumeFraction::sweeps(const MacGrid& mac, const LevelSet& level_set,
                            std::span<const std::uint8_t> cut,
                            const std::vector<grid::IndexBox>& sources, double dt,
                            std::int64_t order) {
  const auto& phi = level_set.phi();
  const auto dilating = [&](std::int64_t c) {  // the dilation term's weight
    if (phi[c] > 0.0) return 0.0;
    if (cut.empty() || cut[c] == 0) return 1.0;
    return std::lower_bound(m_cut_weights.begin(), m_cut_weights.end(), c,
                            [](const auto& entry, std::int64_t cell) { return entry.first < cell; })
        ->second;
  };
  const Eigen::Vector3i n = m_mac.cells();
  const double dx = m_mac.dx();
  const auto mixed = [](double f) { return f > kFullOrEmpty && f < 1.0 - kFullOrEmpty; };
  double clipped = 0.0, outflow = 0.0, dilated = 0.0, divergence = 0.0;
  for (int pass = 0; pass < 3; ++pass) {
    const int a = order % 2 == 0 ? pass : 2 - pass;
    const auto& u_mac = mac.face_velocity(a);
    const Location loc = face_location(a);
    // Each cell F cuts: its plane, the normal from φ^n (found once a cell is first cut).
    const std::int64_t planes = static_cast<std::int64_t>(m_planes.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t p = 0; p < planes; ++p) {
      Plane& plane = m_planes[p];
      if (plane.normal.isZero())
        plane.normal = normal_at(level_set, m_mac.coordinates(Location::Cell, plane.cell));
      if (mixed(m_fraction[plane.cell]))
        plane.height = plane_height(plane.normal, m_fraction[plane.cell]);
    }
    // A pass moves water along the lines of cells of axis a only, each on its own: per line,
    // the water each of its faces carries (+ along the axis), then F − (out − in) +
    // c (u⁺ − u⁻) dt/Δx (Weymouth and Yue 2010, eq. 9). Water moves at most a cell, so only
    // the cells from one before a line's first wet cell to one after its last change; a line
    // outside the wet box, or with no wet cell, is left as it is. Per line, summed in order
    // afterwards: the same bits on any thread count.
    const int b = (a + 1) % 3, e = (a + 2) % 3;
    const std::int64_t lines = std::int64_t(n[b]) * n[e];
    m_line_sums.assign(4 * lines, 0.0);  // clipped, dilated, divergence, outflow per line
    // A line's cells and faces lie a fixed stride apart along a.
    const std::int64_t cell_stride = m_mac.index(Location::Cell, Eigen::Vector3i::Unit(a));
    const std::int64_t face_stride = m_mac.index(loc, Eigen::Vector3i::Unit(a));
    std::vector<int> first(lines, n[a]), last(lines, -1);  // each line's span changed
    std::vector<std::vector<std::int64_t>> cut_now(lines);
    // Split faces move water fragment by fragment, from the pass's starting F.
    FragmentPass fragment_pass;
    if (m_parts != nullptr) fragment_pass = gather_fragments(a, dt);
    const std::uint8_t* split = m_parts != nullptr ? m_split[a].data() : nullptr;
    const auto& line_start = m_line_start[a];
    const auto& line_faces = m_line_faces[a];
#pragma omp parallel
    {
      std::vector<double> carried(n[a] + 1), u(n[a] + 1);
#pragma omp for collapse(2) schedule(static)
      for (int le = m_wet.lo[e]; le <= m_wet.hi[e]; ++le)
        for (int lb = m_wet.lo[b]; lb <= m_wet.hi[b]; ++lb) {
          const std::int64_t line = lb + std::int64_t(n[b]) * le;
          Eigen::Vector3i ijk;
          ijk[a] = 0;
          ijk[b] = lb;
          ijk[e] = le;
          const std::int64_t cell_base = m_mac.index(Location::Cell, ijk);
          const std::int64_t face_base = m_mac.index(loc, ijk);
          const auto cell_at = [&](int i) { return cell_base + i * cell_stride; };
          const auto wet = [&](int i) {
            const std::int64_t c = cell_at(i);
            return m_fraction[c] > kFullOrEmpty || phi[c] <= 0.0;
          };
          int lo = m_wet.lo[a], hi = m_wet.hi[a];
          while (lo <= hi && !wet(lo)) ++lo;
          if (lo > hi) continue;
          while (!wet(hi)) --hi;
          lo = std::max(lo - 1, 0);
          hi = std::min(hi + 1, n[a] - 1);
          first[line] = lo;
          last[line] = hi;
          // The faces lo .. hi + 1: the MAC's, those F moves with instead over them.
          for (int i = lo; i <= hi + 1; ++i) u[i] = u_mac[face_base + i * face_stride];
          for (std::int64_t k = line_start[line]; k < line_start[line + 1]; ++k)
            if (line_faces[k].along >= lo && line_faces[k].along <= hi + 1)
              u[line_faces[k].along] = line_faces[k].u;
          // A split face: its fragments' net flux for the whole cells' dilation; its water is
          // the fragments' (gather_fragments).
          const auto split_at = [&](int i) {
            return split != nullptr && split[face_base + i * face_stride] != 0;
          };
          if (split != nullptr)
            for (int i = lo; i <= hi + 1; ++i)
              if (split_at(i)) u[i] = split_face_flux(a, face_base + i * face_stride);
          for (int i = lo; i <= hi + 1; ++i) {
            carried[i] = 0.0;
            if (split_at(i)) continue;
            // A side's face carries water out where it is open and its flow leaves; none
            // comes in.
            if (i == 0 && !(m_open[2 * a] && u[i] < 0.0)) continue;
            if (i == n[a] && !(m_open[2 * a + 1] && u[i] > 0.0)) continue;
            const double s = std::min(std::abs(u[i]) * dt / dx, 1.0);
            if (s == 0.0) continue;
            const std::int64_t d = cell_at(u[i] > 0.0 ? i - 1 : i);
            const double fraction = m_fraction[d];
            double water;
            if (fraction <= kFullOrEmpty) {
              water = 0.0;
            } else if (!mixed(fraction)) {
              water = s * fraction;
            } else {
              // The donor's slab next to the face, below its plane.
              Eigen::Vector3d box_lo = Eigen::Vector3d::Constant(-0.5),
                              box_hi = Eigen::Vector3d::Constant(0.5);
              if (u[i] > 0.0)
                box_lo[a] = 0.5 - s;
              else
                box_hi[a] = -0.5 + s;
              const Plane& plane = m_planes[m_plane_of[d]];
              water = s * box_fraction_below(plane.normal, plane.height, box_lo, box_hi);
            }
            carried[i] = u[i] > 0.0 ? water : -water;
          }
          double* sums = &m_line_sums[4 * line];
          sums[3] = (m_open[2 * a] && lo == 0 ? -carried[0] : 0.0) +
                    (m_open[2 * a + 1] && hi == n[a] - 1 ? carried[n[a]] : 0.0);
          for (int i = lo; i <= hi; ++i) {
            const std::int64_t c = cell_at(i);
            if (split != nullptr && m_cut_cell[c] != 0) continue;  // its parts': the fragments'
            double value = m_fraction[c] + carried[i] - carried[i + 1];
            if (const double weight = dilating(c); weight != 0.0) {
              const double dilation = weight * (u[i + 1] - u[i]) * dt / dx;
              value += dilation;
              ijk[a] = i;
              const bool emitting =
                  std::any_of(sources.begin(), sources.end(),
                              [&](const grid::IndexBox& box) { return box.contains(ijk); });
              sums[emitting ? 1 : 2] += dilation;
            }
            // Where the air's extrapolated faces converge a cell may take in more than it
            // holds: the excess stays in it (carried on with the flux of a full cell) rather
            // than being lost. Below zero there is nothing to carry.
            const double kept = std::max(value, 0.0);
            sums[0] += kept - value;
            m_fraction[c] = kept;
            if (m_plane_of[c] < 0 && mixed(kept)) cut_now[line].push_back(c);
          }
        }
    }
    // The cells first cut in this pass get planes at the next; the wet box grows to the
    // cells it changed.
    for (std::int64_t line = 0; line < lines; ++line) {
      for (const std::int64_t c : cut_now[line]) add_plane(c);
      if (last[line] < 0) continue;
      m_wet.lo[a] = std::min(m_wet.lo[a], first[line]);
      m_wet.hi[a] = std::max(m_wet.hi[a], last[line]);
    }
    if (m_parts != nullptr) {
      std::vector<std::int64_t> cut_by_fragments;
      clipped += apply_fragments(fragment_pass, cut_by_fragments);
      // A moving shell sweeps each part's room along this axis as the water moves.
      if (m_shell_flux != nullptr && m_shell_flux->size() == m_part_room.size())
        for (size_t p = 0; p < m_part_room.size(); ++p)
          m_part_room[p] += (*m_shell_flux)[p][a] * dt / dx;
      for (const std::int64_t c : cut_by_fragments)
        if (m_plane_of[c] < 0) add_plane(c);
      divergence += fragment_pass.dilation;
    }
    clipped += ordered_sum(lines, [&](std::int64_t l) { return m_line_sums[4 * l]; });
    dilated += ordered_sum(lines, [&](std::int64_t l) { return m_line_sums[4 * l + 1]; });
    divergence += ordered_sum(lines, [&](std::int64_t l) { return m_line_sums[4 * l + 2]; });
    outflow += ordered_sum(lines, [&](std::int64_t l) { return m_line_sums[4 * l + 3]; });
  }
  const double cell = dx * dx * dx;
  m_stats.clipped = clipped * cell;
  m_stats.outflow = outflow * cell;
  m_stats.dilated = dilated * cell;
  m_stats.divergence = divergence * cell;
}

void VolumeFraction::set_cut_cells(const CellParts* parts, const FragmentVelocities* velocities,
                                   const std::vector<Eigen::Vector3d>* shell_flux) {
  m_parts = parts;
  m_fragment_velocity = velocities;
  m_shell_flux = shell_flux;
  m_part_fraction.clear();
  m_part_liquid.clear();
  m_cut_cell.clear();
  for (auto& split : m_split) split.clear();
  if (parts == nullptr) return;
  m_part_fraction.assign(parts->parts().size(), 0.0);
  m_cut_cell.assign(m_mac.size(Location::Cell), 0);
  for (const CellPart& part : parts->parts()) m_cut_cell[part.cell] = 1;
  for (int a = 0; a < 3; ++a) {
    m_split[a].assign(m_mac.size(face_location(a)), 0);
    for (const FaceSplit& split : parts->split_faces(a)) m_split[a][split.face] = 1;
  }
}

double VolumeFraction::slab_water(std::int64_t donor, int axis, bool positive, double s) const {
  const double fraction = m_fraction[donor];
  if (fraction <= kFullOrEmpty) return 0.0;
  if (fraction >= 1.0 - kFullOrEmpty) return s * fraction;
  // The donor's slab next to the face, below its plane.
  Eigen::Vector3d box_lo = Eigen::Vector3d::Constant(-0.5), box_hi = Eigen::Vector3d::Constant(0.5);
  if (positive)
    box_lo[axis] = 0.5 - s;
  else
    box_hi[axis] = -0.5 + s;
  const Plane& plane = m_planes[m_plane_of[donor]];
  return s * box_fraction_below(plane.normal, plane.height, box_lo, box_hi);
}

double VolumeFraction::split_face_flux(int axis, std::int64_t face) const {
  const FaceSplit* split = m_parts->split(axis, face);
  double flux = 0.0;
  const auto fragments = m_parts->fragments_of(axis, *split);
  for (size_t k = 0; k < fragments.size(); ++k)
    flux += conductance(fragments[k]) * (*m_fragment_velocity)[axis][split->first + k];
  return flux;
}

VolumeFraction::FragmentPass VolumeFraction::gather_fragments(int axis, double dt) const {
  const auto parts = m_parts->parts();
  const double dx = m_mac.dx();
  FragmentPass pass;
  pass.part_delta.assign(parts.size(), 0.0);
  const auto water_of = [&](int p) {
    return parts[p].slot ? m_fraction[parts[p].cell] : m_part_fraction[p];
  };
  // Each fragment's water, from its upwind part at its fill (a whole cell: its PLIC slab).
  struct Flow {
    int from_part, to_part;  // −1: a whole cell
    std::int64_t from_cell, to_cell;
    double water;
  };
  std::vector<Flow> flows;
  std::vector<double> given(parts.size(), 0.0), outward(parts.size(), 0.0);
  for (const FaceSplit& split : m_parts->split_faces(axis)) {
    const auto [minus_cell, plus_cell] = cells_beside(m_mac, axis, split.face);
    const auto fragments = m_parts->fragments_of(axis, split);
    for (size_t k = 0; k < fragments.size(); ++k) {
      const FaceFragment& fragment = fragments[k];
      const double w = (*m_fragment_velocity)[axis][split.first + k];
      const double flux = conductance(fragment) * w;
      if (fragment.minus >= 0) outward[fragment.minus] += flux;
      if (fragment.plus >= 0) outward[fragment.plus] -= flux;
      const double s = std::min(std::abs(w) * dt / dx, 1.0);
      if (s == 0.0) continue;
      const bool positive = w > 0.0;
      Flow flow{positive ? fragment.minus : fragment.plus,
                positive ? fragment.plus : fragment.minus, positive ? minus_cell : plus_cell,
                positive ? plus_cell : minus_cell, 0.0};
      if (flow.from_part >= 0) {
        // A part filled past its room gives in proportion, as a cell past F = 1 does (one
        // the shell swept away, all it holds).
        const double room = std::max(m_part_room[flow.from_part], kFullOrEmpty);
        const double fill = std::max(water_of(flow.from_part) / room, 0.0);
        flow.water = s * conductance(fragment) * fill;
        given[flow.from_part] += flow.water;
      } else {
        flow.water = conductance(fragment) * slab_water(flow.from_cell, axis, positive, s);
      }
      if (flow.water > 0.0) flows.push_back(flow);
    }
  }
  // No part gives more than it holds.
  std::vector<double> scale(parts.size(), 1.0);
  for (size_t p = 0; p < parts.size(); ++p)
    if (given[p] > std::max(water_of(static_cast<int>(p)), 0.0))
      scale[p] = std::max(water_of(static_cast<int>(p)), 0.0) / given[p];
  for (const Flow& flow : flows) {
    const double water = flow.from_part >= 0 ? flow.water * scale[flow.from_part] : flow.water;
    if (flow.from_part >= 0)
      pass.part_delta[flow.from_part] -= water;
    else
      pass.whole_delta.push_back({flow.from_cell, -water});
    if (flow.to_part >= 0)
      pass.part_delta[flow.to_part] += water;
    else
      pass.whole_delta.push_back({flow.to_cell, water});
  }
  // Each liquid part's dilation: its fill at the step's start times its outward flux through
  // its fragments and its moving shells' pieces (zero after the projection).
  const bool moving = m_shell_flux != nullptr && m_shell_flux->size() == parts.size();
  for (size_t p = 0; p < parts.size(); ++p) {
    if (m_part_liquid.size() != parts.size() || m_part_liquid[p] == 0) continue;
    const double shell = moving ? (*m_shell_flux)[p][axis] : 0.0;
    const double dilation = m_part_fill[p] * (outward[p] + shell) * dt / dx;
    pass.part_delta[p] += dilation;
    pass.dilation += dilation;
  }
  return pass;
}

double VolumeFraction::apply_fragments(const FragmentPass& pass,
                                       std::vector<std::int64_t>& cut_now) {
  const auto parts = m_parts->parts();
  double clipped = 0.0;
  const auto grow = [&](std::int64_t cell) {
    const Eigen::Vector3i c = m_mac.coordinates(Location::Cell, cell);
    m_wet.lo = m_wet.lo.cwiseMin(c);
    m_wet.hi = m_wet.hi.cwiseMax(c);
  };
  const auto mixed = [](double f) { return f > kFullOrEmpty && f < 1.0 - kFullOrEmpty; };
  for (size_t p = 0; p < parts.size(); ++p) {
    if (pass.part_delta[p] == 0.0) continue;
    double& water = parts[p].slot ? m_fraction[parts[p].cell] : m_part_fraction[p];
    const double value = water + pass.part_delta[p];
    water = std::max(value, 0.0);
    clipped += water - value;
    grow(parts[p].cell);
  }
  for (const auto& [cell, delta] : pass.whole_delta) {
    const double value = m_fraction[cell] + delta;
    m_fraction[cell] = std::max(value, 0.0);
    clipped += m_fraction[cell] - value;
    grow(cell);
    if (m_plane_of[cell] < 0 && mixed(m_fraction[cell])) cut_now.push_back(cell);
  }
  return clipped;
}

void VolumeFraction::fit(const LevelSet& level_set, std::vector<double>& scratch) {
  const auto& phi = level_set.phi();
  const double dx = m_mac.dx();
  const Eigen::Vector3d lo = Eigen::Vector3d::Constant(-0.5), hi = Eigen::Vector3d::Constant(0.5);
  scratch.resize(m_fraction.size());
  const std::int64_t count = m_mac.size(Location::Cell);
#pragma omp parallel for schedule(static)
  for (std::int64_t c = 0; c < count; ++c) {
    if (std::abs(phi[c]) >= std::sqrt(3.0) * dx) {  // no plane through the centre cuts it
      scratch[c] = phi[c] > 0.0 ? 0.0 : 1.0;
      continue;
    }
    const Eigen::Vector3d normal = normal_at(level_set, m_mac.coordinates(Location::Cell, c));
    scratch[c] = box_fraction_below(normal, -phi[c] / dx, lo, hi);
  }
  m_fraction.swap(scratch);
}

std::vector<std::pair<std::int64_t, double>> VolumeFraction::cells_whole_water() const {
  std::vector<std::pair<std::int64_t, double>> whole;
  if (m_parts == nullptr) return whole;
  for (size_t p = 0; p < m_parts->parts().size(); ++p) {  // parts in cell order
    const CellPart& part = m_parts->parts()[p];
    if (whole.empty() || whole.back().first != part.cell) whole.push_back({part.cell, 0.0});
    whole.back().second += part.slot ? m_fraction[part.cell] : m_part_fraction[p];
  }
  return whole;
}

void VolumeFraction::correct(LevelSet& level_set, std::vector<double>& scratch, bool signs_only,
                             std::span<const std::uint8_t> left) {
  auto& phi = level_set.phi();
  const double dx = m_mac.dx();
  const std::int64_t count = m_mac.size(Location::Cell);
  scratch = phi;  // the normals read φ as it was
  std::vector<double>& corrected = scratch;
  // Cut cells: a cell with parts the correction reaches (no ray between centres crosses its
  // shells: a corner cut off) reads its whole water, its far parts' with its slot's.
  const std::vector<std::pair<std::int64_t, double>> whole = cells_whole_water();
  std::int64_t moved = 0, mixed = 0;
#pragma omp parallel for schedule(static) reduction(+ : moved, mixed)
  for (std::int64_t c = 0; c < count; ++c) {
    if (!left.empty() && left[c] != 0) continue;
    double fraction = m_fraction[c];
    if (!m_cut_cell.empty() && m_cut_cell[c] != 0)
      fraction =
          std::lower_bound(whole.begin(), whole.end(), c, [](const auto& entry, std::int64_t cell) {
            return entry.first < cell;
          })->second;
    if (fraction <= kFullOrEmpty) {
      if (phi[c] <= 0.0) corrected[c] = 0.5 * dx, ++moved;  // F holds none: air
      continue;
    }
    if (fraction >= 1.0 - kFullOrEmpty) {
      if (phi[c] > 0.0) corrected[c] = -0.5 * dx, ++moved;  // F fills it: water
      continue;
    }
    ++mixed;
    if (signs_only && (phi[c] <= 0.0) == (fraction >= 0.5)) continue;
    // The centre's signed distance to F's plane (the plane n·x = d, x about the centre).
    const Eigen::Vector3d normal = normal_at(level_set, m_mac.coordinates(Location::Cell, c));
    corrected[c] = -plane_height(normal, fraction) * dx;
    ++moved;
  }
  phi.swap(corrected);
  if (signs_only) {  // the step's last correction: what F holds beyond full, after the step
    const double excess =
        ordered_sum(count, [&](std::int64_t c) { return std::max(m_fraction[c] - 1.0, 0.0); });
    m_stats.excess = excess * dx * dx * dx;
  }
  m_stats.mixed_cells = mixed;
  m_stats.moved_cells += moved;
}

}  // namespace shellflow::grid_fluid
