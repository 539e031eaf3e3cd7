#pragma once
// The UnimaBUS side as a service (SPEC §6): the transport (feed, simulator or replay) and
// the recorder of `unimabus.record`, both handing every telegram to the running banks'
// unimabus::TelegramIntake; one timer at the moment the next device can go off-line; the
// publisher pointed at the transport. On a reload a feed keeps its connections and a
// replay its place when their settings did not change; the simulator starts again.

#include <memory>
#include <string>
#include <vector>

#include "io/lazy_deadline.hpp"
#include "io/service.hpp"
#include "io/unimabus/telegram_recorder.hpp"
#include "unimabus/transport.hpp"

namespace unima::io {

class UnimabusService final : public Service {
 public:
  explicit UnimabusService(Runtime& runtime);
  ~UnimabusService() override;

  void start() override;
  void stop() override;
  void stage(const Banks& next) override;
  void abandon() override;
  void commit(const Banks& previous) override;
  void describe(status::Document& status) const override;

 private:
  std::unique_ptr<unimabus::Transport> make_transport(const config::Config& config);
  std::unique_ptr<TelegramRecorder> make_recorder(const config::Config& config) const;
  std::string take(const unimabus::Telegram& telegram);
  void log(const std::vector<unimabus::TelegramIntake::PresenceChange>& changes) const;

  Runtime& runtime_;
  std::unique_ptr<unimabus::Transport> transport_;
  std::unique_ptr<TelegramRecorder> recorder_;
  LazyDeadline presence_timer_;  // at the next moment a device can go off-line
  bool started_ = false;
  // Staged by a reload:
  std::unique_ptr<unimabus::Transport> next_transport_;  // null: the running one stays
  bool new_recorder_ = false;
  std::unique_ptr<TelegramRecorder> next_recorder_;
};

/// "D1 (unigen-chp at UnimaBUS address 5)", "S2 (IO module in slot 2 at address 1)", "A".
std::string describe_bank(const config::Config& config, banks::BankId bank);

}  // namespace unima::io
