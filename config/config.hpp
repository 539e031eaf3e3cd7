#pragma once
// The daemon's configuration (SPEC §7), as loaded from YAML and validated.

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "banks/address_map.hpp"
#include "banks/bank_id.hpp"
#include "banks/device_table.hpp"
#include "banks/register_store.hpp"
#include "banks/source_ref.hpp"
#include "config/endpoint.hpp"
#include "config/mqtt_identity.hpp"
#include "config/peer_allow_list.hpp"
#include "master/device_profile.hpp"
#include "master/master_value.hpp"
#include "modbus/write_rights.hpp"
#include "modbus/rtu/rtu_timing.hpp"
#include "monitor/monitor_config.hpp"
#include "unimabus/recording.hpp"

namespace unima::config {

using Duration = std::chrono::milliseconds;

enum class TransportKind { sim, feed, replay };
constexpr const char* transport_name(TransportKind kind) {
  return kind == TransportKind::feed ? "feed" : kind == TransportKind::replay ? "replay" : "sim";
}
enum class ModbusMode { slave, master };

struct SimConfig {
  std::uint32_t seed = 1;
  Duration period = std::chrono::seconds(1);
  std::vector<unsigned> io_modules;  // slots 1..7 the simulator fills besides the D_N devices
};

struct ReplayConfig {
  std::string file;
  bool loop = false;
  double speed = 1.0;
  std::string file_origin;  // "file:line:col" of `file`, for check_on_host's message
  std::shared_ptr<const unimabus::Recording> recording;  // read and checked by check_on_host
};

/// unimabus.record: every telegram received, appended in the replay format.
struct RecordConfig {
  std::string file;  // empty: no recording
  std::uint64_t max_size = 10ull << 20;
  unsigned max_files = 5;
};

struct UnimabusConfig {
  std::uint8_t address = 1;  // the bridge's own UnimaBUS address, seed "Addr"
  TransportKind transport = TransportKind::sim;
  std::string listen;        // feed: "host:port" or "unix:/path", as written
  ListenEndpoint listen_at;  // feed: `listen` parsed (config/endpoint); what the feed binds
  std::string listen_origin; // feed: "file:line:col" of `listen`, named when it is taken
  unsigned max_clients = 16; // feed: connections served at once
  Duration offline_after = std::chrono::seconds(5);
  SimConfig sim;
  ReplayConfig replay;
  RecordConfig record;
};

struct TcpSlaveConfig {
  std::string listen = "0.0.0.0";  // an IP address literal (checked by the parse: config/endpoint)
  std::uint16_t port = 502;
  unsigned max_clients = 128;
  Duration idle_timeout = std::chrono::seconds(60);  // 0: never
  Duration frame_timeout = std::chrono::seconds(2);  // a started request must be complete within it
  PeerAllowList allow;     // empty: every peer (SPEC §11)
  bool read_only = false;  // every write answered with exception 01
  std::string port_origin;  // "file:line:col" of `port`, else of the section: named when the port is taken
};

enum class Parity { none, even, odd };
enum class Rs485Direction { off, kernel, rts };

/// The RS-485 line (seed §4.1: "MBSbr", "MBSpar", "MBSsb").
struct RtuConfig {
  std::string device;
  unsigned baud = 19200;
  Parity parity = Parity::none;
  unsigned stop_bits = 1;
  Rs485Direction rs485 = Rs485Direction::off;  // who switches the transceiver's direction
  bool low_latency = false;                    // set a USB adapter's latency timer to 1 ms
  /// The silence that ends an incomplete frame, used exactly; nullopt: `auto`
  /// (modbus::RtuFramerTiming::for_line, t3.5 plus the adapter's latency and a margin).
  std::optional<std::chrono::microseconds> frame_gap;
  std::string origin;  // "file:line:col" of modbus.rtu
  bool operator==(const RtuConfig&) const = default;
};

/// "N", "E" or "O", as in "8N1".
char parity_letter(Parity parity);

/// The character and gap times of `line` (modbus/rtu/rtu_timing: the one computation).
modbus::RtuTiming line_timing(const RtuConfig& line);

/// Functions beyond the seed's 4 and 6 (SPEC §3), each on by default.
struct Extensions {
  bool function_3 = true;
  bool function_16 = true;
  bool function_43 = true;
};

/// A foreign slave the master talks to (modbus.master.devices.N).
struct MasterDeviceConfig {
  const master::DeviceProfile* profile = nullptr;  // what its blocks' points refer to
  std::optional<Duration> min_gap;                 // else the profile's, else master.min_gap
  std::optional<Duration> response_timeout;        // else master.response_timeout
  std::optional<master::SerialDefaults> line;      // as the device is set, when not its profile's default
  std::string origin;                              // "file:line:col" of modbus.master.devices.N
};

/// Master-only settings (modbus.master; docs/master.md).
struct MasterConfig {
  std::string tcp;                      // "host:port" of a Modbus TCP slave to drive instead of modbus.rtu
  HostPort tcp_target;                  // `tcp` parsed (config/endpoint); what the master connects to
  Duration response_timeout{500};
  unsigned retries = 1;                 // of reads; writes are never retried
  unsigned merge_gap = 0;               // registers a merged read may skip
  unsigned max_read_registers = 125;
  Duration stale_after{10'000};         // a value not refreshed this long reads 0x7FFF
  unsigned degrade_after = 3;           // failed transactions in a row that degrade a device
  Duration backoff{1'000};              // first probe interval of a degraded device
  Duration backoff_max{30'000};
  Duration min_gap{0};                  // between two frames to one device
  std::map<std::uint8_t, MasterDeviceConfig> devices;
  std::string origin;                   // "file:line:col" of the section, when given
};

/// Modbus/TCP Security (SPEC §11): the slave over TLS 1.2+ with mutual authentication; a
/// client's role, read from its certificate, says which registers it may write.
struct TlsSlaveConfig {
  TcpSlaveConfig connection = default_connection();  // listen, port, limits, allow, read_only
  std::string certificate;  // PEM, the server's (with its chain)
  std::string key;          // PEM, its private key
  std::string ca;           // PEM, the CA(s) that sign the clients' certificates
  std::map<std::string, modbus::WriteRights> roles;  // a role not listed may write nothing
  std::string origin;       // "file:line:col" of modbus.tls, for errors found at start

  static TcpSlaveConfig default_connection() {
    TcpSlaveConfig c;
    c.port = 802;
    return c;
  }
};

/// modbus.gateway (SPEC §14, docs/gateway.md): Modbus TCP clients reach the foreign slaves
/// on the master's line.
struct GatewayConfig {
  std::array<bool, 256> units{};        // by unit id: forwarded to the line
  PeerAllowList priority;               // peers served before polls and other clients
  Duration wait{2'000};                 // longest a request may wait for the line: then 0x06
  std::optional<Duration> timeout;      // the slave's answer time-out; else its profile's, else 1 s
  Duration cache{0};                    // an identical read answered this young is served again; 0: off
  bool reads_only = false;              // `functions: read`: only functions 1-4 are forwarded, from every port
  std::string origin;                   // "file:line:col" of the section
  bool routes(std::uint8_t unit) const { return units[unit]; }
  bool operator==(const GatewayConfig&) const = default;
};

/// Every master line's gateway by the unit ids it routes (SPEC §14, §18): what the TCP and
/// TLS ports forward, and with which line's settings (`priority`, `functions`). Owns
/// copies, so that the ports may keep it across a reload.
struct GatewayRoutes {
  std::array<bool, 256> units{};  // the union of every master line's units
  std::vector<std::pair<std::string, GatewayConfig>> gateways;  // by line name
  std::array<std::uint8_t, 256> gateway_of{};  // an index into `gateways`, for a routed unit

  const GatewayConfig& of(std::uint8_t unit) const { return gateways[gateway_of[unit]].second; }
};

/// "2-9, 17": the routed unit ids as the config writes them.
std::string unit_ranges_text(const GatewayConfig& gateway);

enum class LineRole { slave, master };
constexpr const char* line_role_name(LineRole role) { return role == LineRole::master ? "master" : "slave"; }

/// An RS-485 line of modbus.lines (SPEC §18), or modbus.rtu as the one line named `rtu`.
struct LineConfig {
  std::string name;                      // [a-z0-9_-]{1,16}; "rtu" for modbus.rtu
  LineRole role = LineRole::slave;
  RtuConfig serial;                      // device, baud, parity, stop bits, frame_gap
  std::uint8_t address = 1;              // a slave line: the address it answers (default modbus.address)
  std::optional<GatewayConfig> gateway;  // a master line: the unit ids TCP and TLS clients reach through it
  std::string key;                       // "modbus.lines.<name>", or "modbus.rtu": what messages name
};

struct ModbusConfig {
  /// master: the master runs (on a master line, or on modbus.master.tcp); slave: it does not.
  /// For modbus.rtu as written; for modbus.lines, master when a line is a master.
  ModbusMode mode = ModbusMode::slave;
  std::uint8_t address = 1;  // seed "MBSAddr"
  std::optional<TcpSlaveConfig> tcp;
  std::optional<TlsSlaveConfig> tls;
  /// modbus.lines in the file's order, or modbus.rtu as one line named `rtu` with the
  /// mode's role: every RTU line the bridge serves. Names, devices and routed units differ.
  std::vector<LineConfig> lines;
  MasterConfig master;
  bool readable_write_banks = true;
  Extensions extensions;

  /// The first line of this role; null when there is none. The parse lets at most one
  /// line be a master (config/modbus_section.cpp says why); slave lines may be several.
  const LineConfig* line_of(LineRole role) const;
  /// The line named `name`; null when there is none.
  const LineConfig* find_line(std::string_view name) const;
  /// Whether the blocks of this kind act: slave blocks without a master or beside a slave
  /// line, master blocks with one (SPEC §4, §18).
  bool serves_slave_blocks() const;
  /// The first master line's gateway (SPEC §14); null without one.
  const GatewayConfig* gateway() const;
  /// Every master line's gateway; nullopt when no line has one.
  std::optional<GatewayRoutes> gateway_routes() const;
  /// The lines of a role, in the file's order.
  std::vector<const LineConfig*> lines_of(LineRole role) const;
  /// What a line's monitor port names and status rows carry (SPEC §18): its name when the
  /// bridge has several lines; empty with one, whose names stay `rtu`, `master`, `gw:`.
  std::string_view shown_name(const LineConfig& line) const;
};

struct DeviceConfig {
  const banks::DeviceTable* table = nullptr;  // seed "Dev_NSel"
  std::uint8_t address = 0;                   // seed "DevNAddr"
};

/// A function block (SPEC §4, seed §7.1–§7.2).
struct Block {
  enum class Type { read, write, capture, poll, send };
  Type type = Type::read;
  std::uint16_t reg = 0;                   // "Registr ModBUS"
  std::optional<banks::SourceRef> source;  // read, send
  unsigned output = 0;                     // write, capture, poll: user analog output 1..16
  std::uint8_t device = 0;                 // capture, poll, send: Modbus address of the foreign device
  Duration period{0};                      // poll, send
  std::string origin;                      // "file:line:col" of the block
  // poll and send (SPEC §4 extensions): what goes over the wire and how it is converted
  std::uint8_t function = 0;               // poll 1, 2, 3, 4 (seed: 4); send 5, 6, 16 (seed: 6)
  master::ValueType data_type = master::ValueType::word;
  master::WordOrder word_order = master::WordOrder::low_first;
  double scale = 1.0;                      // device value x scale = bridge register
  std::uint16_t count = 1;                 // bits read together (functions 1, 2)
  const master::DeviceProfile* profile = nullptr;
  std::string point;                       // the profile point named, if any
  /// capture: the slave line it listens on; poll, send: the master line they go out on.
  /// `line:` as written, else the only line of that role; empty when there is none (a
  /// capture without a slave line, a master on modbus.master.tcp).
  std::string line;

  bool is_slave_block() const { return type == Type::read || type == Type::write || type == Type::capture; }
  /// Registers (or coils) on the foreign slave.
  std::uint16_t extent() const;
};

std::string_view block_type_name(Block::Type type);

struct LogConfig {
  std::string level = "info";
};

/// `unima-bridge status` asks the daemon on this unix socket.
struct StatusConfig {
  std::string socket = "/run/unima-bridge/control.sock";
};

/// SPEC §10: where the values masters wrote are kept across a restart.
struct StateConfig {
  /// Empty: `file: none`, nothing is kept. Default: `state` in systemd's $STATE_DIRECTORY
  /// when the service sets it, otherwise beside the config (`bridge.yaml` -> `bridge.state`).
  std::string file;
};

/// SPEC §13: the read-only HTTP server (metrics, health, the technician's page).
struct HttpTlsConfig {
  std::string certificate;  // PEM, the server's (with its chain)
  std::string key;          // PEM, its private key
  bool operator==(const HttpTlsConfig&) const = default;
};

struct HttpConfig {
  std::string listen = "127.0.0.1";  // an IP address literal
  std::uint16_t port = 8080;
  unsigned max_clients = 16;
  std::optional<HttpTlsConfig> tls;  // HTTPS instead of HTTP
  std::string users;                 // htpasswd-style file for basic authentication; empty: none
  std::string users_origin;          // "file:line:col" of http.users, for its file's errors
  std::string origin;                // "file:line:col" of http, for errors found at start
  std::string port_origin;           // "file:line:col" of http.port, else of http
};

/// mqtt.discovery (SPEC §15): Home Assistant finds the bridge's values by itself.
struct MqttDiscoveryConfig {
  std::string prefix = "homeassistant";  // Home Assistant's discovery prefix
  bool operator==(const MqttDiscoveryConfig&) const = default;
};

/// mqtt.buffer (SPEC §15): the documents made while the broker is unreachable, kept on the
/// disk until they are sent as history.
struct MqttBufferConfig {
  /// Empty: `file: none`, no history is kept. Default: `mqtt-buffer` beside the state file's
  /// default ($STATE_DIRECTORY, or beside the config: `bridge.yaml` -> `bridge.mqtt-buffer`).
  std::string file;
  std::uint64_t max_size = 64ull << 20;
  bool operator==(const MqttBufferConfig&) const = default;
};

/// mqtt (SPEC §12): the bridge as a client of a fleet's broker.
struct MqttConfig {
  std::string broker;        // as written: mqtt://host[:port] or mqtts://host[:port]
  bool tls = false;          // mqtts://
  HostPort endpoint;         // the broker's host (a name or an address) and port (1883, 8883)
  std::string client_id;     // default unima-bridge-<hostname>-<8 hex digits of the machine id> (config/mqtt_identity)
  std::string topic;         // the prefix, default unima/<client_id>
  std::string username;      // empty: none
  std::string password_file; // its first line is the password
  std::string ca, certificate, key;  // mqtts: the broker's CA; the client's certificate and key (optional)
  int version = 4;           // MQTT protocol level: 4 (3.1.1) or 5
  std::chrono::milliseconds period{10'000};  // every bank in full
  bool on_change = true;     // and each bank when it changes (at most every 100 ms)
  bool commands = false;     // set/W/<offset>, set/X/<bit>
  // Where an MQTT 5 command may be answered (SPEC §15): topic filters, default
  // <topic>/reply/#; mqtt/response_topic also keeps the bridge's own topics out.
  std::vector<std::string> response_topics;
  std::optional<MqttDiscoveryConfig> discovery;  // absent: no Home Assistant discovery
  MqttBufferConfig buffer;
  std::string origin;        // "file:line:col" of mqtt
  // What the birth message tells of the machine (SPEC §15), as the parse found it:
  std::string host_name;     // gethostname(2); empty when it has none
  std::string machine_id;    // the first 8 hex digits of /etc/machine-id; empty when there is none
  /// The same client and publishing (where the section stands in the file does not count,
  /// nor the buffer, which changes at the next start, nor where answers may go, which the
  /// next command reads from the running config).
  bool same_client(const MqttConfig& other) const {
    auto a = *this, b = other;
    a.origin = b.origin = {};
    a.buffer = b.buffer = {};
    a.response_topics = b.response_topics = {};
    return a == b;
  }
  bool operator==(const MqttConfig&) const = default;
};

/// Sparkplug B's topic namespace (Sparkplug 3.0 §4.1): every topic of an edge node and a
/// host lies under it. Here, below sparkplug/ and mqtt/, because MQTT's answers must keep
/// off it too (mqtt/response_topic).
inline constexpr std::string_view sparkplug_topic_namespace = "spBv1.0";

/// sparkplug (SPEC §16): the bridge as a Sparkplug B edge node, on a broker of its own
/// connection (which may be the mqtt section's broker). The broker, TLS and credentials
/// keys are mqtt's, read by the same parser.
struct SparkplugConfig {
  std::string broker;        // as written: mqtt://host[:port] or mqtts://host[:port]
  bool tls = false;
  HostPort endpoint;
  std::string client_id;     // default unima-bridge-<group_id>-<edge_node_id>
  std::string username;
  std::string password_file;
  std::string ca, certificate, key;
  int version = 4;
  std::string group_id;      // spBv1.0/<group_id>/...
  std::string edge_node_id;  // default: this machine's name
  std::string primary_host;  // empty: births go out on connecting, not on a host's STATE
  bool commands = false;     // DCMD to W and X metrics writes them
  std::string origin;        // "file:line:col" of sparkplug
  bool same_client(const SparkplugConfig& other) const {
    auto a = *this, b = other;
    a.origin = b.origin = {};
    return a == b;
  }
  bool operator==(const SparkplugConfig&) const = default;
};

/// A deadband of `report.deadband` (SPEC §21) as the file writes it: the value it names is
/// looked up in the value model (report/deadbands), which fails at `origin` when the bank
/// has no such value.
struct DeadbandConfig {
  banks::BankId bank = banks::BankId::D1;
  std::string value;   // the value's name in its bank ("engine_speed", "D1.oil_temperature" in A)
  double deadband = 0;  // in the value's unit
  std::string origin;   // "file:line:col" of its key
  bool operator==(const DeadbandConfig&) const = default;
};

/// report (SPEC §21): when MQTT documents and Sparkplug DDATA count a value as changed and
/// how often a bank's document goes.
struct ReportConfig {
  Duration min_interval{100};           // no bank document sooner than this after its last
  std::optional<Duration> max_interval;  // a full document at least this often; none: mqtt.publish.period
  double default_deadband = 0;           // 0: every change counts (what the bridge did before §21)
  std::vector<DeadbandConfig> deadbands;  // in the order the file writes them
  std::string origin;                     // "file:line:col" of report; empty: not in the file
  bool operator==(const ReportConfig&) const = default;
};

/// remote_config (SPEC §19): who may change the config in force from afar. The CLI over the
/// control socket may always (it is local root); MQTT and HTTP only as this section says.
struct RemoteConfig {
  bool mqtt = false;               // configs are taken on <prefix>/config/set
  std::vector<std::string> http;   // users of http.users who may PUT /api/config; empty: none
  Duration probe{30'000};          // how long a new config must prove itself, 1 s .. 10 min
  unsigned keep = 10;              // applied configs kept in the state directory, 1..1000
  std::string origin;              // "file:line:col" of remote_config
  std::string http_origin;         // "file:line:col" of remote_config.http, else of the section:
                                   //   named when a user is not in the users file (check/)
  bool operator==(const RemoteConfig&) const = default;
};

/// A path the config names on this machine: the parse only notes it, check_on_host looks
/// at what is there.
struct HostPath {
  enum class Use {
    unix_socket,      // the daemon listens there: nothing, or a socket it may replace (config/socket_path)
    log_file,         // the daemon appends there: never through a symbolic link (monitor/log_path)
    state_file,       // the daemon reads and rewrites there: a regular file, or nothing yet
    serial_device,    // the daemon opens it, and retries while it cannot: a warning when it is not there
    secret_file,      // the daemon reads its first line at start (a password): an error when it cannot
    certificate,      // PEM files the daemon loads at start (tls/pem_check): an error when unusable,
    private_key,      //   a warning when a certificate has expired
    ca_certificates,
  };
  Use use = Use::log_file;
  std::string key;     // "status.socket", named in the message
  std::string path;
  std::string origin;  // "file:line:col" of the key; of its section, or of the file, for a default
  std::string certificate;  // private_key: the key of the certificate it must belong to ("http.tls.certificate")
};

struct Config {
  std::string file;
  std::string file_sha256;  // of the text parsed (the file's bytes), as sha256sum prints it: the birth names it
  UnimabusConfig unimabus;
  ModbusConfig modbus;
  std::array<std::uint16_t, banks::bank_count> bank_bases{};
  std::array<std::string, banks::bank_count> bank_origins;  // "file:line:col" of banks set in the file
  std::array<std::optional<DeviceConfig>, 4> devices;
  banks::Mapping mapping;
  std::vector<Block> blocks;
  LogConfig log;
  monitor::MonitorConfig monitor;
  StatusConfig status;
  StateConfig state;
  std::optional<HttpConfig> http;  // absent: no HTTP
  std::optional<MqttConfig> mqtt;  // absent: no MQTT
  std::optional<SparkplugConfig> sparkplug;  // absent: no Sparkplug B
  ReportConfig report;
  /// absent: remote changes come only by the CLI (`unima-bridge config`), always on for local root
  std::optional<RemoteConfig> remote_config;
  std::vector<HostPath> host_paths;  // in the order the file names them
  /// Warnings the parse and check_on_host found (a PLC-style register number, a serial
  /// device not there, an expired certificate), as warning_text writes them; config::warnings
  /// gives them with the rest.
  std::vector<std::string> noted_warnings;

  /// The blocks that act in this mode; the others are ignored (with a warning, SPEC §4).
  std::vector<const Block*> active_blocks() const;
};

/// A config problem; what() starts with "file:line:column: " (1-based).
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What the parse takes from the machine it runs on, handed in so that the parse itself
/// reads no environment and a test can pose as any host.
struct Host {
  std::string name;  // gethostname(2): the default mqtt.client_id; empty when it has none
  /// The first 8 hex digits of machine-id(5), for the default mqtt.client_id
  /// (config/mqtt_identity.hpp); empty when there is none.
  std::string machine_id;
  /// An environment variable's value; empty when it is not set (systemd's $STATE_DIRECTORY).
  std::function<std::string(std::string_view variable)> environment = [](std::string_view) { return std::string(); };

  /// This machine's; `machine_id_path` is a test's stand-in for /etc/machine-id.
  static Host this_machine(const std::string& machine_id_path = std::string(machine_id_file));
};

/// The YAML text as a Config, or a ConfigError naming `origin`:line:column. Pure: it opens
/// no file and looks at nothing on disk (check_on_host does), so any text parses the same
/// on any machine given the same `host`. `origin` names the text in errors, as the file
/// name would.
Config parse_text(const std::string& text, const std::string& origin, const Host& host);

/// What `config` names on this machine, looked at once for `unima-bridge check`, the
/// daemon's start and each reload alike (through load_file): the replay recording is read
/// and parsed (into unimabus.replay.recording); unix socket paths hold nothing or a socket;
/// log files are no symbolic links. A ConfigError names the key's file:line:column.
void check_on_host(Config& config);

/// The text parsed in the place of the file `in_place_of`: errors name `origin` (where the
/// text is kept), while what the config puts "beside the config" by default (the state
/// file, the MQTT buffer) goes beside `in_place_of`. A remote config kept in the state
/// directory (io/remote_config_store) so means what it would in the operator's file; its
/// relative paths need nothing: they are from the daemon's working directory for both.
Config parse_text(const std::string& text, const std::string& origin, const Host& host, const std::string& in_place_of);

/// parse_text, then check_on_host.
Config load_text(const std::string& text, const std::string& origin, const Host& host = Host::this_machine());
Config load_text(const std::string& text, const std::string& origin, const Host& host, const std::string& in_place_of);
/// The file's bytes, or a ConfigError "path: cannot open the config file: …".
std::string read_config_file(const std::string& path);
/// The file read, then load_text: what the daemon and `unima-bridge check` load.
Config load_file(const std::string& path, const Host& host = Host::this_machine());

/// Bank sizes and tables of this config.
banks::BankShapes bank_shapes(const Config& config);
/// Every served window: banks, and the registers of active read and write blocks.
/// Validated by the parse: no two windows overlap.
banks::AddressMap address_map(const Config& config);

/// Whether the bridge takes no write at all (SPEC §11): `modbus.tcp.read_only` is the
/// site's freeze switch for commissioning and maintenance, so it holds for every way a
/// write comes in — the plain, TLS and RTU ports, MQTT commands, and whatever comes next
/// (Sparkplug, the gateway) — not for the plain port alone. A reload that turns it on
/// stops them all without editing their sections. Every way in asks this one question
/// (banks::WritePath is frozen by it); `modbus.tls.read_only` is the TLS port's own, in
/// addition.
bool writes_frozen(const Config& config);

/// report.max_interval, else mqtt.publish.period (SPEC §21): how often a bank's full
/// document goes at least.
Duration max_report_interval(const Config& config);

/// Things that are allowed but probably not meant, for the log at start-up and for
/// `unima-bridge check`: blocks ignored in this mode, capture blocks without an RTU port,
/// and the noted_warnings. Each as warning_text writes it.
std::vector<std::string> warnings(const Config& config);

/// "file:line:column: warning: message", the one form of a config warning (docs/configuration.md).
std::string warning_text(std::string_view origin, std::string_view message);

/// The longest wait between two tries to open a serial line that cannot be opened (an
/// adapter not plugged in): io/modbus/rtu_slave_port backs off up to it, and the warning
/// of a missing device names it.
inline constexpr std::chrono::milliseconds serial_reopen_longest_delay{5000};

}  // namespace unima::config
