// The address map (SPEC §1): windows found at their edges, sorted, and overlaps or a
// window past the last address refused with both windows' names and origins.

#include <gtest/gtest.h>

#include <string>

#include "banks/address_map.hpp"
#include "tests/support/bank_layouts.hpp"

namespace unima::banks {
namespace {

TEST(AddressMap, FindsWindowsAtTheirFirstAndLastAddresses) {
  // Given out of order: the map sorts them.
  const AddressMap map({bank_window(BankId::C, 0x1020, 20), bank_window(BankId::A, 0x1000, 16),
                        bank_window(BankId::B, 0x1010, 1)});
  ASSERT_EQ(map.windows().size(), 3u);

  auto bank_at = [&](std::uint16_t address) -> std::optional<BankId> {
    const Window* w = map.find(address);
    if (!w) return std::nullopt;
    return w->bank;
  };
  EXPECT_EQ(bank_at(0x1000), BankId::A);
  EXPECT_EQ(bank_at(0x100F), BankId::A);
  EXPECT_EQ(bank_at(0x1010), BankId::B);
  EXPECT_EQ(bank_at(0x1020), BankId::C);
  EXPECT_EQ(bank_at(0x1033), BankId::C);
  EXPECT_EQ(bank_at(0x0000), std::nullopt);
  EXPECT_EQ(bank_at(0x0FFF), std::nullopt);
  EXPECT_EQ(bank_at(0x1011), std::nullopt);
  EXPECT_EQ(bank_at(0x101F), std::nullopt);
  EXPECT_EQ(bank_at(0x1034), std::nullopt);
  EXPECT_EQ(bank_at(0xFFFF), std::nullopt);
}

TEST(AddressMap, EmptyMapFindsNothing) {
  const AddressMap map;
  EXPECT_EQ(map.find(0), nullptr);
  EXPECT_EQ(map.find(0x1000), nullptr);
}

TEST(AddressMap, WindowAtTheTopOfTheAddressSpace) {
  const AddressMap map({bank_window(BankId::W, 0xFFF0, 16)});
  ASSERT_NE(map.find(0xFFFF), nullptr);
  EXPECT_EQ(map.find(0xFFFF)->bank, BankId::W);
  EXPECT_EQ(map.find(0xFFEF), nullptr);
}

TEST(AddressMap, AdjacentAfter) {
  const AddressMap map({bank_window(BankId::A, 0x1000, 16), bank_window(BankId::B, 0x1010, 1),
                        bank_window(BankId::C, 0x1020, 20)});
  const Window* a = map.find(0x1000);
  const Window* b = map.find(0x1010);
  const Window* c = map.find(0x1020);
  ASSERT_TRUE(a && b && c);
  EXPECT_EQ(map.adjacent_after(*a), b);   // B starts where A ends
  EXPECT_EQ(map.adjacent_after(*b), nullptr);  // a gap 0x1011..0x101F follows B
  EXPECT_EQ(map.adjacent_after(*c), nullptr);  // the last window
}

TEST(AddressMap, OverlapNamesBothWindowsWithTheirRanges) {
  try {
    AddressMap map({bank_window(BankId::D1, 0x0011, 64), bank_window(BankId::W, 0x0040, 16, "bridge.yaml:4:11")});
    FAIL() << "expected OverlapError";
  } catch (const OverlapError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("bank D1 (0x0011..0x0050)"), std::string::npos) << message;
    EXPECT_NE(message.find("bank W (0x0040..0x004F)"), std::string::npos) << message;
    EXPECT_EQ(message.rfind("bridge.yaml:4:11: ", 0), 0u) << message;
  }
}

TEST(AddressMap, OverlapMessageStartsWithTheOriginOfWhicheverWindowHasOne) {
  // Only the first (lower) window was set by the config.
  try {
    AddressMap map({bank_window(BankId::W, 0x3000, 16), bank_window(BankId::A, 0x2FF8, 16, "cfg.yaml:2:6")});
    FAIL() << "expected OverlapError";
  } catch (const OverlapError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("cfg.yaml:2:6: ", 0), 0u) << message;
    EXPECT_NE(message.find("bank A (0x2FF8..0x3007)"), std::string::npos) << message;
    EXPECT_NE(message.find("bank W (0x3000..0x300F)"), std::string::npos) << message;
  }
}

TEST(AddressMap, OverlapOfAWindowInsideAnother) {
  EXPECT_THROW(AddressMap({bank_window(BankId::D1, 0x1100, 64), bank_window(BankId::B, 0x1120, 1)}), OverlapError);
  // Touching is not overlapping.
  EXPECT_NO_THROW(AddressMap({bank_window(BankId::A, 0x1000, 16), bank_window(BankId::B, 0x1010, 1)}));
}

TEST(AddressMap, WindowRunningPastTheLastAddressThrows) {
  try {
    AddressMap map({bank_window(BankId::D2, 0xFFF0, 64, "bridge.yaml:7:9")});
    FAIL() << "expected OverlapError";
  } catch (const OverlapError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("bridge.yaml:7:9: ", 0), 0u) << message;
    EXPECT_NE(message.find("bank D2"), std::string::npos) << message;
    EXPECT_NE(message.find("0xFFFF"), std::string::npos) << message;
  }
  EXPECT_NO_THROW(AddressMap({bank_window(BankId::D2, 0xFFC0, 64)}));
  EXPECT_THROW(AddressMap({bank_window(BankId::D2, 0xFFC1, 64)}), OverlapError);
}

}  // namespace
}  // namespace unima::banks
