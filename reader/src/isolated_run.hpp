#pragma once
// Work that may crash or never end, run in a child process with a time limit; the child's result
// comes back through a pipe. For a third-party parser given untrusted bytes that it does not check:
// libhdf5 (under libnetcdf's netCDF-4 files) trusts their metadata. fuzz_netcdf, given a netCDF-4
// seed, found within minutes a 56 kB file on which nc_inq_varndims loops in H5HG_read for longer
// than 100 s, and files whose metadata make H5G__dense_iterate free a wild pointer
// (AddressSanitizer: SEGV in free; a release build may go on with a corrupted heap). Neither can
// be caught in the process that runs it, so the parser runs only in the child: even a corruption
// that the child survives unnoticed stays in the child.
#include <functional>
#include <string>

namespace mlce::reader::detail {

struct IsolatedOutcome {
  enum class Kind {
    finished,   ///< the work returned in the child: `output` holds what it returned
    threw,      ///< the work threw in the child: `message` holds the exception's what()
    crashed,    ///< the child died by a signal (`signal`) or exited with another status (`status`:
                ///< a sanitizer's report), or ended without handing over its whole result
    timed_out,  ///< still running after the time limit: killed
    not_run,    ///< no child could be started (pipe or fork failed): nothing is known
  };
  Kind kind = Kind::not_run;
  int signal = 0;  ///< crashed by a signal: its number
  int status = 0;  ///< crashed by exiting: its exit status
  std::string output;   ///< finished: the bytes the work returned
  std::string message;  ///< threw: the exception's text
};

/// Runs `work` in a forked child (a copy of this process; only the calling thread is copied) and
/// waits at most `seconds` for it, reading what it returns as it comes (a result larger than the
/// pipe's buffer does not stall the child). The child writes to /dev/null (stdout, stderr) and
/// leaves with _exit (no atexit handlers, no stdio flush: nothing it buffered is written twice).
/// The result crosses the pipe as a frame (a tag byte, a 64-bit length, the bytes): a child that
/// dies while writing it is `crashed`, never a short `finished`.
IsolatedOutcome run_isolated(const std::function<std::string()>& work, double seconds);

}  // namespace mlce::reader::detail
