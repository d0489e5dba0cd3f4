#include "shellflow/kinematic_shell/motion.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "shellflow/kinematic_shell/analytic_motion.hpp"
#include "shellflow/kinematic_shell/keyframe_motion.hpp"
#include "shellflow/kinematic_shell/wave_motion.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/json_helpers.hpp"

namespace shellflow::kinematic_shell {

namespace {

using Json = nlohmann::json;

/// spec[name], or the default the schema declares for it (`fields` of the object schema).
Json field(const Json& spec, const sdk::Schema::Json& fields, const std::string& name) {
  if (spec.contains(name)) return spec.at(name);
  return Json::parse(fields.at(name).at("default").dump());
}

std::string seconds(double t) {
  char text[32];
  std::snprintf(text, sizeof text, "%g s", t);
  return text;
}

}  // namespace

void StaticMotion::evaluate(double /*t*/, const sdk::Positions& rest, sdk::Positions& positions,
                            sdk::Positions& velocities) const {
  positions = rest;
  velocities.setZero(rest.rows(), 3);
}

sdk::Schema motion_schema() {
  using sdk::Schema;
  const auto key =
      Schema::object(
          "one key pose, applied after \"transform\": rotation about the world "
          "origin, then translation")
          .field("time", Schema::number().unit("s").doc("time of the key; strictly increasing"))
          .field("translate", Schema::vec3(0.0, 0.0, 0.0).unit("m").doc("translation"))
          .field("rotate_axis", Schema::vec3(0.0, 1.0, 0.0).doc("rotation axis (not zero)"))
          .field("rotate_deg", Schema::number(0.0).unit("deg").doc("rotation angle"));
  return Schema::variant("type", "how the shell moves (left out: static)")
      .option("static", Schema::object("the shell stays where \"transform\" put it"))
      .option("keyframes",
              Schema::object("rigid key poses; the pose holds before the first key and after "
                             "the last")
                  .field("interpolation",
                         Schema::string("slerp")
                             .one_of({"slerp", "linear"})
                             .doc("slerp: rigid (rotation slerp the shorter way, translation "
                                  "linear); linear: every node on a straight line between key "
                                  "poses"))
                  .field("keys", Schema::array(key).min_items(2).doc("at least two key poses")))
      .option("analytic",
              Schema::object("x(t) = c + v t + R(ω t)(x0 − c): constant velocity and spin")
                  .field("velocity", Schema::vec3(0.0, 0.0, 0.0).unit("m/s").doc("v"))
                  .field("angular_velocity",
                         Schema::vec3(0.0, 0.0, 0.0).unit("rad/s").doc("ω (right-handed)"))
                  .field("center", Schema::vec3(0.0, 0.0, 0.0)
                                       .unit("m")
                                       .doc("c: world point the rotation is about at t = 0")))
      .option("wave",
              Schema::object("a travelling wave deforms the shell: x(t) = x0 + A sin(k·x0 − ωt "
                             "+ φ) d, exact velocities (x0: the node after \"transform\")")
                  .field("amplitude", Schema::number(0.05).min(0.0).unit("m").doc("A"))
                  .field("wave_vector", Schema::vec3(6.283185307179586, 0.0, 0.0)
                                            .unit("rad/m")
                                            .doc("k: 2π/wavelength along the direction of travel"))
                  .field("angular_frequency",
                         Schema::number(3.0).unit("rad/s").doc("ω (0: a standing wavy shape)"))
                  .field("phase", Schema::number(0.0).unit("rad").doc("φ"))
                  .field("direction", Schema::vec3(0.0, 0.0, 1.0).doc(
                                          "d: the direction nodes move in (normalised; not "
                                          "zero), e.g. the sheet's normal")));
}

std::unique_ptr<Motion> make_motion(const nlohmann::json& spec, const std::string& json_path) {
  if (spec.is_null()) return std::make_unique<StaticMotion>();
  const auto type = spec.value("type", std::string("static"));
  static const sdk::Schema::Json options = motion_schema().json().at("options");
  if (!options.contains(type))
    throw ConfigError(json_path + "/type",
                      "unknown motion \"" + type + "\"; use static, keyframes, analytic or wave");
  const auto& fields = options.at(type).at("fields");
  if (type == "static") return std::make_unique<StaticMotion>();
  if (type == "wave") {
    WaveParameters wave;
    wave.amplitude = field(spec, fields, "amplitude").get<double>();
    wave.wave_vector = sdk::json_vec3(field(spec, fields, "wave_vector"));
    wave.angular_frequency = field(spec, fields, "angular_frequency").get<double>();
    wave.phase = field(spec, fields, "phase").get<double>();
    wave.direction = sdk::json_vec3(field(spec, fields, "direction"));
    if (!(wave.amplitude >= 0.0) || !std::isfinite(wave.amplitude))
      throw ConfigError(json_path + "/amplitude", "the amplitude must be a finite number >= 0 m");
    if (!(wave.direction.norm() > 0.0))
      throw ConfigError(json_path + "/direction", "the direction must not be zero");
    if (!wave.wave_vector.allFinite() || !std::isfinite(wave.angular_frequency) ||
        !std::isfinite(wave.phase))
      throw ConfigError(json_path, "wave_vector, angular_frequency and phase must be finite");
    return std::make_unique<WaveMotion>(wave);
  }
  if (type == "analytic")
    return std::make_unique<AnalyticMotion>(sdk::json_vec3(field(spec, fields, "velocity")),
                                            sdk::json_vec3(field(spec, fields, "angular_velocity")),
                                            sdk::json_vec3(field(spec, fields, "center")));

  const auto interpolation_name = field(spec, fields, "interpolation").get<std::string>();
  if (interpolation_name != "slerp" && interpolation_name != "linear")
    throw ConfigError(json_path + "/interpolation", "use \"slerp\" or \"linear\"");
  const auto& key_fields = fields.at("keys").at("items").at("fields");
  if (!spec.contains("keys") || !spec.at("keys").is_array() || spec.at("keys").size() < 2)
    throw ConfigError(json_path + "/keys", "keyframes need at least two keys");
  std::vector<Keyframe> keys;
  const auto& list = spec.at("keys");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string key_path = json_path + "/keys/" + std::to_string(i);
    const auto& k = list.at(i);
    if (!k.contains("time") || !k.at("time").is_number())
      throw ConfigError(key_path + "/time", "every key needs a \"time\" [s]");
    Keyframe key;
    key.time = k.at("time").get<double>();
    if (i > 0 && !(key.time > keys.back().time))
      throw ConfigError(key_path + "/time",
                        "key times must increase strictly: " + seconds(key.time) + " follows " +
                            seconds(keys.back().time));
    key.translate = sdk::json_vec3(field(k, key_fields, "translate"));
    const Eigen::Vector3d axis = sdk::json_vec3(field(k, key_fields, "rotate_axis"));
    const double degrees = field(k, key_fields, "rotate_deg").get<double>();
    if (degrees != 0.0) {
      if (!(axis.norm() > 0))
        throw ConfigError(key_path + "/rotate_axis", "the rotation axis must not be zero");
      key.rotation = Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.normalized());
    }
    keys.push_back(key);
  }
  return std::make_unique<KeyframeMotion>(std::move(keys), interpolation_name == "slerp"
                                                               ? Interpolation::Slerp
                                                               : Interpolation::Linear);
}

}  // namespace shellflow::kinematic_shell
