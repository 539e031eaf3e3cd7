#include "io/master/master_tcp_link.hpp"

#include <spdlog/spdlog.h>

#include "modbus/mbap.hpp"

namespace unima::io {

using asio::ip::tcp;

MasterTcpLink::MasterTcpLink(asio::io_context& io, const std::string& text, const config::HostPort& target)
    : target_(text), host_(target.host), port_(std::to_string(target.port)), resolver_(io), socket_(io), deadline_(io) {}

MasterTcpLink::~MasterTcpLink() { close(); }

master::MasterResponse MasterTcpLink::check(std::span<const std::uint8_t> response, std::uint8_t unit,
                                            std::span<const std::uint8_t> request_pdu) const {
  return master::check_tcp_response(response, unit, request_pdu);
}

void MasterTcpLink::transact(std::uint8_t unit, const master::Bytes& pdu, std::chrono::milliseconds timeout, Done done) {
  const unsigned generation = ++generation_;
  done_ = std::move(done);
  query_.assign(modbus::mbap_header_size + pdu.size(), 0);
  modbus::write_tcp_adu(++transaction_id_, unit, pdu, query_);
  response_.clear();
  deadline_.expires_after(timeout);
  auto self = shared_from_this();
  deadline_.async_wait([this, self, generation](const boost::system::error_code& ec) {
    if (!ec) finish(generation, false);  // part of an answer may still come: start afresh
  });
  if (connected_) return send(generation);
  resolver_.async_resolve(host_, port_, [this, self, generation](const boost::system::error_code& ec,
                                                           const tcp::resolver::results_type& endpoints) {
    if (generation != generation_) return;
    if (ec) {
      if (last_error_ != ec.message()) spdlog::warn("modbus master: cannot resolve {}: {}", target_, ec.message());
      last_error_ = ec.message();
      return finish(generation, false);  // no answer
    }
    asio::async_connect(socket_, endpoints, [this, self, generation](const boost::system::error_code& e, const tcp::endpoint&) {
      if (generation != generation_) return;
      if (e) {
        if (last_error_ != e.message()) spdlog::warn("modbus master: cannot connect to {}: {}", target_, e.message());
        last_error_ = e.message();
        return finish(generation, false);  // no answer
      }
      if (!last_error_.empty()) spdlog::info("modbus master: connected to {}", target_);
      last_error_.clear();
      connected_ = true;
      boost::system::error_code ignored;
      socket_.set_option(tcp::no_delay(true), ignored);
      buffer_.clear();
      send(generation);
    });
  });
}

void MasterTcpLink::send(unsigned generation) {
  auto self = shared_from_this();
  asio::async_write(socket_, asio::buffer(query_), [this, self, generation](const boost::system::error_code& ec, std::size_t) {
    if (generation != generation_) return;
    if (ec) {
      spdlog::warn("modbus master: {}: {}", target_, ec.message());
      return finish(generation, false);
    }
    read(generation);
  });
}

void MasterTcpLink::read(unsigned generation) {
  // Whole ADUs already buffered first: a late answer to an earlier request is skipped.
  while (true) {
    const auto adu = modbus::parse_tcp_adu(buffer_);
    if (adu.status == modbus::TcpAdu::Status::bad_header) {
      response_ = buffer_;
      return finish(generation, false);  // the stream cannot be re-synchronised
    }
    if (adu.status == modbus::TcpAdu::Status::need_more) break;
    const bool ours = adu.header.transaction_id == transaction_id_;
    if (ours) response_.assign(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(adu.size));
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(adu.size));
    if (ours) return finish(generation, true);
  }
  auto self = shared_from_this();
  socket_.async_read_some(asio::buffer(chunk_), [this, self, generation](const boost::system::error_code& ec, std::size_t n) {
    if (generation != generation_) return;
    if (ec) {
      if (ec != asio::error::operation_aborted) spdlog::warn("modbus master: {}: {}", target_, ec == asio::error::eof ? "closed by the slave" : ec.message());
      response_ = buffer_;
      return finish(generation, false);
    }
    buffer_.insert(buffer_.end(), chunk_.begin(), chunk_.begin() + static_cast<std::ptrdiff_t>(n));
    read(generation);
  });
}

void MasterTcpLink::finish(unsigned generation, bool keep_connection) {
  if (generation != generation_ || !done_) return;
  ++generation_;
  deadline_.cancel();
  resolver_.cancel();
  if (!keep_connection) {
    if (response_.empty()) response_ = buffer_;  // a partial answer, as heard
    disconnect();
  }
  auto done = std::move(done_);
  done_ = nullptr;
  done(std::move(query_), std::move(response_));
}

void MasterTcpLink::disconnect() {
  boost::system::error_code ignored;
  socket_.shutdown(tcp::socket::shutdown_both, ignored);
  socket_.close(ignored);
  connected_ = false;
  buffer_.clear();
}

void MasterTcpLink::close() {
  ++generation_;
  done_ = nullptr;
  deadline_.cancel();
  resolver_.cancel();
  disconnect();
}

}  // namespace unima::io
