#pragma once
// The master over Modbus TCP (SPEC §3 extension, `modbus.master.tcp: host:port`): one
// connection to the target, opened when a request needs it and again after any error; the
// unit id is the device's address. A response whose transaction id is not the request's
// is a late answer to an earlier request and is passed over.

#include <memory>
#include <string>

#include "config/endpoint.hpp"
#include "platform/asio.hpp"
#include "io/master/master_link.hpp"

namespace unima::io {

class MasterTcpLink final : public MasterLink {
 public:
  /// `target` as the config loader parsed `text` ("host:port", "[v6]:port").
  MasterTcpLink(asio::io_context& io, const std::string& text, const config::HostPort& target);
  ~MasterTcpLink() override;

  void transact(std::uint8_t unit, const master::Bytes& pdu, std::chrono::milliseconds timeout, Done done) override;
  void close() override;
  master::MasterResponse check(std::span<const std::uint8_t> response, std::uint8_t unit,
                               std::span<const std::uint8_t> request_pdu) const override;
  std::string describe() const override { return "tcp " + target_; }
  std::string peer() const override { return target_; }

 private:
  void send(unsigned generation);
  void read(unsigned generation);
  void finish(unsigned generation, bool keep_connection);
  void disconnect();

  std::string target_;
  std::string host_;
  std::string port_;
  asio::ip::tcp::resolver resolver_;
  asio::ip::tcp::socket socket_;
  asio::steady_timer deadline_;
  bool connected_ = false;
  std::string last_error_;  // logged when it changes, not at every attempt
  std::uint16_t transaction_id_ = 0;
  std::array<std::uint8_t, 512> chunk_{};
  master::Bytes query_;
  master::Bytes buffer_;    // bytes read, not yet a whole ADU of this transaction
  master::Bytes response_;
  Done done_;
  unsigned generation_ = 0;
};

}  // namespace unima::io
