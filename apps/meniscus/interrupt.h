// Ctrl-C and SIGTERM for the long commands (render, simulate, mesh, convert,
// whitewater): one handler for all. The handler only records the signal (a
// sig_atomic_t, the one thing a handler may safely do besides write(2)); each
// command asks interrupted() between items (a frame, a mesh, a step of the
// simulator), stops there and returns interruptExitCode(): 130 for SIGINT,
// 143 for SIGTERM (128 + the signal, as a shell reports a process a signal
// ended). Every output is written under a temporary name and renamed, so a
// stopped command leaves only whole files, and --resume goes on.
#pragma once

#include <string>

#include "meniscus/result.h"

namespace meniscus::app {

// From here on SIGINT and SIGTERM set the flag instead of ending the process;
// the first prints "stopping after the <item> in progress" (`item`: "frame",
// "mesh"; a literal that lives as long as the process). Further signals
// change nothing (a tool may signal the process and its group both).
void installInterruptHandler(const char* item = "frame");
// Whether a signal asked the run to stop.
bool interrupted();
// 128 + the signal (130 for Ctrl-C, 143 for SIGTERM); 0 when none came.
int interruptExitCode();
// The one line saying where the run stopped and how to go on
// ("meniscus: interrupted after ...; <then>"), on stderr; returns
// interruptExitCode().
int stopInterrupted(const std::string& where, const std::string& then);

// Before the long work starts, so a bad output is said at once, not at the
// first write: the folder of `output` (a file, or a pattern's frame 0) made
// when missing, and writable; else a usage error (exit 2) naming it. Then
// the temporaries that a killed run left there are removed
// (removeStaleTemporaries, include/meniscus/io.h), said in one line.
// `shared`: processes on other machines may write into the folder (--shard,
// mpirun), whose PIDs mean nothing here: only temporaries unchanged for an
// hour are removed.
Status prepareOutputFolder(const std::string& output, bool shared = false);

// Whether `path` holds a whole output (what --resume keeps): an image (a PNG
// ending in its IEND chunk, an EXR starting with its magic number), a mesh or
// a particle file the readers take. Every output is written under a
// temporary name and renamed, so one of ours is whole; these also catch a
// file cut short by another tool.
bool imageComplete(const std::string& path);
bool meshComplete(const std::string& path);
bool particlesComplete(const std::string& path);

}  // namespace meniscus::app
