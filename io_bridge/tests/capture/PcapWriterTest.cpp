// PcapWriter's file read back byte by byte: the classic pcap headers, the Ethernet/IPv4/UDP frame
// around each payload (addresses, ports, lengths, a valid IPv4 checksum), time order kept when
// stamps go back, and whole records when two threads write at once.
#include <io_bridge/PcapWriter.h>

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <thread>
#include <vector>

namespace fieldcast::io {
namespace {

namespace fs = std::filesystem;

struct Record {
  std::uint32_t seconds = 0, microseconds = 0;
  std::vector<std::uint8_t> frame;
};

template <class T>
T native(const std::vector<std::uint8_t>& bytes, std::size_t at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof v);
  return v;
}

std::uint32_t bigEndian(const std::vector<std::uint8_t>& b, std::size_t at, int n) {
  std::uint32_t v = 0;
  for (int k = 0; k < n; ++k) v = (v << 8) | b[at + static_cast<std::size_t>(k)];
  return v;
}

// The records after the 24-byte global header (whose magic and link type are checked here).
std::vector<Record> readCapture(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (bytes.size() < 24) throw std::runtime_error("no global header");
  EXPECT_EQ(native<std::uint32_t>(bytes, 0), 0xA1B2C3D4u);  // microsecond stamps, our byte order
  EXPECT_EQ(native<std::uint32_t>(bytes, 20), 1u);          // Ethernet
  std::vector<Record> records;
  for (std::size_t at = 24; at < bytes.size();) {
    if (at + 16 > bytes.size()) throw std::runtime_error("cut record header");
    Record r{native<std::uint32_t>(bytes, at), native<std::uint32_t>(bytes, at + 4), {}};
    const auto length = native<std::uint32_t>(bytes, at + 8);
    EXPECT_EQ(native<std::uint32_t>(bytes, at + 12), length);
    if (at + 16 + length > bytes.size()) throw std::runtime_error("cut record");
    r.frame.assign(bytes.begin() + static_cast<std::ptrdiff_t>(at + 16),
                   bytes.begin() + static_cast<std::ptrdiff_t>(at + 16 + length));
    records.push_back(std::move(r));
    at += 16 + length;
  }
  return records;
}

class PcapWriterTest : public ::testing::Test {
 protected:
  fs::path mPath = fs::temp_directory_path() / ("fieldcast_pcap_" + std::to_string(getpid()) + ".pcap");
  void TearDown() override { fs::remove(mPath); }
};

TEST_F(PcapWriterTest, FramesCarryTheEndpointsAndThePayload) {
  const std::vector<std::uint8_t> payload{1, 2, 3, 4, 5};
  {
    PcapWriter writer(mPath.string());
    writer.writeUdp({0x0A000001, 40000}, {0xC0A80102, 8004}, payload, 1'700'000'000'123'456);
    EXPECT_EQ(writer.frames(), 1);
  }
  const std::vector<Record> records = readCapture(mPath);
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records[0].seconds, 1'700'000'000u);
  EXPECT_EQ(records[0].microseconds, 123'456u);
  const std::vector<std::uint8_t>& f = records[0].frame;
  ASSERT_EQ(f.size(), 14u + 20u + 8u + payload.size());
  EXPECT_EQ(bigEndian(f, 12, 2), 0x0800u);                    // IPv4
  EXPECT_EQ(f[14], 0x45);                                     // version 4, 20-byte header
  EXPECT_EQ(bigEndian(f, 16, 2), 20u + 8u + payload.size());  // IPv4 total length
  EXPECT_EQ(f[23], 17);                                       // UDP
  EXPECT_EQ(bigEndian(f, 26, 4), 0x0A000001u);                // 10.0.0.1
  EXPECT_EQ(bigEndian(f, 30, 4), 0xC0A80102u);                // 192.168.1.2
  std::uint32_t sum = 0;                                      // a valid header sums to 0xFFFF in one's complement
  for (std::size_t i = 14; i < 34; i += 2) sum += bigEndian(f, i, 2);
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  EXPECT_EQ(sum, 0xFFFFu);
  EXPECT_EQ(bigEndian(f, 34, 2), 40000u);
  EXPECT_EQ(bigEndian(f, 36, 2), 8004u);
  EXPECT_EQ(bigEndian(f, 38, 2), 8u + payload.size());
  EXPECT_TRUE(std::equal(payload.begin(), payload.end(), f.begin() + 42));
}

TEST_F(PcapWriterTest, AStampEarlierThanThePreviousIsRaisedToIt) {
  {
    PcapWriter writer(mPath.string());
    const std::vector<std::uint8_t> payload{9};
    writer.writeUdp({}, {}, payload, 2'000'000);
    writer.writeUdp({}, {}, payload, 1'999'990);  // stamped by another thread a little earlier
    writer.writeUdp({}, {}, payload, 3'000'001);
  }
  const std::vector<Record> records = readCapture(mPath);
  ASSERT_EQ(records.size(), 3u);
  EXPECT_EQ(records[1].seconds, 2u);
  EXPECT_EQ(records[1].microseconds, 0u);
  EXPECT_EQ(records[2].seconds, 3u);
  EXPECT_EQ(records[2].microseconds, 1u);
}

TEST_F(PcapWriterTest, TwoThreadsWriteWholeRecords) {
  constexpr int kEach = 20000;
  {
    PcapWriter writer(mPath.string());
    std::atomic<int> ready{0};
    const auto write = [&](std::uint8_t tag, std::size_t size) {
      const std::vector<std::uint8_t> payload(size, tag);
      ready.fetch_add(1);
      while (ready.load() < 2) {
      }  // both write at once
      for (int k = 0; k < kEach; ++k) writer.writeUdp({}, {}, payload, 1'000'000 + static_cast<std::uint64_t>(k));
    };
    std::thread a(write, std::uint8_t{0xAA}, std::size_t{40});
    std::thread b(write, std::uint8_t{0xBB}, std::size_t{300});
    a.join();
    b.join();
    writer.flush();
    EXPECT_EQ(writer.frames(), 2 * kEach);
  }
  const std::vector<Record> records = readCapture(mPath);
  ASSERT_EQ(records.size(), 2u * kEach);
  for (const Record& r : records) {
    const std::size_t payload = r.frame.size() - 42;
    ASSERT_TRUE(payload == 40 || payload == 300) << payload;
    const std::uint8_t tag = payload == 40 ? 0xAA : 0xBB;
    ASSERT_TRUE(std::all_of(r.frame.begin() + 42, r.frame.end(), [&](std::uint8_t v) { return v == tag; }));
  }
}

TEST_F(PcapWriterTest, AnUnwritablePathIsNamedInTheError) {
  try {
    PcapWriter writer("/nonexistent-dir/x.pcap");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.pcap"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fieldcast::io
