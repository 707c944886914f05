#pragma once
// A byte stream to a file or to standard output ("-"), written with writev so a frame of several
// planes leaves in one system call. Errors come back as values: EPIPE means the reader went away.

#include <sys/uio.h>

#include <filesystem>
#include <string>

namespace fieldcast::io {

class FileOutput {
 public:
  FileOutput() = default;
  ~FileOutput() { close(); }
  FileOutput(const FileOutput&) = delete;
  FileOutput& operator=(const FileOutput&) = delete;

  /// Opens (creating or truncating) `path`, or takes standard output for "-". Throws
  /// std::runtime_error naming the path and the system's reason.
  void open(const std::filesystem::path& path);
  /// Writes every byte of the buffers, retrying short writes and EINTR; the buffers are left as
  /// they were, so the same array may be written again. False on failure, with error() saying why
  /// ("broken pipe: the reader of stdout went away", "No space left…").
  bool writeAll(const iovec* buffers, int count) noexcept;
  bool writeAll(const void* data, std::size_t bytes) noexcept;
  /// Closes the file (never standard output). Idempotent.
  void close() noexcept;
  const std::string& error() const noexcept { return mError; }
  bool isOpen() const noexcept { return mFd >= 0; }
  const std::string& displayName() const noexcept { return mName; }

 private:
  int mFd = -1;
  bool mOwnsFd = false;
  std::string mName;
  std::string mError;
};

}  // namespace fieldcast::io
