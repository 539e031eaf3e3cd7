#pragma once
// The one way a value from outside gets into W, X or a write block's output: Modbus
// TCP, TLS and RTU (through the request handler), MQTT commands, and whatever comes next.
// A write, in this order:
//   0. frozen: while the config makes the bridge read-only (config::writes_frozen), every
//      write is refused, whichever way it came (Status::read_only, exception 01);
//   1. rights: the client's modbus::WriteRights cover every register (else exception 01);
//   2. the register space resolves it all or nothing (else exception 02): where each value
//      lands, nothing written yet;
//   3. without a journal the values go into the store at once. With one, the journal keeps
//      the write's values as one (SPEC §10: on the disk all together or not at all), and
//      the write returns its number, which the answer waits for (io::answer_once_durable);
//      only once that is durable does the journal hand the values back to `commit`, which
//      puts them into the store, in the order the writes were kept and before the answer.
//      A write the journal could not keep changes nothing and is answered exception 04;
//   4. the store's change listener, which unimabus::Publisher::watch installs, hands W,
//      X and the user outputs to the running UnimaBUS transport: nothing reaches UnimaBUS
//      that the state file does not hold.
// Until its commit a write is pending: reads still see the old value (another master must
// not see what may yet be refused), but a read-modify-write (write_bit) builds on the
// latest pending value, so two MQTT bit commands in a row both count.
// The journal is io::StateFile in the daemon (io::Runtime gives it, and has it commit
// into the running banks, so a write pending across a reload lands in the new ones),
// none without `state.file`. Pure: the journal is an interface, its disk is elsewhere.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "banks/register_space.hpp"
#include "modbus/register_model.hpp"

namespace unima::banks {

/// Where written values are kept across a restart, before they take effect.
class WriteJournal {
 public:
  virtual ~WriteJournal() = default;
  /// Keeps the values of one write (W, X, or C at a user output's offset) as one: durable
  /// all together or not at all. Returns the write's number (> 0), which
  /// WriteResult::kept_as carries to the one who answers. Once durable, the values go to
  /// WritePath::commit of the running banks, in the order the writes were kept, before
  /// anyone waiting for the number hears of it; a write that could not be kept never does.
  virtual std::uint64_t keep(std::span<const WrittenValue> write) = 0;
  /// The value of the latest write kept for `bank` at `offset` that is neither committed
  /// nor refused yet; nullopt when none is pending.
  virtual std::optional<std::uint16_t> pending(BankId bank, std::uint16_t offset) const = 0;
};

class WritePath final : public modbus::RegisterModel {
 public:
  /// `journal` may be null: nothing is kept, every write takes effect and is answered at once.
  WritePath(RegisterSpace& space, WriteJournal* journal) : space_(space), journal_(journal) {}

  bool read_registers(std::uint16_t first, std::span<std::uint16_t> out) override { return space_.read(first, out); }
  modbus::WriteResult write_registers(std::uint16_t first, std::span<const std::uint16_t> values,
                                      const modbus::WriteRights* rights) override;
  /// Sets or clears one bit of the register at `address` (an X bit by MQTT), the other
  /// bits as the latest write left them (pending or not): the same checks, one register
  /// written.
  modbus::WriteResult write_bit(std::uint16_t address, unsigned bit, bool on, const modbus::WriteRights* rights);
  /// The bits `mask` of the register at `address` set to those of `bits` (a value of a
  /// register's bits by Sparkplug; 0xFFFF: the whole word), the others as write_bit keeps them.
  modbus::WriteResult write_field(std::uint16_t address, std::uint16_t mask, std::uint16_t bits, const modbus::WriteRights* rights);
  /// Puts a write the journal kept into the store, which publishes it. A value for a bank
  /// this config does not have is left out.
  void commit(std::span<const WrittenValue> write);

  void set_journal(WriteJournal* journal) { journal_ = journal; }
  /// While frozen, every write is refused with Status::read_only and changes nothing.
  void freeze(bool frozen) { frozen_ = frozen; }
  /// The freeze's one home: the ports ask it for what passes no write path (a write
  /// forwarded to the line of foreign slaves).
  bool frozen() const { return frozen_; }

 private:
  void apply(const WrittenValue& value);

  RegisterSpace& space_;
  WriteJournal* journal_;
  bool frozen_ = false;
  std::vector<WrittenValue> resolved_;  // the write being kept; reused, so no allocation per write
};

}  // namespace unima::banks
