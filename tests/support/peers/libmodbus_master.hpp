#pragma once
// libmodbus as a Modbus master or client: an independent implementation of the protocol,
// so that the bridge's slave side and the simulated foreign slaves are not checked only by
// code of this project talking to itself. This owns the context (TCP or RTU); the test
// calls libmodbus on it as it likes.

#include <modbus/modbus.h>

namespace unima::test_support {

class LibmodbusMaster {
 public:
  /// Takes `ctx` (nullptr when it could not be made: never connected), addresses `slave`,
  /// waits `response_seconds` for each response, and connects.
  LibmodbusMaster(modbus_t* ctx, int slave, int response_seconds = 1);
  ~LibmodbusMaster();
  LibmodbusMaster(const LibmodbusMaster&) = delete;
  LibmodbusMaster& operator=(const LibmodbusMaster&) = delete;

  modbus_t* operator*() const { return ctx_; }
  bool connected() const { return connected_; }

 private:
  modbus_t* ctx_;
  bool connected_ = false;
};

}  // namespace unima::test_support
