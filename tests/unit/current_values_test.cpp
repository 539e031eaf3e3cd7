// The values now (values/current_values): evaluated once per change of their bank however
// many consumers ask, again after a change, and a change of a mapped source counts for A.

#include <gtest/gtest.h>

#include "banks/register_store.hpp"
#include "config/config.hpp"
#include "values/current_values.hpp"
#include "values/value_model.hpp"

namespace unima::values {
namespace {

TEST(CurrentValues, ABanksValuesAreEvaluatedOncePerChangeForEveryAsker) {
  const auto config = config::load_text(
      "devices:\n  D1: { type: unigen-chp, address: 5 }\nmapping:\n  A: [ D1.engine_speed ]\n", "values.yaml");
  banks::RegisterStore store(config::bank_shapes(config));
  store.set_mapping(config.mapping);
  const ValueModel model(config);
  CurrentValues current(store, model);
  const auto first = current.of(banks::BankId::D1);
  const auto again = current.of(banks::BankId::D1);
  EXPECT_EQ(first, again);
  EXPECT_EQ(current.evaluations(), 1u);
  store.set_online(banks::BankId::D1, true);
  const auto& online = current.of(banks::BankId::D1);
  EXPECT_EQ(current.evaluations(), 2u);
  EXPECT_EQ(current.of(banks::BankId::D1), online);
  EXPECT_EQ(current.evaluations(), 2u);
  EXPECT_TRUE(current.snapshot()[banks::index_of(banks::BankId::D1)].online);

  // A telegram to D1 changes D1 and A (its engine_speed is mapped there): each is
  // evaluated again, once.
  current.of(banks::BankId::A);
  const auto before = current.evaluations();
  store.store_telegram(banks::BankId::D1, 0, std::vector<std::uint16_t>{1500, 1500});
  current.of(banks::BankId::D1);
  current.of(banks::BankId::A);
  current.of(banks::BankId::A);
  EXPECT_EQ(current.evaluations(), before + 2);
}

}  // namespace
}  // namespace unima::values
