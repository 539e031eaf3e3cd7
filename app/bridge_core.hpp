#pragma once
// What one config of the bridge consists of; shared by bridge.cpp and bridge_status.cpp.

#include <memory>

#include "banks/register_space.hpp"
#include "banks/register_store.hpp"
#include "config/config.hpp"
#include "app/bridge.hpp"
#include "banks/write_path.hpp"
#include "modbus/capture.hpp"
#include "unimabus/telegram_intake.hpp"

namespace unima::app {

struct Bridge::Core {
  config::Config config;
  std::unique_ptr<banks::RegisterStore> store;
  std::unique_ptr<banks::RegisterSpace> space;
  std::unique_ptr<banks::WritePath> writes;  // the one write path (banks/write_path.hpp)
  std::unique_ptr<unimabus::TelegramIntake> intake;  // a telegram's owner
  std::vector<modbus::CaptureRule> capture_rules;
};

}  // namespace unima::app
