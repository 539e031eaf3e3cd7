#include "platform/clock_sync.hpp"

#include <sys/timex.h>

namespace unima::platform {

bool clock_synchronized() {
  timex state{};  // modes 0: read only, no privilege needed
  if (::ntp_adjtime(&state) == -1) return false;
  return (state.status & STA_UNSYNC) == 0;
}

}  // namespace unima::platform
