#pragma once
// A listening server that a reload may move to another address or port (the Modbus TCP
// and TLS slaves, HTTP). The new one may want the same port on another address, so the
// running one lets go of its port while the reload is staged: the reload then commits —
// the new server takes over — or is abandoned — the new one is dropped first, freeing
// the port, and the running one binds it again, the port it had bound (not a new one when
// the config said 0).

#include <memory>
#include <optional>
#include <type_traits>
#include <utility>

namespace unima::io {

template <typename Server>
class MovableListener {
 public:
  using Options = std::remove_cvref_t<decltype(std::declval<const Server&>().options())>;

  explicit MovableListener(std::unique_ptr<Server> server) : server_(std::move(server)) {}

  Server* get() const { return server_.get(); }
  explicit operator bool() const { return server_ != nullptr; }
  Server* operator->() const { return server_.get(); }

  void start() {
    started_ = true;
    if (server_) server_->start();
  }
  void stop() {
    started_ = false;
    if (server_) server_->stop();
  }

  /// A reload to another endpoint: the running server lets go of its port, then
  /// `make_next()` binds the next one (null: no server any more); it may throw.
  template <typename MakeNext>
  void move(MakeNext&& make_next) {
    if (server_) {
      released_ = server_->options();
      released_->port = server_->port();
      server_->stop();
    }
    moving_ = true;
    next_ = make_next();
  }

  /// The reload is refused: `remake(options)` binds the running server's port again.
  template <typename Remake>
  void abandon(Remake&& remake) {
    next_.reset();
    moving_ = false;
    if (!released_) return;
    server_ = remake(*released_);
    released_.reset();
    if (started_) server_->start();
  }

  /// The reload went through: the next server serves, when the endpoint moved.
  void commit() {
    released_.reset();
    if (!std::exchange(moving_, false)) return;
    server_ = std::move(next_);
    if (server_ && started_) server_->start();
  }

 private:
  std::unique_ptr<Server> server_;
  bool started_ = false;
  bool moving_ = false;
  std::unique_ptr<Server> next_;
  std::optional<Options> released_;
};

}  // namespace unima::io
