#pragma once
// Home Assistant's side of a discovery config's value_template (mqtt/discovery.hpp), for
// the tests: the one form the bridge writes, `{{ value_json['key'] }}` with an optional
// ` | default(none)`, evaluated on a bank document as Jinja would — so that a test shows
// the template reaches the value the document really holds, and what text it renders.

#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace unima::test_support {

/// The value `value_template` reaches in `document`: null for a missing key under
/// `default(none)`; nullopt when the template is of another form or its key is missing.
template <typename Json>
std::optional<Json> template_value(std::string_view value_template, const Json& document) {
  constexpr std::string_view open = "{{ value_json['", close = " }}", fallback = " | default(none)";
  if (!value_template.starts_with(open) || !value_template.ends_with(close)) return std::nullopt;
  auto inner = value_template.substr(open.size(), value_template.size() - open.size() - close.size());
  const bool has_default = inner.ends_with(fallback);
  if (has_default) inner.remove_suffix(fallback.size());
  if (!inner.ends_with("']")) return std::nullopt;
  inner.remove_suffix(2);
  std::string key;
  for (std::size_t i = 0; i < inner.size(); ++i) {
    if (inner[i] == '\'') return std::nullopt;  // an unescaped quote would end the key
    if (inner[i] == '\\' && i + 1 < inner.size()) ++i;
    key += inner[i];
  }
  if (document.contains(key)) return document[key];
  if (has_default) return Json(nullptr);
  return std::nullopt;
}

/// The text Jinja renders of a JSON value: True, False, None, a number, a string.
template <typename Json>
std::string jinja_text(const Json& value) {
  if (value.is_null()) return "None";
  if (value.is_boolean()) return value.template get<bool>() ? "True" : "False";
  if (value.is_string()) return value.template get<std::string>();
  return value.dump();
}

}  // namespace unima::test_support
