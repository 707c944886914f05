#include "FileOutput.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <stdexcept>

namespace fieldcast::io {

namespace {

// A write to a closed pipe also leaves a SIGPIPE pending on this thread (the hub's workers block
// it); take it off so it can never be delivered later.
void discardPendingSigpipe() noexcept {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGPIPE);
  sigset_t pending;
  if (sigpending(&pending) == 0 && sigismember(&pending, SIGPIPE) == 1) {
    const timespec zero{0, 0};
    sigtimedwait(&set, nullptr, &zero);
  }
}

}  // namespace

void FileOutput::open(const std::filesystem::path& path) {
  close();
  mError.clear();
  if (path == "-") {
    mFd = STDOUT_FILENO;
    mOwnsFd = false;
    mName = "standard output";
    return;
  }
  mName = path.string();
  if (path.has_parent_path() && !std::filesystem::exists(path.parent_path())) {
    throw std::runtime_error(mName + ": folder " + path.parent_path().string() + " does not exist");
  }
  mFd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (mFd < 0) throw std::runtime_error(mName + ": cannot open for writing: " + std::strerror(errno));
  mOwnsFd = true;
}

bool FileOutput::writeAll(const iovec* buffers, int count) noexcept {
  if (mFd < 0) {
    mError = "not open";
    return false;
  }
  // A buffer cut short is finished from a copy of its remainder: the caller's array is not
  // changed (a Y4M picture written several times over reuses one array)
  iovec rest{};
  while (count > 0) {
    const bool inRest = rest.iov_len > 0;
    const ssize_t n = inRest ? ::writev(mFd, &rest, 1) : ::writev(mFd, buffers, count);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EPIPE) {
        discardPendingSigpipe();
        mError = "broken pipe: the reader of " + mName + " went away";
      } else {
        mError = mName + ": write failed: " + std::strerror(errno);
      }
      return false;
    }
    auto left = static_cast<std::size_t>(n);
    if (inRest) {
      rest.iov_base = static_cast<char*>(rest.iov_base) + left;
      rest.iov_len -= left;
      if (rest.iov_len == 0) {
        ++buffers;
        --count;
      }
      continue;
    }
    // Skip the buffers written whole; a short write leaves the rest of one for `rest`
    while (count > 0 && left >= buffers->iov_len) {
      left -= buffers->iov_len;
      ++buffers;
      --count;
    }
    if (count > 0 && left > 0) rest = {static_cast<char*>(buffers->iov_base) + left, buffers->iov_len - left};
  }
  return true;
}

bool FileOutput::writeAll(const void* data, std::size_t bytes) noexcept {
  iovec v{const_cast<void*>(data), bytes};
  return writeAll(&v, 1);
}

void FileOutput::close() noexcept {
  if (mFd >= 0 && mOwnsFd) ::close(mFd);
  mFd = -1;
  mOwnsFd = false;
}

}  // namespace fieldcast::io
