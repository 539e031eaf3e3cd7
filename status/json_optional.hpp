#pragma once
// A value the status document may lack is null there (never left out, never made up):
// std::optional<T> as nlohmann::json writes and reads it, for the typed parts of the
// document (status/statistic.hpp).

#include <optional>

#include <nlohmann/json.hpp>

namespace nlohmann {

template <class T>
struct adl_serializer<std::optional<T>> {
  static void to_json(json& j, const std::optional<T>& value) {
    if (value) j = *value;
    else j = nullptr;
  }
  static void from_json(const json& j, std::optional<T>& value) {
    if (j.is_null()) value.reset();
    else value = j.get<T>();
  }
};

}  // namespace nlohmann
