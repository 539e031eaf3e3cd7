#pragma once
// Waiting for a condition instead of sleeping a fixed time: a test waits as long as the
// condition takes, and fails at a deadline far beyond that.

#include <chrono>
#include <functional>

namespace unima::test_support {

/// Polls `condition` every 10 ms until it holds or `timeout` passes.
bool eventually(const std::function<bool()>& condition,
                std::chrono::milliseconds timeout = std::chrono::milliseconds(5000));

}  // namespace unima::test_support
