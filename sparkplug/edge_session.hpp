#pragma once
// The bridge as a Sparkplug B edge node (SPEC §16), its decisions without I/O: which
// messages are due and what they carry, the sequence numbers, the primary host's state,
// what a command means. The service (io/mqtt/sparkplug_service) owns the connection,
// the clock, the bdSeq file and the one write path, and asks this class at each turn.
//
// Sparkplug 3.0, as followed here:
//   - bdSeq counts MQTT CONNECTs (0–255, then 0 again): each CONNECT's will is an NDEATH
//     carrying the next bdSeq, and the NBIRTH of that connection carries the same number
//     (§6.4.19 "bdSeq"; an Int64 metric, as the specification's PR #317 settled).
//   - seq (0–255, then 0) runs across NBIRTH, DBIRTH, DDATA and DDEATH; an NBIRTH is always
//     0 (§6.4.2), a rebirth too. NDEATH has none.
//   - Every device is born after the NBIRTH of its connection. A D_N or S_N that is off-line
//     is born (its birth names its metrics, null) and dies at once: a host learns the
//     device and that it is gone. It gets DDEATH when it goes off-line, a new DBIRTH when
//     it is back. A, B, C, W and X are the bridge's own banks and never die.
//   - With a primary host: births wait until `spBv1.0/STATE/<host>` says
//     {"online":true,"timestamp":…}; an offline STATE while the node is born means the node
//     publishes its NDEATH and disconnects (§5.9 "Edge Node Session Establishment" / the
//     Primary Host Application's STATE, §7 of the specification); a STATE older than one
//     seen before on this connection is ignored, and so is one stamped further ahead of the
//     bridge's synchronised clock than max_host_clock_lead: a forged STATE stamped far in
//     the future would otherwise make every real one look old (issue 43).
//   - When a device's messages go is report::ReportSchedule's (SPEC §21), the rule MQTT's
//     bank documents follow, with one schedule for the node's devices: a DDATA, DDEATH or
//     DBIRTH on the leading edge, no sooner than `min_interval` after the device's last
//     message (those within it go together when it is up, as the device is then: never a
//     backlog); a device changed only within its deadbands sends nothing. A born device
//     sends a DDATA of all its metrics at least every `max_interval` after its last
//     message (a birth is one). A DDATA carries every metric whose value differs from
//     what the host was last sent of it, so a move within its deadband rides along with
//     the next DDATA of its device and the host's values are what the schedule compares
//     with. Every metric carries the time its device's values were measured, a re-send
//     too; the payload's own timestamp is when it goes. Births of the node (on connecting,
//     a rebirth) carry every device at once and start the schedule again.
//   - NCMD `Node Control/Rebirth` = true: every birth again, the same bdSeq.
//   - DCMD to a metric of W or X, when commands are taken: a write of its register in
//     the value's unit (W in tenths), or of one bit of X (`x.5`, a Boolean: that bit
//     alone, the others kept), by the value model's own way back (values/value_codec):
//     a value that would not read back as itself (3276.7 into W is 0x7FFF, "not measured")
//     is refused with the reason — the service takes the rest through the one write path.
// NCMD and DCMD come from whoever may publish on the broker: payloads over 64 KiB, that do
// not decode, or whose value is not of a type the metric can take are malformed; anything
// else the bridge does not do is refused. Both are counted, nothing is answered.

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "banks/bank_id.hpp"
#include "report/report_schedule.hpp"
#include "sparkplug/payload.hpp"
#include "values/value_model.hpp"

namespace unima::sparkplug {

inline constexpr std::string_view rebirth_metric = "Node Control/Rebirth";
inline constexpr std::size_t max_command_bytes = 64 * 1024;
/// How far a primary host's STATE may be stamped ahead of the bridge's clock: hosts'
/// clocks are synchronised too, so a minute is slack enough for any that is.
inline constexpr std::uint64_t max_host_clock_lead_ms = 60'000;

struct Message {
  std::string topic;
  std::string payload;  // the encoded Payload
};

/// One device (a bank of the value model) as it is now.
struct DeviceReading {
  const values::BankValues* layout = nullptr;
  std::span<const values::Value> values;  // ValueModel::evaluate's, kept by the caller for the step
  bool online = true;
  std::span<const double> deadbands;      // report::Deadbands::of; empty: every change counts
  std::optional<std::uint64_t> measured_ms;  // when its values were measured (SPEC §21); none: the step's now
};

/// The devices at a step, in the value model's order: how often each changed
/// (banks::RegisterStore::changes) and each as it is now — asked only of a device that may
/// have a message due, so a device changing a thousand times a second is read once per
/// message, not once per change.
struct Devices {
  std::span<const std::uint64_t> changes;
  std::function<DeviceReading(std::size_t device)> now;
};

/// A write a DCMD asks for: the bits `mask` of a register of W or X set to those of `raw`
/// (the whole word, or one value's bits of it: the others are the register's own).
struct CommandWrite {
  banks::BankId bank = banks::BankId::W;
  std::uint16_t offset = 0;
  std::uint16_t raw = 0;
  std::uint16_t mask = 0xFFFF;
  std::string metric;  // its name, for the log
  std::string value;   // what it writes, for the log: the register, or a bit's true/false
  std::size_t value_index = 0;  // the metric's value in the bank's layout (EdgeSession::resend)
};

/// What an NCMD or DCMD means.
struct Command {
  bool rebirth = false;
  std::vector<CommandWrite> writes;
  std::vector<std::string> refused;  // why each metric the bridge does not take is not taken
                                     // (counted and logged, not answered)
  std::string malformed;             // why the whole message is malformed; empty when it is not
};

enum class HostVerdict {
  none,    // nothing to do: the same state, an older STATE, or not our host's
  from_the_future,  // ignored: stamped more than max_host_clock_lead_ms ahead of the clock
  birth,   // the host is online: births are due (when connected)
  death,   // the host went offline while the node was born: NDEATH and disconnect
};

class EdgeSession {
 public:
  struct Settings {
    std::string group_id;
    std::string edge_node_id;
    bool primary_host = false;  // births wait for the host's STATE
    report::Intervals intervals;  // `report`: min_interval, max_interval (on_change: always)
  };
  using Clock = report::ReportSchedule::Clock;
  struct Counters {
    std::uint64_t births = 0;     // NBIRTH and DBIRTH
    std::uint64_t data = 0;       // DDATA
    std::uint64_t deaths = 0;     // DDEATH
    std::uint64_t taken = 0;      // command metrics acted on (rebirths and writes)
    std::uint64_t refused = 0;    // command metrics not acted on
    std::uint64_t malformed = 0;  // command messages that were not understood
  };
  enum class HostState { unknown, online, offline };

  /// `last_bd_seq`: the bdSeq of the last CONNECT before this process (nullopt: none kept).
  EdgeSession(Settings settings, std::optional<std::uint64_t> last_bd_seq);

  /// spBv1.0/<group>/<type>/<node>: this node's, or another config's (a reload's next).
  std::string node_topic(std::string_view type) const;
  static std::string node_topic(std::string_view group_id, std::string_view type, std::string_view edge_node_id);
  /// spBv1.0/<group>/<type>/<node>/<device>
  std::string device_topic(std::string_view type, std::string_view device) const;
  /// spBv1.0/STATE/<host>
  static std::string host_state_topic(std::string_view host);

  /// A CONNECT is about to go: its bdSeq (the last one's + 1, modulo 256), kept as the
  /// session's; the caller stores it before the will goes.
  std::uint64_t begin_connect();
  /// NDEATH with the session's bdSeq: the will, and what a clean goodbye publishes.
  Message death(std::uint64_t now_ms) const;

  void connected();
  void disconnected();
  /// The primary host's STATE payload; `trusted_now_ms`: the bridge's clock when it is
  /// synchronised (nullopt: it is not, and no STATE is judged by it).
  HostVerdict host_state(std::string_view payload, std::optional<std::uint64_t> trusted_now_ms);
  /// Every birth again at the next step (a rebirth request).
  void rebirth() { births_due_ = true; }
  /// A reload that keeps the connection: every birth again (the value model may have
  /// changed), and the devices' messages on `intervals` from them on.
  void reload(const report::Intervals& intervals) {
    settings_.intervals = intervals;
    rebirth();
  }
  /// The value `value_index` of `bank`'s layout in the next DDATA of its device (when its
  /// min_interval allows), changed or not: a DCMD the write path refused left it as it
  /// was, which the host is told.
  void resend(banks::BankId bank, std::size_t value_index);

  /// The messages due at `now` (`now_ms`: the same moment on the system clock, which
  /// payloads carry), in order; their seq numbers taken.
  std::vector<Message> step(const Devices& devices, Clock::time_point now, std::uint64_t now_ms);
  /// When a step has a message due without a new change (a held-back change, a
  /// max_interval): none while the node is not born.
  std::optional<Clock::time_point> next_due() const;

  /// What an NCMD (`device` empty) or a DCMD to `device` means; `commands`: DCMD writes
  /// are taken. `model` names the metrics. Counts it (a write the write path then refuses
  /// is counted by refused_by_write_path()).
  Command command(std::string_view device, std::string_view payload, const values::ValueModel& model, bool commands);
  void refused_by_write_path() {
    --counters_.taken;
    ++counters_.refused;
  }

  bool born() const { return node_born_; }
  bool connected_now() const { return connected_; }
  std::optional<std::uint64_t> bd_seq() const { return bd_seq_; }
  std::uint8_t next_seq() const { return seq_; }
  HostState host() const { return host_; }
  const Counters& counters() const { return counters_; }

 private:
  struct Device {
    banks::BankId bank;
    bool born = false;
    std::vector<values::Value> sent;  // what the host was last sent of each value
    std::vector<std::size_t> resend;  // values sent in the next DDATA, changed or not
  };

  std::uint64_t take_seq();
  /// NBIRTH, then every device's DBIRTH (and DDEATH for one off-line), a schedule anew.
  std::vector<Message> births(const Devices& devices, Clock::time_point now, std::uint64_t now_ms);
  /// What device `index` (due by the schedule) sends: DDEATH, DBIRTH, DDATA, or nothing.
  std::optional<Message> message_of(std::size_t index, const DeviceReading& device, std::uint64_t now_ms);
  Message birth_of(const DeviceReading& device, Device& state, std::uint64_t now_ms);
  Message device_death(Device& state, std::uint64_t now_ms);
  bool may_publish() const;
  Command dcmd(const values::BankValues& layout, const Payload& payload, bool commands);

  Settings settings_;
  std::optional<std::uint64_t> last_bd_seq_;
  std::optional<std::uint64_t> bd_seq_;
  std::uint8_t seq_ = 0;
  bool connected_ = false;
  bool node_born_ = false;
  bool births_due_ = true;
  HostState host_ = HostState::unknown;
  std::optional<std::uint64_t> host_timestamp_;  // the newest STATE's on this connection
  std::vector<Device> devices_;  // in the value model's order, as the schedule's banks
  std::optional<report::ReportSchedule> schedule_;  // from the first births on
  Counters counters_;
};

}  // namespace unima::sparkplug
