#pragma once
// Encode and decode single CIGI 3.3 packets. Each encode writes exactly P::kSize bytes (packet
// id, size, fields, reserved bytes zero) in the given byte order; each decode reads exactly
// P::kSize bytes in the sender's byte order. Neither checks the id and size bytes (the datagram
// decoder does) nor allocates: RT-safe.

#include <io_bridge/cigi/ByteOrder.h>
#include <io_bridge/cigi/Packets.h>

#include <cstdint>
#include <span>

namespace fieldcast::io::cigi {

/// Writes the packet in `order` into `out`. IG Control and Start of Frame get the byte-swap
/// magic and minor version 3.
void encode(const IgControl& p, ByteOrder order, std::span<std::uint8_t, IgControl::kSize> out) noexcept;
void encode(const EntityControl& p, ByteOrder order, std::span<std::uint8_t, EntityControl::kSize> out) noexcept;
void encode(const RateControl& p, ByteOrder order, std::span<std::uint8_t, RateControl::kSize> out) noexcept;
void encode(const CelestialSphereControl& p, ByteOrder order,
            std::span<std::uint8_t, CelestialSphereControl::kSize> out) noexcept;
void encode(const AtmosphereControl& p, ByteOrder order,
            std::span<std::uint8_t, AtmosphereControl::kSize> out) noexcept;
void encode(const ViewControl& p, ByteOrder order, std::span<std::uint8_t, ViewControl::kSize> out) noexcept;
void encode(const ViewDefinition& p, ByteOrder order, std::span<std::uint8_t, ViewDefinition::kSize> out) noexcept;
void encode(const HatHotRequest& p, ByteOrder order, std::span<std::uint8_t, HatHotRequest::kSize> out) noexcept;
void encode(const LosSegmentRequest& p, ByteOrder order,
            std::span<std::uint8_t, LosSegmentRequest::kSize> out) noexcept;
void encode(const LosVectorRequest& p, ByteOrder order, std::span<std::uint8_t, LosVectorRequest::kSize> out) noexcept;
void encode(const StartOfFrame& p, ByteOrder order, std::span<std::uint8_t, StartOfFrame::kSize> out) noexcept;
void encode(const HatHotResponse& p, ByteOrder order, std::span<std::uint8_t, HatHotResponse::kSize> out) noexcept;
void encode(const HatHotExtendedResponse& p, ByteOrder order,
            std::span<std::uint8_t, HatHotExtendedResponse::kSize> out) noexcept;
void encode(const LosResponse& p, ByteOrder order, std::span<std::uint8_t, LosResponse::kSize> out) noexcept;
void encode(const LosExtendedResponse& p, ByteOrder order,
            std::span<std::uint8_t, LosExtendedResponse::kSize> out) noexcept;

/// Reads the packet's fields from `in`, written in `order`. Enumerations read from bit fields
/// take the raw value (a 2-bit field can hold a value the enum does not name).
void decode(std::span<const std::uint8_t, IgControl::kSize> in, ByteOrder order, IgControl& p) noexcept;
void decode(std::span<const std::uint8_t, EntityControl::kSize> in, ByteOrder order, EntityControl& p) noexcept;
void decode(std::span<const std::uint8_t, RateControl::kSize> in, ByteOrder order, RateControl& p) noexcept;
void decode(std::span<const std::uint8_t, CelestialSphereControl::kSize> in, ByteOrder order,
            CelestialSphereControl& p) noexcept;
void decode(std::span<const std::uint8_t, AtmosphereControl::kSize> in, ByteOrder order, AtmosphereControl& p) noexcept;
void decode(std::span<const std::uint8_t, ViewControl::kSize> in, ByteOrder order, ViewControl& p) noexcept;
void decode(std::span<const std::uint8_t, ViewDefinition::kSize> in, ByteOrder order, ViewDefinition& p) noexcept;
void decode(std::span<const std::uint8_t, HatHotRequest::kSize> in, ByteOrder order, HatHotRequest& p) noexcept;
void decode(std::span<const std::uint8_t, LosSegmentRequest::kSize> in, ByteOrder order, LosSegmentRequest& p) noexcept;
void decode(std::span<const std::uint8_t, LosVectorRequest::kSize> in, ByteOrder order, LosVectorRequest& p) noexcept;
void decode(std::span<const std::uint8_t, StartOfFrame::kSize> in, ByteOrder order, StartOfFrame& p) noexcept;
void decode(std::span<const std::uint8_t, HatHotResponse::kSize> in, ByteOrder order, HatHotResponse& p) noexcept;
void decode(std::span<const std::uint8_t, HatHotExtendedResponse::kSize> in, ByteOrder order,
            HatHotExtendedResponse& p) noexcept;
void decode(std::span<const std::uint8_t, LosResponse::kSize> in, ByteOrder order, LosResponse& p) noexcept;
void decode(std::span<const std::uint8_t, LosExtendedResponse::kSize> in, ByteOrder order,
            LosExtendedResponse& p) noexcept;

}  // namespace fieldcast::io::cigi
