#pragma once
// Home Assistant's documented rules for an MQTT discovery config, as the tests check the
// bridge's configs against them: the data in tests/data/home_assistant_discovery_schema.json
// (written from Home Assistant's pages, apart from the bridge's own table of classes in
// mqtt/home_assistant_classes), the rules here — the keys each component knows and needs,
// the sensor device classes with the units and state classes each allows, the binary
// sensor device classes, the entity categories, a display precision a whole number >= 0.

#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace unima::test_support {

class HomeAssistantSchema {
 public:
  using Json = nlohmann::ordered_json;

  explicit HomeAssistantSchema(Json rules) : rules_(std::move(rules)) {}

  /// The rules of the repository's data file.
  static HomeAssistantSchema documented() {
    std::ifstream file(std::string(UNIMA_SOURCE_DIR) + "/tests/data/home_assistant_discovery_schema.json");
    return HomeAssistantSchema(Json::parse(file));
  }

  /// What `config`, a discovery config of `component` ("sensor", "binary_sensor", …), breaks
  /// of the rules, one sentence each: empty when Home Assistant takes it.
  std::vector<std::string> violations(const std::string& component, const Json& config) const {
    std::vector<std::string> found;
    const auto& components = rules_["components"];
    if (!components.contains(component)) return {"unknown component " + component};
    const auto& rules = components[component];
    for (const auto& key : rules["required"])
      if (!config.contains(key.get<std::string>())) found.push_back("no " + key.get<std::string>());
    for (const auto& [key, value] : config.items())
      if (!contains(rules["keys"], Json(key))) found.push_back("unknown key " + key);
    if (config.contains("name") && !(config["name"].is_string() && !config["name"].get<std::string>().empty()))
      found.push_back("name not a text");
    if (config.contains("entity_category") && !contains(rules["entity_categories"], config["entity_category"]))
      found.push_back("entity_category " + config["entity_category"].dump() + " not allowed for " + component);
    if (config.contains("enabled_by_default") && !config["enabled_by_default"].is_boolean())
      found.push_back("enabled_by_default not a boolean");
    if (component == "binary_sensor" && config.contains("device_class") &&
        !contains(rules_["binary_sensor_device_classes"], config["device_class"]))
      found.push_back("binary_sensor device_class " + config["device_class"].dump() + " unknown");
    if (component == "sensor") sensor_violations(config, found);
    return found;
  }

 private:
  static bool contains(const Json& list, const Json& value) {
    for (const auto& item : list)
      if (item == value) return true;
    return false;
  }

  void sensor_violations(const Json& config, std::vector<std::string>& found) const {
    const Json unit = config.contains("unit_of_measurement") ? config["unit_of_measurement"] : Json(nullptr);
    if (config.contains("state_class") && !contains(rules_["state_classes"], config["state_class"]))
      found.push_back("state_class " + config["state_class"].dump() + " unknown");
    if (config.contains("suggested_display_precision")) {
      const auto& precision = config["suggested_display_precision"];
      if (!precision.is_number_integer() || precision.get<long>() < 0)
        found.push_back("suggested_display_precision " + precision.dump() + " not a whole number >= 0");
    }
    if (!config.contains("device_class")) return;
    const auto& classes = rules_["sensor_device_classes"];
    const auto name = config["device_class"].is_string() ? config["device_class"].get<std::string>() : std::string();
    if (!classes.contains(name)) {
      found.push_back("sensor device_class " + config["device_class"].dump() + " unknown");
      return;
    }
    const auto& device_class = classes[name];
    if (!contains(device_class["units"], unit) && !contains(device_class["units"], Json("*")))
      found.push_back(fmt::format("unit {} not one of {} for device_class {}", unit.dump(), device_class["units"].dump(), name));
    if (config.contains("state_class") && !contains(device_class["state_classes"], config["state_class"]))
      found.push_back(fmt::format("state_class {} not one of {} for device_class {}", config["state_class"].dump(),
                                  device_class["state_classes"].dump(), name));
  }

  Json rules_;
};

}  // namespace unima::test_support
