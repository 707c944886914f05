#pragma once
// errno as text, thread-safely (strerror is not: the input and GPIO threads open devices).

#include <cstring>
#include <string>

namespace fieldcast::io {

/// The message of errno value `err`. Thread-safe.
inline std::string errnoMessage(int err) {
  char buf[128];
  return ::strerror_r(err, buf, sizeof buf);  // GNU strerror_r: returns the message pointer
}

}  // namespace fieldcast::io
