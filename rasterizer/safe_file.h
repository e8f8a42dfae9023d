// Opening other people's files safely (docs/errors.md, "Only regular files" and "The scene folder
// rule"): only regular files are read (a FIFO, a device or a socket is refused before anything
// reads it, so nothing blocks or spins), the bytes read are capped, URIs from scene files resolve
// inside the scene's folder, and names are escaped before they reach a one-line message.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "base/status.h"

namespace relief {

// The largest input file read (scene, buffer, image, cache): 1 GiB, checked from fstat before
// a byte is read.
inline constexpr uint64_t kMaxInputFileBytes = 1ULL << 30;

// `s` made safe for a one-line message: bytes below 0x20, 0x7f and (with escape_backslash, so
// that the escape reads back unambiguously in a name) backslash as \xNN; other bytes, UTF-8
// included, unchanged; longer than `max` bytes: its first `max` bytes + "...".
std::string printable(std::string_view s, size_t max = 120, bool escape_backslash = true);

// An open read-only file descriptor, closed on destruction.
class SafeFd {
 public:
  SafeFd() = default;
  explicit SafeFd(int fd) : fd_(fd) {}
  SafeFd(SafeFd&& o) noexcept : fd_(o.fd_) { o.fd_ = -1; }
  SafeFd& operator=(SafeFd&& o) noexcept;
  SafeFd(const SafeFd&) = delete;
  SafeFd& operator=(const SafeFd&) = delete;
  ~SafeFd();
  int get() const { return fd_; }

 private:
  int fd_ = -1;
};

// Opens `path` read-only (O_NONBLOCK, so a FIFO cannot block; O_NOCTTY, O_CLOEXEC) and checks
// with fstat that it is a regular file of at most `max_bytes`; `size` gets its size. Errors, each
// "<printable path>: <what>": `no such file`, `is a directory`, `not a regular file (a FIFO)` (a
// character device, a block device, a socket), `permission denied`, `cannot open: <strerror>`,
// `file is <n> bytes, more than the limit of <max> bytes`.
Result<SafeFd> open_regular_file(const std::string& path, uint64_t* size = nullptr,
                                 uint64_t max_bytes = kMaxInputFileBytes);

// The whole of a regular file (open_regular_file, then read from that descriptor only). A file
// that changes size while read is an error (`changed while being read`).
Result<std::string> read_regular_file(const std::string& path,
                                      uint64_t max_bytes = kMaxInputFileBytes);

// The folder a scene file's URIs resolve in, and whether they may leave it
// (`--allow-outside-scene-dir`).
struct SceneFolder {
  std::string dir;  // the scene file's parent folder as given ("" means ".")
  bool allow_outside = false;
};

// A URI resolved by resolve_scene_uri: `path` (the folder joined with the decoded reference, for
// messages) and `real` (every symlink resolved: what to open).
struct ResolvedUri {
  std::string path;
  std::string real;
  bool inside = true;  // `real` lies in the folder (false only with allow_outside)
};

// Resolves a URI reference from a scene file (percent-encoded, as written; not a data: URI) in
// `folder`. Refused, with a message that does NOT start with a path (callers prefix the file and
// JSON pointer): an empty URI; a scheme (`file:`, `http:`, ...: only relative references and
// data: URIs); a bad percent escape; NUL or another control byte once decoded; an absolute path
// or a reference that leaves the folder after resolving `..` and symlinks (component-wise, both
// sides canonical), unless folder.allow_outside. The file itself is not opened here.
Result<ResolvedUri> resolve_scene_uri(const SceneFolder& folder, std::string_view uri);

// resolve_scene_uri's checks after the percent decoding, for a reference already decoded (what
// tinygltf hands its file callbacks): control bytes, absolute paths, the folder rule.
Result<ResolvedUri> resolve_scene_path(const SceneFolder& folder, const std::string& decoded);

// The URI with %XX escapes decoded; false for a '%' not followed by two hex digits.
bool percent_decode(std::string_view uri, std::string& out);

// Whether `uri` starts with an RFC 3986 scheme ("data:", "file:", "http:", ...).
bool uri_has_scheme(std::string_view uri);

}  // namespace relief
