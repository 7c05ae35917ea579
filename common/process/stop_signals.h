// SIGINT and SIGTERM as a stop request for the whole process: the programs' loops poll
// StopRequested() and end in order. The handler only sets a lock-free atomic flag
// (async-signal-safe). RequestStop() asks for the same from code (a "quit" control, a test).
#pragma once

namespace mostar {

// Installs the handlers for SIGINT and SIGTERM. Idempotent.
void InstallStopSignals();
bool StopRequested();
void RequestStop();

// A signal as a one-shot request (robot_server: SIGUSR2 releases the e-stop at the robot): the
// handler sets a lock-free flag that TakeSignalRequest() returns and clears. For signal
// numbers 1..64 other than SIGINT and SIGTERM; false for others.
bool InstallSignalRequest(int signal_number);
bool TakeSignalRequest(int signal_number);

}  // namespace mostar
