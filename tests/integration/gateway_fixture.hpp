#pragma once
// The gateway's fixture (SPEC §14, issue 31): the daemon in master mode polling the stepper
// driver on a simulated line, with a PLC, the stepper driver and a dead SIC184 behind the
// gateway; raw Modbus TCP requests and the frames the simulator heard and said.

#include <cstdio>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "modbus/rtu/crc16.hpp"
#include "tests/integration/cli_under_test.hpp"
#include "tests/integration/master_fixture.hpp"

namespace unima::test {

constexpr std::uint8_t plc = 5;      // wecon-lx5v: functions 1, 2, 3, 5, 6, 15, 16
constexpr std::uint8_t stepper = 6;  // stepper-driver, polled by the bridge
constexpr std::uint8_t dead = 7;     // routed, but nothing answers

inline std::string hex(const Bytes& bytes) {
  std::string out;
  for (const auto b : bytes) {
    char cell[4];
    std::snprintf(cell, sizeof cell, "%s%02X", out.empty() ? "" : " ", b);
    out += cell;
  }
  return out;
}

inline Bytes rtu_frame(std::uint8_t address, const Bytes& pdu) {
  Bytes frame{address};
  frame.insert(frame.end(), pdu.begin(), pdu.end());
  const auto crc = modbus::crc16(frame);
  frame.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  frame.push_back(static_cast<std::uint8_t>(crc >> 8));
  return frame;
}

struct Answer {
  std::uint16_t transaction = 0;
  std::uint8_t unit = 0;
  Bytes pdu;
};

// One request on a raw socket: the MBAP header as a client writes it, the answer as it came.
inline std::optional<Answer> ask(Socket& socket, std::uint16_t transaction, std::uint8_t unit, const Bytes& pdu,
                          std::chrono::milliseconds timeout = 3000ms) {
  const auto length = pdu.size() + 1;
  Bytes adu{static_cast<std::uint8_t>(transaction >> 8), static_cast<std::uint8_t>(transaction & 0xFF), 0, 0,
            static_cast<std::uint8_t>(length >> 8),      static_cast<std::uint8_t>(length & 0xFF),      unit};
  adu.insert(adu.end(), pdu.begin(), pdu.end());
  socket.send(adu);
  const auto header = socket.receive(7, timeout);
  if (header.size() != 7) return std::nullopt;
  const std::size_t rest = (header[4] << 8 | header[5]) - 1u;
  Answer answer{static_cast<std::uint16_t>(header[0] << 8 | header[1]), header[6], socket.receive(rest, timeout)};
  if (answer.pdu.size() != rest) return std::nullopt;
  return answer;
}

class GatewayTest : public MasterTest {
 protected:
  void SetUp() override {
    MasterTest::SetUp();
    config.monitor_section = "monitor:\n  file: " + monitor_log().string() + "\n";
  }
  std::filesystem::path monitor_log() const { return dir.path() / "monitor.log"; }
  /// The stepper driver polled every 200 ms (its SUBDIVISION, 8, into output 1) beside the
  /// clients; `more`: more lines of the modbus section.
  void start_with(const std::string& gateway, const std::string& more = "") {
    simulate({"5=wecon-lx5v", "6=stepper-driver", "7=sic184-v3,dead"});
    config.master = "retries: 1, response_timeout: 300ms";
    config.blocks = "  - { type: poll, device: 6, profile: stepper-driver, point: SUBDIVISION, period: 200ms, output: 1 }\n";
    config.modbus_extra = "  gateway: " + gateway + "\n" + more;
    start();
  }
  std::size_t heard(const Bytes& frame) const {
    std::size_t n = 0;
    for (const auto& f : sim->frames()) n += f.rx && f.hex == hex(frame);
    return n;
  }
  bool said(const Bytes& frame) const {
    for (const auto& f : sim->frames())
      if (!f.rx && f.hex == hex(frame)) return true;
    return false;
  }
  std::size_t polls() const { return std::stoul(sim->control("count 6").substr(6)); }
  nlohmann::json status() const {
    return nlohmann::json::parse(run(bridge_cli() + " status --json --socket " + config.status_socket).output, nullptr, false);
  }
  /// The status document's row of `unit`, or null while it has none.
  nlohmann::json unit_status(int unit) const {
    const auto s = status();
    if (!s.contains("gateway")) return nullptr;
    for (const auto& u : s["gateway"]["units"])
      if (u["unit"] == unit) return u;
    return nullptr;
  }
};

}  // namespace unima::test
