#pragma once
// The message of the `Error` an action throws, for tests of what a bad file is told.

#include <string>
#include <utility>

namespace unima::test_support {

/// What `action` throws as `Error`, or `none` when it throws nothing.
template <typename Error, typename Action>
std::string error_message(Action&& action, std::string none = "(no error)") {
  try {
    std::forward<Action>(action)();
  } catch (const Error& e) {
    return e.what();
  }
  return none;
}

}  // namespace unima::test_support
