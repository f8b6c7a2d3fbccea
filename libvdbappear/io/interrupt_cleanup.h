#pragma once
// Temporary output files removed when the process is interrupted (SIGINT, SIGTERM, SIGHUP): a
// tool stopped in the middle of a long write or render leaves neither a partial output nor its
// temporary file (io/atomic_file.h registers each one while it exists).
//
// The one piece of process-wide state in the library, as signal handling must be: a fixed table of
// paths that the handler can read without allocating (unlink(2) is async-signal-safe). The handler
// removes the registered files, restores the default action and raises the signal again, so the
// process still ends as interrupted (exit status 128 + signal in a shell).

namespace vdbappear {

// Registers `path` (which must stay valid until unregistered) for removal on interruption, and
// installs the handlers on first use. Returns the slot to pass to unregisterInterruptCleanup, or
// -1 if every slot is taken (the file is then not cleaned up on interruption, only at exit paths).
int registerInterruptCleanup(const char* path);
void unregisterInterruptCleanup(int slot);

}  // namespace vdbappear
