// End to end: `shellflow run configs/rigid_shells_falling.json` loads the bullet_rigid
// plugin, writes one mesh per body per frame, and the shells come to rest on the ground
// (and the box inside the cup) without sinking through it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>
#include "test_paths.hpp"

namespace {

namespace fs = std::filesystem;

constexpr double kMargin = 0.005;  // the scene's "margin": the collision skin [m]

/// Lowest and highest y and the mean x, z of the "v" lines of an OBJ file.
struct Extent {
  double min_y = std::numeric_limits<double>::infinity();
  double mean_x = 0.0, mean_z = 0.0;
  int nodes = 0;
};
Extent obj_extent(const fs::path& file) {
  std::ifstream in(file);
  EXPECT_TRUE(in) << file;
  Extent e;
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("v ", 0) == 0) {
      std::istringstream s(line.substr(2));
      double x = 0, y = 0, z = 0;
      s >> x >> y >> z;
      e.min_y = std::min(e.min_y, y);
      e.mean_x += x;
      e.mean_z += z;
      ++e.nodes;
    }
  e.mean_x /= e.nodes;
  e.mean_z /= e.nodes;
  return e;
}

/// Columns of metrics.csv by header name.
std::vector<double> column(const fs::path& csv, const std::string& name) {
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  std::vector<std::string> names;
  std::istringstream h(header);
  for (std::string n; std::getline(h, n, ',');) names.push_back(n);
  const auto index = std::find(names.begin(), names.end(), name) - names.begin();
  EXPECT_LT(static_cast<size_t>(index), names.size()) << name << " not in " << header;
  std::vector<double> values;
  for (std::string line; std::getline(in, line);) {
    std::istringstream s(line);
    std::string cell;
    for (long i = 0; i <= index; ++i) std::getline(s, cell, ',');
    values.push_back(std::stod(cell));
  }
  return values;
}

TEST(RigidShellsFallingScene, RunsAndComesToRestOnTheGround) {
  const fs::path out =
      fs::temp_directory_path() / ("shellflow_rigid_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string command = shellflow::test_paths::cli() + " run " +
                              shellflow::test_paths::source_dir() +
                              "/configs/rigid_shells_falling.json --out " + out.string() + " > " +
                              (out.string() + ".log") + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;

  for (const std::string body : {"cup", "box", "ball", "can"}) {
    for (int frame : {0, 72})
      ASSERT_TRUE(fs::exists(out / "meshes" /
                             ("shells_" + body + "_" + (frame ? "0072" : "0000") + ".obj")))
          << body << " frame " << frame;
    // Nothing below the skin: contact keeps every node one margin above the plane, to the
    // 1e-4 m of the solver's position correction (measured: 2e-6 m).
    const Extent last = obj_extent(out / "meshes" / ("shells_" + body + "_0072.obj"));
    EXPECT_GT(last.min_y, kMargin - 1e-4) << body;
  }
  // The box fell into the cup (open top 0.6 × 0.6 m at the origin) and rests on its floor:
  // one margin per shell between them, 0.015 m above the ground (measured 0.014995).
  const Extent box = obj_extent(out / "meshes" / "shells_box_0072.obj");
  const Extent cup = obj_extent(out / "meshes" / "shells_cup_0072.obj");
  EXPECT_NEAR(box.min_y, cup.min_y + 2 * kMargin, 1e-3);
  EXPECT_LT(std::abs(box.mean_x - cup.mean_x), 0.3);
  EXPECT_LT(std::abs(box.mean_z - cup.mean_z), 0.3);

  // Contacts only remove energy: the total (kinetic + potential) at the end is far below
  // the start, and no step raises it by more than 1e-3 of the start (measured 1.1e-4:
  // Bullet's split-impulse position correction).
  const auto ke = column(out / "metrics.csv", "shells.kinetic_energy");
  const auto pe = column(out / "metrics.csv", "shells.potential_energy");
  ASSERT_EQ(ke.size(), 72u);
  const double start = ke.front() + pe.front();
  for (size_t i = 1; i < ke.size(); ++i)
    EXPECT_LT(ke[i] + pe[i] - (ke[i - 1] + pe[i - 1]), 1e-3 * start) << "step " << i + 1;
  EXPECT_LT(ke.back() + pe.back(), 0.25 * start);
  EXPECT_GT(column(out / "metrics.csv", "shells.contacts").back(), 0.0);
  fs::remove_all(out);
  fs::remove(out.string() + ".log");
}

}  // namespace
