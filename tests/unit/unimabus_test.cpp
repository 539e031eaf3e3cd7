// The UnimaBUS side (SPEC §6): the feed protocol's codec and line splitting, routing of
// telegrams into the banks, on-line tracking and the simulator's values.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <map>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "banks/register_store.hpp"
#include "banks/table_catalog.hpp"
#include "unimabus/feed_codec.hpp"
#include "unimabus/line_splitter.hpp"
#include "unimabus/presence.hpp"
#include "unimabus/recording.hpp"
#include "unimabus/publisher.hpp"
#include "unimabus/sim_generator.hpp"
#include "unimabus/telegram_router.hpp"

namespace unima::unimabus {
namespace {

using banks::BankId;
using namespace std::chrono_literals;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// ---------------------------------------------------------------------------------------
// parse_feed_line

Telegram parsed(std::string_view line) {
  const FeedLine result = parse_feed_line(line);
  if (const auto* error = std::get_if<std::string>(&result)) {
    ADD_FAILURE() << "'" << line << "' was refused: " << *error;
    return {};
  }
  return std::get<Telegram>(result);
}

std::string refused(std::string_view line) {
  const FeedLine result = parse_feed_line(line);
  if (const auto* error = std::get_if<std::string>(&result)) {
    EXPECT_FALSE(error->empty()) << line;
    return *error;
  }
  ADD_FAILURE() << "'" << line << "' was accepted";
  return {};
}

TEST(FeedCodec, SpecExample) {
  const Telegram t = parsed(R"({"addr":5,"slot":0,"offset":33,"values":[853,854]})");
  EXPECT_EQ(t.address, 5);
  EXPECT_EQ(t.slot, 0);
  EXPECT_EQ(t.offset, 33);
  EXPECT_EQ(t.values, (std::vector<std::uint16_t>{853, 854}));
}

TEST(FeedCodec, FieldOrderAndWhitespaceDoNotMatter) {
  const Telegram t = parsed(R"(  { "values" : [ 1 ] , "offset" : 0, "slot": 7, "addr": 255 }  )");
  EXPECT_EQ(t.address, 255);
  EXPECT_EQ(t.slot, 7);
  EXPECT_EQ(t.offset, 0);
  EXPECT_EQ(t.values, (std::vector<std::uint16_t>{1}));
}

TEST(FeedCodec, NegativeValuesAreTwosComplement) {
  const Telegram t = parsed(R"({"addr":5,"slot":0,"offset":0,"values":[-1,-32768,65535,0,32767]})");
  EXPECT_EQ(t.values, (std::vector<std::uint16_t>{0xFFFF, 0x8000, 0xFFFF, 0x0000, 0x7FFF}));
}

TEST(FeedCodec, TimeFieldIsAccepted) {
  const Telegram t = parsed(R"({"t":1.25,"addr":5,"slot":1,"offset":2,"values":[3]})");
  EXPECT_EQ(t.address, 5);
  EXPECT_EQ(t.slot, 1);
  EXPECT_EQ(t.offset, 2);
  EXPECT_EQ(t.values, (std::vector<std::uint16_t>{3}));
  (void)parsed(R"({"t":17,"addr":5,"slot":1,"offset":2,"values":[3]})");
}

TEST(FeedCodec, ADeviceTypeNamesOneOfTheUnitsComponents) {
  const Telegram usc = parsed(R"({"addr":5,"slot":0,"device":"usc","offset":3,"values":[1500]})");
  ASSERT_NE(usc.device, nullptr);
  EXPECT_EQ(usc.device->id, "usc");
  EXPECT_EQ(usc.offset, 3);
  const Telegram alias = parsed(R"({"addr":5,"slot":0,"device":"microgen-chp","offset":0,"values":[1]})");
  ASSERT_NE(alias.device, nullptr);
  EXPECT_EQ(alias.device->id, "unigen-chp");
  EXPECT_EQ(parsed(R"({"addr":5,"slot":0,"offset":0,"values":[1]})").device, nullptr);
}

TEST(FeedCodec, ABadDeviceIsAnError) {
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"device":"turbine","offset":0,"values":[1]})"), "unknown device type \"turbine\""));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"device":7,"offset":0,"values":[1]})"), "\"device\" must be"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":2,"device":"usc","offset":0,"values":[1]})"), "slot"));
}

TEST(FeedCodec, Errors) {
  EXPECT_TRUE(contains(refused("this is not json"), "JSON"));
  EXPECT_FALSE(refused("").empty());
  EXPECT_FALSE(refused(R"({"addr":5,"slot":0,"offset":33,"values":[853])").empty());  // cut short
  EXPECT_FALSE(refused("[1,2,3]").empty());
  EXPECT_FALSE(refused("42").empty());
  EXPECT_FALSE(refused(R"("text")").empty());
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"offset":33,"values":[1],"colour":"red"})"), "colour"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"offset":33})"), "values"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"offset":33,"values":[]})"), "values"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"offset":33,"values":7})"), "values"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"offset":33,"values":[1,2.5]})"), "values"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"offset":33,"values":[1,"2"]})"), "values"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"offset":33,"values":[true]})"), "values"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"offset":33,"values":[70000]})"), "70000"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"offset":33,"values":[-32769]})"), "-32769"));
  EXPECT_TRUE(contains(refused(R"({"addr":256,"slot":0,"offset":33,"values":[1]})"), "addr"));
  EXPECT_TRUE(contains(refused(R"({"addr":-1,"slot":0,"offset":33,"values":[1]})"), "addr"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":8,"offset":33,"values":[1]})"), "slot"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"offset":65536,"values":[1]})"), "offset"));
  EXPECT_TRUE(contains(refused(R"({"addr":"5","slot":0,"offset":33,"values":[1]})"), "addr"));
  EXPECT_TRUE(contains(refused(R"({"slot":0,"offset":33,"values":[1]})"), "addr"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"offset":33,"values":[1]})"), "slot"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"values":[1]})"), "offset"));
  EXPECT_FALSE(refused(R"({"addr":5,"slot":0,"offset":65535,"values":[1,2]})").empty());  // past 0xFFFF
}

// SPEC §6: anything after the JSON value but white space is an error, a NUL byte too —
// which the JSON library alone would take for the end of the line.
TEST(FeedCodec, NothingButWhiteSpaceMayFollowTheTelegram) {
  using namespace std::string_literals;
  const auto telegram = R"({"addr":5,"slot":0,"offset":1,"values":[1]})"s;
  const auto recorded = R"({"t":0,"addr":5,"slot":0,"offset":1,"values":[1]})"s;
  for (const auto& after : {"\0garbage"s, "\0"s, "  \t\0x"s, " garbage"s, "{}"s, telegram}) {
    SCOPED_TRACE(nlohmann::json(after).dump(-1, ' ', true));
    EXPECT_TRUE(contains(refused(telegram + after), "not JSON"));
    EXPECT_TRUE(std::holds_alternative<std::string>(parse_recorded_line(recorded + after)));
  }
  EXPECT_TRUE(contains(refused('\0' + telegram), "not JSON"));
  EXPECT_TRUE(contains(refused(telegram + "\0garbage"s), "a NUL byte at byte 44"));
  EXPECT_EQ(parsed(telegram + " \t\r\n").values, std::vector<std::uint16_t>{1});
  EXPECT_TRUE(std::holds_alternative<RecordedTelegram>(parse_recorded_line(recorded + " \t")));
}

TEST(FeedCodec, HugeIntegersAreRefusedNotWrapped) {
  // 2^64-1 must not slip through as -1.
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"offset":0,"values":[18446744073709551615]})"), "value"));
  EXPECT_TRUE(contains(refused(R"({"addr":5,"slot":0,"offset":0,"values":[9223372036854775808]})"), "value"));
  EXPECT_TRUE(contains(refused(R"({"addr":18446744073709551615,"slot":0,"offset":0,"values":[1]})"), "addr"));
}

TEST(FeedCodec, FormatChange) {
  EXPECT_EQ(format_change(BankId::W, 3, 1234), "{\"bank\":\"W\",\"offset\":3,\"value\":1234}\n");
  EXPECT_EQ(format_change(BankId::C, 15, 0), "{\"bank\":\"C\",\"offset\":15,\"value\":0}\n");
  EXPECT_EQ(format_change(BankId::X, 0, 65535), "{\"bank\":\"X\",\"offset\":0,\"value\":65535}\n");
}

TEST(FeedCodec, FormatErrorIsValidJsonWithEscapes) {
  const std::string message = "bad \"line\"\\ here\nand\ttab";
  const std::string line = format_error(message);
  ASSERT_FALSE(line.empty());
  EXPECT_EQ(line.back(), '\n');
  EXPECT_EQ(line.find('\n'), line.size() - 1);  // one line only
  EXPECT_TRUE(contains(line, R"(\"line\")")) << line;
  const auto json = nlohmann::json::parse(line);
  ASSERT_TRUE(json.is_object());
  EXPECT_EQ(json.size(), 1u);
  EXPECT_EQ(json.at("error").get<std::string>(), message);
  EXPECT_EQ(format_error("plain"), "{\"error\":\"plain\"}\n");
}

TEST(FeedCodec, FormatErrorSurvivesInvalidUtf8) {
  const std::string line = format_error(std::string("bad \xFF byte"));
  EXPECT_EQ(line.back(), '\n');
  nlohmann::json json;
  EXPECT_NO_THROW(json = nlohmann::json::parse(line));
  EXPECT_TRUE(json.is_object());
}

// ---------------------------------------------------------------------------------------
// LineSplitter

struct Collected {
  std::vector<std::string> lines;
  int overlong = 0;
};

void feed(LineSplitter& splitter, std::string_view bytes, Collected& out) {
  splitter.feed(
      bytes, [&](std::string_view line) { out.lines.emplace_back(line); }, [&] { ++out.overlong; });
}

TEST(LineSplitter, SplitAtEveryBytePosition) {
  const std::string stream = "{\"addr\":5}\r\nsecond line\n\nthird\r\n";
  const std::vector<std::string> expected = {"{\"addr\":5}", "second line", "", "third"};
  for (std::size_t cut = 0; cut <= stream.size(); ++cut) {
    LineSplitter splitter;
    Collected out;
    feed(splitter, std::string_view(stream).substr(0, cut), out);
    feed(splitter, std::string_view(stream).substr(cut), out);
    EXPECT_EQ(out.lines, expected) << "cut at " << cut;
    EXPECT_EQ(out.overlong, 0) << "cut at " << cut;
  }
  LineSplitter splitter;
  Collected out;
  for (char c : stream) feed(splitter, std::string_view(&c, 1), out);
  EXPECT_EQ(out.lines, expected);
  EXPECT_EQ(out.overlong, 0);
}

TEST(LineSplitter, ThreeLinesAtEverySplitPoint) {
  const std::string stream = "alpha\nbeta\r\ngamma\n";
  const std::vector<std::string> expected = {"alpha", "beta", "gamma"};
  for (std::size_t cut = 0; cut <= stream.size(); ++cut) {
    LineSplitter splitter(16);
    Collected out;
    feed(splitter, std::string_view(stream).substr(0, cut), out);
    feed(splitter, std::string_view(stream).substr(cut), out);
    EXPECT_EQ(out.lines, expected) << "cut at " << cut;
  }
  LineSplitter splitter(16);
  Collected out;
  for (char c : stream) feed(splitter, std::string_view(&c, 1), out);
  EXPECT_EQ(out.lines, expected);
}

// The limit counts the line, not the "\r" of its "\r\n".
TEST(LineSplitter, TheLimitCountsTheLineWithoutItsCarriageReturn) {
  const std::string full(16, 'x');
  for (const std::size_t cut : {std::size_t{0}, std::size_t{16}, std::size_t{17}}) {
    LineSplitter splitter(16);
    Collected out;
    const std::string stream = full + "\r\n" + full + "y\r\n" + full + "y\n" + full + "\n";
    feed(splitter, std::string_view(stream).substr(0, cut), out);
    feed(splitter, std::string_view(stream).substr(cut), out);
    EXPECT_EQ(out.lines, (std::vector<std::string>{full, full})) << "cut at " << cut;
    EXPECT_EQ(out.overlong, 2) << "cut at " << cut;
  }
}

TEST(LineSplitter, IncompleteLineWaitsForItsNewline) {
  LineSplitter splitter;
  Collected out;
  feed(splitter, "one\ntw", out);
  EXPECT_EQ(out.lines, (std::vector<std::string>{"one"}));
  feed(splitter, "o", out);
  EXPECT_EQ(out.lines.size(), 1u);
  feed(splitter, "\n", out);
  EXPECT_EQ(out.lines, (std::vector<std::string>{"one", "two"}));
}

TEST(LineSplitter, OverlongLineIsReportedOnceAndTheNextLineComesThrough) {
  const std::string stream = "short\n" + std::string(40, 'x') + "\nafter\n";
  const std::vector<std::string> expected = {"short", "after"};
  {
    LineSplitter splitter(16);
    Collected out;
    feed(splitter, stream, out);
    EXPECT_EQ(out.lines, expected);
    EXPECT_EQ(out.overlong, 1);
  }
  {
    LineSplitter splitter(16);
    Collected out;
    for (char c : stream) feed(splitter, std::string_view(&c, 1), out);
    EXPECT_EQ(out.lines, expected);
    EXPECT_EQ(out.overlong, 1);
  }
  for (std::size_t cut = 0; cut <= stream.size(); ++cut) {
    LineSplitter splitter(16);
    Collected out;
    feed(splitter, std::string_view(stream).substr(0, cut), out);
    feed(splitter, std::string_view(stream).substr(cut), out);
    EXPECT_EQ(out.lines, expected) << "cut at " << cut;
    EXPECT_EQ(out.overlong, 1) << "cut at " << cut;
  }
}

TEST(LineSplitter, LimitIsInclusive) {
  LineSplitter splitter(16);
  Collected out;
  feed(splitter, std::string(16, 'a') + "\n" + std::string(17, 'b') + "\n", out);
  EXPECT_EQ(out.lines, (std::vector<std::string>{std::string(16, 'a')}));
  EXPECT_EQ(out.overlong, 1);
}

TEST(LineSplitter, TwoOverlongLinesAreReportedTwice) {
  LineSplitter splitter(8);
  Collected out;
  feed(splitter, std::string(20, 'a') + "\n" + std::string(20, 'b') + "\nok\n", out);
  EXPECT_EQ(out.lines, (std::vector<std::string>{"ok"}));
  EXPECT_EQ(out.overlong, 2);
}

// ---------------------------------------------------------------------------------------
// TelegramRouter

const banks::DeviceTable& table(std::string_view id) {
  const banks::DeviceTable* t = banks::find_device_type(id);
  if (!t) throw std::runtime_error("missing table");
  return *t;
}

banks::BankShapes shapes() {
  return banks::standard_shapes({&table("unigen-chp"), &table("uvr"), nullptr, nullptr}, banks::io_module_table(),
                                banks::bridge_internal_table());
}

/// Every register of every existing bank as read with all banks on-line.
std::map<std::pair<BankId, std::uint16_t>, std::uint16_t> snapshot(banks::RegisterStore& store) {
  std::map<std::pair<BankId, std::uint16_t>, std::uint16_t> values;
  for (BankId bank : banks::all_banks)
    for (std::uint16_t i = 0; i < store.length(bank); ++i) values[{bank, i}] = store.read(bank, i);
  return values;
}

void all_online(banks::RegisterStore& store) {
  for (BankId bank : banks::all_banks)
    if (banks::is_device_bank(bank) || banks::is_module_bank(bank)) store.set_online(bank, true);
}

struct RouterFixture : ::testing::Test {
  static constexpr std::uint8_t bridge_address = 9;
  RouterFixture()
      : store(shapes()),
        router(standard_routes(bridge_address, store, {{BankId::D1, 5}, {BankId::D2, 6}, {BankId::D3, 7}}), store) {
    all_online(store);
  }
  banks::RegisterStore store;
  TelegramRouter router;
};

TEST_F(RouterFixture, StandardRoutes) {
  const auto routes = standard_routes(bridge_address, store, {{BankId::D1, 5}, {BankId::D2, 6}, {BankId::D3, 7}});
  std::set<std::tuple<BankId, int, int>> got;
  for (const auto& r : routes) got.insert({r.bank, r.address, r.slot});
  std::set<std::tuple<BankId, int, int>> expected = {{BankId::D1, 5, 0}, {BankId::D2, 6, 0}};  // no D3 bank
  for (unsigned n = 1; n <= 7; ++n) expected.insert({banks::module_bank(n), bridge_address, static_cast<int>(n)});
  EXPECT_EQ(got, expected);
  EXPECT_EQ(routes.size(), 9u);
}

TEST_F(RouterFixture, DeviceGetsSlotZeroTelegramsOfItsAddress) {
  const auto before = snapshot(store);
  const auto outcome = router.apply(Telegram{5, 0, 33, {853, 854}});
  EXPECT_TRUE(outcome.error.empty()) << outcome.error;
  EXPECT_EQ(outcome.updated, (std::vector<BankId>{BankId::D1}));
  EXPECT_EQ(store.read(BankId::D1, 33), 853);
  EXPECT_EQ(store.read(BankId::D1, 34), 854);
  // Nothing else changed.
  auto after = snapshot(store);
  after[{BankId::D1, 33}] = before.at({BankId::D1, 33});
  after[{BankId::D1, 34}] = before.at({BankId::D1, 34});
  EXPECT_EQ(after, before);

  const auto d2 = router.apply(Telegram{6, 0, 0, {1, 2, 3}});
  EXPECT_EQ(d2.updated, (std::vector<BankId>{BankId::D2}));
  EXPECT_EQ(store.read(BankId::D2, 2), 3);
}

TEST_F(RouterFixture, ModuleGetsItsSlotAtTheBridgeAddress) {
  const auto outcome = router.apply(Telegram{bridge_address, 3, 0, {11, 12, 13}});
  EXPECT_TRUE(outcome.error.empty()) << outcome.error;
  EXPECT_EQ(outcome.updated, (std::vector<BankId>{BankId::S3}));
  EXPECT_EQ(store.read(BankId::S3, 0), 11);
  EXPECT_EQ(store.read(BankId::S3, 2), 13);
  EXPECT_NE(store.read(BankId::S2, 0), 11);
  EXPECT_NE(store.read(BankId::S4, 0), 11);
}

TEST_F(RouterFixture, OtherAddressesAreIgnored) {
  const auto before = snapshot(store);
  for (const Telegram& t : {Telegram{42, 0, 0, {1, 2}}, Telegram{5, 3, 0, {1, 2}}, Telegram{bridge_address, 0, 0, {1}},
                            Telegram{6, 1, 0, {1}}, Telegram{7, 0, 0, {1}}}) {
    const auto outcome = router.apply(t);
    EXPECT_TRUE(outcome.error.empty()) << outcome.error;
    EXPECT_TRUE(outcome.updated.empty()) << int(t.address) << "/" << int(t.slot);
  }
  EXPECT_EQ(snapshot(store), before);
}

TEST_F(RouterFixture, ValuesPastTheBankAreRefusedWhole) {
  const auto before = snapshot(store);
  const auto outcome = router.apply(Telegram{5, 0, 62, {1, 2, 3}});
  EXPECT_TRUE(outcome.updated.empty());
  EXPECT_TRUE(contains(outcome.error, "D1")) << outcome.error;
  const auto module = router.apply(Telegram{bridge_address, 2, 19, {1, 2}});
  EXPECT_TRUE(module.updated.empty());
  EXPECT_TRUE(contains(module.error, "S2")) << module.error;
  EXPECT_EQ(snapshot(store), before);
  // Right up to the end is fine.
  const auto fits = router.apply(Telegram{5, 0, 62, {1, 2}});
  EXPECT_TRUE(fits.error.empty()) << fits.error;
  EXPECT_EQ(store.read(BankId::D1, 63), 2);
}

// A UVR's D_N is 64 registers (seed §6.1) but its table 49: past the table nothing is
// stored, so those registers keep reading 0x7FFF (SPEC §1).
TEST_F(RouterFixture, ValuesPastTheTableAreRefusedWholeThoughTheBankGoesOn) {
  const auto uvr_length = table("uvr").length();
  ASSERT_LT(uvr_length, banks::device_bank_length);
  const auto before = snapshot(store);
  const auto outcome = router.apply(Telegram{6, 0, static_cast<std::uint16_t>(uvr_length - 1), {1, 2}});
  EXPECT_TRUE(outcome.updated.empty());
  EXPECT_TRUE(contains(outcome.error, "past the end of bank D2 (uvr: 49 registers)")) << outcome.error;
  EXPECT_EQ(snapshot(store), before);
  EXPECT_EQ(store.read(BankId::D2, uvr_length), banks::not_measured);
}

// A unit's CHP controller and its voltage regulator share the unit's address (seed §3.2.1).
struct SharedAddressRouter : ::testing::Test {
  SharedAddressRouter() : store(shapes()), router(standard_routes(1, store, {{BankId::D1, 5}, {BankId::D2, 5}}), store) {
    all_online(store);
  }
  Telegram to(const char* device, std::uint16_t offset, std::vector<std::uint16_t> values) {
    Telegram t{5, 0, offset, std::move(values)};
    t.device = device ? &table(device) : nullptr;
    return t;
  }
  banks::RegisterStore store;
  TelegramRouter router;
};

TEST_F(SharedAddressRouter, ATelegramNamingItsDeviceFillsOnlyThatDevice) {
  const auto before = snapshot(store);
  const auto uvr = router.apply(to("uvr", 0, {77}));
  EXPECT_TRUE(uvr.error.empty()) << uvr.error;
  EXPECT_EQ(uvr.updated, (std::vector<BankId>{BankId::D2}));
  EXPECT_EQ(store.read(BankId::D2, 0), 77);
  EXPECT_EQ(store.read(BankId::D1, 0), before.at({BankId::D1, 0}));

  const auto chp = router.apply(to("microgen-chp", 0, {88}));  // an alias names the same type
  EXPECT_EQ(chp.updated, (std::vector<BankId>{BankId::D1}));
  EXPECT_EQ(store.read(BankId::D1, 0), 88);
  EXPECT_EQ(store.read(BankId::D2, 0), 77);
}

TEST_F(SharedAddressRouter, ATelegramNotNamingItsDeviceIsRefusedAndAppliedToNone) {
  const auto before = snapshot(store);
  const auto outcome = router.apply(to(nullptr, 0, {77}));
  EXPECT_TRUE(outcome.updated.empty());
  EXPECT_FALSE(outcome.ignored);
  EXPECT_TRUE(contains(outcome.error, "D1 (unigen-chp)")) << outcome.error;
  EXPECT_TRUE(contains(outcome.error, "D2 (uvr)")) << outcome.error;
  EXPECT_TRUE(contains(outcome.error, "\"device\"")) << outcome.error;
  EXPECT_EQ(snapshot(store), before);
}

TEST_F(SharedAddressRouter, ADeviceTypeNotConfiguredAtTheAddressIsIgnoredNotAnError) {
  const auto before = snapshot(store);
  const auto usc = router.apply(to("usc", 0, {77}));
  EXPECT_TRUE(usc.error.empty()) << usc.error;
  EXPECT_TRUE(usc.ignored);
  EXPECT_TRUE(usc.updated.empty());
  Telegram elsewhere = to("uvr", 0, {77});
  elsewhere.address = 6;
  EXPECT_TRUE(router.apply(elsewhere).ignored);
  EXPECT_EQ(snapshot(store), before);
}

TEST_F(RouterFixture, ATelegramNamingTheRightDeviceAtAnUnsharedAddressIsTaken) {
  Telegram t{5, 0, 1, {42}};
  t.device = &table("unigen-chp");
  EXPECT_EQ(router.apply(t).updated, (std::vector<BankId>{BankId::D1}));
  t.device = &table("uvr");  // D2 is a uvr, but at address 6
  EXPECT_TRUE(router.apply(t).ignored);
  EXPECT_EQ(store.read(BankId::D1, 1), 42);
}

// ---------------------------------------------------------------------------------------
// Presence

const Presence::Clock::time_point t0 = Presence::Clock::time_point{} + 1000s;

TEST(Presence, HeardIsTrueOnlyOnTheFirstHearing) {
  Presence presence(5s);
  EXPECT_FALSE(presence.online(BankId::D1));
  EXPECT_TRUE(presence.heard(BankId::D1, t0));
  EXPECT_TRUE(presence.online(BankId::D1));
  EXPECT_FALSE(presence.heard(BankId::D1, t0 + 1s));
  EXPECT_FALSE(presence.heard(BankId::D1, t0 + 2s));
  EXPECT_TRUE(presence.heard(BankId::S2, t0 + 2s));
  EXPECT_FALSE(presence.online(BankId::D2));
}

TEST(Presence, ExpiresAtExactlyOfflineAfter) {
  Presence presence(5s);
  presence.heard(BankId::D1, t0);
  EXPECT_TRUE(presence.expire(t0 + 5s - 1ns).empty());
  EXPECT_TRUE(presence.online(BankId::D1));
  EXPECT_EQ(presence.expire(t0 + 5s), (std::vector<BankId>{BankId::D1}));
  EXPECT_FALSE(presence.online(BankId::D1));
  EXPECT_TRUE(presence.expire(t0 + 60s).empty());  // reported once
  EXPECT_TRUE(presence.heard(BankId::D1, t0 + 61s));  // back on-line
}

TEST(Presence, HearingAgainPostponesTheExpiry) {
  Presence presence(5s);
  presence.heard(BankId::D1, t0);
  presence.heard(BankId::D1, t0 + 4s);
  EXPECT_TRUE(presence.expire(t0 + 8s).empty());
  EXPECT_EQ(presence.expire(t0 + 9s), (std::vector<BankId>{BankId::D1}));
}

TEST(Presence, NextExpiryIsTheEarliest) {
  Presence presence(5s);
  EXPECT_FALSE(presence.next_expiry().has_value());
  presence.heard(BankId::D1, t0);
  presence.heard(BankId::S2, t0 + 2s);
  presence.heard(BankId::D4, t0 + 1s);
  EXPECT_EQ(presence.next_expiry(), t0 + 5s);
  presence.heard(BankId::D1, t0 + 3s);  // D1 heard again: D4 is now first
  EXPECT_EQ(presence.next_expiry(), t0 + 6s);
  EXPECT_EQ(presence.expire(t0 + 6s), (std::vector<BankId>{BankId::D4}));
  EXPECT_EQ(presence.next_expiry(), t0 + 7s);
  const auto gone = presence.expire(t0 + 8s);
  EXPECT_EQ(gone, (std::vector<BankId>{BankId::D1, BankId::S2}));
  EXPECT_FALSE(presence.next_expiry().has_value());
}

// ---------------------------------------------------------------------------------------
// SimGenerator

std::vector<SimDevice> plant() {
  return {
      SimDevice{5, 0, table("unigen-chp").length(), &table("unigen-chp")},
      SimDevice{6, 0, table("uvr").length(), &table("uvr")},
      SimDevice{9, 1, banks::io_module_table()->length(), banks::io_module_table()},
      SimDevice{7, 0, 10, nullptr},
  };
}

bool same(const std::vector<Telegram>& a, const std::vector<Telegram>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].address != b[i].address || a[i].slot != b[i].slot || a[i].offset != b[i].offset ||
        a[i].values != b[i].values)
      return false;
  return true;
}

TEST(SimGenerator, OneTelegramPerDeviceWithAllItsRegisters) {
  SimGenerator sim(1, plant());
  const auto devices = plant();
  for (int step = 0; step < 3; ++step) {
    const auto telegrams = sim.tick();
    ASSERT_EQ(telegrams.size(), devices.size());
    for (std::size_t i = 0; i < devices.size(); ++i) {
      EXPECT_EQ(telegrams[i].address, devices[i].address);
      EXPECT_EQ(telegrams[i].slot, devices[i].slot);
      EXPECT_EQ(telegrams[i].offset, 0);
      EXPECT_EQ(telegrams[i].values.size(), devices[i].length);
      // Each D_N names its type, so a unit's components at one address stay apart.
      EXPECT_EQ(telegrams[i].device, devices[i].slot == 0 ? devices[i].table : nullptr);
    }
  }
  SimGenerator nothing(1, {});
  EXPECT_TRUE(nothing.tick().empty());
}

TEST(SimGenerator, SameSeedSameTelegrams) {
  SimGenerator a(1234, plant());
  SimGenerator b(1234, plant());
  for (int step = 0; step < 10; ++step) EXPECT_TRUE(same(a.tick(), b.tick())) << "step " << step;
}

TEST(SimGenerator, DifferentSeedDifferentTelegrams) {
  SimGenerator a(1, plant());
  SimGenerator b(2, plant());
  int differing = 0;
  for (int step = 0; step < 5; ++step) differing += same(a.tick(), b.tick()) ? 0 : 1;
  EXPECT_EQ(differing, 5);
}

TEST(SimGenerator, AnalogValuesChangeOverTime) {
  SimGenerator sim(7, plant());
  const auto devices = plant();
  std::vector<std::vector<std::set<std::uint16_t>>> seen(devices.size());
  for (std::size_t d = 0; d < devices.size(); ++d) seen[d].resize(devices[d].length);
  std::vector<Telegram> first = sim.tick();
  std::vector<Telegram> second = sim.tick();
  EXPECT_FALSE(same(first, second));  // something moves from one tick to the next
  for (const auto& ticks : {first, second})
    for (std::size_t d = 0; d < devices.size(); ++d)
      for (std::size_t i = 0; i < devices[d].length; ++i) seen[d][i].insert(ticks[d].values[i]);
  for (int step = 0; step < 60; ++step) {
    const auto telegrams = sim.tick();
    for (std::size_t d = 0; d < devices.size(); ++d)
      for (std::size_t i = 0; i < devices[d].length; ++i) seen[d][i].insert(telegrams[d].values[i]);
  }
  for (std::size_t d = 0; d < devices.size(); ++d) {
    for (std::size_t i = 0; i < devices[d].length; ++i) {
      const bool analog = !devices[d].table || devices[d].table->registers[i].kind == banks::RegisterKind::analog;
      if (!analog) continue;
      EXPECT_GT(seen[d][i].size(), 1u) << "device " << d << " offset " << i;
      // Plausible: a measured value, never "not measured".
      EXPECT_EQ(seen[d][i].count(banks::not_measured), 0u) << "device " << d << " offset " << i;
    }
  }
}

TEST(SimGenerator, ReserveRegistersAreZero) {
  SimGenerator sim(3, plant());
  const auto devices = plant();
  int reserves = 0;
  for (int step = 0; step < 5; ++step) {
    const auto telegrams = sim.tick();
    for (std::size_t d = 0; d < devices.size(); ++d) {
      if (!devices[d].table) continue;
      for (const auto& r : devices[d].table->registers) {
        if (r.kind != banks::RegisterKind::reserve) continue;
        ++reserves;
        EXPECT_EQ(telegrams[d].values[r.offset], 0) << devices[d].table->id << " " << r.id;
      }
    }
  }
  EXPECT_GT(reserves, 0);
}

TEST(SimGenerator, ThirtyTwoBitCountersOnlyGoUp) {
  SimGenerator sim(11, plant());
  const auto& chp = table("unigen-chp");
  const auto hours = chp.find("operating_hours_low");
  ASSERT_NE(hours, nullptr);
  std::uint32_t previous = 0;
  for (int step = 0; step < 200; ++step) {
    const auto telegrams = sim.tick();
    const auto& values = telegrams[0].values;
    const std::uint32_t counter = values[hours->offset] | std::uint32_t{values[hours->offset + 1]} << 16;
    if (step > 0) {
      EXPECT_EQ(counter, previous + 1);
    }
    previous = counter;
  }
}

struct RecordingTransport : Transport {
  void start() override {}
  void stop() override {}
  void publish(BankId bank, std::uint16_t offset, std::uint16_t value) override { published.push_back({bank, offset, value}); }
  std::vector<std::tuple<BankId, std::uint16_t, std::uint16_t>> published;
};

TEST(Publisher, ChangesOfTheWatchedStoreGoToTheTransport) {
  banks::RegisterStore store(shapes());
  RecordingTransport transport;
  Publisher publisher;
  publisher.set_transport(&transport);
  publisher.watch(store);
  store.write(BankId::W, 3, 1234);
  store.set_user_output(2, 7);
  ASSERT_EQ(transport.published.size(), 2u);
  EXPECT_EQ(transport.published[0], std::make_tuple(BankId::W, std::uint16_t{3}, std::uint16_t{1234}));
  EXPECT_EQ(transport.published[1], std::make_tuple(BankId::C, std::uint16_t{1}, std::uint16_t{7}));
  // A reload watches the new store: changes of the new one go out, with no transport nothing.
  banks::RegisterStore next(shapes());
  publisher.watch(next);
  publisher.set_transport(nullptr);
  next.write(BankId::X, 0, 1);
  EXPECT_EQ(transport.published.size(), 2u);
}

TEST(Publisher, TheSnapshotHoldsTheWrittenWAndXAndTheUserOutputsOfTheWatchedStore) {
  banks::RegisterStore store(shapes());
  Publisher publisher;
  EXPECT_EQ(publisher.snapshot(), "");
  publisher.watch(store);
  store.write(BankId::W, 0, 0x1234);
  store.write(BankId::W, 7, 0x7FFF);  // a master's 0x7FFF is a value it wrote
  const auto snapshot = publisher.snapshot();
  const auto lines = static_cast<std::size_t>(std::count(snapshot.begin(), snapshot.end(), '\n'));
  // W+0 and W+7 only: the unset registers and X are no setpoints (SPEC §10).
  EXPECT_EQ(lines, 2u + banks::c_bank::user_binary_outputs + 1);
  EXPECT_TRUE(snapshot.starts_with(format_change(BankId::W, 0, 0x1234) + format_change(BankId::W, 7, 0x7FFF) +
                                   format_change(BankId::C, 0, 0x7FFF)))
      << snapshot;
  EXPECT_NE(snapshot.find(format_change(BankId::C, banks::c_bank::user_binary_outputs, 0)), std::string::npos);
  EXPECT_EQ(snapshot.find("\"bank\":\"X\""), std::string::npos);
  EXPECT_EQ(snapshot.find("\"bank\":\"A\""), std::string::npos);
  store.write(BankId::X, 0, 0);
  EXPECT_NE(publisher.snapshot().find(format_change(BankId::X, 0, 0)), std::string::npos);
}

}  // namespace
}  // namespace unima::unimabus

namespace unima::unimabus {
namespace {

// ---------------------------------------------------------------------------------------
// Recordings (SPEC §6 record, replay)

using namespace std::chrono_literals;

TEST(Recording, AFormattedTelegramReadsBackTheSame) {
  Telegram t{5, 0, 3, {1500, 65531, 0}};
  t.device = banks::find_device_type("usc");
  const auto line = format_recorded(t, 1.25);
  EXPECT_EQ(line, "{\"t\":1.250000,\"addr\":5,\"slot\":0,\"device\":\"usc\",\"offset\":3,\"values\":[1500,65531,0]}\n");
  const auto parsed = parse_recorded_line(std::string_view(line).substr(0, line.size() - 1));
  ASSERT_TRUE(std::holds_alternative<RecordedTelegram>(parsed));
  const auto& back = std::get<RecordedTelegram>(parsed);
  EXPECT_DOUBLE_EQ(back.t, 1.25);
  EXPECT_EQ(back.telegram.values, t.values);
  EXPECT_EQ(back.telegram.device, t.device);
  EXPECT_EQ(format_recorded(Telegram{9, 2, 0, {1}}, 0), "{\"t\":0.000000,\"addr\":9,\"slot\":2,\"offset\":0,\"values\":[1]}\n");
}

std::string recording_error(std::string_view text) {
  try {
    (void)parse_recording(text, "rec.jsonl");
  } catch (const RecordingError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted: " << text;
  return {};
}

TEST(Recording, BlankLinesAreSkippedAndLinesCounted) {
  const auto r = parse_recording(
      "{\"t\":0,\"addr\":5,\"slot\":0,\"offset\":1,\"values\":[1]}\n"
      "\n"
      "   \r\n"
      "{\"t\":0,\"addr\":5,\"slot\":0,\"offset\":1,\"values\":[2]}\r\n"
      "{\"t\":2.5,\"addr\":5,\"slot\":1,\"offset\":0,\"values\":[3]}",
      "rec.jsonl");
  ASSERT_EQ(r.entries.size(), 3u);
  EXPECT_EQ(r.entries[1].line, 4u);
  EXPECT_EQ(r.entries[2].line, 5u);
  EXPECT_DOUBLE_EQ(r.duration(), 2.5);
}

TEST(Recording, ABadLineOrATimeGoingBackNamesFileAndLine) {
  EXPECT_EQ(recording_error("{\"t\":1,\"addr\":5,\"slot\":0,\"offset\":1,\"values\":[1]}\n"
                            "{\"t\":0.5,\"addr\":5,\"slot\":0,\"offset\":1,\"values\":[1]}\n"),
            "rec.jsonl:2: \"t\" goes back from 1 to 0.5; a recording's times never decrease");
  EXPECT_EQ(recording_error("\n{\"addr\":5,\"slot\":0,\"offset\":1,\"values\":[1]}\n"),
            "rec.jsonl:2: missing \"t\", the seconds since the recording began");
  EXPECT_TRUE(recording_error("{\"t\":-1,\"addr\":5,\"slot\":0,\"offset\":1,\"values\":[1]}").starts_with(
      "rec.jsonl:1: \"t\" must be"));
  EXPECT_TRUE(recording_error("{\"t\":1,\"addr\":5,\"slot\":0,\"offset\":1,\"values\":[1e400]}").starts_with(
      "rec.jsonl:1: "));
  EXPECT_TRUE(recording_error("not json").starts_with("rec.jsonl:1: not JSON"));
}

Recording three_telegrams() {
  return parse_recording(
      "{\"t\":0,\"addr\":5,\"slot\":0,\"offset\":0,\"values\":[1]}\n"
      "{\"t\":1,\"addr\":5,\"slot\":0,\"offset\":0,\"values\":[2]}\n"
      "{\"t\":1,\"addr\":5,\"slot\":0,\"offset\":0,\"values\":[3]}\n",
      "rec.jsonl");
}

TEST(ReplaySchedule, EachTelegramIsDueAtItsTimeDividedByTheSpeedAndTakenOnce) {
  const auto r = three_telegrams();
  ReplaySchedule schedule(r, 2.0, false);
  EXPECT_EQ(schedule.next_due(), ReplaySchedule::Duration{0});
  ASSERT_NE(schedule.take_due(0ms), nullptr);
  EXPECT_EQ(schedule.next_due(), std::chrono::milliseconds(500));
  EXPECT_EQ(schedule.take_due(499ms), nullptr);
  const auto* second = schedule.take_due(500ms);
  ASSERT_NE(second, nullptr);
  EXPECT_EQ(second->telegram.values[0], 2);
  const auto* third = schedule.take_due(500ms);
  ASSERT_NE(third, nullptr);
  EXPECT_EQ(third->telegram.values[0], 3);
  EXPECT_EQ(schedule.next_due(), std::nullopt);  // over: the devices fall silent
  EXPECT_EQ(schedule.take_due(10s), nullptr);
}

TEST(ReplaySchedule, ALoopStartsAgainAfterTheLastLine) {
  const auto r = three_telegrams();
  ReplaySchedule schedule(r, 1.0, true);
  for (int i = 0; i < 3; ++i) ASSERT_NE(schedule.take_due(1s), nullptr);
  // Lines 0, 1, 1 s apart on average 0.5 s: the second pass's t = 0 comes at 1.5 s.
  EXPECT_EQ(schedule.next_due(), std::chrono::milliseconds(1500));
  EXPECT_EQ(schedule.take_due(1500ms)->telegram.values[0], 1);
  EXPECT_EQ(schedule.next_due(), std::chrono::milliseconds(2500));
}

TEST(ReplaySchedule, ALoopedRecordingOfOneInstantStillTakesTime) {
  const auto r = parse_recording("{\"t\":0,\"addr\":5,\"slot\":0,\"offset\":0,\"values\":[1]}\n", "rec.jsonl");
  ReplaySchedule schedule(r, 1.0, true);
  ASSERT_NE(schedule.take_due(0ms), nullptr);
  EXPECT_EQ(schedule.take_due(0ms), nullptr);
  EXPECT_EQ(schedule.next_due(), ReplaySchedule::shortest_pass);
}

// Found by fuzzing (docs/fuzzing.md): 1e9 s played at 0.001 is 1e12 s, past what 64-bit
// nanoseconds hold; the conversion was undefined and came out negative, due at once.
TEST(ReplaySchedule, ATelegramTooFarAwayIsDueAtTheLatest) {
  const auto r = parse_recording("{\"t\":1e9,\"addr\":5,\"slot\":0,\"offset\":0,\"values\":[1]}\n", "rec.jsonl");
  ReplaySchedule slow(r, 0.001, true);
  EXPECT_EQ(slow.next_due(), ReplaySchedule::latest_due);
  EXPECT_EQ(slow.take_due(1s), nullptr);
  ReplaySchedule real_time(r, 1.0, false);
  EXPECT_EQ(real_time.next_due(), std::chrono::seconds(1'000'000'000));
}

}  // namespace
}  // namespace unima::unimabus
