// Checked, atomic output files and the signal-time cleanup of their temporaries (output_file.h).
#include "rasterizer/output_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>

#include "rasterizer/safe_file.h"

namespace relief {
namespace {

namespace fs = std::filesystem;

// ---- temporaries in flight, for the signal handler ----
// A slot is 0 (free), 1 (being filled) or 2 (holds a path the handler unlinks). Only the owner
// edits a slot; the handler reads slots in state 2. No locks, no allocation in the handler.
constexpr int kSlots = 256;
constexpr size_t kSlotPath = 4096;
struct Slot {
  std::atomic<int> state{0};
  char path[kSlotPath];
};
Slot g_slots[kSlots];
static_assert(std::atomic<int>::is_always_lock_free);

int register_temporary(const std::string& path) {
  if (path.size() >= kSlotPath) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (!g_slots[i].state.compare_exchange_strong(expected, 1, std::memory_order_acquire)) continue;
    std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
    g_slots[i].state.store(2, std::memory_order_release);
    return i;
  }
  return -1;  // full: the file is still written, only not removed on a signal
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_slots[slot].state.store(0, std::memory_order_release);
}

extern "C" void on_terminate_signal(int sig) {
  for (Slot& s : g_slots)
    if (s.state.load(std::memory_order_acquire) == 2) ::unlink(s.path);
  ::_exit(128 + sig);
}

// ---- names ----
std::string errno_text(int e) {
  return std::strerror(e);
}

// "<path>: <what>", the path escaped and cut (safe_file.h printable) so the reason stays visible.
Status fail(const std::string& path, const std::string& what) {
  return Status::error(printable(path) + ": " + what);
}

// ".NAME.tmp" with NAME cut so that the whole temporary name stays under NAME_MAX (255).
std::string temp_prefix(const std::string& filename) {
  return "." + filename.substr(0, 200) + ".tmp";
}

std::string temp_name(const std::string& filename) {
  static std::atomic<unsigned> counter{0};
  std::string ext = fs::path(filename).extension().string();
  if (ext.size() > 16) ext.clear();
  return temp_prefix(filename) + std::to_string(::getpid()) + "_" +
         std::to_string(counter.fetch_add(1)) + ext;
}

fs::path folder_of(const std::string& path) {
  const fs::path dir = fs::path(path).parent_path();
  return dir.empty() ? fs::path(".") : dir;
}

// Writes all of `bytes` to `fd`; false with errno set on failure.
bool write_all(int fd, const char* p, size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n > (1u << 30) ? (1u << 30) : n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if (w == 0) {
      errno = EIO;
      return false;
    }
    p += w;
    n -= static_cast<size_t>(w);
  }
  return true;
}

void sync_folder(const fs::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);  // best effort: the renames are done, some file systems refuse a folder fsync
  ::close(fd);
}

// ---- stale temporaries ----
std::mutex g_stale_mutex;
// Folder (canonical) -> names in it that look like ".X.tmp<PID>_<N>...", listed once.
std::map<std::string, std::set<std::string>>& stale_candidates() {
  static auto* m = new std::map<std::string, std::set<std::string>>();
  return *m;
}

bool looks_temporary(const std::string& name) {
  if (name.size() < 8 || name[0] != '.') return false;
  return name.find(".tmp", 1) != std::string::npos;
}

// The PID in `name` when it is prefix + digits + "_", else -1.
long temp_pid(const std::string& name, const std::string& prefix) {
  if (name.compare(0, prefix.size(), prefix) != 0) return -1;
  size_t i = prefix.size();
  long pid = 0;
  const size_t start = i;
  while (i < name.size() && name[i] >= '0' && name[i] <= '9' && i - start < 10)
    pid = pid * 10 + (name[i++] - '0');
  if (i == start || i >= name.size() || name[i] != '_' || pid <= 0) return -1;
  return pid;
}

}  // namespace

void install_output_signal_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    struct sigaction sa;
    std::memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_terminate_signal;
    sigfillset(&sa.sa_mask);  // one handler at a time
    ::sigaction(SIGTERM, &sa, nullptr);
    ::sigaction(SIGINT, &sa, nullptr);  // also when inherited as ignored (a job run with &)
    struct sigaction old;
    if (::sigaction(SIGHUP, nullptr, &old) == 0 && old.sa_handler != SIG_IGN)  // nohup: ignored
      ::sigaction(SIGHUP, &sa, nullptr);
    ::signal(SIGXFSZ, SIG_IGN);
  });
}

int register_signal_removal(const std::string& path) {
  return register_temporary(path);
}

void unregister_signal_removal(int slot) {
  unregister_temporary(slot);
}

Status check_output_path(const std::string& path) {
  if (path.empty()) return Status::error("'': not a file name");
  const fs::path p(path);
  const std::string name = p.filename().string();
  if (name.empty() || name == "." || name == "..") return fail(path, "not a file name");
  const fs::path dir = folder_of(path);
  struct stat st;
  if (::stat(dir.c_str(), &st) != 0) {
    if (errno == ENOENT) return fail(path, "directory does not exist");
    return fail(path, "cannot use its folder: " + errno_text(errno));
  }
  if (!S_ISDIR(st.st_mode))
    return fail(path, "'" + printable(dir.string()) + "' is not a directory");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    return fail(path, "folder is not writable: " + errno_text(errno));
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) return fail(path, "is a directory");
    if (!S_ISREG(st.st_mode)) return fail(path, "not a regular file (a device, FIFO or socket)");
  } else if (errno == ENAMETOOLONG) {
    return fail(path, "cannot write: " + errno_text(errno));
  }
  return {};
}

std::string output_identity(const std::string& path) {
  std::error_code ec;
  fs::path abs = fs::absolute(path, ec);
  if (ec) abs = fs::path(path);
  fs::path canon = fs::weakly_canonical(abs, ec);
  if (ec) canon = abs;
  return canon.lexically_normal().string();
}

void remove_stale_temporaries(const std::string& path) {
  const fs::path dir = folder_of(path);
  const std::string prefix = temp_prefix(fs::path(path).filename().string());
  std::lock_guard<std::mutex> lock(g_stale_mutex);
  const std::string key = output_identity(dir.string());
  auto it = stale_candidates().find(key);
  if (it == stale_candidates().end()) {
    std::set<std::string> names;
    if (DIR* d = ::opendir(dir.c_str())) {
      while (const dirent* e = ::readdir(d)) {
        const std::string n = e->d_name;
        if (looks_temporary(n)) names.insert(n);
      }
      ::closedir(d);
    }
    it = stale_candidates().emplace(key, std::move(names)).first;
  }
  std::set<std::string>& names = it->second;
  for (auto n = names.lower_bound(prefix); n != names.end() && n->rfind(prefix, 0) == 0;) {
    const long pid = temp_pid(*n, prefix);
    bool stale = false;
    if (pid > 0 && pid != ::getpid() && pid <= 0x7fffffffL)
      stale = ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
    if (stale) {
      ::unlink((dir / *n).c_str());
      n = names.erase(n);
    } else {
      ++n;
    }
  }
}

StagedFiles::~StagedFiles() {
  discard();
}

void StagedFiles::discard() {
  for (const File& f : files_) {
    ::unlink(f.tmp.c_str());
    unregister_temporary(f.slot);
  }
  files_.clear();
}

Status StagedFiles::stage(const std::string& path, std::string_view bytes) {
  RELIEF_RETURN_IF_ERROR(check_output_path(path));
  const std::string id = output_identity(path);
  for (const File& f : files_)
    if (output_identity(f.path) == id)
      return fail(path, "is written twice (also as '" + printable(f.path) + "')");
  remove_stale_temporaries(path);
  const fs::path dir = folder_of(path);
  std::error_code ec;
  fs::path abs_dir = fs::absolute(dir, ec);
  if (ec) abs_dir = dir;
  const std::string tmp = (abs_dir / temp_name(fs::path(path).filename().string())).string();
  const int slot = register_temporary(tmp);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) {
    const int e = errno;
    unregister_temporary(slot);
    return fail(path, "cannot write: " + errno_text(e));
  }
  struct stat old;
  if (::stat(path.c_str(), &old) == 0 && S_ISREG(old.st_mode))
    (void)::fchmod(fd, old.st_mode & 0777);  // the permissions of the file replaced (no set-id)
  bool ok = write_all(fd, bytes.data(), bytes.size());
  int e = ok ? 0 : errno;
  if (ok && ::fsync(fd) != 0) ok = false, e = errno;
  struct stat st;
  if (ok && (::fstat(fd, &st) != 0 || static_cast<size_t>(st.st_size) != bytes.size()))
    ok = false, e = EIO;
  if (::close(fd) != 0 && ok) ok = false, e = errno;
  if (!ok) {
    ::unlink(tmp.c_str());
    unregister_temporary(slot);
    return fail(path, "cannot write: " + errno_text(e));
  }
  files_.push_back({tmp, path, slot});
  return {};
}

Status StagedFiles::commit() {
  std::set<std::string> dirs;
  for (size_t i = 0; i < files_.size(); ++i) {
    const File f = files_[i];
    if (::rename(f.tmp.c_str(), f.path.c_str()) != 0) {
      const int e = errno;
      files_.erase(files_.begin(), files_.begin() + static_cast<std::ptrdiff_t>(i));
      discard();
      return fail(f.path, "cannot rename into place: " + errno_text(e));
    }
    unregister_temporary(f.slot);
    dirs.insert(folder_of(f.path).string());
  }
  files_.clear();
  for (const std::string& d : dirs) sync_folder(d);
  return {};
}

Status write_file_atomic(const std::string& path, std::string_view bytes) {
  StagedFiles files;
  RELIEF_RETURN_IF_ERROR(files.stage(path, bytes));
  return files.commit();
}

}  // namespace relief
