#include "mqtt/session_takeover.hpp"

namespace unima::mqtt {

bool SessionTakeover::ended(ConnectionEnd end, Clock::time_point at) {
  const auto connected_at = std::exchange(connected_at_, std::nullopt);
  if (end == ConnectionEnd::taken_over) return true;
  const bool short_close = end == ConnectionEnd::closed_by_broker && connected_at && at - *connected_at < short_session;
  short_closes_in_a_row_ = short_close ? short_closes_in_a_row_ + 1 : 0;
  return short_closes_in_a_row_ >= 2;
}

}  // namespace unima::mqtt
