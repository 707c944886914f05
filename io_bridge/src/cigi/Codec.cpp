// CIGI 3.3 packet layouts (SISO-STD-013 ICD, Version 3.3), as the Wireshark CIGI dissector
// (epan/dissectors/packet-cigi.c, cigi3_3_* / cigi3_2_* / cigi3_*) and the CIGI Class Library
// read them. Offsets are bytes from the packet's start; byte 0 is the packet id, byte 1 the
// size. Bit 0 is a flags byte's least significant bit.
#include <io_bridge/cigi/Codec.h>

#include "WireFields.h"

namespace fieldcast::io::cigi {

using detail::bit;
using detail::bits;
using detail::field;
using detail::FieldReader;
using detail::FieldWriter;
using detail::flag;

namespace {

template <class P, std::size_t N>
FieldWriter<N> startPacket(std::span<std::uint8_t, N> out, ByteOrder order) noexcept {
  static_assert(N == P::kSize);
  FieldWriter<N> w(out, order);
  w.template u8<0>(P::kOpcode);
  w.template u8<1>(P::kSize);
  return w;
}

}  // namespace

// ---- IG Control (1), 24 bytes ---------------------------------------------------------------
// 2 major version | 3 database number (int8) | 4 IG mode (bits 0-1), timestamp valid (2),
// extrapolation enable (3), minor version (4-7) | 5 reserved | 6-7 byte-swap magic |
// 8 host frame number | 12 timestamp | 16 last IG frame number | 20-23 reserved

void encode(const IgControl& p, ByteOrder order, std::span<std::uint8_t, IgControl::kSize> out) noexcept {
  auto w = startPacket<IgControl>(out, order);
  w.u8<2>(kMajorVersion);
  w.u8<3>(static_cast<std::uint8_t>(p.databaseNumber));
  w.u8<4>(bits(static_cast<unsigned>(p.igMode), 0, 2) | bit(p.timestampValid, 2) | bit(p.extrapolationEnabled, 3) |
          bits(kMinorVersion, 4, 4));
  w.u16<6>(kByteSwapMagic);
  w.u32<8>(p.hostFrameNumber);
  w.u32<12>(p.timestampTicks);
  w.u32<16>(p.lastIgFrameNumber);
}

void decode(std::span<const std::uint8_t, IgControl::kSize> in, ByteOrder order, IgControl& p) noexcept {
  const FieldReader r(in, order);
  p.databaseNumber = static_cast<std::int8_t>(r.u8<3>());
  const std::uint8_t flags = r.u8<4>();
  p.igMode = static_cast<IgMode>(field(flags, 0, 2));
  p.timestampValid = flag(flags, 2);
  p.extrapolationEnabled = flag(flags, 3);
  p.hostFrameNumber = r.u32<8>();
  p.timestampTicks = r.u32<12>();
  p.lastIgFrameNumber = r.u32<16>();
}

// ---- Entity Control (2), 48 bytes -----------------------------------------------------------
// 2-3 entity id | 4 entity state (0-1), attach (2), collision detection (3), inherit alpha (4),
// ground/ocean clamp (5-6) | 5 animation direction (0), loop mode (1), animation state (2-3),
// extrapolation enable (4) | 6 alpha | 7 reserved | 8-9 entity type | 10-11 parent id |
// 12 roll | 16 pitch | 20 yaw (float) | 24 latitude/x | 32 longitude/y | 40 altitude/z (double)

void encode(const EntityControl& p, ByteOrder order, std::span<std::uint8_t, EntityControl::kSize> out) noexcept {
  auto w = startPacket<EntityControl>(out, order);
  w.u16<2>(p.entityId);
  w.u8<4>(bits(static_cast<unsigned>(p.entityState), 0, 2) | bits(static_cast<unsigned>(p.attachState), 2, 1) |
          bit(p.collisionDetectionEnabled, 3) | bit(p.inheritAlpha, 4) |
          bits(static_cast<unsigned>(p.groundOceanClamp), 5, 2));
  w.u8<5>(bits(static_cast<unsigned>(p.animationDirection), 0, 1) |
          bits(static_cast<unsigned>(p.animationLoopMode), 1, 1) | bits(static_cast<unsigned>(p.animationState), 2, 2) |
          bit(p.extrapolationEnabled, 4));
  w.u8<6>(p.alpha);
  w.u16<8>(p.entityType);
  w.u16<10>(p.parentId);
  w.f32<12>(p.rollDeg);
  w.f32<16>(p.pitchDeg);
  w.f32<20>(p.yawDeg);
  w.f64<24>(p.latitudeDegOrXM);
  w.f64<32>(p.longitudeDegOrYM);
  w.f64<40>(p.altitudeMOrZM);
}

void decode(std::span<const std::uint8_t, EntityControl::kSize> in, ByteOrder order, EntityControl& p) noexcept {
  const FieldReader r(in, order);
  p.entityId = r.u16<2>();
  const std::uint8_t state = r.u8<4>();
  p.entityState = static_cast<EntityState>(field(state, 0, 2));
  p.attachState = static_cast<AttachState>(field(state, 2, 1));
  p.collisionDetectionEnabled = flag(state, 3);
  p.inheritAlpha = flag(state, 4);
  p.groundOceanClamp = static_cast<GroundOceanClamp>(field(state, 5, 2));
  const std::uint8_t animation = r.u8<5>();
  p.animationDirection = static_cast<AnimationDirection>(field(animation, 0, 1));
  p.animationLoopMode = static_cast<AnimationLoopMode>(field(animation, 1, 1));
  p.animationState = static_cast<AnimationState>(field(animation, 2, 2));
  p.extrapolationEnabled = flag(animation, 4);
  p.alpha = r.u8<6>();
  p.entityType = r.u16<8>();
  p.parentId = r.u16<10>();
  p.rollDeg = r.f32<12>();
  p.pitchDeg = r.f32<16>();
  p.yawDeg = r.f32<20>();
  p.latitudeDegOrXM = r.f64<24>();
  p.longitudeDegOrYM = r.f64<32>();
  p.altitudeMOrZM = r.f64<40>();
}

// ---- Rate Control (8), 32 bytes -------------------------------------------------------------
// 2-3 entity id | 4 articulated part id | 5 apply to articulated part (0), coordinate system (1)
// | 6-7 reserved | 8 x | 12 y | 16 z rate (m/s) | 20 roll | 24 pitch | 28 yaw rate (deg/s)

void encode(const RateControl& p, ByteOrder order, std::span<std::uint8_t, RateControl::kSize> out) noexcept {
  auto w = startPacket<RateControl>(out, order);
  w.u16<2>(p.entityId);
  w.u8<4>(p.articulatedPartId);
  w.u8<5>(bit(p.applyToArticulatedPart, 0) | bits(static_cast<unsigned>(p.frame), 1, 1));
  w.f32<8>(p.xRateMps);
  w.f32<12>(p.yRateMps);
  w.f32<16>(p.zRateMps);
  w.f32<20>(p.rollRateDegps);
  w.f32<24>(p.pitchRateDegps);
  w.f32<28>(p.yawRateDegps);
}

void decode(std::span<const std::uint8_t, RateControl::kSize> in, ByteOrder order, RateControl& p) noexcept {
  const FieldReader r(in, order);
  p.entityId = r.u16<2>();
  p.articulatedPartId = r.u8<4>();
  const std::uint8_t flags = r.u8<5>();
  p.applyToArticulatedPart = flag(flags, 0);
  p.frame = static_cast<RateFrame>(field(flags, 1, 1));
  p.xRateMps = r.f32<8>();
  p.yRateMps = r.f32<12>();
  p.zRateMps = r.f32<16>();
  p.rollRateDegps = r.f32<20>();
  p.pitchRateDegps = r.f32<24>();
  p.yawRateDegps = r.f32<28>();
}

// ---- Celestial Sphere Control (9), 16 bytes -------------------------------------------------
// 2 hour | 3 minute | 4 ephemeris model (0), sun (1), moon (2), star field (3), date/time
// valid (4) | 5-7 reserved | 8 date (MMDDYYYY) | 12 star field intensity (%)

void encode(const CelestialSphereControl& p, ByteOrder order,
            std::span<std::uint8_t, CelestialSphereControl::kSize> out) noexcept {
  auto w = startPacket<CelestialSphereControl>(out, order);
  w.u8<2>(p.hour);
  w.u8<3>(p.minute);
  w.u8<4>(bit(p.ephemerisModelEnabled, 0) | bit(p.sunEnabled, 1) | bit(p.moonEnabled, 2) | bit(p.starFieldEnabled, 3) |
          bit(p.dateTimeValid, 4));
  w.u32<8>(p.dateMMDDYYYY);
  w.f32<12>(p.starFieldIntensityPercent);
}

void decode(std::span<const std::uint8_t, CelestialSphereControl::kSize> in, ByteOrder order,
            CelestialSphereControl& p) noexcept {
  const FieldReader r(in, order);
  p.hour = r.u8<2>();
  p.minute = r.u8<3>();
  const std::uint8_t flags = r.u8<4>();
  p.ephemerisModelEnabled = flag(flags, 0);
  p.sunEnabled = flag(flags, 1);
  p.moonEnabled = flag(flags, 2);
  p.starFieldEnabled = flag(flags, 3);
  p.dateTimeValid = flag(flags, 4);
  p.dateMMDDYYYY = r.u32<8>();
  p.starFieldIntensityPercent = r.f32<12>();
}

// ---- Atmosphere Control (10), 32 bytes ------------------------------------------------------
// 2 atmospheric model enable (0) | 3 humidity (%) | 4 air temperature (°C) | 8 visibility (m) |
// 12 horizontal wind (m/s) | 16 vertical wind (m/s) | 20 wind direction (deg) |
// 24 barometric pressure (mb) | 28-31 reserved

void encode(const AtmosphereControl& p, ByteOrder order,
            std::span<std::uint8_t, AtmosphereControl::kSize> out) noexcept {
  auto w = startPacket<AtmosphereControl>(out, order);
  w.u8<2>(bit(p.atmosphericModelEnabled, 0));
  w.u8<3>(p.humidityPercent);
  w.f32<4>(p.airTemperatureC);
  w.f32<8>(p.visibilityRangeM);
  w.f32<12>(p.horizontalWindSpeedMps);
  w.f32<16>(p.verticalWindSpeedMps);
  w.f32<20>(p.windDirectionDeg);
  w.f32<24>(p.barometricPressureHpa);
}

void decode(std::span<const std::uint8_t, AtmosphereControl::kSize> in, ByteOrder order,
            AtmosphereControl& p) noexcept {
  const FieldReader r(in, order);
  p.atmosphericModelEnabled = flag(r.u8<2>(), 0);
  p.humidityPercent = r.u8<3>();
  p.airTemperatureC = r.f32<4>();
  p.visibilityRangeM = r.f32<8>();
  p.horizontalWindSpeedMps = r.f32<12>();
  p.verticalWindSpeedMps = r.f32<16>();
  p.windDirectionDeg = r.f32<20>();
  p.barometricPressureHpa = r.f32<24>();
}

// ---- View Control (16), 32 bytes ------------------------------------------------------------
// 2-3 view id | 4 group id | 5 x (0), y (1), z (2), roll (3), pitch (4), yaw (5) enables |
// 6-7 entity id | 8 x | 12 y | 16 z offset (m) | 20 roll | 24 pitch | 28 yaw (deg)

void encode(const ViewControl& p, ByteOrder order, std::span<std::uint8_t, ViewControl::kSize> out) noexcept {
  auto w = startPacket<ViewControl>(out, order);
  w.u16<2>(p.viewId);
  w.u8<4>(p.groupId);
  w.u8<5>(bit(p.xOffsetEnabled, 0) | bit(p.yOffsetEnabled, 1) | bit(p.zOffsetEnabled, 2) | bit(p.rollEnabled, 3) |
          bit(p.pitchEnabled, 4) | bit(p.yawEnabled, 5));
  w.u16<6>(p.entityId);
  w.f32<8>(p.xOffsetM);
  w.f32<12>(p.yOffsetM);
  w.f32<16>(p.zOffsetM);
  w.f32<20>(p.rollDeg);
  w.f32<24>(p.pitchDeg);
  w.f32<28>(p.yawDeg);
}

void decode(std::span<const std::uint8_t, ViewControl::kSize> in, ByteOrder order, ViewControl& p) noexcept {
  const FieldReader r(in, order);
  p.viewId = r.u16<2>();
  p.groupId = r.u8<4>();
  const std::uint8_t enables = r.u8<5>();
  p.xOffsetEnabled = flag(enables, 0);
  p.yOffsetEnabled = flag(enables, 1);
  p.zOffsetEnabled = flag(enables, 2);
  p.rollEnabled = flag(enables, 3);
  p.pitchEnabled = flag(enables, 4);
  p.yawEnabled = flag(enables, 5);
  p.entityId = r.u16<6>();
  p.xOffsetM = r.f32<8>();
  p.yOffsetM = r.f32<12>();
  p.zOffsetM = r.f32<16>();
  p.rollDeg = r.f32<20>();
  p.pitchDeg = r.f32<24>();
  p.yawDeg = r.f32<28>();
}

// ---- View Definition (21), 32 bytes ---------------------------------------------------------
// 2-3 view id | 4 group id | 5 near (0), far (1), left (2), right (3), top (4), bottom (5)
// enables, mirror mode (6-7) | 6 pixel replication (0-2), projection type (3), reorder (4),
// view type (5-7) | 7 reserved | 8 near | 12 far (m) | 16 left | 20 right | 24 top | 28 bottom (deg)

void encode(const ViewDefinition& p, ByteOrder order, std::span<std::uint8_t, ViewDefinition::kSize> out) noexcept {
  auto w = startPacket<ViewDefinition>(out, order);
  w.u16<2>(p.viewId);
  w.u8<4>(p.groupId);
  w.u8<5>(bit(p.nearEnabled, 0) | bit(p.farEnabled, 1) | bit(p.leftEnabled, 2) | bit(p.rightEnabled, 3) |
          bit(p.topEnabled, 4) | bit(p.bottomEnabled, 5) | bits(static_cast<unsigned>(p.mirrorMode), 6, 2));
  w.u8<6>(bits(p.pixelReplication, 0, 3) | bits(static_cast<unsigned>(p.projectionType), 3, 1) | bit(p.reorder, 4) |
          bits(p.viewType, 5, 3));
  w.f32<8>(p.nearM);
  w.f32<12>(p.farM);
  w.f32<16>(p.leftDeg);
  w.f32<20>(p.rightDeg);
  w.f32<24>(p.topDeg);
  w.f32<28>(p.bottomDeg);
}

void decode(std::span<const std::uint8_t, ViewDefinition::kSize> in, ByteOrder order, ViewDefinition& p) noexcept {
  const FieldReader r(in, order);
  p.viewId = r.u16<2>();
  p.groupId = r.u8<4>();
  const std::uint8_t enables = r.u8<5>();
  p.nearEnabled = flag(enables, 0);
  p.farEnabled = flag(enables, 1);
  p.leftEnabled = flag(enables, 2);
  p.rightEnabled = flag(enables, 3);
  p.topEnabled = flag(enables, 4);
  p.bottomEnabled = flag(enables, 5);
  p.mirrorMode = static_cast<MirrorMode>(field(enables, 6, 2));
  const std::uint8_t kind = r.u8<6>();
  p.pixelReplication = static_cast<std::uint8_t>(field(kind, 0, 3));
  p.projectionType = static_cast<ProjectionType>(field(kind, 3, 1));
  p.reorder = flag(kind, 4);
  p.viewType = static_cast<std::uint8_t>(field(kind, 5, 3));
  p.nearM = r.f32<8>();
  p.farM = r.f32<12>();
  p.leftDeg = r.f32<16>();
  p.rightDeg = r.f32<20>();
  p.topDeg = r.f32<24>();
  p.bottomDeg = r.f32<28>();
}

// ---- HAT/HOT Request (24), 32 bytes ---------------------------------------------------------
// 2-3 HAT/HOT id | 4 request type (0-1), coordinate system (2) | 5 update period |
// 6-7 entity id | 8 latitude/x | 16 longitude/y | 24 altitude/z (double)

void encode(const HatHotRequest& p, ByteOrder order, std::span<std::uint8_t, HatHotRequest::kSize> out) noexcept {
  auto w = startPacket<HatHotRequest>(out, order);
  w.u16<2>(p.hatHotId);
  w.u8<4>(bits(static_cast<unsigned>(p.requestType), 0, 2) | bits(static_cast<unsigned>(p.coordinateSystem), 2, 1));
  w.u8<5>(p.updatePeriod);
  w.u16<6>(p.entityId);
  w.f64<8>(p.latitudeDegOrXM);
  w.f64<16>(p.longitudeDegOrYM);
  w.f64<24>(p.altitudeMOrZM);
}

void decode(std::span<const std::uint8_t, HatHotRequest::kSize> in, ByteOrder order, HatHotRequest& p) noexcept {
  const FieldReader r(in, order);
  p.hatHotId = r.u16<2>();
  const std::uint8_t flags = r.u8<4>();
  p.requestType = static_cast<HatHotRequestType>(field(flags, 0, 2));
  p.coordinateSystem = static_cast<CoordinateSystem>(field(flags, 2, 1));
  p.updatePeriod = r.u8<5>();
  p.entityId = r.u16<6>();
  p.latitudeDegOrXM = r.f64<8>();
  p.longitudeDegOrYM = r.f64<16>();
  p.altitudeMOrZM = r.f64<24>();
}

// ---- Line of Sight Segment Request (25), 64 bytes -------------------------------------------
// 2-3 LOS id | 4 request type (0), source (1), destination (2), response (3) coordinate
// systems, destination entity id valid (4) | 5 alpha threshold | 6-7 entity id |
// 8/16/24 source lat/x, lon/y, alt/z | 32/40/48 destination lat/x, lon/y, alt/z (double) |
// 56 material mask | 60 update period | 61 reserved | 62-63 destination entity id

void encode(const LosSegmentRequest& p, ByteOrder order,
            std::span<std::uint8_t, LosSegmentRequest::kSize> out) noexcept {
  auto w = startPacket<LosSegmentRequest>(out, order);
  w.u16<2>(p.losId);
  w.u8<4>(bits(static_cast<unsigned>(p.requestType), 0, 1) |
          bits(static_cast<unsigned>(p.sourceCoordinateSystem), 1, 1) |
          bits(static_cast<unsigned>(p.destinationCoordinateSystem), 2, 1) |
          bits(static_cast<unsigned>(p.responseCoordinateSystem), 3, 1) | bit(p.destinationEntityIdValid, 4));
  w.u8<5>(p.alphaThreshold);
  w.u16<6>(p.entityId);
  w.f64<8>(p.sourceLatitudeDegOrXM);
  w.f64<16>(p.sourceLongitudeDegOrYM);
  w.f64<24>(p.sourceAltitudeMOrZM);
  w.f64<32>(p.destinationLatitudeDegOrXM);
  w.f64<40>(p.destinationLongitudeDegOrYM);
  w.f64<48>(p.destinationAltitudeMOrZM);
  w.u32<56>(p.materialMask);
  w.u8<60>(p.updatePeriod);
  w.u16<62>(p.destinationEntityId);
}

void decode(std::span<const std::uint8_t, LosSegmentRequest::kSize> in, ByteOrder order,
            LosSegmentRequest& p) noexcept {
  const FieldReader r(in, order);
  p.losId = r.u16<2>();
  const std::uint8_t flags = r.u8<4>();
  p.requestType = static_cast<LosRequestType>(field(flags, 0, 1));
  p.sourceCoordinateSystem = static_cast<CoordinateSystem>(field(flags, 1, 1));
  p.destinationCoordinateSystem = static_cast<CoordinateSystem>(field(flags, 2, 1));
  p.responseCoordinateSystem = static_cast<CoordinateSystem>(field(flags, 3, 1));
  p.destinationEntityIdValid = flag(flags, 4);
  p.alphaThreshold = r.u8<5>();
  p.entityId = r.u16<6>();
  p.sourceLatitudeDegOrXM = r.f64<8>();
  p.sourceLongitudeDegOrYM = r.f64<16>();
  p.sourceAltitudeMOrZM = r.f64<24>();
  p.destinationLatitudeDegOrXM = r.f64<32>();
  p.destinationLongitudeDegOrYM = r.f64<40>();
  p.destinationAltitudeMOrZM = r.f64<48>();
  p.materialMask = r.u32<56>();
  p.updatePeriod = r.u8<60>();
  p.destinationEntityId = r.u16<62>();
}

// ---- Line of Sight Vector Request (26), 56 bytes --------------------------------------------
// 2-3 LOS id | 4 request type (0), source (1), response (2) coordinate systems | 5 alpha
// threshold | 6-7 entity id | 8 azimuth | 12 elevation (deg) | 16 minimum | 20 maximum range (m)
// | 24/32/40 source lat/x, lon/y, alt/z (double) | 48 material mask | 52 update period |
// 53-55 reserved

void encode(const LosVectorRequest& p, ByteOrder order, std::span<std::uint8_t, LosVectorRequest::kSize> out) noexcept {
  auto w = startPacket<LosVectorRequest>(out, order);
  w.u16<2>(p.losId);
  w.u8<4>(bits(static_cast<unsigned>(p.requestType), 0, 1) |
          bits(static_cast<unsigned>(p.sourceCoordinateSystem), 1, 1) |
          bits(static_cast<unsigned>(p.responseCoordinateSystem), 2, 1));
  w.u8<5>(p.alphaThreshold);
  w.u16<6>(p.entityId);
  w.f32<8>(p.azimuthDeg);
  w.f32<12>(p.elevationDeg);
  w.f32<16>(p.minRangeM);
  w.f32<20>(p.maxRangeM);
  w.f64<24>(p.sourceLatitudeDegOrXM);
  w.f64<32>(p.sourceLongitudeDegOrYM);
  w.f64<40>(p.sourceAltitudeMOrZM);
  w.u32<48>(p.materialMask);
  w.u8<52>(p.updatePeriod);
}

void decode(std::span<const std::uint8_t, LosVectorRequest::kSize> in, ByteOrder order, LosVectorRequest& p) noexcept {
  const FieldReader r(in, order);
  p.losId = r.u16<2>();
  const std::uint8_t flags = r.u8<4>();
  p.requestType = static_cast<LosRequestType>(field(flags, 0, 1));
  p.sourceCoordinateSystem = static_cast<CoordinateSystem>(field(flags, 1, 1));
  p.responseCoordinateSystem = static_cast<CoordinateSystem>(field(flags, 2, 1));
  p.alphaThreshold = r.u8<5>();
  p.entityId = r.u16<6>();
  p.azimuthDeg = r.f32<8>();
  p.elevationDeg = r.f32<12>();
  p.minRangeM = r.f32<16>();
  p.maxRangeM = r.f32<20>();
  p.sourceLatitudeDegOrXM = r.f64<24>();
  p.sourceLongitudeDegOrYM = r.f64<32>();
  p.sourceAltitudeMOrZM = r.f64<40>();
  p.materialMask = r.u32<48>();
  p.updatePeriod = r.u8<52>();
}

// ---- Start of Frame (101), 24 bytes ---------------------------------------------------------
// 2 major version | 3 database number (int8) | 4 IG status | 5 IG mode (0-1), timestamp valid
// (2), Earth reference model (3), minor version (4-7) | 6-7 byte-swap magic | 8 IG frame
// number | 12 timestamp | 16 last host frame number | 20-23 reserved

void encode(const StartOfFrame& p, ByteOrder order, std::span<std::uint8_t, StartOfFrame::kSize> out) noexcept {
  auto w = startPacket<StartOfFrame>(out, order);
  w.u8<2>(kMajorVersion);
  w.u8<3>(static_cast<std::uint8_t>(p.databaseNumber));
  w.u8<4>(p.igStatus);
  w.u8<5>(bits(static_cast<unsigned>(p.igMode), 0, 2) | bit(p.timestampValid, 2) |
          bits(static_cast<unsigned>(p.earthReferenceModel), 3, 1) | bits(kMinorVersion, 4, 4));
  w.u16<6>(kByteSwapMagic);
  w.u32<8>(p.igFrameNumber);
  w.u32<12>(p.timestampTicks);
  w.u32<16>(p.lastHostFrameNumber);
}

void decode(std::span<const std::uint8_t, StartOfFrame::kSize> in, ByteOrder order, StartOfFrame& p) noexcept {
  const FieldReader r(in, order);
  p.databaseNumber = static_cast<std::int8_t>(r.u8<3>());
  p.igStatus = r.u8<4>();
  const std::uint8_t flags = r.u8<5>();
  p.igMode = static_cast<IgMode>(field(flags, 0, 2));
  p.timestampValid = flag(flags, 2);
  p.earthReferenceModel = static_cast<EarthReferenceModel>(field(flags, 3, 1));
  p.igFrameNumber = r.u32<8>();
  p.timestampTicks = r.u32<12>();
  p.lastHostFrameNumber = r.u32<16>();
}

// ---- HAT/HOT Response (102), 16 bytes -------------------------------------------------------
// 2-3 HAT/HOT id | 4 valid (0), response type (1), host frame number LSN (4-7) | 5-7 reserved |
// 8 height (double, m)

void encode(const HatHotResponse& p, ByteOrder order, std::span<std::uint8_t, HatHotResponse::kSize> out) noexcept {
  auto w = startPacket<HatHotResponse>(out, order);
  w.u16<2>(p.hatHotId);
  w.u8<4>(bit(p.valid, 0) | bits(static_cast<unsigned>(p.responseType), 1, 1) | bits(p.hostFrameNumberLsn, 4, 4));
  w.f64<8>(p.heightM);
}

void decode(std::span<const std::uint8_t, HatHotResponse::kSize> in, ByteOrder order, HatHotResponse& p) noexcept {
  const FieldReader r(in, order);
  p.hatHotId = r.u16<2>();
  const std::uint8_t flags = r.u8<4>();
  p.valid = flag(flags, 0);
  p.responseType = static_cast<HatHotResponseType>(field(flags, 1, 1));
  p.hostFrameNumberLsn = static_cast<std::uint8_t>(field(flags, 4, 4));
  p.heightM = r.f64<8>();
}

// ---- HAT/HOT Extended Response (103), 40 bytes ----------------------------------------------
// 2-3 HAT/HOT id | 4 valid (0), host frame number LSN (4-7) | 5-7 reserved | 8 HAT | 16 HOT
// (double, m) | 24 material code | 28 normal azimuth | 32 normal elevation (deg) | 36-39 reserved

void encode(const HatHotExtendedResponse& p, ByteOrder order,
            std::span<std::uint8_t, HatHotExtendedResponse::kSize> out) noexcept {
  auto w = startPacket<HatHotExtendedResponse>(out, order);
  w.u16<2>(p.hatHotId);
  w.u8<4>(bit(p.valid, 0) | bits(p.hostFrameNumberLsn, 4, 4));
  w.f64<8>(p.heightAboveTerrainM);
  w.f64<16>(p.heightOfTerrainM);
  w.u32<24>(p.materialCode);
  w.f32<28>(p.normalAzimuthDeg);
  w.f32<32>(p.normalElevationDeg);
}

void decode(std::span<const std::uint8_t, HatHotExtendedResponse::kSize> in, ByteOrder order,
            HatHotExtendedResponse& p) noexcept {
  const FieldReader r(in, order);
  p.hatHotId = r.u16<2>();
  const std::uint8_t flags = r.u8<4>();
  p.valid = flag(flags, 0);
  p.hostFrameNumberLsn = static_cast<std::uint8_t>(field(flags, 4, 4));
  p.heightAboveTerrainM = r.f64<8>();
  p.heightOfTerrainM = r.f64<16>();
  p.materialCode = r.u32<24>();
  p.normalAzimuthDeg = r.f32<28>();
  p.normalElevationDeg = r.f32<32>();
}

// ---- Line of Sight Response (104), 16 bytes -------------------------------------------------
// 2-3 LOS id | 4 valid (0), entity id valid (1), visible (2), host frame number LSN (4-7) |
// 5 response count | 6-7 entity id | 8 range (double, m)

void encode(const LosResponse& p, ByteOrder order, std::span<std::uint8_t, LosResponse::kSize> out) noexcept {
  auto w = startPacket<LosResponse>(out, order);
  w.u16<2>(p.losId);
  w.u8<4>(bit(p.valid, 0) | bit(p.entityIdValid, 1) | bit(p.visible, 2) | bits(p.hostFrameNumberLsn, 4, 4));
  w.u8<5>(p.responseCount);
  w.u16<6>(p.entityId);
  w.f64<8>(p.rangeM);
}

void decode(std::span<const std::uint8_t, LosResponse::kSize> in, ByteOrder order, LosResponse& p) noexcept {
  const FieldReader r(in, order);
  p.losId = r.u16<2>();
  const std::uint8_t flags = r.u8<4>();
  p.valid = flag(flags, 0);
  p.entityIdValid = flag(flags, 1);
  p.visible = flag(flags, 2);
  p.hostFrameNumberLsn = static_cast<std::uint8_t>(field(flags, 4, 4));
  p.responseCount = r.u8<5>();
  p.entityId = r.u16<6>();
  p.rangeM = r.f64<8>();
}

// ---- Line of Sight Extended Response (105), 56 bytes ----------------------------------------
// 2-3 LOS id | 4 valid (0), entity id valid (1), range valid (2), visible (3), host frame
// number LSN (4-7) | 5 response count | 6-7 entity id | 8 range | 16/24/32 lat/x, lon/y, alt/z
// (double) | 40 red | 41 green | 42 blue | 43 alpha | 44 material code | 48 normal azimuth |
// 52 normal elevation (deg)

void encode(const LosExtendedResponse& p, ByteOrder order,
            std::span<std::uint8_t, LosExtendedResponse::kSize> out) noexcept {
  auto w = startPacket<LosExtendedResponse>(out, order);
  w.u16<2>(p.losId);
  w.u8<4>(bit(p.valid, 0) | bit(p.entityIdValid, 1) | bit(p.rangeValid, 2) | bit(p.visible, 3) |
          bits(p.hostFrameNumberLsn, 4, 4));
  w.u8<5>(p.responseCount);
  w.u16<6>(p.entityId);
  w.f64<8>(p.rangeM);
  w.f64<16>(p.latitudeDegOrXM);
  w.f64<24>(p.longitudeDegOrYM);
  w.f64<32>(p.altitudeMOrZM);
  w.u8<40>(p.red);
  w.u8<41>(p.green);
  w.u8<42>(p.blue);
  w.u8<43>(p.alpha);
  w.u32<44>(p.materialCode);
  w.f32<48>(p.normalAzimuthDeg);
  w.f32<52>(p.normalElevationDeg);
}

void decode(std::span<const std::uint8_t, LosExtendedResponse::kSize> in, ByteOrder order,
            LosExtendedResponse& p) noexcept {
  const FieldReader r(in, order);
  p.losId = r.u16<2>();
  const std::uint8_t flags = r.u8<4>();
  p.valid = flag(flags, 0);
  p.entityIdValid = flag(flags, 1);
  p.rangeValid = flag(flags, 2);
  p.visible = flag(flags, 3);
  p.hostFrameNumberLsn = static_cast<std::uint8_t>(field(flags, 4, 4));
  p.responseCount = r.u8<5>();
  p.entityId = r.u16<6>();
  p.rangeM = r.f64<8>();
  p.latitudeDegOrXM = r.f64<16>();
  p.longitudeDegOrYM = r.f64<24>();
  p.altitudeMOrZM = r.f64<32>();
  p.red = r.u8<40>();
  p.green = r.u8<41>();
  p.blue = r.u8<42>();
  p.alpha = r.u8<43>();
  p.materialCode = r.u32<44>();
  p.normalAzimuthDeg = r.f32<48>();
  p.normalElevationDeg = r.f32<52>();
}

}  // namespace fieldcast::io::cigi
