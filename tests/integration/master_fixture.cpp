#include "tests/integration/master_fixture.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

namespace unima::test {

SlaveSim::SlaveSim(const TempDir& dir, const std::vector<std::string>& slaves, bool pty, bool tcp, unsigned wire_baud)
    : out_path_(dir.path() / "sim.out"), frames_path_(dir.path() / "frames.log"), control_path_(dir.path() / "sim.ctl") {
  std::vector<std::string> args{UNIMA_SLAVE_SIM, "--frames", frames_path_.string(), "--control", control_path_.string()};
  if (pty) args.insert(args.end(), {"--pty", (dir.path() / "ttySIM").string()});
  if (tcp) args.insert(args.end(), {"--tcp", "0"});
  if (wire_baud) args.insert(args.end(), {"--baud", std::to_string(wire_baud)});
  for (const auto& s : slaves) args.insert(args.end(), {"--slave", s});
  std::filesystem::remove(out_path_);  // a simulator started again in `dir` says "ready" anew
  process_ = std::make_unique<test_support::ChildProcess>(args, test_support::writing_to(out_path_));
  ready_ = eventually([&] { return output().find("ready ") != std::string::npos; });
  if (!ready_) return;
  const auto text = output();
  const auto pty_at = text.find("pty=");
  pty_ = text.substr(pty_at + 4, text.find(' ', pty_at) - pty_at - 4);
  tcp_port_ = static_cast<std::uint16_t>(std::stoul(text.substr(text.find("tcp=") + 4)));
}

SlaveSim::~SlaveSim() = default;

std::string SlaveSim::output() const { return read_file(out_path_); }

std::vector<SimFrame> SlaveSim::frames() const {
  std::vector<SimFrame> frames;
  std::istringstream in(read_file(frames_path_));
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    SimFrame f;
    std::string direction, port;
    fields >> f.micros >> direction >> port;
    if (!fields) continue;
    f.rx = direction == "rx";
    f.rtu = port == "rtu";
    std::getline(fields, f.hex);
    if (!f.hex.empty() && f.hex[0] == ' ') f.hex.erase(0, 1);
    frames.push_back(std::move(f));
  }
  return frames;
}

bool SlaveSim::wait_for_frame(const std::string& hex, bool rx, std::chrono::milliseconds timeout) const {
  return eventually(
      [&] {
        for (const auto& f : frames())
          if (f.rx == rx && f.hex == hex) return true;
        return false;
      },
      timeout);
}

std::string SlaveSim::control(const std::string& line) const {
  auto socket = Socket::unix_socket(control_path_.string());
  if (!socket.valid()) return "(no control socket)";
  socket.send(line + "\n");
  return socket.read_line().value_or("(no answer)");
}

void MasterTest::simulate(const std::vector<std::string>& slaves, bool tcp, bool wire) {
  sim = std::make_unique<SlaveSim>(dir, slaves, true, tcp, wire ? line_baud : 0);
  ASSERT_TRUE(sim->ready()) << sim->output();
  config.line = "rtu: { device: " + sim->pty() + ", baud: " + std::to_string(line_baud) + " }";
}

void MasterTest::start() {
  daemon = std::make_unique<Daemon>(dir, config.yaml());
  ASSERT_TRUE(wait_for_port(config.modbus_port)) << diagnostics();
}

std::optional<std::uint16_t> MasterTest::output(unsigned n) {
  ModbusClient client(config.modbus_port);
  const auto values = client.read_input(c_bank + static_cast<int>(n) - 1, 1);
  if (!values) return std::nullopt;
  return (*values)[0];
}

bool MasterTest::output_becomes(unsigned n, std::uint16_t value, std::chrono::milliseconds timeout) {
  ModbusClient client(config.modbus_port);
  return eventually(
      [&] {
        const auto values = client.read_input(c_bank + static_cast<int>(n) - 1, 1);
        return values && (*values)[0] == value;
      },
      timeout);
}

std::string MasterTest::diagnostics() const {
  std::string text = "--- config\n" + config.yaml();
  if (daemon) text += "--- daemon log\n" + daemon->log();
  if (sim) {
    text += "--- sim frames (last 40)\n";
    const auto frames = sim->frames();
    for (std::size_t i = frames.size() > 40 ? frames.size() - 40 : 0; i < frames.size(); ++i)
      text += std::to_string(frames[i].micros) + (frames[i].rx ? " rx " : " tx ") + frames[i].hex + "\n";
    text += "--- sim output\n" + sim->output();
  }
  return text;
}

}  // namespace unima::test
