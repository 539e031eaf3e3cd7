#include "mqtt/command_flow.hpp"

namespace unima::mqtt {

void CommandFlow::taken() {
  ++waiting_;
  if (waiting_ > bounds_.high_water) reading_ = false;
}

void CommandFlow::answered() {
  if (waiting_ > 0) --waiting_;
  if (waiting_ <= bounds_.low_water) reading_ = true;
}

}  // namespace unima::mqtt
