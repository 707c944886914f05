// libFuzzer target for the CIGI datagram decoders. Each input is decoded as a host→IG and as an
// IG→host datagram. Besides "no crash, no sanitizer report", it checks the decoder's promises:
// an accepted datagram starts with its control packet and hands out at least it; a rejected one
// hands out nothing; every datagram is counted exactly once.
#include <io_bridge/cigi/DatagramDecoder.h>
#include <io_bridge/cigi/MessageBuilder.h>

#include "FuzzSeedCorpus.h"
#include "SamplePackets.h"

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <span>
#include <vector>

namespace {

using namespace fieldcast::io::cigi;
namespace td = fieldcast::io::cigi::testdata;

void writeSeed(const std::filesystem::path& dir, const char* name, std::span<const std::uint8_t> bytes) {
  std::ofstream(dir / name, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

template <class Packet>
void check(DatagramDecoder<Packet>& decoder, std::span<const std::uint8_t> bytes, std::vector<Packet>& packets) {
  const std::uint64_t before = decoder.counters().datagramsAccepted + decoder.counters().rejectedTotal();
  const DecodeResult r = decoder.decode(bytes, packets);
  const std::uint64_t after = decoder.counters().datagramsAccepted + decoder.counters().rejectedTotal();
  if (after != before + 1) std::abort();
  if (r.accepted()) {
    if (packets.empty() || packets.front().index() != 0) std::abort();
  } else if (!packets.empty()) {
    std::abort();
  }
}

}  // namespace

// Seeds the corpus directory (the first non-flag argument) with valid messages of both
// directions in both byte orders.
extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  if (const auto dir = fieldcast::io::testdata::emptyCorpusDirectory(*argc, *argv)) {
    for (const ByteOrder order : {ByteOrder::Big, ByteOrder::Little}) {
      const bool big = order == ByteOrder::Big;
      HostMessageBuilder host(order);
      host.start(td::sampleIgControl());
      host.add(td::sampleEntityControl());
      host.add(td::sampleRateControl());
      host.add(td::sampleHatHotRequest());
      host.add(td::sampleLosSegmentRequest());
      writeSeed(*dir, big ? "host_big" : "host_little", host.bytes());
      host.start(td::sampleIgControl());
      host.add(td::sampleCelestialSphereControl());
      host.add(td::sampleAtmosphereControl());
      host.add(td::sampleViewControl());
      host.add(td::sampleViewDefinition());
      host.add(td::sampleLosVectorRequest());
      writeSeed(*dir, big ? "host_views_big" : "host_views_little", host.bytes());
      IgMessageBuilder ig(order);
      ig.start(td::sampleStartOfFrame());
      ig.add(td::sampleHatHotResponse());
      ig.add(td::sampleHatHotExtendedResponse());
      ig.add(td::sampleLosResponse());
      ig.add(td::sampleLosExtendedResponse());
      writeSeed(*dir, big ? "ig_big" : "ig_little", ig.bytes());
    }
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static HostDatagramDecoder hostDecoder;
  static IgDatagramDecoder igDecoder;
  static std::vector<HostPacket> hostPackets;
  static std::vector<IgPacket> igPackets;
  const std::span<const std::uint8_t> bytes(data, size);
  check(hostDecoder, bytes, hostPackets);
  check(igDecoder, bytes, igPackets);
  return 0;
}
