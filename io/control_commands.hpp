#pragma once
// The requests the control socket takes besides the status (`unima-bridge config …`):
// one JSON object per line, {"command": "config apply", "text": "…"}, and one JSON answer.
// Who may do what is the kernel's word on the peer (SO_PEERCRED): the daemon's own user and
// root may apply, revert and read the text in force (it may hold passwords); whoever may
// connect (the socket is 0660) may read the history.

#include "io/config_changes.hpp"
#include "io/control_socket.hpp"

namespace unima::io {

/// Answers `request` through `reply`, once; `changes` null: the daemon takes no changes.
void answer_control_request(ConfigChanges* changes, const ControlRequest& request, const ControlSocket::Reply& reply);

}  // namespace unima::io
