#pragma once
// The one way a value from outside gets into W, X or a write block's output: Modbus
// TCP, TLS and RTU (through the request handler), MQTT commands, and whatever comes next.
// A write, in this order:
//   0. frozen: while the config makes the bridge read-only (config::writes_frozen), every
//      write is refused, whichever way it came (Status::read_only, exception 01);
//   1. rights: the client's modbus::WriteRights cover every register (else exception 01);
//   2. the register space takes it all or nothing (else exception 02), into the store;
//   3. the journal keeps each value for a restart, and the write returns the number the
//      answer must wait for (io::answer_once_durable: never acknowledged before it is
//      durable, SPEC §10);
//   4. the store's change listener, which unimabus::Publisher::watch installs, hands W,
//      X and the user outputs to the running UnimaBUS transport.
// The journal is io::StateFile in the daemon (app/bridge.cpp gives it), none without
// `state.file`. Pure: the journal is an interface, its disk is elsewhere.

#include <cstdint>
#include <span>

#include "banks/register_space.hpp"
#include "modbus/register_model.hpp"

namespace unima::banks {

/// Where written values are kept across a restart.
class WriteJournal {
 public:
  virtual ~WriteJournal() = default;
  /// Keeps `value` of `bank` at `offset` (W, X, or C at a user output's offset); returns
  /// its number (> 0), which WriteResult::kept_as carries to the one who answers.
  virtual std::uint64_t keep(BankId bank, std::uint16_t offset, std::uint16_t value) = 0;
};

class WritePath final : public modbus::RegisterModel {
 public:
  /// `journal` may be null: nothing is kept, every write is answered at once.
  WritePath(RegisterSpace& space, WriteJournal* journal) : space_(space), journal_(journal) {}

  bool read_registers(std::uint16_t first, std::span<std::uint16_t> out) override { return space_.read(first, out); }
  modbus::WriteResult write_registers(std::uint16_t first, std::span<const std::uint16_t> values,
                                      const modbus::WriteRights* rights) override;
  /// Sets or clears one bit of the register at `address` (an X bit by MQTT), the other
  /// bits as they are: the same checks, one register written.
  modbus::WriteResult write_bit(std::uint16_t address, unsigned bit, bool on, const modbus::WriteRights* rights);

  void set_journal(WriteJournal* journal) { journal_ = journal; }
  /// While frozen, every write is refused with Status::read_only and changes nothing.
  void freeze(bool frozen) { frozen_ = frozen; }

 private:
  RegisterSpace& space_;
  WriteJournal* journal_;
  bool frozen_ = false;
};

}  // namespace unima::banks
