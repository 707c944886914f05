// FileOutput::writeAll when the system writes only part of what it is given: a pipe whose writer a
// signal keeps interrupting returns short counts, as a pipe to a stopped reader or a nearly full
// disk can.
#include "FileOutput.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

namespace fieldcast::io {
namespace {

std::atomic<int> gInterruptions{0};
void countInterruption(int) { gInterruptions.fetch_add(1, std::memory_order_relaxed); }

// One array written three times, as Y4mSink writes a first picture that also stands for the frames
// before it: every copy arrives whole and in order, and the array is left as it was. With the
// array's entries moved past what a short write took, the later copies came out cut.
TEST(FileOutput, ShortWritesResumeAndLeaveTheCallersBuffersAsTheyWere) {
  const std::filesystem::path fifo =
      std::filesystem::temp_directory_path() / ("fieldcast_file_output_" + std::to_string(getpid()) + ".fifo");
  std::filesystem::remove(fifo);
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  struct sigaction interrupt {};
  interrupt.sa_handler = countInterruption;  // no SA_RESTART: a blocked write returns what it wrote
  struct sigaction previous {};
  ASSERT_EQ(sigaction(SIGUSR1, &interrupt, &previous), 0);

  std::vector<char> head(6), picture(150'001), tail(40'000);
  for (std::size_t i = 0; i < picture.size(); ++i) picture[i] = static_cast<char>(i * 131 + i / 251);
  for (std::size_t i = 0; i < tail.size(); ++i) tail[i] = static_cast<char>(i * 7 + 3);
  head.assign({'F', 'R', 'A', 'M', 'E', '\n'});
  iovec parts[3] = {{head.data(), head.size()}, {picture.data(), picture.size()}, {tail.data(), tail.size()}};
  const iovec before[3] = {parts[0], parts[1], parts[2]};
  std::string expected;
  for (int copy = 0; copy < 3; ++copy) {
    for (const iovec& v : before) expected.append(static_cast<const char*>(v.iov_base), v.iov_len);
  }

  std::string received;
  std::thread reader([&] {  // slow, so the writer waits in its writes and the signals cut them
    const int fd = ::open(fifo.c_str(), O_RDONLY);
    if (fd < 0) return;
    char chunk[4096];
    for (ssize_t n; (n = ::read(fd, chunk, sizeof chunk)) != 0;) {
      if (n > 0) received.append(chunk, static_cast<std::size_t>(n));
      usleep(100);
    }
    ::close(fd);
  });
  FileOutput out;
  out.open(fifo);  // returns once the reader has the FIFO open
  std::atomic<bool> written{false};
  const pthread_t writer = pthread_self();
  std::thread interrupter([&] {
    while (!written.load()) {
      pthread_kill(writer, SIGUSR1);
      usleep(200);
    }
  });
  bool ok = true;
  for (int copy = 0; copy < 3 && ok; ++copy) ok = out.writeAll(parts, 3);
  written = true;
  interrupter.join();
  out.close();
  reader.join();
  sigaction(SIGUSR1, &previous, nullptr);
  std::filesystem::remove(fifo);

  ASSERT_TRUE(ok) << out.error();
  EXPECT_GT(gInterruptions.load(), 3) << "the writes were hardly interrupted: nothing was tested";
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(parts[k].iov_base, before[k].iov_base) << k;
    EXPECT_EQ(parts[k].iov_len, before[k].iov_len) << k;
  }
  ASSERT_EQ(received.size(), expected.size());
  EXPECT_TRUE(received == expected) << "the bytes arrived changed or out of order";
}

}  // namespace
}  // namespace fieldcast::io
