#pragma once
// Work that may crash or never end, run first in a child process with a time limit. For a
// third-party parser given untrusted bytes that it does not check: libhdf5 (under libnetcdf's
// netCDF-4 files) trusts their metadata. fuzz_netcdf, given a netCDF-4 seed, found within minutes a
// 56 kB file on which nc_inq_varndims loops in H5HG_read for longer than 100 s, and files whose
// metadata make H5G__dense_iterate free a wild pointer (AddressSanitizer: SEGV in free; a release
// build may go on with a corrupted heap). Neither can be caught in the process that runs it.
#include <functional>

namespace mlce::reader::detail {

struct IsolatedOutcome {
  enum class Kind {
    finished,   ///< the child ran the work to its end or to an exception (the work is deterministic:
                ///< run again in this process it does the same, and any error is thrown here)
    crashed,    ///< the child died by a signal (`signal`) or exited with another status (`status`:
                ///< a sanitizer's report)
    timed_out,  ///< still running after the time limit: killed
    not_run,    ///< no child could be started (fork failed): nothing is known
  };
  Kind kind = Kind::not_run;
  int signal = 0;  ///< crashed by a signal: its number
  int status = 0;  ///< crashed by exiting: its exit status
};

/// Runs `work` in a forked child (a copy of this process; only the calling thread is copied) and
/// waits at most `seconds` for it. The child writes to /dev/null (stdout, stderr), its exceptions
/// are swallowed, and it leaves with _exit (no atexit handlers, no stdio flush: nothing it
/// buffered is written twice). Its results are lost: the caller runs `work` again when it finished.
IsolatedOutcome run_isolated(const std::function<void()>& work, double seconds);

}  // namespace mlce::reader::detail
