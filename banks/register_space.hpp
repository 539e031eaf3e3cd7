#pragma once
// The Modbus view of the banks: reads and writes by protocol address, with the access
// rules of SPEC §1 (readable banks, write-only W and X unless configured readable).

#include <cstdint>
#include <functional>
#include <span>

#include "banks/address_map.hpp"
#include "banks/register_store.hpp"

namespace unima::banks {

/// A value of a write as the store takes it: W+offset, X, or, for a write block
/// (MBS_RegW), bank C at its user output's offset. What the state file keeps.
struct WrittenValue {
  BankId bank = BankId::W;
  std::uint16_t offset = 0;
  std::uint16_t value = 0;

  friend bool operator==(const WrittenValue&, const WrittenValue&) = default;
};

struct AccessRules {
  /// W and X are write-only in the seed; reading them back is an extension (SPEC §1).
  bool readable_write_banks = true;
};

class RegisterSpace {
 public:
  using Landed = std::function<void(const WrittenValue&)>;

  RegisterSpace(AddressMap map, RegisterStore& store, AccessRules rules)
      : map_(std::move(map)), store_(store), rules_(rules) {}

  /// Fills `out` from `first` on. False, and `out` unspecified, when any register of the
  /// range is not readable (the caller answers exception 02).
  bool read(std::uint16_t first, std::span<std::uint16_t> out) const;
  /// Where a write of `values` from `first` lands, all or nothing: false, and `landed`
  /// never called, when any register is not writable; else `landed` hears each value.
  /// Writes nothing: banks::WritePath applies the values (write_path.hpp).
  bool resolve(std::uint16_t first, std::span<const std::uint16_t> values, const Landed& landed) const;

  const AddressMap& map() const { return map_; }
  RegisterStore& store() { return store_; }
  const RegisterStore& store() const { return store_; }

 private:
  bool readable(const Window& w) const;
  /// Reads `out` from `address` on, all inside `w`, which is readable.
  void read_window(const Window& w, std::uint16_t address, std::span<std::uint16_t> out) const;
  static bool writable(const Window& w) {
    return w.kind == Window::Kind::write_block || (w.kind == Window::Kind::bank && is_write_bank(w.bank));
  }
  /// Calls fn(window, first address in it, count) over the range; false at the first gap.
  template <typename Fn>
  bool for_each_window(std::uint16_t first, std::size_t count, Fn&& fn) const;

  AddressMap map_;
  RegisterStore& store_;
  AccessRules rules_;
};

}  // namespace unima::banks
