// Error values for bad input. A Status carries one line of text that names the offending file,
// JSON pointer or parameter and what was expected; the CLI prints it and exits non-zero.
// kind() separates usage errors (exit 2) from input errors (exit 1).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "base/check.h"

namespace relief {

enum class ErrorKind { kInput, kUsage };

class [[nodiscard]] Status {
 public:
  Status() = default;
  static Status error(std::string message, ErrorKind kind = ErrorKind::kInput) {
    Status s;
    s.message_ = std::move(message);
    s.kind_ = kind;
    s.failed_ = true;
    return s;
  }
  static Status usage(std::string message) { return error(std::move(message), ErrorKind::kUsage); }
  bool ok() const { return !failed_; }
  explicit operator bool() const { return ok(); }
  const std::string& message() const { return message_; }
  ErrorKind kind() const { return kind_; }
  int exit_code() const { return ok() ? 0 : (kind_ == ErrorKind::kUsage ? 2 : 1); }
  // Prefixes context ("scene.gltf: ") to the message.
  Status with_context(const std::string& context) const {
    if (ok()) return *this;
    Status s = *this;
    s.message_ = context + ": " + message_;
    return s;
  }

 private:
  std::string message_;
  ErrorKind kind_ = ErrorKind::kInput;
  bool failed_ = false;
};

// A value or the Status that explains why there is none.
template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : value_(std::move(value)) {}  // NOLINT: implicit by design
  Result(Status status) : status_(std::move(status)) { CHECK(!status_.ok()); }  // NOLINT
  bool ok() const { return value_.has_value(); }
  explicit operator bool() const { return ok(); }
  const Status& status() const { return status_; }
  T& value() & {
    CHECK(ok());
    return *value_;
  }
  const T& value() const& {
    CHECK(ok());
    return *value_;
  }
  T&& value() && {
    CHECK(ok());
    return std::move(*value_);
  }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

 private:
  std::optional<T> value_;
  Status status_;
};

#define RELIEF_RETURN_IF_ERROR(expr)       \
  do {                                     \
    ::relief::Status relief_s_ = (expr);   \
    if (!relief_s_.ok()) return relief_s_; \
  } while (0)

}  // namespace relief
