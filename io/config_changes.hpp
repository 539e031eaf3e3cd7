#pragma once
// The way every channel that carries a config from afar (the control socket, HTTP's
// /api/config, MQTT's config/set) reaches the one flow of SPEC §19. app's coordinator
// implements it — it reloads the bridge and probes the services — and sets it in the
// runtime; a channel only passes the text and who sent it, and returns the answer.

#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "remote/change_answer.hpp"
#include "remote/config_status.hpp"

namespace unima::io {

class ConfigChanges {
 public:
  using Done = std::function<void(const remote::ChangeAnswer&)>;

  virtual ~ConfigChanges() = default;
  /// The text of a whole config, checked, applied and probed; `done` is called once, on the
  /// loop, when the flow ends (at once when it is refused or busy).
  virtual void apply(std::string text, remote::Source source, std::string by, Done done) = 0;
  /// Back to the operator's file, through the same flow.
  virtual void revert(remote::Source source, std::string by, Done done) = 0;
  /// The config in force: source, sha256, file, applied time, last result; with its text
  /// when `with_text` (it may hold passwords: only for who may change it).
  virtual nlohmann::json in_force(bool with_text) const = 0;
  /// The config the last change put out of force, for the page's diff (its text: as
  /// in_force's): {"number" (null: the operator's file), "text"}, the text null with a
  /// "text_error" when it cannot be had; null when there is nothing to compare with.
  virtual nlohmann::json replaced() const = 0;
  /// The remote configs kept, newest first.
  virtual nlohmann::json history() const = 0;
  /// The status document's "config_in_force".
  virtual remote::ConfigStatus status() const = 0;
};

}  // namespace unima::io
