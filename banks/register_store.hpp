#pragma once
// The values of all banks, by bank and offset. Knows what an off-line device reads
// (SPEC §1) and tells a listener about every value the bridge publishes to UnimaBUS, and
// another that something a read returns may have changed (who publishes northbound).
// Pure: no clock, no I/O. Presence time-outs are decided outside and set here.

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "banks/bank_id.hpp"
#include "banks/device_table.hpp"
#include "banks/source_ref.hpp"
#include "banks/tenths.hpp"

namespace unima::banks {

/// Size and table of one bank in this config; length 0 means the bank does not exist.
/// A D_N bank may be longer than its table (banks::device_bank_length).
struct BankShape {
  std::uint16_t length = 0;
  const DeviceTable* table = nullptr;
};
using BankShapes = std::array<BankShape, bank_count>;

/// How many registers of a bank, from offset 0, hold values — what telegrams may fill and
/// sources may name: its table's, or all of them. A D_N past its table reads 0x7FFF.
inline std::uint16_t filled_length(const BankShape& shape) {
  return shape.table ? std::min(shape.table->length(), shape.length) : shape.length;
}

/// The shapes of a config: every bank its fixed length (SPEC §1); a D_N exists when a
/// device is configured for it, and `device_tables` says which table.
BankShapes standard_shapes(const std::array<const DeviceTable*, 4>& device_tables, const DeviceTable* io_module,
                           const DeviceTable* bridge_internal);

/// Offsets inside bank C (seed 004 §6.2.3).
namespace c_bank {
inline constexpr std::uint16_t user_analog_outputs = 0x00;  // 16 registers
inline constexpr std::uint16_t user_binary_inputs = 0x10;
inline constexpr std::uint16_t user_binary_outputs = 0x12;
inline constexpr std::uint16_t online_bits = 0x13;
inline constexpr std::uint16_t modbus_error_bit = 15;
inline constexpr unsigned user_output_count = 16;
}  // namespace c_bank

class RegisterStore {
 public:
  /// A value the bridge publishes to UnimaBUS changed (W, X, C user outputs), or was written.
  using ChangeListener = std::function<void(BankId bank, std::uint16_t offset, std::uint16_t value)>;

  explicit RegisterStore(const BankShapes& shapes);

  bool exists(BankId bank) const { return bank_(bank).length != 0; }
  std::uint16_t length(BankId bank) const { return bank_(bank).length; }
  const DeviceTable* table(BankId bank) const { return shapes_[index_of(bank)].table; }

  /// Registers [offset, offset + out.size()) of a bank, as a Modbus master reads them.
  /// Precondition: the range lies inside the bank.
  void read(BankId bank, std::uint16_t offset, std::span<std::uint16_t> out) const;
  std::uint16_t read(BankId bank, std::uint16_t offset) const;

  /// Values a UnimaBUS telegram carried into a D_N or S_N bank. A telegram is taken
  /// whole or not at all: false, and nothing stored, when it runs past the end of the
  /// bank's table (or the bank does not exist) — the registers of a D_N past its table
  /// read 0x7FFF whatever a telegram says.
  bool store_telegram(BankId bank, std::uint16_t offset, std::span<const std::uint16_t> values);
  /// banks::filled_length of the bank's shape.
  std::uint16_t filled_length(BankId bank) const { return bank_(bank).filled_length; }
  void set_online(BankId bank, bool online);
  bool online(BankId bank) const { return bank_(bank).online; }

  /// A Modbus write into W or X. Precondition: bank is W or X and offset inside it.
  void write(BankId bank, std::uint16_t offset, std::uint16_t value);
  /// True once a master wrote W+offset or X (or the state file brought the value back):
  /// an unset register is never published as if it were a setpoint (SPEC §10).
  bool written(BankId bank, std::uint16_t offset) const { return bank_(bank).carried[offset] != 0; }
  /// User analog output n (1..16) = C+(n-1): the output of a function block (SPEC §4).
  void set_user_output(unsigned n, std::uint16_t value);
  /// Banks A, B and C+0x10/+0x12 read their sources at every read, so a mapped register
  /// changes the moment its source does. A's sources must not be A, B, C+0x10 or C+0x12,
  /// nor the bits' B, C+0x10 or C+0x12 (config/source_ref_parser): a read would never end.
  /// Bank A shows its sources in tenths of their unit (banks/tenths.hpp).
  void set_mapping(const Mapping& mapping);
  /// The value of a source: a register, or 0/1 for a bit source. A bit of a register that
  /// is not measured reads 0, as bits of an off-line device do (SPEC §1).
  std::uint16_t read_source(const SourceRef& source) const;
  /// True when the register holds a value a telegram (or a write) put there.
  bool measured(BankId bank, std::uint16_t offset) const;

  /// C+0x13 bit 15; the 2 s hold is kept by the caller, who has the clock.
  void set_modbus_error(bool error);
  std::uint16_t online_bits() const;

  void set_change_listener(ChangeListener listener) { listener_ = std::move(listener); }
  /// Called after anything a read may return differently changed: a telegram, presence, a
  /// write, a user output, the Modbus error bit. Which bank is not said: A, B and C read
  /// their sources in the others, so whoever listens reads again what it publishes.
  void set_content_listener(std::function<void()> listener) { content_listener_ = std::move(listener); }

  /// Carries over what the old config's store held: W, X, the user outputs, and the
  /// D_N/S_N values of banks whose table did not change (for a SIGHUP reload).
  void take_state_from(const RegisterStore& old);

 private:
  struct Bank {
    std::uint16_t length = 0;
    std::uint16_t filled_length = 0;
    std::vector<std::uint16_t> raw;
    std::vector<std::uint16_t> offline;  // what each register reads while not measured
    std::vector<std::uint8_t> carried;   // 1 once a telegram carried the register
    /// D_N and S_N: what a Modbus read returns, kept equal to
    /// `online && carried[r] ? raw[r] : offline[r]` by every change of those, so that a
    /// read — far more frequent than telegrams and presence changes — is one copy.
    std::vector<std::uint16_t> served;
    bool online = false;
  };
  static void refresh_served(Bank& bank, std::size_t from, std::size_t count);
  const Bank& bank_(BankId bank) const { return banks_[index_of(bank)]; }
  Bank& bank_(BankId bank) { return banks_[index_of(bank)]; }
  void notify(BankId bank, std::uint16_t offset, std::uint16_t value) const {
    if (listener_) listener_(bank, offset, value);
  }
  void content_changed() const {
    if (content_listener_) content_listener_();
  }

  BankShapes shapes_;
  std::array<Bank, bank_count> banks_;
  std::uint16_t mapped_bits(const std::array<std::optional<SourceRef>, Mapping::entries>& sources) const;
  /// C+0x10 and C+0x12 are published like the user analog outputs; they change when their
  /// sources do, so every change of a source checks them.
  void publish_mapped_bits();
  std::uint16_t published_user_inputs_ = 0;
  std::uint16_t published_user_outputs_ = 0;

  bool modbus_error_ = false;
  Mapping mapping_;
  std::array<TenthsConversion, Mapping::entries> analog_conversions_{};  // of mapping_.analog
  ChangeListener listener_;
  std::function<void()> content_listener_;
};

}  // namespace unima::banks
