// SIGINT and SIGTERM as a stop request for the whole process: the programs' loops poll
// StopRequested() and end in order. The handler only sets a lock-free atomic flag
// (async-signal-safe). RequestStop() asks for the same from code (a "quit" control, a test).
#pragma once

namespace mostar {

// Installs the handlers for SIGINT and SIGTERM. Idempotent.
void InstallStopSignals();
bool StopRequested();
void RequestStop();

}  // namespace mostar
