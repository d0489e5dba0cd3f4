#pragma once
// Per-step figures a plugin reports; the runtime writes them as columns of metrics.csv,
// prefixed with the plugin instance's name.

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace shellflow::sdk {

class Metrics {
 public:
  void set(std::string_view key, double value) {
    for (auto& [k, v] : m_values)
      if (k == key) {
        v = value;
        return;
      }
    m_values.emplace_back(std::string(key), value);
  }
  const std::vector<std::pair<std::string, double>>& values() const { return m_values; }
  void clear() { m_values.clear(); }

 private:
  std::vector<std::pair<std::string, double>> m_values;
};

}  // namespace shellflow::sdk
