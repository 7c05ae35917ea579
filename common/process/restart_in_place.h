// A program that must start over while running (its host's address changed under a profile
// that announces the host's addresses: dds::Participant::NeedsNewParticipant) ends in order and
// then replaces its image with a fresh start of itself: the same executable, the same
// arguments, the same process id. A service manager sees no exit: systemd keeps the unit
// active (no RestartSec wait), its watchdog and notification socket stay, and the new image
// says READY again. Every file descriptor above 2 is closed across the exec, so devices and
// sockets the old image left open do not leak into the new one.
#pragma once

#include <string>

namespace mostar {

// Keeps argv for RestartInPlace. Call first thing in main().
void RememberCommandLine(int argc, char** argv);

// Asks for a restart: RequestStop() (the loops end in order) and RestartRequested() true.
void RequestRestart();
bool RestartRequested();

// Replaces the process image with `executable` (default: this program, /proc/self/exe) run with
// the remembered arguments. Returns only on failure, with `error` set (nothing remembered, exec
// failed).
bool RestartInPlace(std::string* error, const std::string& executable = "/proc/self/exe");

// The end of main(): when a restart was requested and `status` is 0 (the orderly end), restarts
// in place and, if that fails, says why on stderr as `program` and returns 1; otherwise
// returns `status`.
int RestartIfRequested(int status, const char* program);

}  // namespace mostar
