// Cost of the CIGI codec per datagram. The typical host message: IG Control + Entity Control +
// Rate Control + HAT/HOT Request + LOS Segment Request (200 bytes), decoded as the IG receives it
// (into a reused packet vector), from a sender of our byte order and of the other one. The goal
// for decode (issue 19) is far under 20 µs. Time per iteration = time per datagram.
#include <io_bridge/cigi/DatagramDecoder.h>
#include <io_bridge/cigi/MessageBuilder.h>

#include "SamplePackets.h"

#include <benchmark/benchmark.h>

#include <vector>

namespace {

using namespace fieldcast::io::cigi;
namespace td = fieldcast::io::cigi::testdata;

std::vector<std::uint8_t> typicalHostMessage(ByteOrder order) {
  HostMessageBuilder builder(order);
  builder.start(td::sampleIgControl());
  builder.add(td::sampleEntityControl());
  builder.add(td::sampleRateControl());
  builder.add(td::sampleHatHotRequest());
  builder.add(td::sampleLosSegmentRequest());
  return {builder.bytes().begin(), builder.bytes().end()};
}

void decodeBench(benchmark::State& state, ByteOrder order) {
  const std::vector<std::uint8_t> datagram = typicalHostMessage(order);
  HostDatagramDecoder decoder;
  std::vector<HostPacket> packets;
  for (auto _ : state) {
    const DecodeResult r = decoder.decode(datagram, packets);
    benchmark::DoNotOptimize(r);
    benchmark::DoNotOptimize(packets.data());
  }
  if (decoder.counters().datagramsAccepted != static_cast<std::uint64_t>(state.iterations())) {
    state.SkipWithError("datagram not accepted");
  }
  state.SetLabel(std::to_string(datagram.size()) + " bytes, 5 packets");
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * datagram.size()));
}

void BM_DecodeHostDatagram(benchmark::State& state) { decodeBench(state, nativeByteOrder()); }
BENCHMARK(BM_DecodeHostDatagram);

void BM_DecodeHostDatagramByteSwapped(benchmark::State& state) { decodeBench(state, swappedByteOrder()); }
BENCHMARK(BM_DecodeHostDatagramByteSwapped);

// The IG's answer each frame: Start of Frame + HAT/HOT Extended Response + LOS Extended Response.
void BM_EncodeIgMessage(benchmark::State& state) {
  IgMessageBuilder builder;
  const StartOfFrame sof = td::sampleStartOfFrame();
  const HatHotExtendedResponse hat = td::sampleHatHotExtendedResponse();
  const LosExtendedResponse los = td::sampleLosExtendedResponse();
  for (auto _ : state) {
    builder.start(sof);
    builder.add(hat);
    builder.add(los);
    benchmark::DoNotOptimize(builder.bytes().data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_EncodeIgMessage);

}  // namespace

BENCHMARK_MAIN();
