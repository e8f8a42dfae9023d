// Regular-file-only input, the scene folder rule and message escaping (safe_file.h).
#include "rasterizer/safe_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace relief {
namespace {

namespace fs = std::filesystem;

const char* kind_of(mode_t m) {
  if (S_ISFIFO(m)) return "a FIFO";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISSOCK(m)) return "a socket";
  return "not a plain file";
}

Status fail(const std::string& path, const std::string& what) {
  return Status::error(printable(path) + ": " + what);
}

Status errno_status(const std::string& path, int err) {
  switch (err) {
    case ENOENT:
    case ENOTDIR:
      return fail(path, "no such file");
    case EACCES:
    case EPERM:
      return fail(path, "permission denied");
    case ELOOP:
      return fail(path, "too many levels of symbolic links");
    case ENAMETOOLONG:
      return fail(path, "file name too long");
    case EISDIR:
      return fail(path, "is a directory");
    default:
      return fail(path, std::string("cannot open: ") + std::strerror(err));
  }
}

// stat's verdict on a file that is about to be opened (nothing is opened for a special file).
Status check_mode(const std::string& path, const struct stat& st, uint64_t max_bytes) {
  if (S_ISDIR(st.st_mode)) return fail(path, "is a directory");
  if (!S_ISREG(st.st_mode))
    return fail(path, std::string("not a regular file (") + kind_of(st.st_mode) + ")");
  if (st.st_size < 0 || static_cast<uint64_t>(st.st_size) > max_bytes)
    return fail(path, "file is " + std::to_string(static_cast<long long>(st.st_size)) +
                          " bytes, more than the limit of " + std::to_string(max_bytes) + " bytes");
  return Status();
}

int hex(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// Whether `inner` is `outer` or lies below it, component by component (both canonical).
bool inside(const fs::path& outer, const fs::path& inner) {
  auto o = outer.begin(), i = inner.begin();
  for (; o != outer.end(); ++o, ++i) {
    if (o->empty()) continue;  // a trailing separator
    if (i == inner.end() || *o != *i) return false;
  }
  return true;
}

}  // namespace

std::string printable(std::string_view s, size_t max, bool escape_backslash) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  const size_t n = s.size() > max ? max : s.size();
  out.reserve(n + 8);
  for (size_t k = 0; k < n; ++k) {
    const auto c = static_cast<unsigned char>(s[k]);
    if (c < 0x20 || c == 0x7f || (c == '\\' && escape_backslash)) {
      out += "\\x";
      out += digits[c >> 4];
      out += digits[c & 15];
    } else {
      out += static_cast<char>(c);
    }
  }
  if (s.size() > max) out += "...";
  return out;
}

SafeFd& SafeFd::operator=(SafeFd&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = o.fd_;
    o.fd_ = -1;
  }
  return *this;
}

SafeFd::~SafeFd() {
  if (fd_ >= 0) ::close(fd_);
}

Result<SafeFd> open_regular_file(const std::string& path, uint64_t* size, uint64_t max_bytes) {
  if (path.empty()) return Status::error("(empty file name): no such file");
  if (path.find('\0') != std::string::npos) return fail(path, "file name holds a NUL byte");
  // stat first: a device is never opened (opening some has side effects), a FIFO never waited on.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return errno_status(path, errno);
  RELIEF_RETURN_IF_ERROR(check_mode(path, st, max_bytes));
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return errno_status(path, errno);
  SafeFd file(fd);
  // What was opened may have been swapped in after the stat: check the descriptor itself.
  struct stat now {};
  if (::fstat(fd, &now) != 0) return errno_status(path, errno);
  RELIEF_RETURN_IF_ERROR(check_mode(path, now, max_bytes));
  if (size) *size = static_cast<uint64_t>(now.st_size);
  return file;
}

Result<std::string> read_regular_file(const std::string& path, uint64_t max_bytes) {
  uint64_t size = 0;
  Result<SafeFd> fd = open_regular_file(path, &size, max_bytes);
  if (!fd.ok()) return fd.status();
  std::string bytes;
  try {
    bytes.resize(static_cast<size_t>(size));
  } catch (const std::bad_alloc&) {
    return fail(path, "out of memory reading " + std::to_string(size) + " bytes");
  }
  size_t got = 0;
  while (got < bytes.size()) {
    const ssize_t r = ::read(fd->get(), bytes.data() + got, bytes.size() - got);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) return fail(path, std::string("read error: ") + std::strerror(errno));
    if (r == 0) return fail(path, "changed while being read (shorter than its size)");
    got += static_cast<size_t>(r);
  }
  char extra = 0;
  ssize_t r = 0;
  do {
    r = ::read(fd->get(), &extra, 1);
  } while (r < 0 && errno == EINTR);
  if (r > 0) return fail(path, "changed while being read (longer than its size)");
  return bytes;
}

bool percent_decode(std::string_view uri, std::string& out) {
  out.clear();
  out.reserve(uri.size());
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] != '%') {
      out += uri[i];
      continue;
    }
    if (i + 2 >= uri.size()) return false;
    const int hi = hex(uri[i + 1]), lo = hex(uri[i + 2]);
    if (hi < 0 || lo < 0) return false;
    out += static_cast<char>(hi * 16 + lo);
    i += 2;
  }
  return true;
}

bool uri_has_scheme(std::string_view uri) {
  // scheme = ALPHA *( ALPHA / DIGIT / "+" / "-" / "." ) ":"  (RFC 3986 section 3.1)
  if (uri.empty() || !std::isalpha(static_cast<unsigned char>(uri[0]))) return false;
  for (size_t i = 1; i < uri.size(); ++i) {
    const auto c = static_cast<unsigned char>(uri[i]);
    if (c == ':') return true;
    if (!std::isalnum(c) && c != '+' && c != '-' && c != '.') return false;
  }
  return false;
}

namespace {
Result<ResolvedUri> resolve_decoded(const SceneFolder& folder, const std::string& decoded,
                                    const std::string& shown);
}  // namespace

Result<ResolvedUri> resolve_scene_uri(const SceneFolder& folder, std::string_view uri) {
  const std::string shown = "'" + printable(uri, 60) + "'";
  if (uri.empty()) return Status::error("empty URI");
  if (uri_has_scheme(uri))
    return Status::error(shown +
                         ": URI schemes are not allowed (only relative references and "
                         "data: URIs)");
  std::string decoded;
  if (!percent_decode(uri, decoded))
    return Status::error(shown + ": bad percent escape (expected %XX)");
  return resolve_decoded(folder, decoded, shown);
}

Result<ResolvedUri> resolve_scene_path(const SceneFolder& folder, const std::string& decoded) {
  return resolve_decoded(folder, decoded, "'" + printable(decoded, 60) + "'");
}

namespace {

// resolve_scene_path, with `shown` (the URI as the file writes it) in messages.
Result<ResolvedUri> resolve_decoded(const SceneFolder& folder, const std::string& decoded,
                                    const std::string& shown) {
  if (decoded.empty()) return Status::error("empty URI");
  for (char c : decoded)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      return Status::error(shown + ": URI holds a NUL or control character");
  if (decoded[0] == '/' && !folder.allow_outside)
    return Status::error(shown +
                         ": an absolute path (URIs are relative to the scene's folder; "
                         "--allow-outside-scene-dir allows it)");
  const fs::path dir = folder.dir.empty() ? fs::path(".") : fs::path(folder.dir);
  const fs::path joined = dir / decoded;
  ResolvedUri r;
  r.path = folder.dir.empty() ? decoded : joined.string();
  std::error_code ec;
  const fs::path real_dir = fs::weakly_canonical(dir, ec);
  if (ec)
    return Status::error(shown + ": cannot resolve the scene's folder (" + ec.message() + ")");
  const fs::path real = fs::weakly_canonical(joined, ec);
  if (ec) return Status::error(shown + ": cannot resolve (" + ec.message() + ")");
  r.inside = inside(real_dir, real);
  if (!folder.allow_outside && !r.inside)
    return Status::error(
        shown + ": leads outside the scene's folder (--allow-outside-scene-dir allows it)");
  r.real = real.string();
  return r;
}

}  // namespace

}  // namespace relief
