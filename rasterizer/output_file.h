// Checked, atomic output files (docs/errors.md, "Writing outputs" and "Signals").
//
// Every output (image, AOV, statistics, export, bake, cache, report) is written to a temporary
// sibling ".NAME.tmp<PID>_<N><ext>" with checked write(2) loops, fsync and a checked close, and
// renamed over NAME only when all of it reached the disk; on any failure the temporary is removed
// and an existing file at NAME is left as it was. Temporaries in flight are registered so that
// SIGTERM / SIGINT remove them (install_output_signal_handlers); a temporary that a SIGKILL left
// behind is removed by the next write to the same output once its PID is no live process.
// Errors are one line that names the user's path, never the temporary.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "base/status.h"

namespace relief {

// SIGTERM and SIGINT: unlink every registered temporary, then _exit(128 + signal) (143, 130);
// SIGHUP the same (129) unless it was ignored when the process started (nohup).
// SIGXFSZ is ignored, so a write past RLIMIT_FSIZE fails with EFBIG (an error) instead of killing
// the process. Idempotent; call once at program start.
void install_output_signal_handlers();

// Registers `path` (an absolute path: e.g. the empty claim file of `relief render --placeholder`)
// for removal by the SIGTERM / SIGINT / SIGHUP handler above, until unregister_signal_removal;
// returns the slot, or -1 when too many are registered (the path is then left on a signal).
int register_signal_removal(const std::string& path);
void unregister_signal_removal(int slot);

// Checks that `path` can be written before any work is done: it names a file (not "dir/"), its
// folder exists, is a folder and is writable, and `path` is not a directory, device, FIFO or
// socket (a symbolic link is replaced by the file, never written through). Errors (exit 1) start
// with `path`.
Status check_output_path(const std::string& path);

// The key two output paths share when they are one file: the weakly canonical path (".", "..",
// symbolic links of the folders and of the file resolved).
std::string output_identity(const std::string& path);

// A set of outputs written together: stage() writes each fully to its temporary, commit()
// renames them all into place. Temporaries not committed are removed by the destructor.
class StagedFiles {
 public:
  StagedFiles() = default;
  ~StagedFiles();
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;

  // Writes `bytes` to a fresh temporary beside `path` (checked writes, fsync, close). Errors name
  // `path`; nothing is left on disk for a failed stage. A path staged twice is an error.
  Status stage(const std::string& path, std::string_view bytes);
  // Renames every staged temporary over its path in staging order, then syncs the folders.
  Status commit();

 private:
  struct File {
    std::string tmp;
    std::string path;
    int slot;  // in the signal registry, or -1
  };
  void discard();
  std::vector<File> files_;
};

// stage() and commit() of one file.
Status write_file_atomic(const std::string& path, std::string_view bytes);

// Removes the ".NAME.tmp<PID>_*" siblings of `path` whose PID is no live process (left by a
// killed run). Called by stage(); each folder is listed once per process.
void remove_stale_temporaries(const std::string& path);

}  // namespace relief
