#pragma once
// What the bridge tells UnimaBUS (SPEC §6): the registers it publishes — W, X and the
// user outputs C+0x00..0x12 — each change as it happens, and the values of all of them
// to a feed client that connects (the snapshot). Pure: the transport is handed in, and
// the store of the running config is watched (a reload hands in the new one).

#include <cstdint>
#include <string>

#include "banks/register_store.hpp"
#include "unimabus/transport.hpp"

namespace unima::unimabus {

class Publisher {
 public:
  Publisher() = default;
  Publisher(const Publisher&) = delete;
  Publisher& operator=(const Publisher&) = delete;

  /// From now on every published change of `store` goes to the transport; the store must
  /// outlive the watch (a reload watches the new store before the old one goes).
  void watch(banks::RegisterStore& store);
  /// Where changes go; null while there is none (a reload switching transports).
  void set_transport(Transport* transport) { transport_ = transport; }
  /// The published registers of the watched store, as feed lines: the W and X registers a
  /// master has written (unset ones are left out), then C+0x00..0x12.
  std::string snapshot() const;

 private:
  banks::RegisterStore* store_ = nullptr;
  Transport* transport_ = nullptr;
};

}  // namespace unima::unimabus
