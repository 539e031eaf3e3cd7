#pragma once
// Whether the kernel believes its clock is synchronised (an NTP daemon, systemd-timesyncd or
// chrony told it so): the birth message says it (SPEC §15), because a bridge whose clock
// never synchronised stamps its documents with a time a historian should not trust.

namespace unima::platform {

/// ntp_adjtime(3)'s STA_UNSYNC clear; false too when the call fails.
bool clock_synchronized();

}  // namespace unima::platform
