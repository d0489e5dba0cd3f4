#include "shellflow/geometry/mesh_generators.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <utility>

#include "shellflow/sdk/error.hpp"

namespace shellflow::geometry {
namespace {

constexpr double kPi = std::numbers::pi;
// Sums over a few thousand triangles of O(1) values: round-off well below 1e-12 relative.
constexpr double kRoundOff = 1e-12;

Eigen::Vector3d node(const SurfaceMesh& m, int i) {
  return m.positions.row(i).transpose();
}

double area(const SurfaceMesh& m) {
  double a = 0;
  for (int t = 0; t < m.triangles.rows(); ++t) {
    const Eigen::Vector3d p = node(m, m.triangles(t, 0));
    const Eigen::Vector3d q = node(m, m.triangles(t, 1));
    const Eigen::Vector3d r = node(m, m.triangles(t, 2));
    a += 0.5 * (q - p).cross(r - p).norm();
  }
  return a;
}

/// Σ over triangles of the signed volume of the tetrahedron (reference, triangle): the
/// enclosed volume of a closed outward mesh (or of a cup whose opening lies in a plane
/// through `reference`), negative if the normals point inwards.
double signed_volume(const SurfaceMesh& m, const Eigen::Vector3d& reference = {0, 0, 0}) {
  double v = 0;
  for (int t = 0; t < m.triangles.rows(); ++t) {
    const Eigen::Vector3d p = node(m, m.triangles(t, 0)) - reference;
    const Eigen::Vector3d q = node(m, m.triangles(t, 1)) - reference;
    const Eigen::Vector3d r = node(m, m.triangles(t, 2)) - reference;
    v += p.dot(q.cross(r)) / 6.0;
  }
  return v;
}

/// Directed edge (a, b) → how many triangles traverse it in that direction.
std::map<std::pair<int, int>, int> directed_edges(const SurfaceMesh& m) {
  std::map<std::pair<int, int>, int> edges;
  for (int t = 0; t < m.triangles.rows(); ++t)
    for (int c = 0; c < 3; ++c) ++edges[{m.triangles(t, c), m.triangles(t, (c + 1) % 3)}];
  return edges;
}

/// Edges used by exactly one triangle (the boundary); fails the test if any edge is used
/// twice in the same direction or by more than two triangles (non-manifold or flipped).
std::vector<std::pair<int, int>> boundary_edges(const SurfaceMesh& m) {
  const auto edges = directed_edges(m);
  std::vector<std::pair<int, int>> boundary;
  for (const auto& [e, count] : edges) {
    EXPECT_EQ(count, 1) << "edge " << e.first << "-" << e.second
                        << " traversed twice in one direction";
    if (!edges.contains({e.second, e.first})) boundary.push_back(e);
  }
  return boundary;
}

void expect_watertight(const SurfaceMesh& m) {
  EXPECT_TRUE(boundary_edges(m).empty()) << "a closed mesh has no boundary edge";
  // Every node is used (no orphans) and the surface is a sphere: V − E + F = 2.
  std::set<int> used(m.triangles.data(), m.triangles.data() + m.triangles.size());
  EXPECT_EQ(static_cast<int>(used.size()), m.positions.rows());
  const auto edge_count = static_cast<long>(directed_edges(m).size()) / 2;
  EXPECT_EQ(m.positions.rows() - edge_count + m.triangles.rows(), 2);
}

bool has_edge(const SurfaceMesh& m, int a, int b) {
  const auto edges = directed_edges(m);
  return edges.contains({a, b}) || edges.contains({b, a});
}

// Grid ------------------------------------------------------------------------------------

TEST(MakeGrid, NumbersNodesRowByRowAndCountsTriangles) {
  const int nu = 5, nv = 4;
  const auto m = make_grid(2.0, 3.0, nu, nv, GridPattern::Regular);
  ASSERT_EQ(m.positions.rows(), nu * nv);
  EXPECT_EQ(m.triangles.rows(), 2 * (nu - 1) * (nv - 1));
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const Eigen::Vector3d p = node(m, i + nu * j);
      // Centred at the origin, i along +x, j along +y (exact: k/(n−1) − 0.5 times a size).
      EXPECT_DOUBLE_EQ(p.x(), 2.0 * (i / 4.0 - 0.5));
      EXPECT_DOUBLE_EQ(p.y(), 3.0 * (j / 3.0 - 0.5));
      EXPECT_EQ(p.z(), 0.0);
    }
  EXPECT_NEAR(area(m), 6.0, 6.0 * kRoundOff);
  for (int t = 0; t < m.triangles.rows(); ++t) {
    const Eigen::Vector3d n = (node(m, m.triangles(t, 1)) - node(m, m.triangles(t, 0)))
                                  .cross(node(m, m.triangles(t, 2)) - node(m, m.triangles(t, 0)));
    EXPECT_GT(n.z(), 0.0) << "triangle " << t << " must face +z";
  }
  // An open sheet: the boundary is the rectangle's perimeter, 2(nu−1) + 2(nv−1) edges.
  EXPECT_EQ(static_cast<int>(boundary_edges(m).size()), 2 * (nu - 1) + 2 * (nv - 1));
}

TEST(MakeGrid, PatternsChooseTheDocumentedDiagonals) {
  const int nu = 6, nv = 5;
  const auto regular = make_grid(1, 1, nu, nv, GridPattern::Regular);
  const auto herringbone = make_grid(1, 1, nu, nv, GridPattern::Herringbone);
  const auto alternating = make_grid(1, 1, nu, nv, GridPattern::Alternating);
  auto id = [&](int i, int j) { return i + nu * j; };
  for (int j = 0; j + 1 < nv; ++j)
    for (int i = 0; i + 1 < nu; ++i) {
      const bool ac_regular = has_edge(regular, id(i, j), id(i + 1, j + 1));
      const bool ac_herring = has_edge(herringbone, id(i, j), id(i + 1, j + 1));
      const bool ac_alt = has_edge(alternating, id(i, j), id(i + 1, j + 1));
      // Exactly one diagonal per quad.
      EXPECT_NE(ac_herring, has_edge(herringbone, id(i + 1, j), id(i, j + 1)));
      EXPECT_NE(ac_alt, has_edge(alternating, id(i + 1, j), id(i, j + 1)));
      EXPECT_TRUE(ac_regular);
      EXPECT_EQ(ac_herring, i % 2 == 0) << "herringbone alternates from column to column";
      EXPECT_EQ(ac_alt, (i + j) % 2 == 0) << "alternating is a checkerboard";
    }
}

TEST(MakeGrid, RejectsDegenerateArguments) {
  EXPECT_THROW(make_grid(1, 1, 1, 4, GridPattern::Regular), std::invalid_argument);
  EXPECT_THROW(make_grid(0, 1, 3, 4, GridPattern::Regular), std::invalid_argument);
}

// Boxes -----------------------------------------------------------------------------------

TEST(MakeBox, IsWatertightOutwardAndExact) {
  const Eigen::Vector3d size(1.0, 2.0, 0.5);
  for (int n : {1, 2, 5}) {
    const auto m = make_box(size, n);
    expect_watertight(m);
    EXPECT_EQ(m.positions.rows(), (n + 1) * (n + 1) * (n + 1) - (n - 1) * (n - 1) * (n - 1));
    EXPECT_EQ(m.triangles.rows(), 12 * n * n);
    // Planar faces: volume and area are exact up to round-off.
    EXPECT_NEAR(signed_volume(m), 1.0, kRoundOff);
    EXPECT_NEAR(signed_volume(m, {0.3, -0.7, 0.1}), 1.0, kRoundOff);  // independent of reference
    EXPECT_NEAR(area(m), 2 * (2.0 + 0.5 + 1.0), kRoundOff * 7);
    EXPECT_NEAR(m.positions.colwise().mean().norm(), 0.0, kRoundOff);  // centred
  }
}

TEST(MakeOpenBox, IsACupOpenTowardsPlusY) {
  const Eigen::Vector3d size(1.0, 2.0, 0.5);
  const int n = 3;
  const auto m = make_open_box(size, n);
  const auto rim = boundary_edges(m);
  EXPECT_EQ(static_cast<int>(rim.size()), 4 * n);
  for (const auto& [a, b] : rim) {
    EXPECT_DOUBLE_EQ(node(m, a).y(), 1.0);
    EXPECT_DOUBLE_EQ(node(m, b).y(), 1.0);
  }
  EXPECT_EQ(m.triangles.rows(), 10 * n * n);
  // Nodes of the missing top face's interior are not kept.
  EXPECT_EQ(m.positions.rows(),
            (n + 1) * (n + 1) * (n + 1) - (n - 1) * (n - 1) * (n - 1) - (n - 1) * (n - 1));
  // With the reference point on the opening's plane, the missing lid adds nothing: the
  // signed volume is the cup's volume, positive for outward normals.
  EXPECT_NEAR(signed_volume(m, {0, 1.0, 0}), 1.0, kRoundOff);
  EXPECT_NEAR(area(m), 2 * (2.0 + 0.5 + 1.0) - 0.5, kRoundOff * 7);
}

// Cylinder and sphere: convergence ------------------------------------------------------

TEST(MakeOpenCylinder, IsACupWhoseVolumeAndAreaConvergeAtSecondOrder) {
  const double r = 0.5, h = 1.5;
  double previous_volume_error = 0, previous_area_error = 0;
  for (int segments : {16, 32, 64, 128}) {
    const auto m = make_open_cylinder(r, h, segments, 4, true);
    const auto rim = boundary_edges(m);
    ASSERT_EQ(static_cast<int>(rim.size()), segments);
    for (const auto& [a, b] : rim) EXPECT_DOUBLE_EQ(node(m, a).y(), h);
    const double volume = signed_volume(m, {0, h, 0});
    const double surface = area(m);
    const double volume_error = std::abs(volume - kPi * r * r * h);
    const double area_error = std::abs(surface - (2 * kPi * r * h + kPi * r * r));
    EXPECT_GT(volume, 0.0) << "outward normals";
    if (previous_volume_error > 0) {
      // Inscribed polygon: error ∝ (2π/segments)^2 (sin x/x = 1 − x²/6 + …), so doubling
      // the segments divides it by 4 up to the O(h^4) term (≤ 2% at 16 segments).
      EXPECT_NEAR(previous_volume_error / volume_error, 4.0, 0.1);
      EXPECT_NEAR(previous_area_error / area_error, 4.0, 0.1);
    }
    previous_volume_error = volume_error;
    previous_area_error = area_error;
  }
  EXPECT_LT(previous_volume_error, 1e-3);
  // Without a cap the cup is a tube: two rims.
  EXPECT_EQ(static_cast<int>(boundary_edges(make_open_cylinder(r, h, 12, 3, false)).size()), 24);
}

TEST(MakeSphere, IsWatertightOnTheSphereAndConvergesAtSecondOrder) {
  const double r = 0.7;
  double previous_volume_error = 0, previous_area_error = 0;
  for (int level = 0; level <= 5; ++level) {
    const auto m = make_sphere(r, level);
    expect_watertight(m);
    EXPECT_EQ(m.triangles.rows(), 20 * (1 << (2 * level)));
    for (int i = 0; i < m.positions.rows(); ++i) EXPECT_NEAR(node(m, i).norm(), r, kRoundOff);
    const double volume = signed_volume(m);
    EXPECT_GT(volume, 0.0) << "outward normals";
    const double volume_error = 4.0 / 3.0 * kPi * r * r * r - volume;
    const double area_error = 4 * kPi * r * r - area(m);
    EXPECT_GT(volume_error, 0.0) << "an inscribed polyhedron is smaller than the sphere";
    if (level >= 3) {
      // O(h^2) with h halving per level: the ratio tends to 4; the icosphere's triangles
      // become uniform only gradually (measured 3.93, 3.98, 4.00 at levels 3, 4, 5),
      // hence ±0.1 (an O(h) error would give 2).
      EXPECT_NEAR(previous_volume_error / volume_error, 4.0, 0.1);
      EXPECT_NEAR(previous_area_error / area_error, 4.0, 0.1);
    }
    previous_volume_error = volume_error;
    previous_area_error = area_error;
  }
}

// Revolution --------------------------------------------------------------------------------

TEST(MakeRevolution, ACupProfileIsTheOpenCylinderWithItsFloor) {
  // (0, 0) → (r, 0) → (r, h): a floor closed at the axis and a wall; its volume and area
  // are the inscribed N-gon's exactly: N/2 r² sin(2π/N) h and the same plus N r sin(π/N) h
  // times 2 for the wall.
  const double r = 0.125, h = 0.2;
  const int n = 48;
  const auto m = make_revolution({{0.0, 0.0}, {r, 0.0}, {r, h}}, n, 12);
  const auto rim = boundary_edges(m);
  ASSERT_EQ(static_cast<int>(rim.size()), n);
  for (const auto& [a, b] : rim) EXPECT_DOUBLE_EQ(node(m, a).y(), h);
  const double polygon = 0.5 * n * r * r * std::sin(2.0 * kPi / n);
  const double perimeter = 2.0 * n * r * std::sin(kPi / n);
  EXPECT_NEAR(signed_volume(m, {0, h, 0}), polygon * h, kRoundOff);
  EXPECT_NEAR(area(m), polygon + perimeter * h, kRoundOff);
  // Rings spread by arc length: the floor (r = 0.125) gets 12 · 0.125/0.325 ≈ 4.6 → 5 of
  // the 12, the wall 7; the floor's first is a fan round the axis node.
  EXPECT_EQ(m.positions.rows(), 1 + 12 * n);
  EXPECT_EQ(m.triangles.rows(), n + 2 * n * 11);
}

TEST(MakeRevolution, ASemicircleProfileIsAWatertightSphereAtSecondOrder) {
  const double r = 0.3;
  double previous = 0.0;
  for (const int n : {16, 32, 64, 128}) {
    std::vector<Eigen::Vector2d> profile;
    for (int i = 0; i <= n / 2; ++i) {
      const double a = kPi * (double(i) / (n / 2) - 0.5);
      profile.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    profile.front().x() = profile.back().x() = 0.0;  // the poles exactly on the axis
    const auto m = make_revolution(profile, n, n / 2);
    expect_watertight(m);
    const double volume = signed_volume(m);
    EXPECT_GT(volume, 0.0) << "outward normals (the profile goes up the outside)";
    const double error = 4.0 / 3.0 * kPi * r * r * r - volume;
    EXPECT_GT(error, 0.0) << "inscribed";
    // O(h²) with h halving: the ratio tends to 4 (±0.1 as for the icosphere).
    if (previous > 0.0) {
      EXPECT_NEAR(previous / error, 4.0, 0.1);
    }
    previous = error;
  }
}

TEST(MakeRevolution, JoinsTwoSheetsAtAnAxisPointInside) {
  // A goblet: foot disk, stem, the stem's top closed at the axis, where the bowl's floor
  // starts. Only the bowl's rim is a boundary; the axis point is one node.
  const int n = 24;
  const auto m = make_revolution(
      {{0.0, 0.0}, {0.05, 0.0}, {0.01, 0.02}, {0.01, 0.08}, {0.0, 0.08}, {0.04, 0.1}, {0.05, 0.16}},
      n, 40);
  const auto rim = boundary_edges(m);
  ASSERT_EQ(static_cast<int>(rim.size()), n);
  for (const auto& [a, b] : rim) EXPECT_DOUBLE_EQ(node(m, a).y(), 0.16);
  int on_axis = 0;
  for (int i = 0; i < m.positions.rows(); ++i)
    if (node(m, i).head<1>().norm() == 0.0 && node(m, i).z() == 0.0) ++on_axis;
  EXPECT_EQ(on_axis, 2);  // the foot's centre and the joint
}

TEST(MakeRevolution, RejectsBadProfilesNamingTheEntry) {
  const auto expect_error = [](const nlohmann::json& spec, const std::string& where) {
    try {
      make_mesh(spec, "/mesh");
      ADD_FAILURE() << "no error for " << spec.dump();
    } catch (const ConfigError& e) {
      const std::string message = e.json_path() + ": " + e.what();
      EXPECT_NE(message.find(where), std::string::npos) << message;
    }
  };
  expect_error({{"type", "revolution"}}, "/mesh/profile");
  expect_error({{"type", "revolution"}, {"profile", {{0.1, 0.0}}}}, "/mesh/profile");
  expect_error({{"type", "revolution"}, {"profile", {{0.1, 0.0}, {-0.1, 0.2}}}}, "/mesh/profile/1");
  expect_error({{"type", "revolution"}, {"profile", {{0.1, 0.0}, {0.1, 0.0}}}}, "/mesh/profile/1");
  expect_error({{"type", "revolution"}, {"profile", {{0.1, 0.0}, {0.2}}}}, "/mesh/profile/1");
  // A segment along the axis sweeps nothing.
  expect_error({{"type", "revolution"}, {"profile", {{0.0, 0.0}, {0.0, 0.1}, {0.1, 0.1}}}}, "axis");
  EXPECT_EQ(make_mesh({{"type", "revolution"}, {"profile", {{0.0, 0.0}, {0.1, 0.0}, {0.1, 0.1}}},
                       {"segments", 8}, {"rings", 4}})
                .triangles.rows(),
            8 + 2 * 8 * 3);
}

// Boat hull ---------------------------------------------------------------------------------

TEST(MakeBoatHull, IsAnOpenHullBelowItsGunwaleOfTheVolumeItsSectionsImply) {
  const double length = 1.5, beam = 0.4, depth = 0.2, fullness = 3.0;
  // V = ∫ A(x) dx with A the half superellipse of half-axes b(u), d(u):
  // A = 2 Γ(1+1/n)²/Γ(1+2/n) b d, b = beam/2 √(1−u²), d = depth √(1−u⁴), x = length/2 u.
  const double c = 2.0 * std::pow(std::tgamma(1.0 + 1.0 / fullness), 2) /
                   std::tgamma(1.0 + 2.0 / fullness);
  double integral = 0.0;  // ∫_{−1}^{1} √(1−u²) √(1−u⁴) du, midpoint rule (error < 1e-7)
  const int samples = 200000;
  for (int i = 0; i < samples; ++i) {
    const double u = -1.0 + (i + 0.5) * 2.0 / samples;
    integral += std::sqrt((1.0 - u * u) * (1.0 - u * u * u * u)) * 2.0 / samples;
  }
  const double exact = c * 0.5 * beam * depth * 0.5 * length * integral;
  double previous = 0.0;
  for (const int n : {16, 32, 64, 128}) {
    const auto m = make_boat_hull(length, beam, depth, fullness, 2 * n, n);
    // Open only along the gunwale, which lies in y = 0; bow and stern are single nodes.
    const auto rim = boundary_edges(m);
    EXPECT_EQ(static_cast<int>(rim.size()), 2 * 2 * n);
    for (const auto& [a, b] : rim) EXPECT_NEAR(node(m, a).y(), 0.0, kRoundOff);
    EXPECT_NEAR(m.positions.col(0).maxCoeff(), 0.5 * length, kRoundOff);
    EXPECT_NEAR(m.positions.col(1).minCoeff(), -depth, kRoundOff);
    EXPECT_NEAR(m.positions.col(2).maxCoeff(), 0.5 * beam, kRoundOff);
    // Mirror symmetric across z = 0: the nodes' z sum to zero.
    EXPECT_NEAR(m.positions.col(2).sum(), 0.0, 1e-9);
    const double volume = signed_volume(m);  // the gunwale's plane passes the origin
    EXPECT_GT(volume, 0.0) << "outward normals";
    const double error = std::abs(exact - volume);
    // The √ ends and the superellipse's corners converge more slowly than O(h²); the
    // error halves at least with each doubling, and is below 1 % at the finest.
    if (previous > 0.0) {
      EXPECT_LT(error, 0.5 * previous);
    }
    previous = error;
  }
  EXPECT_LT(previous, 0.01 * exact);
  EXPECT_THROW(make_boat_hull(1.0, 0.3, 0.1, 0.5, 8, 8), std::invalid_argument);
}

// OBJ -------------------------------------------------------------------------------------

class ObjFile : public ::testing::Test {
 protected:
  void SetUp() override {
    m_dir = std::filesystem::temp_directory_path() /
            ("shellflow_mesh_generators_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(m_dir);
  }
  void TearDown() override { std::filesystem::remove_all(m_dir); }
  std::filesystem::path m_dir;
};

TEST_F(ObjFile, RoundTripsAQuadAndATriangleAndDropsUnusedVertices) {
  const auto file = m_dir / "shape.obj";
  {
    std::ofstream out(file);
    // Values exactly representable in float (tinyobjloader reads in single precision).
    out << "# a unit square and a triangle above it\n"
           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
           "v 9 9 9\n"  // unused
           "v 0.5 0.25 -1.75\n"
           "f 1 2 3 4\nf 1 2 6\n";
  }
  const auto m = load_obj(file);
  ASSERT_EQ(m.positions.rows(), 5);
  ASSERT_EQ(m.triangles.rows(), 3);
  // Used vertices keep the file's order; values exact.
  EXPECT_EQ(node(m, 2), Eigen::Vector3d(1, 1, 0));
  EXPECT_EQ(node(m, 4), Eigen::Vector3d(0.5, 0.25, -1.75));
  EXPECT_DOUBLE_EQ(
      area(m),
      1.0 + 0.5 * (Eigen::Vector3d(1, 0, 0).cross(Eigen::Vector3d(0.5, 0.25, -1.75))).norm());
  for (int i = 0; i < m.triangles.size(); ++i) EXPECT_LT(m.triangles.data()[i], 5);
  // make_mesh reads the same file through the scene form.
  const auto via_scene = make_mesh({{"type", "obj"}, {"file", file.string()}});
  EXPECT_EQ(via_scene.positions, m.positions);
  EXPECT_EQ(via_scene.triangles, m.triangles);
}

TEST_F(ObjFile, MissingOrEmptyFileIsAnIoErrorNamingThePath) {
  const auto missing = m_dir / "no_such_cup.obj";
  try {
    load_obj(missing);
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  const auto empty = m_dir / "points.obj";
  std::ofstream(empty) << "v 0 0 0\nv 1 0 0\n";
  try {
    load_obj(empty);
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(empty.string()), std::string::npos) << e.what();
  }
}

// Scene form ------------------------------------------------------------------------------

TEST(MeshSchema, EveryNumericFieldHasADefaultARangeAndADoc) {
  const auto schema = mesh_schema().json();
  ASSERT_EQ(schema.at("kind"), "variant");
  ASSERT_EQ(schema.at("key"), "type");
  for (const char* option : {"grid", "box", "open_box", "open_cylinder", "sphere", "obj"})
    ASSERT_TRUE(schema.at("options").contains(option)) << option;
  for (const auto& [name, option] : schema.at("options").items())
    for (const auto& [field, spec] : option.at("fields").items()) {
      EXPECT_TRUE(spec.contains("doc")) << name << "/" << field;
      const auto kind = spec.at("kind").get<std::string>();
      if (kind == "number" || kind == "integer") {
        EXPECT_TRUE(spec.contains("default")) << name << "/" << field;
        EXPECT_TRUE(spec.contains("min")) << name << "/" << field;
      }
    }
}

TEST(MakeMesh, FillsDefaultsFromTheSchemaAndChecksSizes) {
  const auto grid = make_mesh({{"type", "grid"}, {"nodes_u", 3}});
  EXPECT_EQ(grid.positions.rows(), 3 * 11);  // nodes_v defaults to 11
  const auto herring =
      make_mesh({{"type", "grid"}, {"nodes_u", 3}, {"nodes_v", 3}, {"pattern", "herringbone"}});
  EXPECT_EQ(herring.triangles, make_grid(1, 1, 3, 3, GridPattern::Herringbone).triangles);
  EXPECT_EQ(make_mesh({{"type", "sphere"}, {"subdivisions", 1}}).triangles.rows(), 80);
  EXPECT_EQ(
      make_mesh({{"type", "open_cylinder"}, {"segments", 5}, {"rings", 2}, {"bottom_cap", false}})
          .triangles.rows(),
      20);
  try {
    make_mesh({{"type", "box"}, {"size", {1, -1, 1}}}, "/solids/0/mesh");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/solids/0/mesh/size");
  }
  EXPECT_THROW(make_mesh({{"type", "torus"}}), ConfigError);
}

TEST(Transform, ScalesThenRotatesThenTranslates) {
  const auto t = transform_from_json(
      {{"scale", 2.0}, {"rotate_axis", {0, 0, 3}}, {"rotate_deg", 90}, {"translate", {1, 2, 3}}});
  // (1,0,0) → scale (2,0,0) → 90° about z (0,2,0) → translate (1,4,3); cos(π/2) round-off.
  EXPECT_LT((t * Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(1, 4, 3)).norm(), kRoundOff);
  // Defaults: the identity, exactly.
  EXPECT_EQ(transform_from_json(nlohmann::json::object()) * Eigen::Vector3d(1, 2, 3),
            Eigen::Vector3d(1, 2, 3));
  EXPECT_THROW(transform_from_json({{"rotate_axis", {0, 0, 0}}, {"rotate_deg", 10}}), ConfigError);

  auto m = make_grid(1, 1, 2, 2, GridPattern::Regular);
  apply_transform(t, m);
  EXPECT_LT((node(m, 1) - t * Eigen::Vector3d(0.5, -0.5, 0)).norm(), kRoundOff);
  EXPECT_NEAR(area(m), 4.0, kRoundOff);  // scale 2 → area × 4
}

}  // namespace
}  // namespace shellflow::geometry
