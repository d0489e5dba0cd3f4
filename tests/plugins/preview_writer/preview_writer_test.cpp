// preview_writer: the plugin's files — names, sizes, PNG contents, every-n, params.

#include "shellflow/preview_writer/preview_writer.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>

#include "preview_fixture.hpp"
#include "shellflow/sdk/error.hpp"

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb_image.h>
#pragma GCC diagnostic pop

namespace shellflow::preview_writer {
namespace {

using namespace testing;
using writer_testing::SyntheticFluid;

class PreviewWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    m_out = std::filesystem::temp_directory_path() /
            ("shellflow_preview_writer_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(m_out);
    std::filesystem::create_directories(m_out);
  }
  void TearDown() override { std::filesystem::remove_all(m_out); }

  /// The slab scene's settings as scene params (what the runtime hands the plugin).
  static nlohmann::json slab_params(int every) {
    const PreviewSettings s = slab_settings();
    auto v = [](const Eigen::Vector3d& x) { return nlohmann::json::array({x.x(), x.y(), x.z()}); };
    return {{"folder", "previews"},
            {"every", every},
            {"camera",
             {{"position", v(s.camera_position)},
              {"look_at", v(s.look_at)},
              {"up", v(s.up)},
              {"fov_deg", s.vertical_fov_deg},
              {"width", s.width},
              {"height", s.height}}},
            {"absorption", s.absorption},
            {"step_voxels", s.step_voxels},
            {"smoke_color", v(s.smoke_color)},
            {"background_color", v(s.background_color)},
            {"shell_color", v(s.shell_color)},
            {"ambient", s.ambient},
            {"density_field", "density"}};
  }

  std::set<std::string> files_in(const std::filesystem::path& folder) const {
    std::set<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(folder))
      names.insert(entry.path().filename().string());
    return names;
  }

  std::filesystem::path m_out;
};

TEST_F(PreviewWriterTest, WritesOnePngPerFrameWithTheRenderedPixels) {
  SyntheticFluid fluid;
  add_slab(fluid);
  PreviewWriter writer(slab_params(2), sdk::Context{});
  writer.begin({m_out, "slab", 24.0});
  for (int frame = 0; frame < 5; ++frame) writer.write_frame({frame, frame / 24.0, {}, &fluid});
  EXPECT_EQ(files_in(m_out / "previews"),
            (std::set<std::string>{"slab_0000.png", "slab_0002.png", "slab_0004.png"}));

  int width = 0, height = 0, channels = 0;
  unsigned char* pixels =
      stbi_load((m_out / "previews" / "slab_0002.png").c_str(), &width, &height, &channels, 0);
  ASSERT_NE(pixels, nullptr) << stbi_failure_reason();
  EXPECT_EQ(width, 31);
  EXPECT_EQ(height, 21);
  EXPECT_EQ(channels, 3);
  // The file holds exactly the renderer's bytes (PNG is lossless).
  const RgbImage image = writer.renderer().render({2, 2.0 / 24.0, {}, &fluid});
  ASSERT_EQ(image.rgb.size(), static_cast<size_t>(width) * height * 3);
  EXPECT_TRUE(std::equal(image.rgb.begin(), image.rgb.end(), pixels));
  // And the centre pixel is the slab's Beer–Lambert value (row-major from the top).
  const double T = std::exp(-kSigma * kRho * kSlabLength);
  const unsigned char* centre = pixels + 3 * (kCentreX + width * kCentreY);
  EXPECT_NEAR(centre[0], 255.0 * T, kQuantisation);
  stbi_image_free(pixels);
}

TEST_F(PreviewWriterTest, ShellsOnlyFrameWritesAnImage) {
  PreviewWriter writer(slab_params(1), sdk::Context{});
  writer.begin({m_out, "shells", 24.0});
  const std::vector<sdk::ShellSurface> shells{square_shell(0.0, 0.2)};
  writer.write_frame({3, 0.125, shells, nullptr});
  int width = 0, height = 0, channels = 0;
  unsigned char* pixels =
      stbi_load((m_out / "previews" / "shells_0003.png").c_str(), &width, &height, &channels, 3);
  ASSERT_NE(pixels, nullptr) << stbi_failure_reason();
  const unsigned char* centre = pixels + 3 * (kCentreX + width * kCentreY);
  EXPECT_EQ(centre[0], 204);  // round(255 · 0.8): the shell facing the camera
  EXPECT_EQ(centre[1], 153);  // round(255 · 0.6)
  EXPECT_EQ(centre[2], 102);  // round(255 · 0.4)
  stbi_image_free(pixels);
}

TEST_F(PreviewWriterTest, WaterParamsReachTheRendererAndTheImage) {
  auto params = slab_params(1);
  params["water_color"] = {0.2, 0.4, 0.6};
  params["water_rim_color"] = {1.0, 1.0, 1.0};
  params["water_field"] = "surface_phi";
  PreviewWriter writer(params, sdk::Context{});
  const PreviewSettings& s = writer.renderer().settings();
  EXPECT_EQ(s.water_color, Eigen::Vector3d(0.2, 0.4, 0.6));
  EXPECT_EQ(s.water_rim_color, Eigen::Vector3d(1.0, 1.0, 1.0));
  EXPECT_EQ(s.water_field, "surface_phi");
  // The ball under the configured field name: the centre pixel is the water's shade at
  // normal incidence, (1 − F0) water + F0 rim with F0 = 0.02 (preview_renderer_test).
  SyntheticFluid fluid;
  add_water_ball(fluid);
  SyntheticFluid renamed;
  const auto& ball = fluid.field("phi");
  renamed.add("surface_phi", ball.location, ball.origin, ball.dx, ball.dims, 1).data[0] =
      ball.data[0];
  const RgbImage image = writer.renderer().render({0, 0.0, {}, &renamed});
  const Eigen::Vector3d expected = 0.98 * s.water_color + 0.02 * s.water_rim_color;
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(image.at(kCentreX, kCentreY)[c], 255.0 * expected[c], kQuantisation);
  // Under the default name "phi" nothing is drawn with this configuration.
  EXPECT_EQ(writer.renderer().render({0, 0.0, {}, &fluid}).at(kCentreX, kCentreY),
            Eigen::Vector3i(255, 128, 64));  // round(255 · (1, 0.5, 0.25)): background
}

TEST_F(PreviewWriterTest, WallParamsAndTheScenesGravityReachTheRenderer) {
  auto params = slab_params(1);
  params["floor_color"] = {0.3, 0.3, 0.3};
  params["grid_color"] = {0.6, 0.6, 0.6};
  params["wall_color"] = {0.1, 0.2, 0.3};
  params["floor_shadow"] = 0.25;
  sdk::Context context;
  context.gravity = {0.0, 0.0, -9.81};
  const PreviewWriter writer(params, context);
  const PreviewSettings& s = writer.renderer().settings();
  EXPECT_TRUE(s.walls);  // on by default
  EXPECT_EQ(s.wall_colours.floor, Eigen::Vector3d(0.3, 0.3, 0.3));
  EXPECT_EQ(s.wall_colours.grid, Eigen::Vector3d(0.6, 0.6, 0.6));
  EXPECT_EQ(s.wall_colours.wall, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(s.floor_shadow, 0.25);
  EXPECT_EQ(s.down, Eigen::Vector3d(0.0, 0.0, -9.81));
  sdk::DomainView box;
  box.lower = {-1.0, -1.0, -1.0};
  box.upper = {1.0, 1.0, 1.0};
  EXPECT_EQ(writer.renderer().walls(box)->floor(), 4);  // z_min: gravity along −z
  // No gravity: the floor is the wall down in the image (the camera's up is +y).
  context.gravity = Eigen::Vector3d::Zero();
  EXPECT_EQ(PreviewWriter(params, context).renderer().walls(box)->floor(), 2);
  params["walls"] = false;
  EXPECT_FALSE(PreviewWriter(params, context).renderer().settings().walls);
  params["walls"] = true;
  params["wall_color"] = {0.1, 1.2, 0.3};
  try {
    PreviewWriter bad(params, context);
    FAIL() << "a colour component above 1 was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/wall_color");
  }
}

TEST_F(PreviewWriterTest, BadCameraIsAConfigErrorNamingIt) {
  auto params = slab_params(1);
  params["camera"]["up"] = {0.0, 0.0, -2.0};  // parallel to the view direction
  try {
    PreviewWriter writer(params, sdk::Context{});
    FAIL() << "an up vector along the view direction was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/camera");
  }
  params = slab_params(1);
  params["smoke_color"] = {1.5, 0.0, 0.0};
  try {
    PreviewWriter writer(params, sdk::Context{});
    FAIL() << "a colour component above 1 was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/smoke_color");
  }
  params = slab_params(1);
  params["water_rim_color"] = {0.5, -0.1, 0.5};
  try {
    PreviewWriter writer(params, sdk::Context{});
    FAIL() << "a negative colour component was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/water_rim_color");
  }
  EXPECT_EQ(preview_file_name("plume", 7), "plume_0007.png");
}

}  // namespace
}  // namespace shellflow::preview_writer
