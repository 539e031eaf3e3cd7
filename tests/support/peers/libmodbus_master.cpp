#include "tests/support/peers/libmodbus_master.hpp"

#include <cstdint>

namespace unima::test_support {

LibmodbusMaster::LibmodbusMaster(modbus_t* ctx, int slave, int response_seconds) : ctx_(ctx) {
  if (!ctx_) return;
  modbus_set_slave(ctx_, slave);
  modbus_set_response_timeout(ctx_, static_cast<std::uint32_t>(response_seconds), 0);
  connected_ = modbus_connect(ctx_) == 0;
}

LibmodbusMaster::~LibmodbusMaster() {
  if (!ctx_) return;
  modbus_close(ctx_);
  modbus_free(ctx_);
}

}  // namespace unima::test_support
