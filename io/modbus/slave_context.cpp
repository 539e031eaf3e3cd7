#include "io/modbus/slave_context.hpp"

#include "io/runtime.hpp"
#include "platform/asio.hpp"

namespace unima::io {

SlaveContext slave_context(Runtime& runtime) {
  SlaveContext context;
  context.registers = runtime.banks->writes.get();
  context.state = runtime.state.get();
  context.unit_id = runtime.config().modbus.address;
  context.writes_frozen = runtime.banks->writes->frozen();
  const auto& ext = runtime.config().modbus.extensions;
  context.options.max_read_registers = modbus::max_read_registers_tcp;
  context.options.read_holding_registers = ext.function_3;
  context.options.write_multiple_registers = ext.function_16;
  context.options.device_identification = ext.function_43;
  // The error hold and the monitor live as long as the runtime, which outlives the ports.
  context.on_fault = [&runtime] { runtime.error_hold.fault(); };
  context.on_transaction = [monitor = runtime.monitor.get()](const modbus::Transaction& t) { monitor->observe(t); };
  if (auto routes = runtime.config().modbus.gateway_routes()) {
    context.gateway = std::make_shared<const config::GatewayRoutes>(std::move(*routes));
    context.line = &runtime.gateway_line;  // lives as long as the runtime, which outlives the ports
  }
  return context;
}

}  // namespace unima::io
