#pragma once
/// The optional error-message out-parameter used by the loaders and writers: `std::string* error` may be null.

#include <string>

namespace iraf_vo {

/// Stores `msg` in `*error` when the caller asked for the message (error != nullptr).
inline void setError(std::string* error, const std::string& msg) {
  if (error) *error = msg;
}

}  // namespace iraf_vo
